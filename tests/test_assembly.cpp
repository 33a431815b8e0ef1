// Finite-difference checks of every derivative the assembly path provides: element forces,
// constraint Jacobians and Hessians, parameter derivatives, and the integrators' systems.
#include <gtest/gtest.h>

#include "TestModels.hpp"
#include "constraints/Distance.hpp"
#include "core/Assembler.hpp"
#include "elements/RigidBar.hpp"
#include "integrators/Idas.hpp"
#include "integrators/InitialState.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {


VecX perturbed(const VecX& x, unsigned seed, double scale) {
  std::srand(seed);
  return x + scale * VecX::Random(x.size());
}

}  // namespace

static void checkForceJacobians(const Scene& sc) {
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  const VecX q = perturbed(sc.model->initialPositions(), 1, 0.1);
  const VecX v = perturbed(VecX::Zero(as.n()), 2, 1.0);
  SparseAccumulator kq, kv;
  kq.begin(as.n(), as.n());
  as.addForceJacobian(kq, q, v, p, -1.0, 0.0, 0, 0, 0);
  kv.begin(as.n(), as.n());
  as.addForceJacobian(kv, q, v, p, 0.0, -1.0, 0, 0, 0);
  const MatX fdq = fdJacobian([&](const VecX& x) { return as.force(x, v, p); }, q);
  const MatX fdv = fdJacobian([&](const VecX& x) { return as.force(q, x, p); }, v);
  EXPECT_LT(relErr(MatX(kq.finish()), fdq), 1e-7);
  EXPECT_LT(relErr(MatX(kv.finish()), fdv), 1e-7);
  EXPECT_GT(fdq.norm(), 1.0);  // the check is not vacuous
}

TEST(Assembly, ConservativeForceIsMinusPotentialGradient) {
  Scene sc = readSceneText(R"(
dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: n1, position: [1, 0.2]}
  - {name: n2, position: [1.5, -1]}
elements:
  - {type: rigid_bar, nodes: [A, n1], mass: 2}
  - {type: spring_damper, nodes: [n1, n2], stiffness: 40, natural_length: 0.7}
integrator: {type: idas, t_end: 1}
)", "conservative.yaml");
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  const VecX q = sc.model->initialPositions();
  const VecX zero = VecX::Zero(as.n());
  const MatX grad = fdJacobian([&](const VecX& x) { return VecX::Constant(1, as.potentialEnergy(x, p)); }, q);
  EXPECT_LT(relErr(as.force(q, zero, p), VecX(-grad.transpose())), 1e-8);
}

static void checkConstraintDerivatives(const Scene& sc) {
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  const VecX q = perturbed(sc.model->initialPositions(), 3, 0.1);
  const VecX w = perturbed(VecX::Zero(as.m()), 4, 1.0);
  const VecX v = perturbed(VecX::Zero(as.n()), 5, 1.0);
  SparseAccumulator J, H, R;
  J.begin(as.m(), as.n());
  as.addPhiQ(J, q, p, 1.0, 0, 0, false);
  const MatX fdJ = fdJacobian([&](const VecX& x) { return as.phi(x, p); }, q);
  EXPECT_LT(relErr(MatX(J.finish()), fdJ), 1e-8);
  // Transposed block equals the transpose.
  SparseAccumulator JT;
  JT.begin(as.n(), as.m());
  as.addPhiQ(JT, q, p, 1.0, 0, 0, true);
  EXPECT_LT(relErr(MatX(JT.finish()), MatX(fdJ.transpose())), 1e-8);
  // The residual's Phi and Phi_q^T w in one pass: Phi itself, and the transpose of the
  // differenced Jacobian times w.
  VecX phi, phiQTw;
  as.constraintTerms(q, p, w, phi, phiQTw);
  EXPECT_EQ(phi, as.phi(q, p));
  EXPECT_LT(relErr(phiQTw, VecX(fdJ.transpose() * w)), 1e-8);
  // Hessian contraction: d(Phi_q^T w)/dq.
  H.begin(as.n(), as.n());
  as.addHessian(H, q, p, w, 1.0, 0, 0);
  const MatX fdH = fdJacobian([&](const VecX& x) { return as.phiQTransposeTimes(x, p, w); }, q);
  EXPECT_LT(relErr(MatX(H.finish()), fdH), 1e-7);
  // Rows of d(Phi_q v)/dq.
  R.begin(as.m(), as.n());
  as.addHessianRows(R, q, p, v, 1.0, 0, 0);
  const MatX fdR = fdJacobian([&](const VecX& x) { return as.phiQTimes(x, p, v); }, q);
  EXPECT_LT(relErr(MatX(R.finish()), fdR), 1e-7);
  // Vector forms agree with the blocks.
  EXPECT_LT(relErr(as.hessianQuadratic(q, p, v), VecX(fdR * v)), 1e-7);
  EXPECT_LT(relErr(as.hessianTimes(q, p, w, v), VecX(fdH * v)), 1e-7);
}

static void checkParameterDerivatives(const Scene& sc) {
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  ASSERT_GE(p.size(), 8);
  const VecX q = perturbed(sc.model->initialPositions(), 6, 0.1);
  const VecX v = perturbed(VecX::Zero(as.n()), 7, 1.0);
  const VecX a = perturbed(VecX::Zero(as.n()), 8, 1.0);
  const VecX l = perturbed(VecX::Zero(as.m()), 9, 1.0);
  for (int k = 0; k < p.size(); ++k) {
    auto inP = [&](const std::function<VecX(const VecX&)>& f) -> VecX {
      return fdJacobian([&](const VecX& x) { VecX pp = p; pp[k] = x[0]; return f(pp); },
                        VecX::Constant(1, p[k])).col(0);
    };
    SCOPED_TRACE("parameter " + sc.model->parameters[k].name);
    EXPECT_LT(relErr(as.forceParamDerivative(q, v, p, k), inP([&](const VecX& pp) { return as.force(q, v, pp); })), 1e-7);
    EXPECT_LT(relErr(as.massParamDerivativeTimes(p, k, a), inP([&](const VecX& pp) { return VecX(as.mass(pp) * a); })), 1e-7);
    EXPECT_LT(relErr(as.phiParamDerivative(q, p, k), inP([&](const VecX& pp) { return as.phi(q, pp); })), 1e-7);
    EXPECT_LT(relErr(as.phiQParamDerivativeTimes(q, p, k, v), inP([&](const VecX& pp) { return as.phiQTimes(q, pp, v); })), 1e-7);
    EXPECT_LT(relErr(as.phiQParamDerivativeTransposeTimes(q, p, k, l),
                     inP([&](const VecX& pp) { return as.phiQTransposeTimes(q, pp, l); })), 1e-7);
    VecX phiP, phiQPTl;  // both in one pass, as the fixed-step sensitivity right-hand sides take them
    as.constraintParamTerms(q, p, k, l, phiP, phiQPTl);
    EXPECT_LT(relErr(phiP, inP([&](const VecX& pp) { return as.phi(q, pp); })), 1e-7);
    EXPECT_LT(relErr(phiQPTl, inP([&](const VecX& pp) { return as.phiQTransposeTimes(q, pp, l); })), 1e-7);
  }
}

/// pinMassless: with the velocity rows of constraints touching massless coordinates pinned
/// (mu_r = 0, as integrateIdas runs such models).
static void checkGglSystem(const Scene& sc, bool pinMassless = false) {
  Assembler as(*sc.model);
  const int n = as.n(), m = as.m(), N = 2 * (n + m);
  const VecX p = sc.model->nominalParameters();
  const SpMat M = as.mass(p);
  const std::vector<int> pinned = pinMassless ? gglPinnedRows(as, masslessCoordinates(as, p)) : std::vector<int>();
  if (pinMassless) EXPECT_FALSE(pinned.empty());
  VecX y = perturbed(VecX::Zero(N), 10, 1.0);
  y.head(n) = perturbed(sc.model->initialPositions(), 11, 0.1);
  const VecX yp = perturbed(VecX::Zero(N), 12, 1.0);
  const double cj = 37.0;
  SparseAccumulator acc;
  const MatX J = MatX(gglJacobian(as, p, y, cj, acc, pinned));
  const MatX Fy = fdJacobian([&](const VecX& x) { return gglResidual(as, p, M, x, yp, pinned); }, y);
  const MatX Fyp = fdJacobian([&](const VecX& x) { return gglResidual(as, p, M, y, x, pinned); }, yp);
  EXPECT_LT(relErr(J, MatX(Fy + cj * Fyp)), 1e-7);
  // The sensitivity residual is F_y s + F_y' s' + F_p.
  const VecX s = perturbed(VecX::Zero(N), 13, 1.0), sd = perturbed(VecX::Zero(N), 14, 1.0);
  for (int k = 0; k < p.size(); ++k) {
    const VecX Fp = fdJacobian([&](const VecX& x) {
      VecX pp = p; pp[k] = x[0];
      return gglResidual(as, pp, as.mass(pp), y, yp, pinned); }, VecX::Constant(1, p[k]));
    EXPECT_LT(relErr(gglSensitivityResidual(as, p, M, y, yp, k, s, sd, pinned), VecX(Fy * s + Fyp * sd + Fp)), 1e-7)
        << "parameter " << k;
  }
}

TEST(SparseAccumulator, ReusesPatternAndRebuildsWhenSequenceChanges) {
  SparseAccumulator acc;
  acc.begin(3, 3);
  acc.add(0, 0, 1.0); acc.add(2, 1, 2.0); acc.add(0, 0, 3.0);
  MatX A = MatX(acc.finish());
  EXPECT_EQ(A(0, 0), 4.0);
  EXPECT_EQ(A(2, 1), 2.0);
  acc.begin(3, 3);
  acc.add(0, 0, 5.0); acc.add(2, 1, 6.0); acc.add(0, 0, 7.0);
  A = MatX(acc.finish());
  EXPECT_EQ(A(0, 0), 12.0);
  EXPECT_EQ(A(2, 1), 6.0);
  acc.begin(3, 3);  // a different sequence
  acc.add(0, 0, 1.0); acc.add(1, 2, 8.0);
  A = MatX(acc.finish());
  EXPECT_EQ(A(0, 0), 1.0);
  EXPECT_EQ(A(1, 2), 8.0);
  EXPECT_EQ(A(2, 1), 0.0);
}

TEST(SparseAccumulator, BlocksReplayAndRebuildWhenTheSequenceChangesInsideABlock) {
  // addBlock's replay against a dense sum of the same blocks: the same blocks again (values
  // only), then a block whose map changes in its middle (the rest of it, and what follows,
  // recorded anew), then the new sequence replayed.
  const MatX B = (MatX(3, 3) << 1, 2, 3, 4, 5, 6, 7, 8, 9).finished();
  const std::vector<int> mapA = {0, -1, 2}, mapB = {3, 1, 2}, mapC = {3, 1, 0};
  SparseAccumulator acc;
  auto assemble = [&](const std::vector<int>& second, double s) {
    acc.begin(4, 4);
    acc.addBlock(mapA, mapA, B, s);
    acc.addBlock(second, mapA, B, 2.0 * s, 0, 0);
    acc.addBlock(mapB, second, B, -s);
    return MatX(acc.finish());
  };
  auto dense = [&](const std::vector<int>& second, double s) {
    MatX D = MatX::Zero(4, 4);
    auto put = [&](const std::vector<int>& rows, const std::vector<int>& cols, double f) {
      for (size_t j = 0; j < cols.size(); ++j)
        for (size_t i = 0; i < rows.size(); ++i)
          if (rows[i] >= 0 && cols[j] >= 0) D(rows[i], cols[j]) += f * B(Eigen::Index(i), Eigen::Index(j));
    };
    put(mapA, mapA, s);
    put(second, mapA, 2.0 * s);
    put(mapB, second, -s);
    return D;
  };
  EXPECT_EQ(assemble(mapB, 1.0), dense(mapB, 1.0));    // recorded
  EXPECT_EQ(assemble(mapB, 0.5), dense(mapB, 0.5));    // replayed
  EXPECT_EQ(assemble(mapC, 1.5), dense(mapC, 1.5));    // changed at the second block's third row
  EXPECT_EQ(assemble(mapC, -2.0), dense(mapC, -2.0));  // the new sequence replayed
  EXPECT_EQ(assemble(mapB, 3.0), dense(mapB, 3.0));    // and back
}

TEST(Assembly, ForceJacobiansMatchFiniteDifferences) {
  checkForceJacobians(mixedScene());
  checkForceJacobians(mixedScene3D());
}

TEST(Assembly, ConstraintJacobianAndHessiansMatchFiniteDifferences) {
  checkConstraintDerivatives(mixedScene());
  checkConstraintDerivatives(mixedScene3D());
}

TEST(Assembly, ParameterDerivativesMatchFiniteDifferences) {
  checkParameterDerivatives(mixedScene());
  checkParameterDerivatives(mixedScene3D());
}

TEST(Assembly, GglJacobianAndSensitivityResidualMatchFiniteDifferences) {
  checkGglSystem(mixedScene());
  checkGglSystem(mixedScene3D());
}

// A massless beam (inertia: none) carrying a mass, with a distance constraint on one of its
// massless nodes: that row's velocity-level GGL row is pinned (mu_r = 0) in IDAS.
TEST(Assembly, GglSystemWithMasslessPinnedRowsMatchesFiniteDifferences) {
  checkGglSystem(readSceneText(R"(
dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: root, position: [0, 0], ground: true}
  - {name: n1, position: [0.3, 0.05]}
  - {name: n2, position: [0.6, 0.1]}
  - {name: tip, position: [1, 0]}
  - {name: anchor, position: [1, -1], ground: true}
  - {name: above, position: [0.6, 1], ground: true}
elements:
  - {name: spring, type: beam, nodes: [root, n1, n2, tip], E: 1.0e6, inertia: none,
     section: {area: 1.0e-4, inertia: 1.0e-9}}
  - {name: mass, type: rigid_bar, nodes: [tip, anchor], mass: 3.0}
constraints:
  - {name: tie, type: distance, nodes: [n2, above]}
parameters:
  - {name: A, of: spring, property: area}
  - {name: m, of: mass, property: mass}
integrator: {type: idas, t_end: 1.0}
output: {directory: unused}
)", "massless_pinned.yaml"), true);
}

