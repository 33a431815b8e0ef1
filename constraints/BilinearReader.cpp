// Scene readers of the dot-product constraints (constraints/Bilinear.hpp): perpendicular
// (the cross of a universal joint) and point_on_plane (fixed to space or to a rigid body).
#include "constraints/Bilinear.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

/// perpendicular {nodes: [a, b, c, d], value?}: (x_b - x_a).(x_d - x_c) = value (default initial).
void readPerpendicular(SceneContext& ctx, const YAML::Node& c, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  const Model& m = ctx.m;
  r.allowKeys(c, path, {"name", "type", "nodes", "value"});
  const auto ids = ctx.nodeList(c, path, 4, 4, true);  // [a, b, c, d]: a = c is common
  const VecX e1 = m.nodes[ids[1]].position - m.nodes[ids[0]].position;
  const VecX e2 = m.nodes[ids[3]].position - m.nodes[ids[2]].position;
  const double c0 = (!c["value"] || r.isAuto(c["value"])) ? e1.dot(e2) : r.number(c["value"], path + ".value");
  if (m.dim != 3) r.fail(c["type"], path + ".type", "perpendicular needs a spatial scene (dimension 3)");
  ctx.m.constraints.push_back(BilinearConstraint::perpendicular(name, ids, c0));
}

/// point_on_plane {nodes or beam, point, normal, body?}: each node kept on the plane through
/// `point` with `normal` at t = 0, fixed to rigid body `body` or to space; one constraint per
/// node. Nodes of the plane's own body are skipped: their distance to the plane is fixed already.
void readPointOnPlane(SceneContext& ctx, const YAML::Node& c, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  r.allowKeys(c, path, {"name", "type", "nodes", "beam", "body", "point", "normal"});
  if (m.dim != 3) r.fail(c["type"], path + ".type", "point_on_plane needs a spatial scene (dimension 3)");
  std::vector<int> ids;
  if (c["beam"]) {  // every node of a beam (e.g. a spring drawn as a curve)
    const std::string b = r.text(c["beam"], path + ".beam");
    if (!ctx.bodies.count(b)) r.fail(c["beam"], path + ".beam", "no beam named '" + b + "' (defined under elements)");
    ids = ctx.bodies[b].nodes;
    if (c["nodes"]) r.fail(c["nodes"], path + ".nodes", "give either nodes or beam, not both");
  } else {
    ids = ctx.nodeList(c, path, 1, 100000);
  }
  const Eigen::Vector3d origin = r.vector(r.require(c, "point", path), path + ".point", 3);
  const Eigen::Vector3d normal = r.vector(r.require(c, "normal", path), path + ".normal", 3);
  if (!(normal.norm() > 0)) r.fail(c["normal"], path + ".normal", "expected a non-zero normal vector");
  const SceneContext::RigidBodyInfo* body = nullptr;
  if (c["body"]) {
    const std::string b = r.text(c["body"], path + ".body");
    auto it = ctx.rigidBodies.find(b);
    if (it == ctx.rigidBodies.end())
      r.fail(c["body"], path + ".body", "no rigid_body named '" + b + "' (defined before this constraint)");
    body = &it->second;
  }
  for (size_t i = 0; i < ids.size(); ++i) {
    const Node& nd = m.nodes[ids[i]];
    const double off = normal.normalized().dot(Eigen::Vector3d(nd.position) - origin);
    if (std::abs(off) > 1e-9 * std::max(1.0, origin.norm()))
      r.fail(c["beam"] ? c["beam"] : c["nodes"][i], c["beam"] ? path + ".beam" : at(path + ".nodes", i),
             "node '" + nd.name + "' is " + std::to_string(off) + " m off the plane at t = 0");
    if (nd.ground || (body && body->members.count(ids[i]))) continue;
    const std::string cn = ids.size() == 1 ? name : name + "[" + nd.name + "]";
    if (body)
      m.constraints.push_back(BilinearConstraint::pointOnBodyPlane(cn, body->basic, body->X0, ids[i], origin, normal));
    else
      m.constraints.push_back(BilinearConstraint::pointOnFixedPlane(cn, ids[i], origin, normal));
  }
}

}  // namespace flexsens
