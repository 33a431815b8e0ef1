// Scene reader of point_torque (elements/PlanarTorque.hpp).
#include "elements/PlanarTorque.hpp"
#include "scene/KindTable.hpp"
#include "scene/TimeFunctionReader.hpp"

namespace flexsens {

/// point_torque {nodes: [A, B], torque, function?} (planar): a torque tau f(t) [N m],
/// counter-clockwise, on the body through nodes A and B; `torque` and the function's constants
/// are bindable.
void readPointTorque(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  r.allowKeys(el, path, {"name", "type", "nodes", "torque", "function"});
  if (ctx.m.dim != 2)
    r.fail(el["type"], path + ".type", "point_torque is planar (dimension 2): it acts on the line through two nodes");
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
