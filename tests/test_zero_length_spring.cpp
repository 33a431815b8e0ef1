// Springs of zero natural length (natural_length: 0): the force k (x_b - x_a) is smooth also
// where the two nodes coincide, which a length-and-direction formula is not. Checked against
// the closed form (a linear spring to ground under a point load: x = F / k) and the Jacobian
// against central differences at and near coincidence.
#include <gtest/gtest.h>

#include "elements/RigidBar.hpp"
#include "integrators/Static.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;

namespace {
LocalState state(const VecX& x, const VecX& p) {
  LocalState s;
  s.dim = 2;
  s.x = x;
  s.v = VecX::Zero(4);
  s.p = &p;
  return s;
}
}  // namespace

TEST(ZeroLengthSpring, ForceAndJacobianAtAndNearCoincidence) {
  const double k = 250.0;  // [N/m]
  SpringDamper sp("bushing", 0, 1, {k, 0}, {0.0, -1}, {0.0, -1});
  const VecX p = VecX::Constant(1, k);
  for (const double gap : {0.0, 1e-13, 1e-3}) {
    VecX x(4);
    x << 0.3, -0.2, 0.3 + gap, -0.2 + 0.5 * gap;
    VecX Q;
    sp.force(state(x, p), Q);
    const VecX dx = x.tail(2) - x.head(2);
    EXPECT_LT((Q.head(2) - k * dx).norm(), 1e-12 * k) << gap;
    EXPECT_LT((Q.tail(2) + k * dx).norm(), 1e-12 * k) << gap;
    MatX Kq, Kv;
    sp.forceJacobian(state(x, p), Kq, Kv);
    MatX fd(4, 4);
    const double h = 1e-7;
    for (int j = 0; j < 4; ++j) {
      VecX xp = x, xm = x, Qp, Qm;
      xp[j] += h;
      xm[j] -= h;
      sp.force(state(xp, p), Qp);
      sp.force(state(xm, p), Qm);
      fd.col(j) = (Qp - Qm) / (2 * h);
    }
    EXPECT_LT((Kq - fd).lpNorm<Eigen::Infinity>(), 1e-6 * k) << "gap " << gap << "\n" << Kq << "\n" << fd;
    // the stiffness as a parameter: dQ/dk = dx
    VecX dQ;
    MatX dM;
    ASSERT_TRUE(sp.parameterDerivative(state(x, p), 0, dQ, dM));
    EXPECT_LT((dQ.head(2) - dx).norm(), 1e-15 + 1e-12 * dx.norm());
  }
}

TEST(ZeroLengthSpring, SceneStaticDeflectionIsForceOverStiffness) {
  const char* text = R"(dimension: 2
nodes:
  - {name: anchor, position: [1, 2], ground: true}
  - {name: p, position: [1, 2]}
elements:
  - {name: bushing, type: spring_damper, nodes: [anchor, p], stiffness: 400, natural_length: 0}
  - {name: pull, type: point_force, node: p, force: [3, -8]}
static: {load_steps: 1}
)";
  const Scene sc = readSceneText(text, "bushing.yaml");
  Assembler as(*sc.model);
  StaticSettings set;
  set.stepLoadFactor = true;
  set.steps = 1;
  const VecX q = solveStatic(as, sc.model->nominalParameters(), sc.model->initialPositions(), set);
  EXPECT_NEAR(q[0], 1.0 + 3.0 / 400.0, 1e-14);
  EXPECT_NEAR(q[1], 2.0 - 8.0 / 400.0, 1e-14);
}
