// Discrete shells (elements/ShellTriangle.hpp, ShellHinge.hpp, ShellMesh.hpp, ShellReader.cpp).
// References independent of the code under test: central finite differences (force
// Jacobians, parameter derivatives, potential gradients, the dihedral angle's gradient and
// Hessian), the AD kernels (equal to the analytic ones to 1e-10), zero force under rigid
// motion, the closed-form edge forces of a uniformly stretched sheet (plane-stress
// St. Venant-Kirchhoff written out here), the angle and gradient of a hinge folded by a known
// angle, the energy per area of uniform curvatures (the hinge weight's calibration), Kirchhoff's
// natural frequencies of a simply supported square plate,
//   omega_mn = pi^2 (m^2 + n^2) / a^2 sqrt(D / (rho t)),  D = E t^3 / (12 (1 - nu^2)),
// Navier's series for the same plate under a uniform load, momentum and the O(dt^2) energy error
// of the trapezoidal rule in free flight, the PIM's cloud counts and the exact mass integrals of
// the F-R twin.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkUnstructuredGrid.h>

#include "ShellPlates.hpp"
#include "StaticFrames.hpp"
#include "TestModels.hpp"
#include "app/Modes.hpp"
#include "core/Assembler.hpp"
#include "elements/ShellHinge.hpp"
#include "elements/ShellMesh.hpp"
#include "elements/ShellTriangle.hpp"
#include "integrators/FixedStep.hpp"
#include "integrators/InitialState.hpp"
#include "integrators/Static.hpp"
#include "pim/MassProperties.hpp"
#include "pim/Pim.hpp"
#include "app/Run.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;
using flexsens::test::expectParameterDerivatives;
using flexsens::test::fdJacobian;
using flexsens::test::relMax;
using flexsens::test::PlateMesh;
using flexsens::test::shiftedRows;
using flexsens::test::transverseFrequencies;
using flexsens::test::transverseMatrices;

namespace {

/// p = (E, nu, density, thickness, alpha, beta): a soft sheet (rubber-like) with strong damping, so
/// that at a 5% strain the elastic, weight and damping forces are of one order and central
/// differences in each parameter stay above round-off.
VecX shellParams() { return (VecX(6) << 2.0e5, 0.3, 1200.0, 0.004, 20.0, 0.02).finished(); }
/// Properties bound to p = shellParams() when `bound`, else constants of those values.
std::shared_ptr<ShellProperties> shellProps(bool bound, Law law = Law::SaintVenantKirchhoff) {
  auto pr = std::make_shared<ShellProperties>();
  pr->law.law = law;
  const VecX v = shellParams();
  Quantity* q[6] = {&pr->E, &pr->nu, &pr->density, &pr->thickness, &pr->alpha, &pr->beta};
  for (int k = 0; k < 6; ++k) *q[k] = bound ? Quantity{0.0, k} : Quantity{v[k], -1};
  return pr;
}

struct Local {
  VecX p, g;
  LocalState s;
  Local(const VecX& x, const VecX& v, bool gravity) : p(shellParams()), g(Eigen::Vector3d(0.4, -1.1, -9.81)) {
    s.dim = 3;
    s.x = x;
    s.v = v;
    s.p = &p;
    s.gravity = gravity ? &g : nullptr;
  }
};

/// Rest positions of a hinge with its edge x0-x1 along a skew axis u, folded by `fold` [rad]:
/// wing 1 along w (normal to u), wing 2 along -w turned about u towards n1 = u x w.
VecX hingeRest(double fold) {
  const Eigen::Vector3d u = Eigen::Vector3d(0.9, 0.2, -0.1).normalized();
  const Eigen::Vector3d w = u.cross(Eigen::Vector3d(0.1, 0.3, 1.0)).normalized();
  VecX X(12);
  X << Eigen::Vector3d::Zero(), 0.21 * u, 0.09 * u + 0.16 * w,
      Eigen::AngleAxisd(-fold, u) * Eigen::Vector3d(0.12 * u - 0.14 * w);
  return X;
}

void expectKernelsAgree(const ShellTriangle& e, const VecX& x, const VecX& v, int np) {
  Local L(x, v, true);
  MatX K, Kv, Kad, Kvad;
  e.forceJacobian(L.s, K, Kv);
  e.forceJacobianAD(L.s, Kad, Kvad);
  EXPECT_GT(K.norm(), 0.0);
  EXPECT_LT(relMax(Kad, K), 1e-10) << "AD vs analytic dQ/dq";
  if (Kv.norm() > 0 || Kvad.norm() > 0) EXPECT_LT(relMax(Kvad, Kv), 1e-10) << "AD vs analytic dQ/dv";
  auto fq = [&](const VecX& q) { LocalState s = L.s; s.x = q; VecX Q; e.force(s, Q); return Q; };
  auto fv = [&](const VecX& w) { LocalState s = L.s; s.v = w; VecX Q; e.force(s, Q); return Q; };
  EXPECT_LT(relMax(fdJacobian(fq, x), K), 1e-6) << "FD vs analytic dQ/dq";
  EXPECT_LT(relMax(fdJacobian(fv, v, 1e-4), Kv), 1e-6) << "FD vs analytic dQ/dv";
  flexsens::test::expectForceMatchesTemplate(e, L.s);
  // -dU/dq = Q at zero velocity (elastic energy + gravity)
  Local L0(x, VecX::Zero(x.size()), true);
  VecX Q;
  e.force(L0.s, Q);
  auto U = [&](const VecX& q) { LocalState s = L0.s; s.x = q; VecX r(1); r[0] = e.potential(s); return r; };
  EXPECT_LT(relMax(-fdJacobian(U, x).transpose(), Q), 1e-6) << "-dU/dq vs Q";
  expectParameterDerivatives(e, L.s, L.p, np);
}

}  // namespace

TEST(Shell, TriangleDerivativesAgainstFiniteDifferencesAndAD) {
  VecX X(9);
  X << 0.0, 0.0, 0.0, 0.3, 0.05, 0.02, 0.08, 0.25, -0.03;
  std::srand(3);
  const VecX x = X + 0.05 * VecX::Random(9), v = 0.4 * VecX::Random(9);
  for (const Law law : {Law::SaintVenantKirchhoff, Law::NeoHookean}) {
    SCOPED_TRACE(law == Law::NeoHookean ? "neo-Hookean" : "St. Venant-Kirchhoff");
    ShellTriangle e("t", {0, 1, 2}, shellProps(true, law), X);
    expectKernelsAgree(e, x, v, 6);
  }
  ShellTriangle e("t", {0, 1, 2}, shellProps(true), X);
  // mass: M = rho t A / 12 (1 + delta_ij) I, total rho t A
  Local L(x, v, false);
  MatX M;
  ASSERT_TRUE(e.mass(L.s, M));
  const double A = 0.5 * Eigen::Vector3d(X.segment<3>(3)).cross(Eigen::Vector3d(X.segment<3>(6))).norm();
  EXPECT_NEAR(M.sum(), 3.0 * 1200.0 * 0.004 * A, 1e-12);
  EXPECT_NEAR(M(0, 0), 1200.0 * 0.004 * A / 6.0, 1e-14);
  EXPECT_NEAR(M(0, 3), 1200.0 * 0.004 * A / 12.0, 1e-14);
}

TEST(Shell, HingeDerivativesAgainstFiniteDifferencesAndAD) {
  for (const double fold : {0.0, 0.6, -2.5}) {
    for (const bool flatRest : {false, true}) {
      SCOPED_TRACE("rest fold " + std::to_string(fold) + (flatRest ? " flat rest" : ""));
      const VecX X = hingeRest(fold);
      // thickness is a parameter too: E -> 0, nu -> 1, thickness -> 2
      auto pr = shellProps(false);
      pr->E = {0.0, 0};
      pr->nu = {0.0, 1};
      pr->thickness = {0.0, 2};
      pr->beta = {0.0, -1};  // undamped first: Q = -dU/dq
      ShellHinge e("h", {0, 1, 2, 3}, pr, X, flatRest);
      std::srand(5);
      const VecX x = X + 0.03 * VecX::Random(12), v = VecX::Random(12);
      Local L(x, v, true);
      VecX p3 = (VecX(3) << 2.0e6, 0.3, 0.004).finished();
      L.s.p = &p3;
      MatX K, Kv, Kad, Kvad;
      e.forceJacobian(L.s, K, Kv);
      e.forceJacobianAD(L.s, Kad, Kvad);
      EXPECT_LT(relMax(Kad, K), 1e-10);
      EXPECT_EQ(Kv.norm(), 0.0);
      auto fq = [&](const VecX& q) { LocalState s = L.s; s.x = q; VecX Q; e.force(s, Q); return Q; };
      EXPECT_LT(relMax(fdJacobian(fq, x), K), 1e-6);
      auto U = [&](const VecX& q) { LocalState s = L.s; s.x = q; VecX r(1); r[0] = e.potential(s); return r; };
      VecX Q;
      e.force(L.s, Q);
      EXPECT_LT(relMax(-fdJacobian(U, x).transpose(), Q), 1e-6);
      expectParameterDerivatives(e, L.s, p3, 3);
      MatX M;
      EXPECT_FALSE(e.mass(L.s, M));  // massless
      EXPECT_NEAR(e.restAngle(), flatRest ? 0.0 : fold, 1e-12);
      // Kelvin-Voigt: beta -> 3 (the moment beta D w dtheta/dt is of the elastic one's order)
      pr->beta = {0.0, 3};
      VecX p4 = (VecX(4) << 2.0e6, 0.3, 0.004, 0.01).finished();
      L.s.p = &p4;
      flexsens::test::expectDampedKernels(e, L.s, p4, 4);
      flexsens::test::expectForceMatchesTemplate(e, L.s);
      pr->beta = {0.0, -1};
    }
  }
}

// The dihedral angle of a hinge folded by a known angle phi about its edge, after a large
// rotation and translation; the gradient against the closed form for the wing tips,
//   d theta / d x3 = n2_hat / h3,  d theta / d x2 = n1_hat / h2  (h: distance to the edge line,
//   n1 = e x a, n2 = b x e as in ShellHinge.hpp), translation and rotation invariance, and
//   the Hessian against central differences of the gradient.
TEST(Shell, DihedralAngleOfAKnownFold) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.3, Eigen::Vector3d(0.2, -1.0, 0.6).normalized()).toRotationMatrix();
  const Eigen::Vector3d c(0.7, -2.0, 5.0);
  for (const double phi : {0.0, 0.4, -1.1, 2.9}) {
    SCOPED_TRACE("phi = " + std::to_string(phi));
    // edge along x; wing 1 at +y; wing 2 at -y rotated about x by phi (towards +z = n1 for phi > 0)
    const Eigen::Vector3d x0(0, 0, 0), x1(0.5, 0, 0), x2(0.2, 0.3, 0);
    const Eigen::Vector3d x3 = Eigen::AngleAxisd(-phi, Eigen::Vector3d::UnitX()) * Eigen::Vector3d(0.35, -0.2, 0);
    VecX x(12);
    x << R * x0 + c, R * x1 + c, R * x2 + c, R * x3 + c;
    VecX g;
    MatX H;
    const double theta = ShellHinge::dihedralAngle(x, &g, &H);
    EXPECT_NEAR(theta, phi, 1e-13);
    const Eigen::Vector3d e = R * (x1 - x0), a = R * (x2 - x0), b = R * (x3 - x0);
    const Eigen::Vector3d n1 = e.cross(a).normalized(), n2 = b.cross(e).normalized();
    const double h2 = 0.3, h3 = 0.2;  // distances of the wing tips to the edge line [m]
    EXPECT_LT((g.segment<3>(9) - n2 / h3).norm(), 1e-12 / h3);
    // raising either wing tip along its triangle's normal deepens the fold
    EXPECT_LT((g.segment<3>(6) - n1 / h2).norm(), 1e-12 / h2);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), mom = Eigen::Vector3d::Zero();
    for (int i = 0; i < 4; ++i) {
      sum += g.segment<3>(3 * i);
      mom += Eigen::Vector3d(x.segment<3>(3 * i)).cross(Eigen::Vector3d(g.segment<3>(3 * i)));
    }
    EXPECT_LT(sum.norm(), 1e-12);
    EXPECT_LT(mom.norm(), 1e-11);
    auto th = [](const VecX& y) { VecX r(1); r[0] = ShellHinge::dihedralAngle(y); return r; };
    auto gr = [](const VecX& y) { VecX r; ShellHinge::dihedralAngle(y, &r); return r; };
    EXPECT_LT(relMax(fdJacobian(th, x).transpose(), g), 1e-8);
    EXPECT_LT(relMax(fdJacobian(gr, x), H), 1e-6);
    EXPECT_LT(relMax(H, H.transpose()), 1e-12);
  }
}

// A bent rest state moved rigidly (rotation by 2 rad, translation): zero elastic force on
// the triangles and the hinge (gravity off), relative to the force of a 1% stretch.
TEST(Shell, RigidMotionGivesZeroElasticForce) {
  const VecX X = hingeRest(0.8);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.0, Eigen::Vector3d(1.0, 0.4, -0.7).normalized()).toRotationMatrix();
  VecX x(12);
  for (int i = 0; i < 4; ++i) x.segment<3>(3 * i) = R * X.segment<3>(3 * i) + Eigen::Vector3d(3.0, -1.0, 0.5);
  auto pr = shellProps(false);
  std::vector<std::unique_ptr<Element>> els;
  std::vector<Eigen::Vector3d> rest;
  for (int i = 0; i < 4; ++i) rest.push_back(X.segment<3>(3 * i));
  const ShellMeshCounts n = buildShell("s", rest, {{0, 1, 2}, {1, 0, 3}}, {0, 1, 2, 3}, pr, false, els,
                                       [](int i) { return std::to_string(i); });
  ASSERT_EQ(n.triangles, 2);
  ASSERT_EQ(n.hinges, 1);
  ASSERT_EQ(n.boundaryEdges, 4);
  const VecX p(0);
  for (const auto& el : els) {
    SCOPED_TRACE(el->name());
    std::vector<int> idx = el->nodes();
    VecX xl(3 * idx.size()), xs(3 * idx.size());
    for (size_t j = 0; j < idx.size(); ++j) {
      xl.segment<3>(3 * j) = x.segment<3>(3 * idx[j]);
      xs.segment<3>(3 * j) = 1.01 * X.segment<3>(3 * idx[j]);  // 1% stretch (and, for the hinge, no fold change)
    }
    LocalState s;
    s.dim = 3;
    s.p = &p;
    s.x = xl;
    s.v = VecX::Zero(xl.size());
    VecX Q, Qs;
    el->force(s, Q);
    EXPECT_NEAR(el->potential(s), 0.0, 1e-18);
    s.x = xs;
    el->force(s, Qs);
    if (el->kind() == "shell_triangle") {
      EXPECT_GT(Qs.norm(), 1.0);
      EXPECT_LT(Q.norm(), 1e-12 * Qs.norm());
    } else {
      EXPECT_LT(Q.norm(), 1e-14);  // [N]: D ~ 1e-3 N m, theta - theta0 ~ 1e-16
    }
  }
}

// A rectangular sheet a x b (two triangles and a hinge on the diagonal) in a tilted plane,
// stretched uniformly by lambda1 along its side a and lambda2 along b: Green-Lagrange
// E = diag((l1^2 - 1)/2, (l2^2 - 1)/2), plane-stress S11 = E/(1 - nu^2) (E11 + nu E22),
// S22 = E/(1 - nu^2) (E22 + nu E11); the first Piola-Kirchhoff stress P = F S acts on the
// edges, so each corner carries half of the two edge forces next to it: at corner (0, 0)
// Q = t/2 (b l1 S11 d1 + a l2 S22 d2), d1, d2 the current side directions. The hinge stays
// flat: no force.
TEST(Shell, UniformStretchGivesTheMembraneForceExactly) {
  const double a = 0.4, b = 0.25, l1 = 1.07, l2 = 0.96;
  const double E0 = shellParams()[0], nu = shellParams()[1], t = shellParams()[3];  // [Pa], [-], [m]
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, 1.0, -0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d d1 = R.col(0), d2 = R.col(1), o(0.2, -0.1, 0.3);
  std::vector<Eigen::Vector3d> rest{o, o + a * d1, o + a * d1 + b * d2, o + b * d2};
  for (const bool otherDiagonal : {false, true}) {
    SCOPED_TRACE(otherDiagonal ? "diagonal 1-3" : "diagonal 0-2");
    const std::vector<std::array<int, 3>> tris =
        otherDiagonal ? std::vector<std::array<int, 3>>{{0, 1, 3}, {1, 2, 3}} : std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 2, 3}};
    std::vector<std::unique_ptr<Element>> els;
    buildShell("sheet", rest, tris, {0, 1, 2, 3}, shellProps(false), false, els, [](int i) { return std::to_string(i); });
    ASSERT_EQ(els.size(), 3u);
    VecX x(12);
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector3d r = rest[i] - o;
      x.segment<3>(3 * i) = o + l1 * r.dot(d1) * d1 + l2 * r.dot(d2) * d2;
    }
    VecX Q = VecX::Zero(12);
    const VecX p(0);
    for (const auto& el : els) {
      LocalState s;
      s.dim = 3;
      s.p = &p;
      const auto& idx = el->nodes();
      s.x.resize(3 * idx.size());
      for (size_t j = 0; j < idx.size(); ++j) s.x.segment<3>(3 * j) = x.segment<3>(3 * idx[j]);
      VecX Qe;
      el->force(s, Qe);
      if (el->kind() == "shell_hinge") EXPECT_LT(Qe.norm(), 1e-9);
      for (size_t j = 0; j < idx.size(); ++j) Q.segment<3>(3 * idx[j]) += Qe.segment<3>(3 * j);
    }
    const double E11 = 0.5 * (l1 * l1 - 1), E22 = 0.5 * (l2 * l2 - 1), c = E0 / (1 - nu * nu);
    const double S11 = c * (E11 + nu * E22), S22 = c * (E22 + nu * E11);
    const Eigen::Vector3d f1 = 0.5 * t * b * l1 * S11 * d1, f2 = 0.5 * t * a * l2 * S22 * d2;  // [N]
    VecX expected(12);
    expected << f1 + f2, -f1 + f2, -f1 - f2, f1 - f2;
    EXPECT_LT((Q - expected).lpNorm<Eigen::Infinity>(), 1e-10 * expected.lpNorm<Eigen::Infinity>());
    // output stresses: E = E11 d1 d1^T + E22 d2 d2^T, S likewise, Cauchy sigma = F S F^T / J
    // = (l1^2 S11 d1 d1^T + l2^2 S22 d2 d2^T) / (l1 l2), von Mises sqrt(s1^2 - s1 s2 + s2^2)
    const double s1 = l1 * S11 / l2, s2 = l2 * S22 / l1;
    const MatX Ee = E11 * d1 * d1.transpose() + E22 * d2 * d2.transpose();
    const MatX Se = S11 * d1 * d1.transpose() + S22 * d2 * d2.transpose();
    const MatX sige = s1 * d1 * d1.transpose() + s2 * d2 * d2.transpose();
    for (const auto& el : els) {
      const auto* tri = dynamic_cast<const ShellTriangle*>(el.get());
      if (!tri) continue;
      LocalState ls;
      ls.dim = 3;
      ls.p = &p;
      ls.x.resize(9);
      for (int j = 0; j < 3; ++j) ls.x.segment<3>(3 * j) = x.segment<3>(3 * tri->nodes()[j]);
      MatX E, S, sig;
      double vm;
      tri->membraneStress(ls, E, S, sig, vm);
      EXPECT_LT((E - Ee).norm(), 1e-13);
      EXPECT_LT((S - Se).norm(), 1e-10 * Se.norm());
      EXPECT_LT((sig - sige).norm(), 1e-10 * sige.norm());
      EXPECT_NEAR(vm, std::sqrt(s1 * s1 - s1 * s2 + s2 * s2), 1e-10 * std::abs(s1));
    }
  }
}

// Neo-Hookean membrane (material: neo_hookean): a triangle stretched uniformly in its plane by
// l1, l2 (large: 40% and -15%) against the 3-D compressible neo-Hookean law written out here,
// S = mu (I - C^-1) + lambda ln J C^-1 with C = diag(l1^2, l2^2, c) in the stretch axes, the
// thickness stretch^2 c found by bisection on S33(c) = 0 (the free faces of a thin sheet).
// The shell's in-plane S must be that S's 2x2 block, and its nodal forces -A t F S G_i.
TEST(Shell, NeoHookeanMembraneUnderLargeStretchMatchesThe3DLawWithFreeFaces) {
  const double E0 = shellParams()[0], nu = shellParams()[1], t = shellParams()[3];
  const double mu = E0 / (2 * (1 + nu)), lam = E0 * nu / ((1 + nu) * (1 - 2 * nu));
  const double l1 = 1.4, l2 = 0.85;
  auto s33 = [&](double c) { return mu * (1 - 1 / c) + lam * 0.5 * std::log(l1 * l1 * l2 * l2 * c) / c; };
  double lo = 1e-3, hi = 10.0;  // S33 increases with c: bisection to round-off
  for (int it = 0; it < 200; ++it) (s33(0.5 * (lo + hi)) > 0 ? hi : lo) = 0.5 * (lo + hi);
  const double c = 0.5 * (lo + hi), lnJ = 0.5 * std::log(l1 * l1 * l2 * l2 * c);
  const double S11 = mu * (1 - 1 / (l1 * l1)) + lam * lnJ / (l1 * l1);
  const double S22 = mu * (1 - 1 / (l2 * l2)) + lam * lnJ / (l2 * l2);
  EXPECT_LT(std::abs(s33(c)), 1e-9 * mu);
  // a rest triangle in a tilted plane, its edge 0-1 along d1, the stretch along d1 and d2
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.5, Eigen::Vector3d(1.0, -0.4, 0.7).normalized()).toRotationMatrix();
  const Eigen::Vector3d d1 = R.col(0), d2 = R.col(1), o(0.1, 0.2, -0.3);
  VecX X(9), x(9);
  const double xy[3][2] = {{0, 0}, {0.3, 0}, {0.1, 0.2}};
  for (int i = 0; i < 3; ++i) {
    X.segment<3>(3 * i) = o + xy[i][0] * d1 + xy[i][1] * d2;
    x.segment<3>(3 * i) = o + l1 * xy[i][0] * d1 + l2 * xy[i][1] * d2;
  }
  ShellTriangle e("t", {0, 1, 2}, shellProps(false, Law::NeoHookean), X);
  const VecX p(0);
  LocalState ls;
  ls.dim = 3;
  ls.p = &p;
  ls.x = x;
  MatX Eg, S, sig;
  double vm;
  e.membraneStress(ls, Eg, S, sig, vm);
  const MatX Se = S11 * d1 * d1.transpose() + S22 * d2 * d2.transpose();
  std::printf("neo-Hookean: thickness stretch %.6f, S11 %.6e S22 %.6e Pa; shell |S - S_3D| = %.2e Pa\n", std::sqrt(c),
              S11, S22, (S - Se).norm());
  EXPECT_LT((S - Se).norm(), 1e-10 * Se.norm());
  // forces: Q_i = -A t F S G_i with F = l1 d1 d1^T + l2 d2 d2^T on the plane, G_i = grad N_i
  const double A = 0.5 * 0.3 * 0.2;
  const Eigen::Vector2d G[3] = {{-1 / 0.3, (0.1 / 0.3 - 1) / 0.2}, {1 / 0.3, -0.1 / 0.3 / 0.2}, {0, 1 / 0.2}};
  VecX Q;
  ls.v = VecX::Zero(9);
  e.force(ls, Q);
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d expected = -A * t * (l1 * S11 * G[i][0] * d1 + l2 * S22 * G[i][1] * d2);
    EXPECT_LT((Q.segment<3>(3 * i) - expected).norm(), 1e-10 * expected.norm()) << "node " << i;
  }
}

// The hinge weight's calibration (ShellHinge.hpp): six triangles around a node, its nodes on
// the surface z = x^T H x / 2 (small curvature, so theta is linear in H to 1e-6). Every hinge
// of a uniform mesh under a uniform H folds as its parallel neighbours do, and a unit area
// holds 1 / (2 A_t) edges of each of the three directions, so the mesh's energy per unit area
// is the six hinges' energy over 4 A_t. Equilateral triangles: D/2 [(tr H)^2 - 8/3 det H]
// (derived in ShellHinge.hpp from the slope jumps of the linear interpolant): exactly
// Kirchhoff's D/2 (Delta w)^2 for any cylinder, 1/3 of the sphere's and 8/3 of the saddle's
// (the Gaussian-curvature term of nu = -1/3). Right triangles (a square grid cut by one
// diagonal): a cylinder bent about a side costs Kirchhoff's energy, one bent about the cut
// diagonal 3 times as much (measured 3.0000, asserted only > 2.5: the anisotropy behind the
// right-triangle plate's wrong limit below).
TEST(Shell, HingeEnergyPerAreaOfUniformCurvature) {
  auto pr = shellProps(false);
  const double D = shell::bendingStiffness(2.0e5, 0.3, 0.004), h = 0.1, k = 1e-4;  // [N m], [m], [1/m]
  auto energyDensity = [&](const std::vector<Eigen::Vector2d>& ring, const Eigen::Matrix2d& H) {
    std::vector<Eigen::Vector3d> X{Eigen::Vector3d::Zero()};
    for (const auto& r : ring) X.emplace_back(r.x(), r.y(), 0.5 * r.dot(H * r));
    std::vector<std::array<int, 3>> tris;
    for (int i = 0; i < 6; ++i) tris.push_back({0, 1 + i, 1 + (i + 1) % 6});
    std::vector<std::unique_ptr<Element>> els;
    buildShell("patch", X, tris, {0, 1, 2, 3, 4, 5, 6}, pr, true, els, [](int i) { return std::to_string(i); });
    double U = 0.0;
    const VecX p(0);
    int hinges = 0;
    for (const auto& el : els) {
      if (el->kind() != "shell_hinge") continue;
      LocalState s;
      s.dim = 3;
      s.p = &p;
      s.x.resize(12);
      for (int j = 0; j < 4; ++j) s.x.segment<3>(3 * j) = X[el->nodes()[j]];
      U += el->potential(s);
      ++hinges;
    }
    EXPECT_EQ(hinges, 6);
    return U;  // [J], the six hinges
  };
  std::vector<Eigen::Vector2d> equi, right;
  for (int i = 0; i < 6; ++i) equi.emplace_back(h * std::cos(M_PI * i / 3), h * std::sin(M_PI * i / 3));
  right = {{h, 0}, {h, h}, {0, h}, {-h, 0}, {-h, -h}, {0, -h}};  // the cut diagonal along (1, 1)
  const double AtEqui = std::sqrt(3.0) / 4 * h * h, AtRight = 0.5 * h * h;
  auto kirchhoff = [&](const Eigen::Matrix2d& H) { return 0.5 * D * H.trace() * H.trace(); };
  for (const double phi : {0.0, 0.3, 1.0, 2.2}) {
    const Eigen::Vector2d d(std::cos(phi), std::sin(phi));
    const Eigen::Matrix2d H = k * d * d.transpose();
    EXPECT_NEAR(energyDensity(equi, H) / (4 * AtEqui) / kirchhoff(H), 1.0, 1e-5) << "cylinder at " << phi;
  }
  const Eigen::Matrix2d sphere = k * Eigen::Matrix2d::Identity();
  Eigen::Matrix2d saddle, twist;
  saddle << k, 0, 0, -k;
  twist << 0, k, k, 0;
  EXPECT_NEAR(energyDensity(equi, sphere) / (4 * AtEqui) / (0.5 * D * (4 - 8.0 / 3) * k * k), 1.0, 1e-5);
  EXPECT_NEAR(energyDensity(equi, saddle) / (4 * AtEqui) / (0.5 * D * 8.0 / 3 * k * k), 1.0, 1e-5);
  EXPECT_NEAR(energyDensity(equi, twist) / (4 * AtEqui) / (0.5 * D * 8.0 / 3 * k * k), 1.0, 1e-5);
  const Eigen::Vector2d ex(1, 0), ed = Eigen::Vector2d(1, 1).normalized();
  const double side = energyDensity(right, k * ex * ex.transpose()) / (4 * AtRight) / (0.5 * D * k * k);
  const double diag = energyDensity(right, k * ed * ed.transpose()) / (4 * AtRight) / (0.5 * D * k * k);
  std::printf("right triangles: cylinder about a side %.4f, about the cut diagonal %.4f times Kirchhoff's energy\n", side, diag);
  EXPECT_NEAR(side, 1.0, 1e-5);
  EXPECT_GT(diag, 2.5);
}

// ------------------------------------------------------------------ plate frequencies
namespace {

constexpr double kA = 1.0, kE = 2.1e11, kNu = 0.3, kRho = 7800.0, kT = 0.01;  // [m], [Pa], [-], [kg/m^3], [m]

/// Squares of side a / n, each cut by the same diagonal (right triangles).
PlateMesh rightTriangles(int n) {
  PlateMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.X.emplace_back(kA * i / n, kA * j / n, 0.0);
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.tris.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.tris.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  m.h = std::sqrt(2.0) * kA / n;
  return m;
}

/// Shell elements of a plate mesh built here (steel, kE .. kT), simply supported: its boundary
/// nodes fixed (no hinge on a boundary edge, so the rotation about the edge is free).
std::vector<std::unique_ptr<Element>> plateElements(const PlateMesh& pm, std::vector<bool>& fixed) {
  auto pr = std::make_shared<ShellProperties>();
  pr->E = {kE, -1};
  pr->nu = {kNu, -1};
  pr->density = {kRho, -1};
  pr->thickness = {kT, -1};
  std::vector<int> ids(pm.X.size());
  fixed.resize(pm.X.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    ids[i] = static_cast<int>(i);
    const Eigen::Vector3d& x = pm.X[i];
    fixed[i] = x.x() < 1e-12 || x.y() < 1e-12 || x.x() > kA - 1e-12 || x.y() > kA - 1e-12;
  }
  std::vector<std::unique_ptr<Element>> els;
  buildShell("plate", pm.X, pm.tris, ids, pr, false, els, [](int i) { return std::to_string(i); });
  return els;
}

std::vector<double> plateFrequencies(const PlateMesh& pm, int count) {
  std::vector<bool> fixed;
  const auto els = plateElements(pm, fixed);
  return transverseFrequencies(els, pm.X, fixed, count);
}

double kirchhoff(int m, int n) {
  const double D = kE * kT * kT * kT / (12.0 * (1.0 - kNu * kNu));
  return M_PI * M_PI * (m * m + n * n) / (kA * kA) * std::sqrt(D / (kRho * kT));
}

}  // namespace

// Shifted-row (near-equilateral) meshes converge to Kirchhoff's simply supported plate: the
// first three frequencies (modes (1,1), (1,2), (2,1)) at three mesh sizes, each halving h,
// approach the analytic values from above at first order (measured: errors 5.7/3.7/4.5%,
// 3.5/2.0/2.6%, 1.6/1.0/1.05%, rates 1.0-1.3; a fourth mesh 52x60, 18 s, gave 0.82/0.50/0.54%).
TEST(Shell, SimplySupportedPlateFrequenciesConverge) {
  const double ref[3] = {kirchhoff(1, 1), kirchhoff(1, 2), kirchhoff(2, 1)};
  const std::array<std::array<int, 2>, 3> sizes{{{7, 8}, {13, 15}, {26, 30}}};
  std::vector<std::array<double, 3>> err;
  std::vector<double> hs;
  for (const auto& [nx, ny] : sizes) {
    const PlateMesh pm = shiftedRows(nx, ny);
    const auto w = plateFrequencies(pm, 3);
    std::array<double, 3> e{};
    for (int k = 0; k < 3; ++k) e[k] = (w[k] - ref[k]) / ref[k];
    std::printf("shifted rows %dx%d (h = %.4f m): omega = %.4f %.4f %.4f rad/s (Kirchhoff %.4f %.4f %.4f), rel. errors %+.4f %+.4f %+.4f\n",
                nx, ny, pm.h, w[0], w[1], w[2], ref[0], ref[1], ref[2], e[0], e[1], e[2]);
    err.push_back(e);
    hs.push_back(pm.h);
  }
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE("mode " + std::to_string(k + 1));
    for (size_t i = 0; i < err.size(); ++i) EXPECT_GT(err[i][k], 0.0);  // from above
    for (size_t i = 1; i < err.size(); ++i) {
      const double rate = std::log(err[i - 1][k] / err[i][k]) / std::log(hs[i - 1] / hs[i]);
      std::printf("mode %d: observed rate %.2f from h = %.4f to %.4f m\n", k + 1, rate, hs[i - 1], hs[i]);
      EXPECT_GT(rate, 0.7);
    }
    EXPECT_LT(err.back()[k], 0.02);
  }
}

// Right triangles (every square cut by the same diagonal) do not converge to Kirchhoff's plate:
// the hinge energy of that pattern stiffens the twist (about 3 times Kirchhoff's 2 Hxy^2 per
// unit area), so modes (1,1) and (2,1) stay 33% too high and (1,2) 10% at every size.
TEST(Shell, RightTriangleMeshesConvergeToAStifferPlate) {
  const double ref[3] = {kirchhoff(1, 1), kirchhoff(1, 2), kirchhoff(2, 1)};
  std::vector<double> first;
  for (int n : {8, 16, 32}) {
    const PlateMesh pm = rightTriangles(n);
    const auto w = plateFrequencies(pm, 3);
    std::printf("right triangles %dx%d (h = %.4f m): rel. errors %+.4f %+.4f %+.4f\n", n, n, pm.h,
                (w[0] - ref[0]) / ref[0], (w[1] - ref[1]) / ref[1], (w[2] - ref[2]) / ref[2]);
    first.push_back((w[0] - ref[0]) / ref[0]);
  }
  for (double e : first) EXPECT_GT(e, 0.3);
  EXPECT_LT(std::abs(first[2] - first[1]), 0.01);  // not converging towards 0
}

// The same plate as a scene (type: shell, tests/scenes/shell/square.geo, edges grounded) on
// Gmsh's unstructured (frontal-Delaunay, near-equilateral) triangles at four element sizes.
// Measured errors (modes 1-3): size 0.2: 2.5/1.4/3.3%, 0.1: 0.3/0.1/0.4%, 0.05: 1.6/0.6/1.0%,
// 0.025: 0.4/0.1/0.2% (0.07: 0.9/0.1/1.2%, 0.035: 0.6/0.3/0.6%): within 2% from size 0.1 on
// and trending to Kirchhoff's values, but not monotonically (no clean rate: each mesh's
// triangle shapes differ). At the coarsest, `flexsens modes`'
// analysis (src/app/Modes, all three coordinates of every free node) gives the same first
// three frequencies as the transverse problem.
TEST(Shell, UnstructuredGmshPlateFrequencies) {
  const double ref[3] = {kirchhoff(1, 1), kirchhoff(1, 2), kirchhoff(2, 1)};
  for (const double size : {0.2, 0.1, 0.05, 0.025}) {
    const auto plate = test::squarePlateScene(size, "ground", kE, kNu, kRho, kT);
    const Model& m = *plate.sc.model;
    const auto& X = plate.X;
    const auto& fixed = plate.fixed;
    const auto w = transverseFrequencies(m.elements, X, fixed, 3);
    double h = 0.0;
    int tris = 0;
    for (const auto& el : m.elements)
      if (el->kind() == "shell_triangle") {
        ++tris;
        for (int j = 0; j < 3; ++j) h = std::max(h, (X[el->nodes()[j]] - X[el->nodes()[(j + 1) % 3]]).norm());
      }
    std::printf("Gmsh size %.2f (%d triangles, longest edge %.4f m): rel. errors %+.4f %+.4f %+.4f\n", size, tris, h,
                (w[0] - ref[0]) / ref[0], (w[1] - ref[1]) / ref[1], (w[2] - ref[2]) / ref[2]);
    for (int k = 0; k < 3; ++k) EXPECT_LT(std::abs(w[k] - ref[k]) / ref[k], size > 0.03 ? 0.04 : 0.01) << "mode " << k + 1;
    if (size == 0.2) {
      Assembler as(m);
      const VecX p = m.nominalParameters();
      const State s = consistentState(as, p);
      const ModalAnalysis a = analyzeModes(as, s, p, 3);
      EXPECT_EQ(a.tangent, m.n);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.modes[k].omega(), w[k], 1e-8 * w[k]) << "mode " << k + 1;
    }
  }
}

// rest_shape read from a scene (tests/scenes/shell/folded.msh: two triangles folded about their
// shared edge, the wing tip a Physical Point "apex"): `initial` starts unstressed, `flat`
// starts with the hinge's energy D/2 |e|^2/(A1 + A2) theta0^2, theta0 the angle between the
// triangles' normals computed here from the mesh coordinates.
TEST(Shell, SceneRestShapeInitialOrFlat) {
  const Eigen::Vector3d x0(0, 0, 0), x1(1, 0, 0), x2(0.5, 1, 0), x3(0.5, -0.5, 0.8);
  const Eigen::Vector3d n1 = (x1 - x0).cross(x2 - x0), n2 = (x3 - x0).cross(x1 - x0);
  const double theta0 = std::acos(n1.normalized().dot(n2.normalized()));
  const double w = 1.0 / (0.5 * n1.norm() + 0.5 * n2.norm());  // |e|^2 = 1 m^2
  const double E0 = 1.0e9, nu = 0.3, t = 0.002, D = E0 * t * t * t / (12 * (1 - nu * nu));
  for (const bool flat : {false, true}) {
    std::ostringstream text;
    text << "dimension: 3\nelements:\n  - {name: sheet, type: shell, mesh: folded.msh, group: sheet, E: " << E0
         << ", nu: " << nu << ", density: 1000, thickness: " << t << (flat ? ", rest_shape: flat" : "")
         << "}\nparameters:\n  - {name: t, of: sheet, property: thickness}\n"
            "integrator: {type: trapezoidal, t_end: 0.01, dt: 0.001}\n";
    const Scene sc = readSceneText(text.str(), test::sourceDir() + "/tests/scenes/shell/scene.yaml");
    const Model& m = *sc.model;
    ASSERT_EQ(m.nodes.size(), 4u);
    ASSERT_GE(m.nodeIndex("apex"), 0);
    EXPECT_LT((m.nodes[m.nodeIndex("apex")].position - x3).norm(), 1e-15);
    Assembler as(m);
    const VecX p = m.nominalParameters();
    const double U = as.potentialEnergy(m.initialPositions(), p);
    EXPECT_NEAR(U, flat ? 0.5 * D * w * theta0 * theta0 : 0.0, 1e-12 * D) << (flat ? "flat" : "initial");
  }
}

// Free flight (no gravity, no supports) of the folded sheet of folded.msh with rest_shape: flat,
// so that its hinge springs open and flaps (theta0 = 1.1 rad of stored bending) while the sheet
// translates and tumbles: the trapezoidal rule conserves linear momentum to round-off (internal
// forces sum to zero) and energy to O(dt^2) (halving dt divides the largest deviation by 3..5);
// angular momentum to O(dt^2) as well (the scheme does not conserve it).
namespace {
struct ShellFlight {
  double E0 = 0, dE = 0, dP = 0, L0 = 0, dL = 0;
};
ShellFlight flyFoldedSheet(double dt) {
  std::ostringstream text;
  text << "dimension: 3\nelements:\n  - {name: sheet, type: shell, mesh: folded.msh, group: sheet, E: 1.0e6, nu: 0.3,"
          " density: 1000, thickness: 0.05, rest_shape: flat, velocity: [0.3, -0.1, 0.2], angular_velocity: [0.5, -1, 2],"
          " center: [0.5, 0.2, 0.2]}\nintegrator: {type: trapezoidal, t_end: 2, dt: "
       << dt << ", frame_interval: " << dt << "}\n";
  const Scene sc = readSceneText(text.str(), test::sourceDir() + "/tests/scenes/shell/scene.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = m.nominalParameters();
  StateWithSens start = initialState(as, p);
  start.dp.clear();
  test::Recorder rec;
  integrateFixedStep(as, p, start, sc.integrator, rec);
  const SpMat M = as.mass(p);
  ShellFlight f;
  Eigen::Vector3d P0, L0v;
  for (size_t k = 0; k < rec.frames.size(); ++k) {
    const auto& fr = rec.frames[k];
    const VecX Mv = M * fr.x.v;
    const double E = 0.5 * fr.x.v.dot(Mv) + as.potentialEnergy(fr.x.q, p);
    Eigen::Vector3d P = Eigen::Vector3d::Zero(), L = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      const int d = m.dof(static_cast<int>(i), 0);
      P += Mv.segment<3>(d);
      L += Eigen::Vector3d(fr.x.q.segment<3>(d)).cross(Eigen::Vector3d(Mv.segment<3>(d)));
    }
    if (k == 0) {
      f.E0 = E;
      P0 = P;
      L0v = L;
      f.L0 = L.norm();
    }
    f.dE = std::max(f.dE, std::abs(E - f.E0));
    f.dP = std::max(f.dP, (P - P0).norm() / P0.norm());
    f.dL = std::max(f.dL, (L - L0v).norm());
  }
  return f;
}
}  // namespace

TEST(Shell, FreeFlightConservesMomentumAndEnergyToSecondOrder) {
  const ShellFlight a = flyFoldedSheet(0.01), b = flyFoldedSheet(0.005);
  std::printf("E0 %.6e J, |L0| %.6e; dt 0.01: max |dE| %.3e J, |dP|/|P0| %.2e, |dL| %.3e; dt 0.005: %.3e, %.2e, %.3e; "
              "energy ratio %.2f, angular-momentum ratio %.2f\n",
              a.E0, a.L0, a.dE, a.dP, a.dL, b.dE, b.dP, b.dL, a.dE / b.dE, a.dL / b.dL);
  EXPECT_LT(a.dP, 1e-11);
  EXPECT_LT(b.dP, 1e-11);
  EXPECT_GT(a.dE / b.dE, 3.0);
  EXPECT_LT(a.dE / b.dE, 5.0);
  EXPECT_LT(a.dE, 1e-2 * a.E0);
  EXPECT_GT(a.dL / b.dL, 3.0);
  EXPECT_LT(a.dL / b.dL, 5.0);
}

// Static: the simply supported square plate (square.geo, Gmsh triangles) under its own weight
// at 0.1 g (centre deflection 1.6e-5 m = t/600: linear) against Navier's series for a uniform
// load q = rho t g, w(a/2, a/2) = 16 q / (pi^6 D) sum_{m,n odd} (-1)^((m+n)/2 - 1) /
// (m n (m^2 + n^2)^2 / a^4) (Timoshenko & Woinowsky-Krieger: 0.00406 q a^4 / D), summed here.
TEST(Shell, SimplySupportedPlateUnderUniformLoadMatchesNavier) {
  const double g = 0.981, q = kRho * kT * g, D = kE * kT * kT * kT / (12.0 * (1.0 - kNu * kNu));
  double sum = 0.0;
  for (int m = 1; m < 400; m += 2)
    for (int n = 1; n < 400; n += 2)
      sum += ((((m + n) / 2 - 1) % 2) ? -1.0 : 1.0) / (m * n * std::pow(m * m + n * n, 2.0));
  const double navier = 16.0 * q * std::pow(kA, 4) / (std::pow(M_PI, 6) * D) * sum;  // [m]
  EXPECT_NEAR(navier * D / (q * std::pow(kA, 4)), 0.00406, 5e-6);                     // the tabulated coefficient
  for (const double size : {0.1, 0.05, 0.025}) {
    std::ostringstream text;
    text.precision(17);
    text << "dimension: 3\ngravity: [0, 0, " << -g << "]\nelements:\n  - {name: plate, type: shell, mesh: square.geo, group: plate, size: "
         << size << ", E: " << kE << ", nu: " << kNu << ", density: " << kRho << ", thickness: " << kT
         << ", ground: [edges]}\nstatic: {load_steps: 1}\n";
    const Scene sc = readSceneText(text.str(), test::sourceDir() + "/tests/scenes/shell/scene.yaml");
    const Model& m = *sc.model;
    const VecX qs = test::staticEquilibrium(m, 1e-14);
    const double w = -qs[m.dof(m.nodeIndex("centre"), 2)];
    std::printf("Gmsh size %.3f: centre deflection %.6e m, Navier %.6e m, rel. error %+.4f\n", size, w, navier, (w - navier) / navier);
    EXPECT_LT(std::abs(w - navier) / navier, size > 0.03 ? 0.04 : 0.01);
  }
}

// The same load on the shifted-row meshes: the compliance q int w dA (work of the consistent
// load F = M g on the deflection K^-1 F) against Navier's q^2 64 a^6 / (pi^8 D)
// sum_{m,n odd} 1 / (m^2 n^2 (m^2 + n^2)^2). Measured errors -11.4%, -7.3%, -3.4%: first
// order, from below (the meshes are too stiff by about twice the frequencies' relative error,
// as omega^2 ~ K and compliance ~ 1/K).
TEST(Shell, ShiftedRowPlateComplianceMatchesNavier) {
  const double g = 0.981, q = kRho * kT * g, D = kE * kT * kT * kT / (12.0 * (1.0 - kNu * kNu));
  double sum = 0.0;
  for (int m = 1; m < 400; m += 2)
    for (int n = 1; n < 400; n += 2) sum += 1.0 / (double(m) * m * n * n * std::pow(m * m + n * n, 2.0));
  const double navier = q * q * 64.0 * std::pow(kA, 6) / (std::pow(M_PI, 8) * D) * sum;  // [J]
  std::vector<double> err, hs;
  for (const auto& [nx, ny] : std::vector<std::array<int, 2>>{{7, 8}, {13, 15}, {26, 30}}) {
    const PlateMesh pm = shiftedRows(nx, ny);
    std::vector<bool> fixed;
    const auto els = plateElements(pm, fixed);
    MatX K, M;
    VecX unit;
    std::vector<int> zdof;
    transverseMatrices(els, pm.X, fixed, K, M, zdof, &unit);
    const VecX F = -g * unit;  // [N]
    const VecX w = K.ldlt().solve(F);
    const double c = F.dot(w);
    err.push_back((c - navier) / navier);
    hs.push_back(pm.h);
    std::printf("shifted rows %dx%d: compliance %.6e J, Navier %.6e J, rel. error %+.4f\n", nx, ny, c, navier, err.back());
  }
  for (size_t i = 1; i < err.size(); ++i) {
    const double rate = std::log(err[i - 1] / err[i]) / std::log(hs[i - 1] / hs[i]);
    std::printf("compliance: observed rate %.2f from h = %.4f to %.4f m\n", rate, hs[i - 1], hs[i]);
    EXPECT_GT(rate, 0.5);
  }
  for (double e : err) EXPECT_LT(e, 0.0);
  EXPECT_GT(err.back(), -0.04);
}

// PIM of a shell: rigidizing the free square plate (its mesh nodes a planar cloud in 3D) leaves
// its 6 rigid motions (d - m_r = 6); the F-R twin's mass properties are the plate's exact
// integrals: m = rho t a^2, centre (a/2, a/2, 0), inertia about the centre m a^2/12 (x, y) and
// m a^2/6 (z) (thin plate; the consistent mass of straight triangles integrates these exactly).
TEST(Shell, PimRigidizedPlateLeavesSixMotionsAndTwinHasThePlateIntegrals) {
  const std::string text =
      "dimension: 3\nelements:\n  - {name: plate, type: shell, mesh: square.geo, group: plate, size: 0.25, E: 2.1e11,"
      " nu: 0.3, density: 7800, thickness: 0.01}\nparameters:\n  - {name: t, of: plate, property: thickness}\n"
      "cases:\n  - {name: F1, parameters: [t], rigidize: [plate]}\nintegrator: {type: trapezoidal, t_end: 0.001, dt: 0.001}\n";
  const std::string file = test::sourceDir() + "/tests/scenes/shell/scene.yaml";
  {
    const Scene sc = readSceneText(text, file, "F1");
    const Model& m = *sc.model;
    Assembler as(m);
    const PimReport r = pimCounts(as, *sc.pimCase, m.initialPositions(), m.nominalParameters());
    EXPECT_EQ(r.m, 0);
    EXPECT_EQ(r.d, m.n);
    EXPECT_EQ(r.lambdaGenerated, m.n - 6);
    EXPECT_EQ(r.lambdaDropped, 0);
    EXPECT_EQ(r.ds, 6);
  }
  const Scene sc = readSceneText(text, file);
  const Model& m = *sc.model;
  std::vector<int> all(m.nodes.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  const MassProperties mp = rigidMassProperties(m, all, m.nominalParameters());
  const double mass = 7800 * 0.01 * kA * kA;
  EXPECT_NEAR(mp.mass, mass, 1e-12 * mass);
  EXPECT_NEAR(mp.centre[0], kA / 2, 1e-12);
  EXPECT_NEAR(mp.centre[1], kA / 2, 1e-12);
  EXPECT_NEAR(mp.centre[2], 0.0, 1e-12);
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  I.diagonal() << mass * kA * kA / 12, mass * kA * kA / 12, mass * kA * kA / 6;
  EXPECT_LT((mp.inertia - I).norm(), 1e-12 * I.norm());
}

// Output: `flexsens static` on the simply supported plate under its own weight writes the shell
// triangles as VTK_TRIANGLE cells (element_kind 8) with finite membrane strain and stresses
// (their values: UniformStretchGivesTheMembraneForceExactly).
TEST(Shell, StaticRunWritesTriangleCellsWithMembraneStress) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("flexsens_shell_vtu_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string text = "dimension: 3\ngravity: [0, 0, -9.81]\nelements:\n  - {name: plate, type: shell, mesh: " +
                           test::sourceDir() + "/tests/scenes/shell/square.geo, group: plate, size: 0.25, E: 2.1e11, nu: 0.3,"
                           " density: 7800, thickness: 0.01, ground: [edges]}\nstatic: {load_steps: 1}\n";
  { std::ofstream(dir / "plate.yaml") << text; }
  const auto g = test::staticLastFrame(dir / "plate.yaml", dir / "out");
  ASSERT_NE(g, nullptr);
  const Scene sc = readSceneText(text, (dir / "plate.yaml").string());
  int tris = 0;
  for (const auto& e : sc.model->elements) tris += e->kind() == "shell_triangle";
  ASSERT_EQ(g->GetNumberOfCells(), tris);
  vtkDataArray* kind = g->GetCellData()->GetArray("element_kind");
  vtkDataArray* vm = g->GetCellData()->GetArray("von_mises");
  ASSERT_NE(kind, nullptr);
  ASSERT_NE(vm, nullptr);
  ASSERT_NE(g->GetCellData()->GetArray("stress_cauchy"), nullptr);
  for (vtkIdType c = 0; c < g->GetNumberOfCells(); ++c) {
    EXPECT_EQ(g->GetCellType(c), VTK_TRIANGLE);
    EXPECT_EQ(kind->GetTuple1(c), 8.0);
    EXPECT_TRUE(std::isfinite(vm->GetTuple1(c)));
  }
  fs::remove_all(dir);
}
