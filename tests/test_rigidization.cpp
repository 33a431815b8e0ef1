// The rigidization generator on 1D, 2D and 3D point clouds (paper section 4): counts,
// constraints satisfied by the cloud and by any rigid motion of it, finite-difference Jacobian.
#include <gtest/gtest.h>

#include "TestModels.hpp"
#include "core/Assembler.hpp"
#include "pim/Rigidization.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

Model cloud(int dim, const MatX& X) {
  Model m;
  m.dim = dim;
  m.gravity = VecX::Zero(dim);
  for (int i = 0; i < X.cols(); ++i) {
    Node nd;
    nd.name = "p" + std::to_string(i);
    nd.position = X.col(i);
    nd.velocity = VecX::Zero(dim);
    m.nodes.push_back(nd);
  }
  m.finalize();
  return m;
}

/// Rigidizes the cloud X and checks: cloud dimension, d = n - m rigid-body DOFs, Lambda = 0
/// on the cloud and on a rotated+translated copy, Jacobian against finite differences.
void check(int dim, const MatX& X, int cloudDim, int rigidDofs, const MatX& R) {
  Model m = cloud(dim, X);
  std::vector<int> ids;
  for (int i = 0; i < X.cols(); ++i) ids.push_back(i);
  Rigidization rz = rigidize("body", ids, m, X, "test");
  EXPECT_EQ(rz.cloudDimension, cloudDim);
  Assembler lam(m, &rz.constraints);
  EXPECT_EQ(m.n - lam.m(), rigidDofs);
  const VecX p;
  const VecX q0 = m.initialPositions();
  EXPECT_LT(lam.phi(q0, p).lpNorm<Eigen::Infinity>(), 1e-12);
  VecX q1 = q0;
  for (int i = 0; i < X.cols(); ++i) q1.segment(dim * i, dim) = R * X.col(i) + VecX::Constant(dim, 0.3);
  EXPECT_LT(lam.phi(q1, p).lpNorm<Eigen::Infinity>(), 1e-12);
  VecX q2 = q0 + 0.01 * VecX::Random(q0.size());  // a deformation violates it
  EXPECT_GT(lam.phi(q2, p).lpNorm<Eigen::Infinity>(), 1e-5);
  SparseAccumulator acc;
  acc.begin(lam.m(), m.n);
  lam.addPhiQ(acc, q2, p, 1.0, 0, 0, false);
  EXPECT_LT(relErr(MatX(acc.finish()), fdJacobian([&](const VecX& x) { return lam.phi(x, p); }, q2)), 1e-8);
}

}  // namespace

TEST(Rigidization, PlanarLineAndPlanarCloud) {
  std::srand(7);
  const double a = 0.4;
  MatX R(2, 2);
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  MatX line(2, 4);
  line << 0, 1, 0.25, 2.0, 0, 0.5, 0.125, 1.0;  // collinear
  check(2, line, 1, 3, R);  // planar bar: 2 translations + rotation
  const MatX plate = MatX::Random(2, 6);
  check(2, plate, 2, 3, R);
}

TEST(Rigidization, SpatialLinePlaneAndVolume) {
  std::srand(8);
  const MatX R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  MatX line(3, 4);
  line << 0, 1, 2, -0.5, 0, 1, 2, -0.5, 0, 2, 4, -1;
  check(3, line, 1, 5, R);  // paper 4.1: d = 5 (no spin about the line)
  MatX plane = MatX::Random(3, 6);
  plane.row(2) = 0.5 * plane.row(0) - plane.row(1);  // coplanar through the origin
  check(3, plane, 2, 6, R);  // paper 4.2: d = 6
  check(3, MatX::Random(3, 7), 3, 6, R);  // paper 4.3: d = 6
}
