// Scene reader of planar_rigid_body (elements/PlanarRigidBody.hpp): the body's mass matrix on
// its two basic points, their distance, and each further node attached rigidly (linear).
#include "constraints/Distance.hpp"
#include "elements/PlanarRigidBody.hpp"
#include "pim/Rigidization.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

/// planar_rigid_body {nodes: [A, B, attached...], mass, center_of_mass: [x, y], inertia}:
/// A, B the basic points; inertia about the centre of mass [kg m^2]. Joints are shared nodes
/// (a revolute joint in the plane) or constraints on the attached points.
void readPlanarRigidBody(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  r.allowKeys(el, path, {"name", "type", "nodes", "mass", "center_of_mass", "inertia"});
  if (m.dim != 2) r.fail(el["type"], path + ".type", "a planar rigid body needs a planar scene (dimension 2); use rigid_body in 3D");
  const auto ids = ctx.nodeList(el, path, 2, 100000);
  const Quantity mass{r.positive(r.require(el, "mass", path), path + ".mass"), -1};
  const Quantity inertia{r.positive(r.require(el, "inertia", path), path + ".inertia"), -1};
  const VecX com = r.vector(r.require(el, "center_of_mass", path), path + ".center_of_mass", 2);
  const VecX xA = m.nodes[ids[0]].position, xB = m.nodes[ids[1]].position;
  if (!(ctx.distance(ids[0], ids[1]) > 1e-9))
    r.fail(el["nodes"][1], at(path + ".nodes", 1), "coincides with the first basic point; the two basic points must be apart");
  auto body = std::make_unique<PlanarRigidBody>(name, ids[0], ids[1], xA, xB, com, mass, inertia);
  ctx.bindAll(name, body->properties());
  m.elements.push_back(std::move(body));
  ctx.planarRigidBodies[name] = {ids[0], ids[1]};
  if (!(m.nodes[ids[0]].ground && m.nodes[ids[1]].ground))
    m.constraints.push_back(std::make_unique<DistanceConstraint>(name + ".AB", ids[0], ids[1], Quantity{ctx.distance(ids[0], ids[1]), -1}));
  // r_P - (1 - xi) r_A - xi r_B - eta R (r_B - r_A) = 0, R = [[0, -1], [1, 0]].
  for (size_t k = 2; k < ids.size(); ++k) {
    const Eigen::Vector2d c = PlanarRigidBody::bodyCoordinates(xA, xB, m.nodes[ids[k]].position);
    Eigen::Matrix2d R;
    R << 0, -1, 1, 0;
    MatX J(2, 6);
    J << -(1 - c[0]) * Eigen::Matrix2d::Identity() + c[1] * R, -c[0] * Eigen::Matrix2d::Identity() - c[1] * R,
        Eigen::Matrix2d::Identity();
    m.constraints.push_back(std::make_unique<AttachedPointConstraint>(name + "." + m.nodes[ids[k]].name,
                                                                      std::vector<int>{ids[0], ids[1], ids[k]}, J));
  }
}

}  // namespace flexsens
