// Scene readers of the drivers (constraints/Driver.hpp): prescribed_coordinate,
// prescribed_distance, motor. Each prescribes its quantity as the initial value plus
// `function` (scene/TimeFunctionReader.hpp), whose constants are bindable by name.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "constraints/Driver.hpp"
#include "scene/KindTable.hpp"
#include "scene/SceneParts.hpp"
#include "scene/TimeFunctionReader.hpp"

namespace flexsens {

namespace {

/// A driver's initial speed f'(0) against the rate of its coordinate, distance or angle that
/// the scene's given initial velocities imply, s' = Phi_q v / (dPhi/ds). Both define the start
/// of the motion: when they differ the initial state would project the given velocities away
/// and the driver would jerk the body to its speed in the first step (an energy audit gain of
/// 2.6e9 J on a slider-crank). Checked only when a velocity is given on one of the driver's
/// nodes; without one the velocities are derived from the drivers.
void requireConsistentSpeed(SceneContext& ctx, const YAML::Node& c, const std::string& path, const Driver& d,
                            const char* unit) {
  const std::string* given = nullptr;
  for (int id : d.nodes())
    if (!given) given = ctx.velocitySource(id);
  if (!given) return;
  const int dim = ctx.m.dim;
  LocalState s;
  s.dim = dim;
  s.x.resize(dim * d.nodes().size());
  s.v.resize(s.x.size());
  for (size_t i = 0; i < d.nodes().size(); ++i) {
    s.x.segment(dim * i, dim) = ctx.m.nodes[d.nodes()[i]].position.head(dim);
    s.v.segment(dim * i, dim) = ctx.m.nodes[d.nodes()[i]].velocity.head(dim);
  }
  const VecX p;  // no parameter is bound yet: every constant is its nominal value
  s.p = &p;
  MatX J;
  d.jacobian(s, J);
  const double scale = d.reactionScale(s.x, nullptr);
  const double implied = (J * s.v)(0) / scale, prescribed = d.function().at(0.0, p).df;
  if (std::abs(implied - prescribed) <= 1e-6 * std::max({1.0, std::abs(implied), std::abs(prescribed)})) return;
  std::ostringstream os;
  os << "the driver's initial speed, the slope of its function at t = 0, is " << prescribed << " " << unit
     << "/s, but the initial velocities given (" << *given << ") move its "
     << (std::string(unit) == "rad" ? "angle" : "coordinate") << " at " << implied << " " << unit
     << "/s; make them agree (a `ramp` starts at rest: f'(0) = 0; `{type: linear, slope: w}` "
        "drives at speed w from t = 0), or leave the velocities out and let the drivers set them";
  ctx.r.fail(c["function"], path + ".function", os.str());
}

}  // namespace

/// prescribed_coordinate {node, axis, function}: x_axis(t) = x_axis(0) + f(t) [m].
void readPrescribedCoordinate(SceneContext& ctx, const YAML::Node& c, const std::string& path,
                              const std::string& name) {
  const YamlReader& r = ctx.r;
  r.allowKeys(c, path, {"name", "type", "node", "axis", "function"});
  const int id = ctx.node(r.require(c, "node", path), path + ".node");
  if (ctx.m.nodes[id].ground)
    r.fail(c["node"], path + ".node", "node '" + ctx.m.nodes[id].name + "' is a ground node: it cannot be driven");
  const YAML::Node ax = r.require(c, "axis", path);
  const int comp = axisIndex(ctx.m, r.text(ax, path + ".axis"));
  if (comp < 0) {
    std::string axes;
    for (int k = 0; k < ctx.m.dim; ++k) axes += std::string(axes.empty() ? "" : ", ") + ctx.m.axisName(k);
    r.fail(ax, path + ".axis", "expected one of the scene's axes (" + axes + ")");
  }
  auto f = readTimeFunction(ctx, r.require(c, "function", path), path + ".function", name);
  auto d = std::make_unique<CoordinateDriver>(name, id, ctx.m.dim, comp, ctx.m.nodes[id].position[comp], std::move(f));
  requireConsistentSpeed(ctx, c, path, *d, "m");
  ctx.m.constraints.push_back(std::move(d));
}

/// prescribed_distance {nodes: [a, b], function}: |x_b - x_a|(t) = L(0) + f(t) [m].
void readPrescribedDistance(SceneContext& ctx, const YAML::Node& c, const std::string& path,
                            const std::string& name) {
  const YamlReader& r = ctx.r;
  r.allowKeys(c, path, {"name", "type", "nodes", "function"});
  const auto ids = ctx.nodeList(c, path, 2, 2);
  const double L0 = ctx.distance(ids[0], ids[1]);
  if (!(L0 > 1e-9)) r.fail(c["nodes"], path + ".nodes", "the two nodes coincide at t = 0: a distance driver needs them apart");
  auto f = readTimeFunction(ctx, r.require(c, "function", path), path + ".function", name);
  auto d = std::make_unique<DistanceDriver>(name, ids[0], ids[1], ctx.m.dim, L0, std::move(f));
  requireConsistentSpeed(ctx, c, path, *d, "m");
  ctx.m.constraints.push_back(std::move(d));
}

/// motor {nodes: [a, b, c, d], function} (planar): the angle from direction a->b to direction
/// c->d, counter-clockwise, is its initial value + f(t) [rad]; a, b may be ground nodes.
void readMotor(SceneContext& ctx, const YAML::Node& c, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  r.allowKeys(c, path, {"name", "type", "nodes", "function"});
  if (ctx.m.dim != 2)
    r.fail(c["type"], path + ".type", "a motor is planar (dimension 2); in 3D drive a distance or a coordinate");
  const auto ids = ctx.nodeList(c, path, 4, 4, true);
  const VecX u = ctx.m.nodes[ids[1]].position - ctx.m.nodes[ids[0]].position;
  const VecX w = ctx.m.nodes[ids[3]].position - ctx.m.nodes[ids[2]].position;
  if (!(u.norm() > 1e-9) || !(w.norm() > 1e-9))
    r.fail(c["nodes"], path + ".nodes", "the directions a->b and c->d must have nonzero length at t = 0");
  const double theta0 = std::atan2(u[0] * w[1] - u[1] * w[0], u.dot(w));
  auto f = readTimeFunction(ctx, r.require(c, "function", path), path + ".function", name);
  auto d = std::make_unique<AngleDriver>(name, ids, theta0, std::move(f));
  requireConsistentSpeed(ctx, c, path, *d, "rad");
  ctx.m.constraints.push_back(std::move(d));
}

}  // namespace flexsens
