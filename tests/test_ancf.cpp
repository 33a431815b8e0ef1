// ANCF cable element (elements/AncfCable): derivatives against finite differences and AD,
// rigid-motion invariance, the uniform-stretch patch test, and the cantilever against the
// external references of /work/shared/reference/beams-and-checks.md (linear tip deflection,
// natural frequencies with their convergence rate, the elastica table at N = 8).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "TestModels.hpp"
#include "app/Modes.hpp"
#include "app/Run.hpp"
#include "core/Assembler.hpp"
#include "elements/AncfCable.hpp"
#include "elements/PointForce.hpp"
#include "integrators/Static.hpp"
#include "pim/Pim.hpp"
#include "pim/Rigidization.hpp"
#include "pim/Sdof.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;
using flexsens::test::fdJacobian;
using flexsens::test::relMax;

namespace {

/// Max-norm relative difference.

/// Local state of one element with its own storage for p and gravity.
struct Local {
  VecX p, g;
  LocalState s;
  Local(int dim, VecX x, VecX params, bool gravity = true) : p(std::move(params)) {
    g = VecX::Zero(dim);
    if (gravity) {
      g[0] = 0.7;
      g[1] = -9.81;
      if (dim == 3) g[2] = 1.3;
    }
    s.dim = dim;
    s.gradients = 1;
    s.v = VecX::Zero(x.size());
    s.x = std::move(x);
    s.p = &p;
    s.gravity = &g;
  }
};

/// Rest coordinates of a planar element on a circular arc of radius R from angle 0 to th
/// (positions and unit tangents), and of a straight spatial element along (1, 2, 2)/3.
VecX arcRest(double R, double th) {
  VecX x(8);
  x << R, 0, 0, 1, R * std::cos(th), R * std::sin(th), -std::sin(th), std::cos(th);
  return x;
}
VecX straight3D(double L) {
  const Eigen::Vector3d t(1.0 / 3, 2.0 / 3, 2.0 / 3);
  VecX x(12);
  x << 0.1, -0.2, 0.3, t, Eigen::Vector3d(0.1, -0.2, 0.3) + L * t, t;
  return x;
}
VecX perturbed(const VecX& x, double scale, unsigned seed) {
  std::srand(seed);
  return x + scale * VecX::Random(x.size());
}

/// Every derivative of one element at a deformed state: dQ/dq analytic vs central FD and vs
/// AD; dQ/dp and dM/dp analytic vs FD (in p) and vs AD; -dU/dq = Q (potential vs force).
void checkDerivatives(const AncfCable& e, Local& L, int nParams) {
  const LocalState& s = L.s;
  MatX K, Kv, Kad, Kvad;
  e.forceJacobian(s, K, Kv);
  e.forceJacobianAD(s, Kad, Kvad);
  EXPECT_LT(relMax(Kad, K), 1e-10) << "AD vs analytic dQ/dq";
  EXPECT_EQ(Kv.norm(), 0.0);
  EXPECT_EQ(Kvad.norm(), 0.0);
  EXPECT_FALSE(e.velocityDependent());  // as declared (the assembly skips it for dQ/dv alone)
  EXPECT_GT(K.norm(), 0.0);
  auto force = [&](const VecX& x) {
    LocalState t = s;
    t.x = x;
    VecX Q;
    e.force(t, Q);
    return Q;
  };
  EXPECT_LT(relMax(fdJacobian(force, s.x, 1e-6), K), 1e-6) << "FD vs analytic dQ/dq";
  // Potential: its negative gradient is the force.
  auto energy = [&](const VecX& x) {
    LocalState t = s;
    t.x = x;
    return VecX::Constant(1, e.potential(t));
  };
  VecX Q;
  e.force(s, Q);
  EXPECT_LT(relMax(-fdJacobian(energy, s.x, 1e-6).transpose(), Q), 1e-6) << "-dU/dq vs Q";
  test::expectParameterDerivatives(e, s, L.p, nParams);
}

}  // namespace

TEST(AncfCable, PlanarCurvedDerivativesMatchFiniteDifferencesAndAD) {
  const VecX rest = arcRest(0.8, 0.6);
  for (bool square : {true, false}) {
    SCOPED_TRACE(square ? "square section" : "explicit section");
    AncfCable e("c", {0, 1}, square ? test::squareSection() : test::explicitSection(), rest);
    Local L(2, perturbed(rest, 0.05, 3), square ? test::squareParams() : test::explicitParams());
    checkDerivatives(e, L, square ? 3 : 4);
  }
}

TEST(AncfCable, SpatialDerivativesMatchFiniteDifferencesAndAD) {
  const VecX rest = straight3D(0.5);
  for (bool square : {true, false}) {
    SCOPED_TRACE(square ? "square section" : "explicit section");
    AncfCable e("c", {0, 1}, square ? test::squareSection() : test::explicitSection(), rest);
    Local L(3, perturbed(rest, 0.05, 5), square ? test::squareParams() : test::explicitParams());
    checkDerivatives(e, L, square ? 3 : 4);
  }
}

// Any rigid motion of the rest shape (slopes rotate with it) leaves no elastic force.
TEST(AncfCable, RigidMotionGivesZeroElasticForce) {
  const double th = 0.9;
  {  // planar, curved rest
    const VecX rest = arcRest(0.8, 0.6);
    AncfCable e("c", {0, 1}, test::squareSection(), rest);
    Eigen::Matrix2d R;
    R << std::cos(th), -std::sin(th), std::sin(th), std::cos(th);
    VecX x(8);
    x << R * rest.segment<2>(0) + Eigen::Vector2d(0.3, -1.1), R * rest.segment<2>(2),
        R * rest.segment<2>(4) + Eigen::Vector2d(0.3, -1.1), R * rest.segment<2>(6);
    Local L(2, x, test::squareParams(), false);
    VecX Q;
    e.force(L.s, Q);
    EXPECT_LT(Q.lpNorm<Eigen::Infinity>(), 1e-9);  // elastic forces of unit strain ~ EA = 5e2 N
    EXPECT_LT(std::abs(e.potential(L.s)), 1e-14);
  }
  {  // spatial, straight rest
    const VecX rest = straight3D(0.5);
    AncfCable e("c", {0, 1}, test::squareSection(), rest);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(th, Eigen::Vector3d(0.2, -0.5, 0.8).normalized()).toRotationMatrix();
    VecX x(12);
    for (int i = 0; i < 4; ++i) x.segment<3>(3 * i) = R * rest.segment<3>(3 * i);
    x.segment<3>(0) += Eigen::Vector3d(1, 2, 3);
    x.segment<3>(6) += Eigen::Vector3d(1, 2, 3);
    Local L(3, x, test::squareParams(), false);
    VecX Q;
    e.force(L.s, Q);
    EXPECT_LT(Q.lpNorm<Eigen::Infinity>(), 1e-9);
  }
}

// Zero-energy modes of one free element at rest: with the default 3 axial points only the
// rigid motions (3 in the plane; 5 for the straight spatial cable, which has no rotation about
// its own axis); with the reduced 2 points one more: positions fixed, both slopes lengthened
// along the axis by the same amount (u' = c P2, the Legendre polynomial that vanishes at both
// Gauss points). In a chain that mode is global; a clamped slope removes it (checked on the
// cantilever below).
TEST(AncfCable, ZeroEnergyModesAreRigidMotionsAndTheReducedAxialMode) {
  for (int d : {2, 3}) {
    SCOPED_TRACE(d);
    const VecX t = d == 2 ? VecX::Unit(2, 0) : VecX(straight3D(1.0).segment(3, 3));
    VecX rest(4 * d), mode = VecX::Zero(4 * d);
    rest << VecX::Zero(d), t, 0.5 * t, t;
    mode << VecX::Zero(d), t, VecX::Zero(d), t;
    Local L(d, rest, test::squareParams(), false);
    for (int axialPoints : {3, 2}) {
      SCOPED_TRACE(axialPoints);
      AncfCable e("c", {0, 1}, test::squareSection(), rest, axialPoints, 3);
      MatX K, Kv;
      e.forceJacobian(L.s, K, Kv);
      Eigen::SelfAdjointEigenSolver<MatX> es(-K);
      const VecX ev = es.eigenvalues();
      int zeros = 0;
      for (int i = 0; i < ev.size(); ++i) zeros += std::abs(ev[i]) < 1e-9 * ev.maxCoeff() ? 1 : 0;
      EXPECT_EQ(zeros, (d == 2 ? 3 : 5) + (axialPoints == 2 ? 1 : 0));
      EXPECT_GT(ev.minCoeff(), -1e-9 * ev.maxCoeff());  // positive semidefinite at rest
      if (axialPoints == 2) EXPECT_LT((K * mode).norm(), 1e-12 * K.norm());
      else EXPECT_GT((K * mode).norm(), 1e-3 * K.norm());
    }
  }
}

// Uniform stretch by lambda: engineering strain eps = lambda - 1 everywhere, no curvature, so
// the end nodes carry -+EA eps along the axis and the slopes carry nothing.
TEST(AncfCable, UniformStretchGivesAxialForceEAStrain) {
  const double Lel = 0.4, lambda = 1.3;
  for (int d : {2, 3}) {
    SCOPED_TRACE(d);
    VecX rest = VecX::Zero(4 * d), x = VecX::Zero(4 * d);
    const VecX t = d == 2 ? VecX((VecX(2) << 0.6, 0.8).finished()) : VecX((VecX(3) << 2.0 / 3, -1.0 / 3, 2.0 / 3).finished());
    rest << VecX::Zero(d), t, Lel * t, t;
    x << VecX::Zero(d), lambda * t, lambda * Lel * t, lambda * t;
    AncfCable e("c", {0, 1}, test::squareSection(), rest);
    Local L(d, x, test::squareParams(), false);
    VecX Q;
    e.force(L.s, Q);
    const double EA = 5.0e6 * 0.01 * 0.01;  // squareParams: E [Pa] times side^2 [m^2]
    const VecX N = EA * (lambda - 1.0) * t;
    EXPECT_LT((Q.segment(0, d) - N).norm(), 1e-12 * N.norm());
    EXPECT_LT((Q.segment(2 * d, d) + N).norm(), 1e-12 * N.norm());
    EXPECT_LT(Q.segment(d, d).norm() + Q.segment(3 * d, d).norm(), 1e-12 * N.norm());
  }
}

// ------------------------------------------------------------------------- cantilever
namespace {

// Square steel section of side 1 mm (EA / EI = 1.2e7 / m^2: axial strain <= 4e-7 at alpha = 5,
// far below the errors resolved), length 1 m.
constexpr double kL = 1.0, kSide = 0.001, kE = 2.0e11, kRho = 7850.0;

struct Cantilever {
  std::unique_ptr<Model> model;
  std::shared_ptr<BeamSection> sec;
  int tip = -1;
  double EI() const { return sec->EI(VecX()); }
  double rhoA() const { return sec->rhoA(VecX()); }
};

/// N elements along x; node 0 ground and clamped (slope (1, 0) fixed); a PointForce on the
/// tip with its y component bound to parameter 0 ("Fy" [N]). The clamp removes the reduced
/// quadrature's mode, so the cantilever uses 2 axial points (locking-free) unless told.
Cantilever buildCantilever(int N, int axialPoints = 2,
                           int bendingPoints = AncfCable::kBendingPoints) {
  Cantilever c;
  c.sec = std::make_shared<BeamSection>();
  c.sec->square = true;
  c.sec->E.constant = kE;
  c.sec->density.constant = kRho;
  c.sec->side.constant = kSide;
  c.model = std::make_unique<Model>();
  Model& m = *c.model;
  m.dim = 2;
  m.gravity = VecX::Zero(2);
  const double h = kL / N;
  for (int i = 0; i <= N; ++i) {
    Node nd;
    nd.name = "n" + std::to_string(i);
    nd.position = (VecX(2) << i * h, 0.0).finished();
    nd.velocity = VecX::Zero(2);
    nd.slope = (VecX(2) << 1.0, 0.0).finished();
    nd.ground = nd.clamped = i == 0;
    m.nodes.push_back(nd);
  }
  for (int i = 0; i < N; ++i) {
    VecX rest(8);
    rest << i * h, 0, 1, 0, (i + 1) * h, 0, 1, 0;
    m.elements.push_back(std::make_unique<AncfCable>("e" + std::to_string(i), std::vector<int>{i, i + 1},
                                                     c.sec, rest, axialPoints, bendingPoints));
  }
  c.tip = N;
  Quantity fx, fy;
  fy.param = 0;
  m.elements.push_back(std::make_unique<PointForce>("tip_load", c.tip, std::vector<Quantity>{fx, fy}));
  m.parameters.push_back({"Fy", 0.0, "tip_load.y"});
  m.finalize();
  return c;
}

/// The stiffness -dQ/dq and mass at the straight state, restricted to the transverse (y, y')
/// coordinates: in the linearization of a straight beam they decouple from the axial ones.
void transverse(const Cantilever& c, MatX& K, MatX& M) {
  const Model& m = *c.model;
  Assembler as(m);
  const VecX p = VecX::Zero(1), q = m.initialPositions();
  SparseAccumulator acc;
  acc.begin(m.n, m.n);
  as.addForceJacobian(acc, q, VecX::Zero(m.n), p, 1.0, 0.0, 0, 0, 0);  // adds -dQ/dq
  const MatX Kf = MatX(acc.finish()), Mf = MatX(as.mass(p));
  std::vector<int> idx;
  for (int i = 1; i < static_cast<int>(m.nodes.size()); ++i) {
    idx.push_back(m.dof(i, 1));
    idx.push_back(m.dof(i, 3));
  }
  K.resize(idx.size(), idx.size());
  M.resize(idx.size(), idx.size());
  for (size_t a = 0; a < idx.size(); ++a)
    for (size_t b = 0; b < idx.size(); ++b) {
      K(a, b) = Kf(idx[a], idx[b]);
      M(a, b) = Mf(idx[a], idx[b]);
    }
}

const double kBetaL[] = {1.8751040687, 4.6940911330, 7.8547574382};

}  // namespace

// Hermite cubics contain the exact linear solution (a cubic), so the tip deflection of the
// linearized cantilever is P L^3 / (3 EI) for every N, to round-off.
TEST(AncfCantilever, LinearTipDeflectionIsExact) {
  for (int N : {1, 2, 5}) {
    const Cantilever c = buildCantilever(N);
    MatX K, M;
    transverse(c, K, M);
    VecX f = VecX::Zero(K.rows());
    const double P = 1.0;  // [N]
    f[K.rows() - 2] = P;   // y of the tip
    const VecX u = K.ldlt().solve(f);
    const double ref = P * kL * kL * kL / (3.0 * c.EI());
    EXPECT_NEAR(u[K.rows() - 2] / ref, 1.0, 1e-10) << "N = " << N;
    EXPECT_NEAR(u[K.rows() - 1] / (P * kL * kL / (2.0 * c.EI())), 1.0, 1e-10) << "tip slope, N = " << N;
    // the clamp removes every zero-energy mode: the whole stiffness is positive definite
    Assembler as(*c.model);
    SparseAccumulator acc;
    acc.begin(c.model->n, c.model->n);
    as.addForceJacobian(acc, c.model->initialPositions(), VecX::Zero(c.model->n), VecX::Zero(1), 1.0, 0.0, 0, 0, 0);
    EXPECT_EQ(Eigen::LLT<MatX>(MatX(acc.finish())).info(), Eigen::Success) << "N = " << N;
  }
}

// The eigenvalue error of cubic Hermite elements is O(h^4) (2 (p + 1 - m), p = 3, m = 2), and
// with consistent mass the frequencies converge from above. Observed relative errors of
// omega_1..3 at N = 4, 8, 16 (N = 2 is pre-asymptotic for omega_2, omega_3: rates 2.9, 4.8):
// see the printed table; the rate of the finest pair must be within 4 +- 0.2 for each mode,
// and every rate above 3.5.
TEST(AncfCantilever, FrequenciesConvergeAtFourthOrder) {
  const int Ns[] = {4, 8, 16};
  double err[3][3];
  for (int k = 0; k < 3; ++k) {
    const Cantilever c = buildCantilever(Ns[k]);
    MatX K, M;
    transverse(c, K, M);
    Eigen::GeneralizedSelfAdjointEigenSolver<MatX> es(K, M);
    ASSERT_EQ(es.info(), Eigen::Success);
    const double w0 = std::sqrt(c.EI() / (c.rhoA() * std::pow(kL, 4)));  // [rad/s]
    for (int j = 0; j < 3; ++j) {
      const double ref = kBetaL[j] * kBetaL[j] * w0;
      err[k][j] = (std::sqrt(es.eigenvalues()[j]) - ref) / ref;
      std::printf("N = %d: omega_%d = %.8f rad/s, reference %.8f, relative error %.3e\n", Ns[k], j + 1,
                  std::sqrt(es.eigenvalues()[j]), ref, err[k][j]);
      EXPECT_GT(err[k][j], 0.0);  // consistent mass, conforming: bounds from above
    }
  }
  for (int j = 0; j < 3; ++j)
    for (int k = 1; k < 3; ++k) {
      const double rate = std::log2(err[k - 1][j] / err[k][j]);
      std::printf("omega_%d: rate N = %d -> %d: %.2f\n", j + 1, Ns[k - 1], Ns[k], rate);
      EXPECT_GT(rate, 3.5);
      if (k == 2) EXPECT_NEAR(rate, 4.0, 0.2);
    }
  EXPECT_LT(err[2][2], 1e-4);  // omega_3 at N = 16
}

// `flexsens modes` (app/Modes: K and M on the constraints' tangent space, element states with
// their slopes) on the same cantilever at N = 8: its three lowest modes are the bending modes,
// equal to the direct transverse eigenproblem above (1e-9) and to beta_n L within the O(h^4)
// error of N = 8. (Modes once built element states without slopes and threw on ANCF models.)
TEST(AncfCantilever, ModesReportTheBendingFrequencies) {
  const Cantilever c = buildCantilever(8);
  Assembler as(*c.model);
  const VecX p = VecX::Zero(1);
  const ModalAnalysis a = analyzeModes(as, consistentState(as, p), p, 3);
  MatX K, M;
  transverse(c, K, M);
  Eigen::GeneralizedSelfAdjointEigenSolver<MatX> es(K, M);
  ASSERT_EQ(es.info(), Eigen::Success);
  const double w0 = std::sqrt(c.EI() / (c.rhoA() * std::pow(kL, 4)));
  for (int j = 0; j < 3; ++j) {
    const double ref = kBetaL[j] * kBetaL[j] * w0;
    std::printf("modes: omega_%d = %.8f rad/s, direct %.8f, beta_n L %.8f\n", j + 1, a.modes[j].omega(),
                std::sqrt(es.eigenvalues()[j]), ref);
    EXPECT_FALSE(a.modes[j].rigid);
    EXPECT_NEAR(a.modes[j].omega() / std::sqrt(es.eigenvalues()[j]), 1.0, 1e-9);
    EXPECT_NEAR(a.modes[j].omega() / ref, 1.0, 2e-3);
  }
}

// Large deflection under a dead tip load P = alpha EI / L^2: the elastica table at N = 8.
// Observed relative errors (2 axial, 3 bending points): rotation <= 2.4e-5, v/L <= 2.1e-5,
// u/L <= 8.6e-5 for alpha 1..5; at alpha = 0.2, u/L is off by 4.6e-7 absolute (1.7e-4
// relative), within the table's rounding of 5e-7. With the default 3 axial points this thin
// beam (L / side = 1000) locks: errors up to 3.6e-3 (printed, not asserted).
TEST(AncfCantilever, ElasticaAtEightElements) {
  struct Ref {
    double alpha, rot, v, u;
  };
  const Ref table[] = {{0.2, 0.099636, 0.066364, 0.002647},
                       {1.0, 0.461352, 0.301721, 0.056433},
                       {2.0, 0.781750, 0.493457, 0.160642},
                       {5.0, 1.215368, 0.713792, 0.387628}};
  const Cantilever c = buildCantilever(8);
  const Model& m = *c.model;
  Assembler as(m);
  for (const Ref& ref : table) {
    const VecX p = VecX::Constant(1, -ref.alpha * c.EI() / (kL * kL));
    StaticSettings set;
    set.steps = 10;
    set.paramsAt = linearLoadPath(VecX::Zero(1), p);
    const VecX q = solveStatic(as, p, m.initialPositions(), set);
    const double x = q[m.dof(c.tip, 0)], y = q[m.dof(c.tip, 1)];
    const double rot = std::atan2(-q[m.dof(c.tip, 3)], q[m.dof(c.tip, 2)]);  // tip slope angle
    const double e[3] = {std::abs(rot / ref.rot - 1), std::abs(-y / kL / ref.v - 1),
                         std::abs((kL - x) / kL / ref.u - 1)};
    std::printf("alpha = %.1f: relative errors rotation %.2e, v/L %.2e, u/L %.2e\n", ref.alpha, e[0], e[1], e[2]);
    // the table's six decimals: +-5e-7 absolute
    EXPECT_LT(e[0], 1e-4 + 5e-7 / ref.rot);
    EXPECT_LT(e[1], 1e-4 + 5e-7 / ref.v);
    EXPECT_LT(e[2], 1e-4 + 5e-7 / ref.u);
  }
  const Cantilever full = buildCantilever(8, 3);
  Assembler asFull(*full.model);
  const Ref& ref = table[3];
  const VecX p = VecX::Constant(1, -ref.alpha * full.EI() / (kL * kL));
  StaticSettings set;
  set.paramsAt = linearLoadPath(VecX::Zero(1), p);
  const VecX q = solveStatic(asFull, p, full.model->initialPositions(), set);
  std::printf("3 axial points, alpha = 5: relative error v/L %.2e (locking)\n",
              std::abs(-q[full.model->dof(full.tip, 1)] / kL / ref.v - 1));
}

// ------------------------------------------------------------------------------ scenes
namespace {

/// A chain A - n1 - n2 - n3 as ancf_cable; A ground (`clamped` or pinned); n1 turns by 90 deg.
std::string chainScene(bool clamped, int dim = 2) {
  const std::string z = dim == 3 ? ", 0" : "";
  return "dimension: " + std::to_string(dim) + "\n"
         "gravity: [0, -9.81" + z + "]\n"
         "nodes:\n"
         "  - {name: A, position: [0, 0" + z + "], ground: true" + (clamped ? ", clamped: true" : "") + "}\n"
         "  - {name: n1, position: [1, 0" + z + "]}\n"
         "  - {name: n2, position: [1, 1" + z + "], slope: [0, 3" + z + "]}\n"
         "  - {name: n3, position: [1, 2" + z + "]}\n"
         "elements:\n"
         "  - {name: c, type: ancf_cable, nodes: [A, n1, n2, n3], E: 2.0e11, density: 7850,\n"
         "     section: {side: 0.01}, rest_shape: " + std::string(dim == 3 ? "straight" : "initial") + "}\n"
         "integrator: {type: trapezoidal, t_end: 0.1, dt: 0.01}\n";
}

}  // namespace

// Slopes from the chain's tangent (mean of the unit directions at n1) or the scene (n2, made
// unit); a clamped ground node has no coordinates, a pinned one keeps its slope's; labels.
TEST(AncfScene, SlopesClampAndPin) {
  const Scene clamped = readSceneText(chainScene(true), "chain.yaml");
  const Model& m = *clamped.model;
  EXPECT_EQ(m.n, 3 * 4);
  const VecX t1 = (VecX(2) << 1.0, 1.0).finished().normalized();
  EXPECT_LT((m.nodes[1].slope - t1).norm(), 1e-15);
  EXPECT_LT((m.nodes[2].slope - VecX::Unit(2, 1)).norm(), 1e-15);
  EXPECT_LT((m.nodes[0].slope - VecX::Unit(2, 0)).norm(), 1e-15);  // the end's chord direction
  EXPECT_EQ(m.coordinateLabel(0), "x(n1)");
  EXPECT_EQ(m.coordinateLabel(3), "y'(n1)");
  EXPECT_LT((m.initialPositions().segment(2, 2) - t1).norm(), 1e-15);
  const Scene pinned = readSceneText(chainScene(false), "chain.yaml");
  EXPECT_EQ(pinned.model->n, 3 * 4 + 2);
  EXPECT_EQ(pinned.model->coordinateLabel(0), "x'(A)");
  EXPECT_EQ(pinned.model->dof(0, 0), -1);
  EXPECT_EQ(pinned.model->dof(0, 2), 0);
}

// Gravity on an ANCF body is its weight: the y forces on the positions of a free straight
// chain sum to -rho A L g, the x forces and the slope forces of the whole body to zero.
TEST(AncfScene, GravityLoadIsTheWeight) {
  const Scene sc = readSceneText(
      "dimension: 2\ngravity: [0, -9.81]\nnodes:\n"
      "  - {name: a, position: [0, 0]}\n  - {name: b, position: [0.3, 0]}\n  - {name: c, position: [1, 0]}\n"
      "elements:\n  - {type: ancf_cable, nodes: [a, b, c], E: 2.0e11, density: 7850, section: {side: 0.01}}\n"
      "integrator: {type: trapezoidal, t_end: 0.1, dt: 0.01}\n",
      "free.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX Q = as.force(m.initialPositions(), VecX::Zero(m.n), m.nominalParameters());
  double fx = 0, fy = 0;
  for (int i = 0; i < 3; ++i) {
    fx += Q[m.dof(i, 0)];
    fy += Q[m.dof(i, 1)];
  }
  const double W = 7850 * 1e-4 * 1.0 * 9.81;  // [N]
  EXPECT_NEAR(fy / -W, 1.0, 1e-13);
  EXPECT_NEAR(fx, 0.0, 1e-13 * W);
}

// ------------------------------------------------------------------------ PIM: slopes
// Rigidizing an undeformed ANCF body also fixes its free slopes as directions in the body:
// what is left are the rigid motions, 3 in the plane; a straight spatial cable has 5 (a line
// of points has no rotation about itself, and the cable carries no torsion).
TEST(AncfRigidization, LeavesTheRigidMotions) {
  for (int dim : {2, 3}) {
    SCOPED_TRACE(dim);
    std::string text = dim == 2 ? chainScene(false) : chainScene(false, 3);
    // free the ground node: a body floating in space
    text.replace(text.find(", ground: true"), std::string(", ground: true").size(), "");
    if (dim == 3) {  // a straight spatial chain (the 3D cable needs a straight rest shape)
      text.replace(text.find("[1, 0, 0]"), 9, "[1, 1, 1]");
      text.replace(text.find("[1, 1, 0], slope: [0, 3, 0]"), 27, "[2, 2, 2], slope: [1, 1, 1]");
      text.replace(text.find("[1, 2, 0]"), 9, "[3, 3, 3]");
    }
    const Scene sc = readSceneText(text, "body.yaml");
    const Model& m = *sc.model;
    std::vector<int> all;
    for (int i = 0; i < 4; ++i) all.push_back(i);
    MatX X(dim, 4);
    for (int i = 0; i < 4; ++i) X.col(i) = m.nodes[i].position;
    RigidizeOptions withSlopes;
    withSlopes.slopes = true;  // an ANCF body
    Rigidization R = rigidize("c", all, m, X, "test", nullptr, withSlopes);
    int slopeRows = 0;
    for (const auto& c : R.constraints) slopeRows += c->kind() == "attached_slope" ? c->rows() : 0;
    EXPECT_EQ(slopeRows, 4 * dim);
    Assembler as(m, &R.constraints);
    const VecX q = m.initialPositions(), p = m.nominalParameters();
    EXPECT_LT(as.phi(q, p).lpNorm<Eigen::Infinity>(), 1e-12);  // undeformed: satisfied
    const MatX J = as.phiQDense(q, p);
    // FD check of the slope rows' Jacobian (linear, so FD is exact up to round-off)
    EXPECT_LT(relMax(fdJacobian([&](const VecX& x) { return as.phi(x, p); }, q), J), 1e-8);
    Eigen::FullPivLU<MatX> lu(J);
    lu.setThreshold(1e-10);
    EXPECT_EQ(m.n - lu.rank(), dim == 2 ? 3 : 5);
    EXPECT_EQ(lu.rank(), J.rows());  // no redundant equation
  }
}

// An SDOF may name a slope component ("x'"): its value is the slope's, its gradient the unit
// row of that coordinate.
TEST(AncfRigidization, SdofOnSlopeComponent) {
  const Scene sc = readSceneText(chainScene(false), "chain.yaml");
  const Model& m = *sc.model;
  LinearSdof z;
  z.terms.push_back({1, 3, 1.0});  // y'(n1)
  const VecX q = m.initialPositions();
  EXPECT_DOUBLE_EQ(z.value(m, q), m.nodes[1].slope[1]);
  const VecX g = z.gradient(m, q);
  EXPECT_EQ(g.sum(), 1.0);
  EXPECT_EQ(g[m.dof(1, 3)], 1.0);
}

// The example scene reads: 4 free nodes with position and slope, the pinned A's slope.
TEST(AncfScene, PendulumExampleReads) {
  const Scene sc = readScene(test::sourceDir() + "/examples/ancf/pendulum.yaml");
  EXPECT_EQ(sc.model->n, 4 * 4 + 2);
  EXPECT_EQ(sc.model->elements.size(), 4u);
}

// A PIM case rigidizes an ancf_cable (its slopes included) and names a slope component as SDOF.
TEST(AncfRigidization, SceneCaseWithSlopeSdof) {
  std::string text = chainScene(false);
  text += "parameters:\n  - {name: E_c, of: c, property: E}\n"
          "cases:\n  - {name: S1, parameters: [E_c], rigidize: [c], sdofs: [{node: n1, component: \"y'\"}]}\n";
  const Scene sc = readSceneText(text, "case.yaml", "S1");
  ASSERT_TRUE(sc.pimCase);
  ASSERT_EQ(sc.pimCase->sdofs.size(), 1u);
  EXPECT_EQ(sc.pimCase->sdofs[0]->name, "y'(n1)");
  int slopeRows = 0;
  for (const auto& c : sc.pimCase->lambda) slopeRows += c->kind() == "attached_slope" ? c->rows() : 0;
  EXPECT_EQ(slopeRows, 4 * 2);  // A (pinned: slope free), n1, n2, n3
}
