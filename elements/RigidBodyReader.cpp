// Scene reader of rigid_body (elements/RigidBody.hpp): a 3D body in natural coordinates, its
// rigidity from the PIM's rigidization generator (pim/Rigidization.hpp), its initial twist.
#include <stdexcept>

#include "elements/RigidBody.hpp"
#include "pim/Rigidization.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

namespace {

/// Inertia about the centre of mass, global axes at t = 0: [Ixx, Iyy, Izz] (principal, along
/// x, y, z) or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (tensor entries, Ixy = -int x y dm) [kg m^2].
std::array<Quantity, 6> readInertia(const YamlReader& r, const YAML::Node& el, const std::string& path) {
  const YAML::Node in = r.require(el, "inertia", path);
  const std::string ip = path + ".inertia";
  if (!in.IsSequence() || (in.size() != 3 && in.size() != 6))
    r.fail(in, ip, "expected [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] in kg m^2");
  std::array<Quantity, 6> inertia;
  for (size_t i = 0; i < in.size(); ++i) inertia[i] = {r.number(in[i], at(ip, i)), -1};
  Eigen::Matrix3d I;
  I << inertia[0].constant, inertia[3].constant, inertia[4].constant, inertia[3].constant,
      inertia[1].constant, inertia[5].constant, inertia[4].constant, inertia[5].constant, inertia[2].constant;
  const Eigen::Vector3d moments =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(RigidBody::secondMoments(I)).eigenvalues();
  if (!(moments.minCoeff() >= -1e-12 * I.norm()) || !(I.diagonal().minCoeff() > 0))
    r.fail(in, ip, "not an inertia tensor of a physical body: the moments must be positive and satisfy "
                   "the triangle inequalities (Ixx <= Iyy + Izz, ...)");
  return inertia;
}

/// Initial twist: v = v_G + omega x (r - r_G) on every node of the body.
void readTwist(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::vector<int>& ids,
               const Eigen::Vector3d& com) {
  const YamlReader& r = ctx.r;
  if (!el["velocity"] && !el["angular_velocity"]) return;
  const Eigen::Vector3d vG = el["velocity"] ? r.vector(el["velocity"], path + ".velocity", 3) : VecX::Zero(3);
  const Eigen::Vector3d w =
      el["angular_velocity"] ? r.vector(el["angular_velocity"], path + ".angular_velocity", 3) : VecX::Zero(3);
  for (int id : ids) {
    const Node& nd = ctx.m.nodes[id];
    const Eigen::Vector3d v = vG + w.cross(Eigen::Vector3d(nd.position) - com);
    if (nd.ground) {
      if (v.norm() > 1e-12)
        r.fail(el["angular_velocity"] ? el["angular_velocity"] : el["velocity"], path,
               "gives ground node '" + nd.name + "' a velocity; a body hinged to the "
               "ground turns about an axis through its ground nodes");
      continue;
    }
    ctx.setVelocity(id, v, el, path);
  }
}

}  // namespace

void readRigidBody(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  r.allowKeys(el, path, {"name", "type", "nodes", "mass", "center_of_mass", "inertia", "velocity",
                         "angular_velocity"});
  ctx.requireSpatial(el, path, "a rigid body");
  const auto ids = ctx.nodeList(el, path, 4, 100000);
  const Quantity mass{r.positive(r.require(el, "mass", path), path + ".mass"), -1};
  const Eigen::Vector3d com = r.vector(r.require(el, "center_of_mass", path), path + ".center_of_mass", 3);
  const std::array<Quantity, 6> inertia = readInertia(r, el, path);
  RigidizeOptions opt;
  opt.inOrder = true;
  opt.linked = [&ctx](int a, int b) { return ctx.linked(a, b); };
  Rigidization R = rigidize(name, ids, m, ctx.positions(), ctx.where(el["nodes"], path + ".nodes"), nullptr, opt);
  if (R.cloudDimension < 3)
    r.fail(el["nodes"], path + ".nodes", "the nodes of rigid body '" + name + "' are coplanar (" +
                                             std::to_string(R.cloudDimension) + "D cloud); a 3D rigid body "
                                             "needs four non-coplanar basic points: add a point off their plane");
  Eigen::Matrix<double, 3, 4> X0;
  for (int k = 0; k < 4; ++k) X0.col(k) = m.nodes[R.basicPoints[k]].position;
  // The body's own test of its basic frame (|det E| against its size cubed) is stricter than
  // the rigidization's distance tolerance for long slivers: its verdict, with the location.
  std::unique_ptr<RigidBody> body;
  try {
    body = std::make_unique<RigidBody>(name, R.basicPoints, X0, mass, com, inertia);
  } catch (const std::invalid_argument& e) {
    r.fail(el["nodes"], path + ".nodes", std::string(e.what()) + " (nearly: their frame spans almost no volume); "
                                             "a 3D rigid body needs four basic points well off each other's plane");
  }
  ctx.bindAll(name, body->properties());
  m.elements.push_back(std::move(body));
  for (auto& c : R.constraints) m.constraints.push_back(std::move(c));
  SceneContext::RigidBodyInfo info;
  info.basic = R.basicPoints;
  info.X0 = X0;
  info.com = com;
  info.members.insert(ids.begin(), ids.end());
  ctx.rigidBodies[name] = info;
  readTwist(ctx, el, path, ids, com);
}

}  // namespace flexsens
