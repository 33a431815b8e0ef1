// Scene readers of the drivers (constraints/Driver.hpp): prescribed_coordinate,
// prescribed_distance, motor. Each prescribes its quantity as the initial value plus
// `function` (scene/TimeFunctionReader.hpp), whose constants are bindable by name.
#include <cmath>

#include "constraints/Driver.hpp"
#include "scene/KindTable.hpp"
#include "scene/SceneParts.hpp"
#include "scene/TimeFunctionReader.hpp"

namespace flexsens {

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
  ctx.m.constraints.push_back(std::make_unique<CoordinateDriver>(name, id, ctx.m.dim, comp,
                                                                 ctx.m.nodes[id].position[comp], std::move(f)));
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
  ctx.m.constraints.push_back(std::make_unique<DistanceDriver>(name, ids[0], ids[1], ctx.m.dim, L0, std::move(f)));
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
  ctx.m.constraints.push_back(std::make_unique<AngleDriver>(name, ids, theta0, std::move(f)));
}

}  // namespace flexsens
