// Scene reader of point_force (elements/PointForce.hpp).
#include "elements/PlanarFollowerForce.hpp"
#include "elements/PointForce.hpp"
#include "scene/KindTable.hpp"
#include "scene/TimeFunctionReader.hpp"

namespace flexsens {

/// point_force {node, force: [dim numbers], function?}: a load F f(t) [N] on a node (f = 1
/// without `function`: a dead load), each component bindable as a parameter by its axis name
/// (e.g. `property: y`), the function's constants by theirs (e.g. `property: amplitude`).
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
    // follower: true, body: [A, B]: the force turns with the planar body through A and B.
    if (m.dim != 2)
      r.fail(el["follower"], path + ".follower", "follower forces are planar (dimension 2) for now; in 3D give a dead load");
    if (!el["body"]) r.require(el, "body", path);
    const YAML::Node b = el["body"];
    r.requireList(b, path + ".body");
    if (b.size() != 2) r.fail(b, path + ".body", "expected two node names [A, B]: the body's direction A->B");
    const int a = ctx.node(b[0], at(path + ".body", 0)), bb = ctx.node(b[1], at(path + ".body", 1));
    if (!(ctx.distance(a, bb) > 1e-9)) r.fail(b, path + ".body", "the two nodes coincide at t = 0: they must span the body");
    auto ff = std::make_unique<PlanarFollowerForce>(name, id, a, bb, VecX(m.nodes[bb].position - m.nodes[a].position),
                                                    comps, std::move(fn));
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
