// Scene reader of point_force (elements/PointForce.hpp).
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
  r.allowKeys(el, path, {"name", "type", "node", "force", "function"});
  const int id = ctx.node(r.require(el, "node", path), path + ".node");
  if (m.nodes[id].ground)
    r.fail(el["node"], path + ".node", "node '" + m.nodes[id].name + "' is a ground node: a load on it does nothing");
  const VecX f = r.vector(r.require(el, "force", path), path + ".force", m.dim);
  std::vector<Quantity> comps;
  for (int c = 0; c < m.dim; ++c) comps.push_back({f[c], -1});
  std::unique_ptr<TimeFunction> fn;
  if (el["function"]) fn = readTimeFunction(ctx, el["function"], path + ".function", name);
  auto pf = std::make_unique<PointForce>(name, id, comps, std::move(fn));
  // Bind by the scene's axis names (a planar xz scene's second component is "z").
  auto props = pf->properties();
  for (int c = 0; c < m.dim; ++c) ctx.bind(name + "." + std::string(1, m.axisName(c)), props[c].second);
  ctx.m.elements.push_back(std::move(pf));
}

}  // namespace flexsens
