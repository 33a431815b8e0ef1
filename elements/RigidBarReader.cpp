// Scene readers of the two-node elements: rigid_bar and spring_damper (elements/RigidBar.hpp).
#include "constraints/Distance.hpp"
#include "elements/RigidBar.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

/// rigid_bar {nodes: [a, b], mass, length?}: natural-coordinate mass plus its own distance.
void readRigidBar(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  r.allowKeys(el, path, {"name", "type", "nodes", "mass", "length"});
  const auto ids = ctx.nodeList(el, path, 2, 2);
  const Quantity mass{r.positive(r.require(el, "mass", path), path + ".mass"), -1};
  auto bar = std::make_unique<RigidBar>(name, ids[0], ids[1], mass);
  auto con = std::make_unique<DistanceConstraint>(name + ".length", ids[0], ids[1],
                                                  ctx.length(el, "length", path + ".length", ids[0], ids[1]));
  ctx.bindAll(name, bar->properties());
  ctx.bindAll(name, con->properties());
  ctx.m.elements.push_back(std::move(bar));
  ctx.m.constraints.push_back(std::move(con));
}

/// spring_damper {nodes: [a, b], stiffness, damping?, natural_length?}: massless, linear.
void readSpringDamper(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  r.allowKeys(el, path, {"name", "type", "nodes", "stiffness", "damping", "natural_length"});
  const auto ids = ctx.nodeList(el, path, 2, 2);
  const Quantity k{r.nonNegative(r.require(el, "stiffness", path), path + ".stiffness"), -1};
  const Quantity c{el["damping"] ? r.nonNegative(el["damping"], path + ".damping") : 0.0, -1};
  // natural_length may be 0 (a zero-length spring, e.g. a bushing between coincident points).
  const YAML::Node L0 = el["natural_length"];
  const Quantity length = (L0 && !r.isAuto(L0) && r.number(L0, path + ".natural_length") == 0.0)
                              ? Quantity{0.0, -1}
                              : ctx.length(el, "natural_length", path + ".natural_length", ids[0], ids[1]);
  auto sp = std::make_unique<SpringDamper>(name, ids[0], ids[1], k, c, length);
  ctx.bindAll(name, sp->properties());
  ctx.bodies[name] = {ids, sp->properties()[2].second};
  ctx.m.elements.push_back(std::move(sp));
}

}  // namespace flexsens
