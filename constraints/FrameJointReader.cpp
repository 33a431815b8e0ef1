// Scene readers of the frame joints between ancf_beam ends: `weld` and `hinge`. Both are
// linear in the nodes' coordinates (positions r and gradients J = (r_x, r_y, r_z)), so their
// Jacobian is constant and their Hessian zero:
//  - weld {nodes: [A, B]}: r_B = r_A and J_B = J_A C, C = J_A0^-1 J_B0 (12 rows): the two
//    ends keep their relative orientation at any angle, and the material at the joint deforms
//    as one (the gradient is continuous across it, as at a node two elements share);
//  - hinge {nodes: [A, B], axis}: r_B = r_A and J_B c_B = J_A c_A, c = J0^-1 axis (6 rows): the
//    material line along the axis is shared, every rotation about it is free.
// A and B: coincident ancf_beam nodes at t = 0 (J_A0, J_B0 their starting gradients).
#include <sstream>

#include "pim/Rigidization.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

namespace {

/// The two coincident ancf_beam nodes of a frame joint and their starting gradients.
struct JointEnds {
  std::vector<int> ids;
  Eigen::Matrix3d JA, JB;
};

JointEnds readEnds(SceneContext& ctx, const YAML::Node& c, const std::string& path, const std::string& kind) {
  const YamlReader& r = ctx.r;
  JointEnds ends;
  ends.ids = ctx.nodeList(c, path, 2, 2);
  for (int j = 0; j < 2; ++j) {
    const Node& nd = ctx.m.nodes[ends.ids[j]];
    if (nd.gradients(ctx.m.dim) != 3)
      r.fail(c["nodes"][j], at(path + ".nodes", j),
             "a " + kind + " joins ancf_beam ends: node '" + nd.name + "' carries no gradients (r_x, r_y, r_z); end an "
             "ancf_beam chain there (a positions-only node takes a spherical joint)");
  }
  const double gap = ctx.distance(ends.ids[0], ends.ids[1]);
  if (gap > 1e-9)
    r.fail(c["nodes"], path + ".nodes", "a " + kind + " joins coincident beam ends; these are " + std::to_string(gap) +
                                            " m apart");
  ends.JA = Eigen::Map<const Eigen::Matrix3d>(ctx.m.nodes[ends.ids[0]].slope.data());
  ends.JB = Eigen::Map<const Eigen::Matrix3d>(ctx.m.nodes[ends.ids[1]].slope.data());
  return ends;
}

/// Rows r_B - r_A = 0 on the local coordinates (r_A, J_A, r_B, J_B), 12 per node.
MatX positionRows(int rows) {
  MatX J = MatX::Zero(rows, 24);
  J.block<3, 3>(0, 0) = -Eigen::Matrix3d::Identity();
  J.block<3, 3>(0, 12) = Eigen::Matrix3d::Identity();
  return J;
}

}  // namespace

void readWeld(SceneContext& ctx, const YAML::Node& c, const std::string& path, const std::string& name) {
  ctx.r.allowKeys(c, path, {"name", "type", "nodes"});
  ctx.requireSpatial(c, path, "weld");
  const JointEnds e = readEnds(ctx, c, path, "weld");
  const Eigen::Matrix3d C = e.JA.inverse() * e.JB;  // J_B0 = J_A0 C
  MatX J = positionRows(12);
  for (int k = 0; k < 3; ++k) {  // column k of J_B minus sum_j C_jk (column j of J_A)
    J.block<3, 3>(3 + 3 * k, 12 + 3 + 3 * k) = Eigen::Matrix3d::Identity();
    for (int j = 0; j < 3; ++j) J.block<3, 3>(3 + 3 * k, 3 + 3 * j) = -C(j, k) * Eigen::Matrix3d::Identity();
  }
  ctx.m.constraints.push_back(std::make_unique<AttachedPointConstraint>(name, e.ids, J, 3, std::string("weld")));
}

void readHinge(SceneContext& ctx, const YAML::Node& c, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  r.allowKeys(c, path, {"name", "type", "nodes", "axis"});
  ctx.requireSpatial(c, path, "hinge");
  const JointEnds e = readEnds(ctx, c, path, "hinge");
  const Eigen::Vector3d axis = r.vector(r.require(c, "axis", path), path + ".axis", 3);
  if (!(axis.norm() > 0)) r.fail(c["axis"], path + ".axis", "expected a nonzero direction (the hinge's axis at t = 0)");
  const Eigen::Vector3d cA = e.JA.inverse() * axis.normalized(), cB = e.JB.inverse() * axis.normalized();
  MatX J = positionRows(6);
  for (int j = 0; j < 3; ++j) {  // J_B c_B - J_A c_A
    J.block<3, 3>(3, 12 + 3 + 3 * j) = cB[j] * Eigen::Matrix3d::Identity();
    J.block<3, 3>(3, 3 + 3 * j) = -cA[j] * Eigen::Matrix3d::Identity();
  }
  ctx.m.constraints.push_back(std::make_unique<AttachedPointConstraint>(name, e.ids, J, 3, std::string("hinge")));
}

}  // namespace flexsens
