// 3D rigid bodies in natural coordinates, joint angles, rotational spring-dampers and the
// spatial constraints, against independent references: rigid-body mechanics (kinetic energy
// of a known twist, weight through the centre of mass), finite differences, closed-form angles.
#include <gtest/gtest.h>

#include <cmath>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "core/Assembler.hpp"
#include "elements/JointAngle.hpp"
#include "elements/RigidBody.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

Eigen::Matrix3d tensor(double xx, double yy, double zz, double xy, double xz, double yz) {
  Eigen::Matrix3d I;
  I << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  return I;
}

}  // namespace

TEST(RigidBody, KineticEnergyOfAnyTwistEqualsRigidBodyMechanics) {
  // T = 1/2 m |v_G|^2 + 1/2 w^T I w for v_k = v_G + w x (r_k - r_G): the natural-coordinate
  // mass matrix must reproduce it for every twist, whatever the basic points.
  Eigen::Matrix<double, 3, 4> X;
  X << 0.1, 1.3, -0.2, 0.4,  //
      -0.3, 0.2, 1.1, 0.5,   //
      0.2, 0.0, 0.3, 1.4;
  const Eigen::Vector3d G(0.35, 0.4, 0.5);
  const Eigen::Matrix3d I = tensor(0.9, 0.7, 0.5, 0.05, -0.1, 0.08);
  std::array<Quantity, 6> in;
  const double vals[6] = {I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)};
  for (int i = 0; i < 6; ++i) in[i] = {vals[i], -1};
  RigidBody body("b", {0, 1, 2, 3}, X, Quantity{2.5, -1}, G, in);
  LocalState s;
  s.dim = 3;
  const VecX p;
  s.p = &p;
  MatX M;
  ASSERT_TRUE(body.mass(s, M));
  for (int trial = 0; trial < 5; ++trial) {
    std::srand(100 + trial);
    const Eigen::Vector3d vG = Eigen::Vector3d::Random(), w = Eigen::Vector3d::Random();
    VecX v(12);
    for (int k = 0; k < 4; ++k) v.segment<3>(3 * k) = vG + w.cross(Eigen::Vector3d(X.col(k)) - G);
    const double expected = 0.5 * 2.5 * vG.squaredNorm() + 0.5 * w.dot(I * w);
    EXPECT_NEAR(0.5 * v.dot(M * v), expected, 1e-12 * std::max(1.0, expected));
  }
  // The weight acts at the centre of mass: Q . x = m g . r_G for the initial positions, and
  // its moment about any point is (r_G - o) x m g.
  const VecX g = Eigen::Vector3d(0.3, -0.2, -9.81);
  s.gravity = &g;
  VecX x(12);
  for (int k = 0; k < 4; ++k) x.segment<3>(3 * k) = X.col(k);
  s.x = x;
  s.v = VecX::Zero(12);
  VecX Q;
  body.force(s, Q);
  Eigen::Vector3d F = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k) {
    F += Q.segment<3>(3 * k);
    moment += Eigen::Vector3d(X.col(k)).cross(Eigen::Vector3d(Q.segment<3>(3 * k)));
  }
  EXPECT_LT((F - 2.5 * Eigen::Vector3d(g)).norm(), 1e-12);
  EXPECT_LT((moment - G.cross(2.5 * Eigen::Vector3d(g))).norm(), 1e-12);
}

TEST(RigidBody, SecondMomentsOfABoxFromItsInertiaTensor) {
  // Box a x b x c, mass m: int x^2 dm = m a^2 / 12, Ixx = m (b^2 + c^2) / 12.
  const double m = 3.0, a = 2.0, b = 1.0, c = 0.5;
  const Eigen::Matrix3d I = tensor(m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12, 0, 0, 0);
  const Eigen::Matrix3d S = RigidBody::secondMoments(I);
  EXPECT_NEAR(S(0, 0), m * a * a / 12, 1e-14);
  EXPECT_NEAR(S(1, 1), m * b * b / 12, 1e-14);
  EXPECT_NEAR(S(2, 2), m * c * c / 12, 1e-14);
}

TEST(JointAngle, ValueGradientAndHessian) {
  // Closed form: axis z, from-vector along x, to-vector at 30 degrees in xy, tilted in z
  // (the tilt does not change the angle about the axis).
  VecX x(18);
  x << 0.3, -0.2, 1.0, 0.3, -0.2, 2.5,  // axis points (along +z)
      1.0, 1.0, 0.0, 3.0, 1.0, 0.7,      // from: (2, 0, 0.7)
      0.0, 0.0, 0.0, std::cos(M_PI / 6), std::sin(M_PI / 6), -0.4;
  EXPECT_NEAR(jointAngleT<double>(x, nullptr), M_PI / 6, 1e-14);
  // Generic configurations: gradient and Hessian against finite differences.
  for (unsigned seed : {1u, 2u, 3u}) {
    std::srand(seed);
    const VecX y = VecX::Random(18);
    VecX g;
    jointAngleT<double>(y, &g);
    const MatX fdg = fdJacobian([&](const VecX& z) { return VecX::Constant(1, jointAngleT<double>(z, nullptr)); }, y);
    EXPECT_LT(relErr(VecX(g), VecX(fdg.transpose())), 1e-7);
    const MatX fdH = fdJacobian([&](const VecX& z) { VecX gz; jointAngleT<double>(z, &gz); return gz; }, y);
    const MatX H = jointAngleHessian(y);
    EXPECT_LT(relErr(H, fdH), 1e-6) << "seed " << seed;
    EXPECT_LT((H - H.transpose()).norm(), 1e-10 * H.norm());
  }
}

TEST(RigidBody, MixedSceneCountsAndConsistentStart) {
  Scene sc = mixedScene3D();
  const Model& m = *sc.model;
  // Free nodes P, PX, E1, S, PY, E2, Q, F, F2: n = 27. bar1: 5 distances (O-OX is ground)
  // + PX attached (3); bar2: 6 distances; cross 1; two planes; spherical 3: m = 20.
  EXPECT_EQ(m.n, 27);
  EXPECT_EQ(m.m, 20);
  Assembler as(m);
  const VecX p = m.nominalParameters();
  EXPECT_LT(as.phi(m.initialPositions(), p).lpNorm<Eigen::Infinity>(), 1e-12);
}
