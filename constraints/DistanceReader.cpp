// Scene readers of the point constraints (constraints/Distance.hpp): distance, fixed, spherical.
#include "constraints/Distance.hpp"
#include "pim/Rigidization.hpp"  // AttachedPointConstraint
#include "scene/KindTable.hpp"

namespace flexsens {

/// distance {nodes: [a, b], length?}: |x_b - x_a| = length (default: the initial distance).
void readDistance(SceneContext& ctx, const YAML::Node& c, const std::string& path, const std::string& name) {
  ctx.r.allowKeys(c, path, {"name", "type", "nodes", "length"});
  const auto ids = ctx.nodeList(c, path, 2, 2);
  auto con = std::make_unique<DistanceConstraint>(name, ids[0], ids[1],
                                                  ctx.length(c, "length", path + ".length", ids[0], ids[1]));
  ctx.bindAll(name, con->properties());
  ctx.m.constraints.push_back(std::move(con));
}

/// fixed {node, position?}: the node held at position (default: its initial one).
void readFixed(SceneContext& ctx, const YAML::Node& c, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  const Model& m = ctx.m;
  r.allowKeys(c, path, {"name", "type", "node", "position"});
  const int id = ctx.node(r.require(c, "node", path), path + ".node");
  if (m.nodes[id].ground) r.fail(c["node"], path + ".node", "node '" + m.nodes[id].name + "' is a ground node already");
  const VecX pos = c["position"] ? r.vector(c["position"], path + ".position", m.dim) : m.nodes[id].position;
  ctx.m.constraints.push_back(std::make_unique<FixedNodeConstraint>(name, id, pos));
}

/// spherical {nodes: [a, b]}: two coincident points kept together.
void readSpherical(SceneContext& ctx, const YAML::Node& c, const std::string& path, const std::string& name) {
  ctx.r.allowKeys(c, path, {"name", "type", "nodes"});
  const auto ids = ctx.nodeList(c, path, 2, 2);
  const double gap = ctx.distance(ids[0], ids[1]);
  if (gap > 1e-9)
    ctx.r.fail(c["nodes"], path + ".nodes", "a spherical joint joins coincident points; these are " +
                                                std::to_string(gap) + " m apart");
  ctx.m.constraints.push_back(std::make_unique<AttachedPointConstraint>(name, ids, VecX(), ctx.m.dim));
}

}  // namespace flexsens
