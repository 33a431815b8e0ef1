// Scene reader of point_torque: planar (elements/PlanarTorque.hpp) and spatial
// (elements/SpatialTorque.hpp).
#include "elements/GradientTorque.hpp"
#include "elements/PlanarTorque.hpp"
#include "elements/SpatialTorque.hpp"
#include "scene/KindTable.hpp"
#include "scene/TimeFunctionReader.hpp"

namespace flexsens {

namespace {

/// nodes: [A, B] on the end of an ANCF chain (both with free slopes) bends the end element
/// instead of turning the section (2-4x the error of a positions-only beam on the roll-up).
void refuseCoupleOnSlopes(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::vector<int>& ids) {
  ctx.afterElements.push_back([&ctx, el, path, ids] {
    for (int id : ids)
      if (!ctx.m.nodes[id].slopeFree()) return;
    ctx.r.fail(el["nodes"], path + ".nodes", "nodes '" + ctx.m.nodes[ids[0]].name + "' and '" + ctx.m.nodes[ids[1]].name +
               "' carry slope coordinates (ANCF): a couple on their positions bends the element between them; give "
               "node: " + ctx.m.nodes[ids.back()].name + " to apply the torque through its slope");
  });
}

/// point_torque {nodes: [A, B] or [A, B, C], torque: [Tx, Ty, Tz], function?, follower?}
/// (spatial): a torque T0 f(t) [N m] in global components on the body through the nodes;
/// with two nodes T0 must be perpendicular to A-B (only that part acts on them); `follower:
/// true` (three nodes) turns it with the body. Components bindable by axis name (x, y, z).
void readSpatialTorque(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  const Model& m = ctx.m;
  const YAML::Node list = r.require(el, "nodes", path);
  if (!list.IsSequence() || (list.size() != 2 && list.size() != 3))
    r.fail(list, path + ".nodes", "expected [A, B] or [A, B, C]: two or three node names of one body");
  const std::vector<int> ids = ctx.nodeList(el, path, 2, 3);
  if (ids.size() == 2) refuseCoupleOnSlopes(ctx, el, path, ids);
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

/// point_torque {node: X, torque, function?, follower?}: the torque through the slope coordinates
/// of ANCF node X (elements/GradientTorque.hpp). Runs after the elements: X's chain sets them.
void readGradientTorque(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  const int dim = ctx.m.dim;
  const int id = ctx.node(el["node"], path + ".node");
  const Node& nd = ctx.m.nodes[id];
  if (!nd.hasSlope())
    r.fail(el["node"], path + ".node", "node '" + nd.name + "' carries no slope coordinates (it is on no ancf_cable or "
           "ancf_beam); a torque on a positions-only body takes nodes: [A, B] of that body");
  if (nd.clamped)
    r.fail(el["node"], path + ".node", "node '" + nd.name + "' is clamped: its slope is fixed, a torque there does nothing");
  const int g = nd.gradients(dim);
  std::unique_ptr<TimeFunction> fn;
  if (el["function"]) fn = readTimeFunction(ctx, el["function"], path + ".function", name);
  const bool follower = el["follower"] && r.boolean(el["follower"], path + ".follower");
  std::unique_ptr<Element> inner;
  std::vector<Quantity*> props;
  if (dim == 2) {
    if (follower) r.fail(el["follower"], path + ".follower", "planar torques have no follower form (a planar torque turns with any body)");
    inner = std::make_unique<PlanarTorque>(name, id, id, Quantity{r.number(r.require(el, "torque", path), path + ".torque"), -1},
                                           std::move(fn));
  } else {
    const Eigen::Vector3d T0 = r.vector(r.require(el, "torque", path), path + ".torque", 3);
    MatX X0 = MatX::Zero(3, g == 1 ? 2 : 3);  // A at the origin, then r' (cable) or r_y, r_z (ancf_beam)
    for (int c = 1; c < X0.cols(); ++c) X0.col(c) = nd.slope.segment(3 * (c - 1 + (g == 3 ? 1 : 0)), 3);
    if (g == 1 && follower)
      r.fail(el["follower"], path + ".follower", "a follower torque needs a triad; an ancf_cable node has one slope (an ancf_beam node has three gradients)");
    if (g == 1 && std::abs(T0.dot(X0.col(1))) > 1e-9 * T0.norm())
      r.fail(el["torque"], path + ".torque", "has a component along the slope of node '" + nd.name + "' at t = 0 (a twist), which "
             "an ancf_cable does not carry: give a torque perpendicular to the cable (an ancf_beam carries twist)");
    std::vector<Quantity> comps;
    for (int c = 0; c < 3; ++c) comps.push_back({T0[c], -1});
    inner = std::make_unique<SpatialTorque>(name, std::vector<int>(X0.cols(), id), comps, std::move(fn), follower, X0);
  }
  auto t = std::make_unique<GradientTorque>(name, id, g, std::move(inner));
  auto tp = t->properties();
  if (dim == 2) ctx.bind(name + ".torque", tp[0].second);
  for (int c = 0; dim == 3 && c < 3; ++c) ctx.bind(name + "." + std::string(1, ctx.m.axisName(c)), tp[c].second);
  ctx.m.elements.push_back(std::move(t));
}

}  // namespace

/// point_torque {nodes: [A, B], torque, function?} (planar): a torque tau f(t) [N m],
/// counter-clockwise, on the body through nodes A and B; `torque` and the function's constants
/// are bindable. In 3D see readSpatialTorque.
void readPointTorque(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  if (ctx.m.dim == 3) r.allowKeys(el, path, {"name", "type", "nodes", "node", "torque", "function", "follower"});
  else r.allowKeys(el, path, {"name", "type", "nodes", "node", "torque", "function"});
  if (el["node"] && el["nodes"])
    r.fail(el["node"], path + ".node", "give nodes: [A, B] (a couple on a body's nodes) or node: X (through the slope of ANCF node X), not both");
  if (el["node"]) {
    ctx.afterElements.push_back([&ctx, el, path, name] { readGradientTorque(ctx, el, path, name); });
    return;
  }
  if (ctx.m.dim == 3) return readSpatialTorque(ctx, el, path, name);
  const auto ids = ctx.nodeList(el, path, 2, 2);
  refuseCoupleOnSlopes(ctx, el, path, ids);
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
