// The right-angle cantilever of examples/frames (Simo & Vu-Quoc's data: EA = GA = 1e6,
// EI = GJ = 1e3, rho A = 1, rho J = diag(20, 10, 10)) linearized: its lowest natural
// frequencies from the ancf_beam model against an independent linear 3D frame model written
// here (Euler-Bernoulli elements with consistent mass, rotary and polar inertia; the textbook
// 12 x 12 matrices), 10 elements per leg in both. This checks the welded ancf_beam frame's mass
// (including the given rotary inertia), bending and torsion stiffness and the weld in one go.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "TestModels.hpp"
#include "app/Modes.hpp"
#include "app/Run.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;

namespace {

struct FrameData {
  double EA = 1e6, GJ = 1e3, EI = 1e3;      // [N], [N m^2], [N m^2]
  double rhoA = 1.0, rhoJp = 20.0, rhoI = 10.0;  // [kg/m], [kg m], [kg m]
};

/// Local 12 x 12 stiffness and mass of a straight element of length L, DOFs (u, v, w, tx, ty, tz)
/// at each end; bending in x-y with (v, tz), in x-z with (w, -ty).
void frameElement(const FrameData& d, double L, MatX& K, MatX& M) {
  K = MatX::Zero(12, 12);
  M = MatX::Zero(12, 12);
  auto put = [](MatX& A, const std::vector<int>& idx, const MatX& B) {
    for (size_t a = 0; a < idx.size(); ++a)
      for (size_t b = 0; b < idx.size(); ++b) A(idx[a], idx[b]) += B(Eigen::Index(a), Eigen::Index(b));
  };
  MatX bar(2, 2), lumpBar(2, 2), kb(4, 4), mt(4, 4), mr(4, 4);
  bar << 1, -1, -1, 1;
  lumpBar << 2, 1, 1, 2;
  kb << 12, 6 * L, -12, 6 * L, 6 * L, 4 * L * L, -6 * L, 2 * L * L, -12, -6 * L, 12, -6 * L, 6 * L, 2 * L * L, -6 * L,
      4 * L * L;
  mt << 156, 22 * L, 54, -13 * L, 22 * L, 4 * L * L, 13 * L, -3 * L * L, 54, 13 * L, 156, -22 * L, -13 * L, -3 * L * L,
      -22 * L, 4 * L * L;
  mr << 36, 3 * L, -36, 3 * L, 3 * L, 4 * L * L, -3 * L, -L * L, -36, -3 * L, 36, -3 * L, 3 * L, -L * L, -3 * L, 4 * L * L;
  kb *= d.EI / (L * L * L);
  const MatX mb = d.rhoA * L / 420.0 * mt + d.rhoI / (30.0 * L) * mr;
  const MatX S = Eigen::Vector4d(1, -1, 1, -1).asDiagonal();
  put(K, {0, 6}, d.EA / L * bar);
  put(K, {3, 9}, d.GJ / L * bar);
  put(K, {1, 5, 7, 11}, kb);
  put(K, {2, 4, 8, 10}, S * kb * S);
  put(M, {0, 6}, d.rhoA * L / 6.0 * lumpBar);
  put(M, {3, 9}, d.rhoJp * L / 6.0 * lumpBar);
  put(M, {1, 5, 7, 11}, mb);
  put(M, {2, 4, 8, 10}, S * mb * S);
}

/// Lowest `count` angular frequencies [rad/s] of the L-frame: clamped at (0, 10, 0), leg 1 to the
/// elbow (10, 10, 0), leg 2 to the tip (10, 0, 0), `perLeg` elements each.
std::vector<double> frameFrequencies(int perLeg, int count) {
  std::vector<Eigen::Vector3d> x;
  for (int i = 0; i <= perLeg; ++i) x.emplace_back(10.0 * i / perLeg, 10.0, 0.0);
  for (int i = 1; i <= perLeg; ++i) x.emplace_back(10.0, 10.0 - 10.0 * i / perLeg, 0.0);
  const Eigen::Index nd = 6 * Eigen::Index(x.size());
  MatX K = MatX::Zero(nd, nd), M = MatX::Zero(nd, nd), k, m;
  for (size_t e = 0; e + 1 < x.size(); ++e) {
    const Eigen::Vector3d d = x[e + 1] - x[e];
    const double L = d.norm();
    const Eigen::Vector3d ex = d / L, ez(0, 0, 1), ey = ez.cross(ex);
    Eigen::Matrix3d R;
    R << ex.transpose(), ey.transpose(), ez.transpose();
    MatX T = MatX::Zero(12, 12);
    for (int b = 0; b < 4; ++b) T.block(3 * b, 3 * b, 3, 3) = R;
    frameElement(FrameData{}, L, k, m);
    const Eigen::Index at = 6 * Eigen::Index(e);
    K.block(at, at, 12, 12) += T.transpose() * k * T;
    M.block(at, at, 12, 12) += T.transpose() * m * T;
  }
  const Eigen::Index nf = nd - 6;  // the root's six DOFs clamped
  Eigen::GeneralizedSelfAdjointEigenSolver<MatX> eig(K.bottomRightCorner(nf, nf), M.bottomRightCorner(nf, nf));
  std::vector<double> w;
  for (int i = 0; i < count; ++i) w.push_back(std::sqrt(eig.eigenvalues()(i)));
  return w;
}

}  // namespace

// Measured: +0.06%, +0.04%, +0.01%, +0.31%, +0.21%, +0.06% for modes 1-6; the ancf_beam has shear
// flexibility (GA = 1e6) and section deformation the Euler-Bernoulli frame lacks.
TEST(FrameModes, RightAngleCantileverMatchesIndependentFrameModel) {
  const Scene sc = readScene(test::sourceDir() + "/examples/frames/right_angle_cantilever.yaml");
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  const ModalAnalysis a = analyzeModes(as, consistentState(as, p), p, 6);
  const std::vector<double> ref = frameFrequencies(10, 6);
  std::vector<double> ours;
  for (const Mode& md : a.modes)
    if (!md.rigid && ours.size() < ref.size()) ours.push_back(md.omega());
  ASSERT_EQ(ours.size(), ref.size());
  for (size_t i = 0; i < ref.size(); ++i) {
    std::printf("mode %zu: ancf_beam %.6f rad/s, frame model %.6f rad/s (%+.3f%%)\n", i + 1, ours[i], ref[i],
                100.0 * (ours[i] / ref[i] - 1.0));
    EXPECT_NEAR(ours[i] / ref[i], 1.0, 5e-3) << "mode " << i + 1;
  }
}
