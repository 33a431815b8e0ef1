// Scene reader of point_force (elements/PointForce.hpp).
#include "elements/PlanarFollowerForce.hpp"
#include "elements/PointForce.hpp"
#include "elements/SpatialFollowerForce.hpp"
#include "scene/KindTable.hpp"
#include "scene/TimeFunctionReader.hpp"

namespace flexsens {

/// point_force {node, force: [dim numbers], function?}: a load F f(t) [N] on a node (f = 1
/// without `function`: a dead load), each component bindable as a parameter by its axis name
/// (e.g. `property: y`), the function's constants by theirs (e.g. `property: amplitude`).
/// `follower: true` with `body: [A, B]` (planar) or `body: [A, B, C]` (spatial): F is given at
/// t = 0 and turns with the body through those nodes.
void readPointForce(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  const Model& m = ctx.m;
  r.allowKeys(el, path, {"name", "type", "node", "force", "function", "follower", "body"});
  const bool follower = el["follower"] && r.boolean(el["follower"], path + ".follower");
  const int id = ctx.node(r.require(el, "node", path), path + ".node");
  if (m.nodes[id].ground)
    r.fail(el["node"], path + ".node", "node '" + m.nodes[id].name + "' is a ground node: a load on it does nothing");
  const VecX f = r.vector(r.require(el, "force", path), path + ".force", m.dim);
  std::vector<Quantity> comps;
  for (int c = 0; c < m.dim; ++c) comps.push_back({f[c], -1});
  std::unique_ptr<TimeFunction> fn;
  if (el["function"]) fn = readTimeFunction(ctx, el["function"], path + ".function", name);
  if (follower) {
    // follower: true, body: [A, B] (planar) or [A, B, C] (spatial): the force turns with the
    // body through those nodes.
    if (!el["body"]) r.require(el, "body", path);
    const YAML::Node b = el["body"];
    r.requireList(b, path + ".body");
    const size_t n = m.dim == 2 ? 2 : 3;
    if (b.size() != n)
      r.fail(b, path + ".body",
             m.dim == 2 ? "expected two node names [A, B]: the body's direction A->B"
                        : "expected three node names [A, B, C] of the body, not collinear: its triad "
                          "(A->B, A->C, their cross product) turns the force");
    std::vector<int> ids;
    for (size_t k = 0; k < n; ++k) ids.push_back(ctx.node(b[k], at(path + ".body", k)));
    std::unique_ptr<Element> ff;
    if (m.dim == 2) {
      if (!(ctx.distance(ids[0], ids[1]) > 1e-9))
        r.fail(b, path + ".body", "the two nodes coincide at t = 0: they must span the body");
      ff = std::make_unique<PlanarFollowerForce>(name, id, ids[0], ids[1],
                                                 VecX(m.nodes[ids[1]].position - m.nodes[ids[0]].position), comps,
                                                 std::move(fn));
    } else {
      Eigen::Matrix3d X0;
      for (int k = 0; k < 3; ++k) X0.col(k) = m.nodes[ids[k]].position;
      const Eigen::Vector3d d1 = X0.col(1) - X0.col(0), d2 = X0.col(2) - X0.col(0);
      if (!(d1.cross(d2).norm() > 1e-6 * d1.norm() * d2.norm()))
        r.fail(b, path + ".body", "the three nodes are collinear (or coincide) at t = 0: they must span a plane of the body");
      ff = std::make_unique<SpatialFollowerForce>(name, id, ids[0], ids[1], ids[2], X0, comps, std::move(fn));
    }
    auto props = ff->properties();
    for (int c = 0; c < m.dim; ++c) ctx.bind(name + "." + std::string(1, m.axisName(c)), props[c].second);
    ctx.m.elements.push_back(std::move(ff));
    return;
  }
  if (el["body"]) r.fail(el["body"], path + ".body", "'body' belongs to a follower force (follower: true)");
  auto pf = std::make_unique<PointForce>(name, id, comps, std::move(fn));
  // Bind by the scene's axis names (a planar xz scene's second component is "z").
  auto props = pf->properties();
  for (int c = 0; c < m.dim; ++c) ctx.bind(name + "." + std::string(1, m.axisName(c)), props[c].second);
  ctx.m.elements.push_back(std::move(pf));
}

}  // namespace flexsens
