// Scene reader of rotational_spring_damper (elements/RotationalSpring.hpp).
#include "elements/RotationalSpring.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

/// rotational_spring_damper {axis: [a, b], from: [c, d], to: [e, f], stiffness, damping?,
/// rest_angle?}: torque -k (theta - theta0) - c theta' [N m]; theta0 defaults to the initial angle.
void readRotationalSpring(SceneContext& ctx, const YAML::Node& el, const std::string& path,
                          const std::string& name) {
  const YamlReader& r = ctx.r;
  r.allowKeys(el, path, {"name", "type", "axis", "from", "to", "stiffness", "damping", "rest_angle"});
  ctx.requireSpatial(el, path, "a rotational spring-damper");
  const AngleNodes an = ctx.angleNodes(el, path);
  const Quantity k{r.nonNegative(r.require(el, "stiffness", path), path + ".stiffness"), -1};
  const Quantity c{el["damping"] ? r.nonNegative(el["damping"], path + ".damping") : 0.0, -1};
  const double theta = ctx.initialAngle(an, el, path);
  const double rest = (!el["rest_angle"] || r.isAuto(el["rest_angle"])) ? theta
                                                                        : r.number(el["rest_angle"], path + ".rest_angle");
  auto sp = std::make_unique<RotationalSpringDamper>(name, an, k, c, rest);
  ctx.bindAll(name, sp->properties());
  ctx.m.elements.push_back(std::move(sp));
}

}  // namespace flexsens
