// Scene reader of point_torque: planar (elements/PlanarTorque.hpp) and spatial
// (elements/SpatialTorque.hpp).
#include "elements/PlanarTorque.hpp"
#include "elements/SpatialTorque.hpp"
#include "scene/KindTable.hpp"
#include "scene/TimeFunctionReader.hpp"

namespace flexsens {

namespace {

/// point_torque {nodes: [A, B] or [A, B, C], torque: [Tx, Ty, Tz], function?, follower?}
/// (spatial): a torque T0 f(t) [N m] in global components on the body through the nodes;
/// with two nodes T0 must be perpendicular to A-B (only that part acts on them); `follower:
/// true` (three nodes) turns it with the body. Components bindable by axis name (x, y, z).
void readSpatialTorque(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  const Model& m = ctx.m;
  r.allowKeys(el, path, {"name", "type", "nodes", "torque", "function", "follower"});
  const YAML::Node list = r.require(el, "nodes", path);
  if (!list.IsSequence() || (list.size() != 2 && list.size() != 3))
    r.fail(list, path + ".nodes", "expected [A, B] or [A, B, C]: two or three node names of one body");
  const std::vector<int> ids = ctx.nodeList(el, path, 2, 3);
  bool allGround = true;
  for (int id : ids) allGround = allGround && m.nodes[id].ground;
  if (allGround) r.fail(list, path + ".nodes", "all nodes are ground nodes: a torque on them does nothing");
  const bool follower = el["follower"] && r.boolean(el["follower"], path + ".follower");
  const Eigen::Vector3d T0 = r.vector(r.require(el, "torque", path), path + ".torque", 3);
  MatX X0(3, ids.size());
  for (size_t k = 0; k < ids.size(); ++k) X0.col(k) = m.nodes[ids[k]].position;
  const Eigen::Vector3d d1 = X0.col(1) - X0.col(0);
  if (ids.size() == 2) {
    if (follower)
      r.fail(list, path + ".nodes", "a follower torque turns with the body: give three non-collinear nodes of it [A, B, C]");
    if (!(d1.norm() > 1e-9)) r.fail(list, path + ".nodes", "the two nodes coincide at t = 0: they must span the body");
    // A turn about A-B does not move A and B: that component cannot be applied through them.
    if (std::abs(T0.dot(d1)) / d1.norm() > 1e-9 * T0.norm())
      r.fail(el["torque"], path + ".torque",
             "has a component along the axis A-B of the two nodes at t = 0, which two nodes cannot apply: give a "
             "third node of the body (nodes: [A, B, C]) or a torque perpendicular to A-B");
  } else {
    const Eigen::Vector3d d2 = X0.col(2) - X0.col(0);
    if (!(d1.cross(d2).norm() > 1e-6 * d1.norm() * d2.norm()))
      r.fail(list, path + ".nodes", "the three nodes are collinear (or coincide) at t = 0: they must span a plane of the body");
  }
  std::vector<Quantity> comps;
  for (int c = 0; c < 3; ++c) comps.push_back({T0[c], -1});
  std::unique_ptr<TimeFunction> fn;
  if (el["function"]) fn = readTimeFunction(ctx, el["function"], path + ".function", name);
  auto t = std::make_unique<SpatialTorque>(name, ids, comps, std::move(fn), follower, X0);
  auto props = t->properties();
  for (int c = 0; c < 3; ++c) ctx.bind(name + "." + std::string(1, m.axisName(c)), props[c].second);
  ctx.m.elements.push_back(std::move(t));
}

}  // namespace

/// point_torque {nodes: [A, B], torque, function?} (planar): a torque tau f(t) [N m],
/// counter-clockwise, on the body through nodes A and B; `torque` and the function's constants
/// are bindable. In 3D see readSpatialTorque.
void readPointTorque(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  if (ctx.m.dim == 3) return readSpatialTorque(ctx, el, path, name);
  const YamlReader& r = ctx.r;
  r.allowKeys(el, path, {"name", "type", "nodes", "torque", "function"});
  const auto ids = ctx.nodeList(el, path, 2, 2);
  if (ctx.m.nodes[ids[0]].ground && ctx.m.nodes[ids[1]].ground)
    r.fail(el["nodes"], path + ".nodes", "both nodes are ground nodes: a torque on them does nothing");
  if (!(ctx.distance(ids[0], ids[1]) > 1e-9))
    r.fail(el["nodes"], path + ".nodes", "the two nodes coincide at t = 0: they must span the body");
  const Quantity tau{r.number(r.require(el, "torque", path), path + ".torque"), -1};
  std::unique_ptr<TimeFunction> fn;
  if (el["function"]) fn = readTimeFunction(ctx, el["function"], path + ".function", name);
  auto t = std::make_unique<PlanarTorque>(name, ids[0], ids[1], tau, std::move(fn));
  ctx.bind(name + ".torque", t->properties()[0].second);
  ctx.m.elements.push_back(std::move(t));
}

}  // namespace flexsens
