// Massless parts (beam key `inertia: none`): the free nodes' rows of M are zero and their
// equations of motion are equilibrium equations.
//  (a) a massless 4-segment beam between a ground node and a 1 kg mass: the axial oscillation
//      x(t) = L + (v0 / omega) sin(omega t), omega = sqrt(EA / (L M)), its derivative with
//      respect to the section area A in closed form and by central finite differences of runs; IDAS and the
//      trapezoidal rule; `modes` gives omega with the six massless coordinates condensed;
//  (b) a massless cantilever under a tip load: the dynamic run (bdf1, trapezoidal) stays at the
//      static solver's equilibrium, and its sensitivity to the load matches finite differences
//      of static solutions;
//  (c) a massless node without stiffness in some direction is a named error; maggi_rk4 refuses.
#include <gtest/gtest.h>

#include <cmath>

#include "TestModels.hpp"
#include "app/Modes.hpp"
#include "app/Run.hpp"
#include "elements/Beam.hpp"
#include "elements/PointForce.hpp"
#include "integrators/InitialState.hpp"
#include "integrators/Static.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

// EA = 1e6 Pa * 1e-4 m^2 = 100 N, L = 1 m, tip mass M = m_bar / 3 = 1 kg: omega = 10 rad/s.
constexpr double kEA = 100.0, kM = 1.0, kV0 = 0.01, kOmega = 10.0;

Scene massOnMasslessBeam() {
  return readSceneText(R"(
dimension: 2
gravity: [0, 0]
nodes:
  - {name: root, position: [0, 0], ground: true}
  - {name: n1, position: [0.25, 0]}
  - {name: n2, position: [0.5, 0]}
  - {name: n3, position: [0.75, 0]}
  - {name: tip, position: [1, 0], velocity: [0.01, 0]}
  - {name: anchor, position: [1, -1], ground: true}
elements:
  - {name: spring, type: beam, nodes: [root, n1, n2, n3, tip], E: 1.0e6, inertia: none,
     section: {area: 1.0e-4, inertia: 1.0e-9}}
  - {name: mass, type: rigid_bar, nodes: [tip, anchor], mass: 3.0}
parameters:
  - {name: A, of: spring, property: area}
integrator: {type: idas, t_end: 1.0}
output: {directory: unused}
)", "massless_spring.yaml");
}

/// Runs from the consistent initial state (with sensitivities) to t_end; returns the last frame.
StateWithSens runTo(const Scene& sc, const IntegratorSettings& set) {
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  const StateWithSens start = initialState(as, p);
  Recorder rec;
  integrate(as, p, start, set, rec);
  return rec.frames.back();
}

}  // namespace

TEST(Massless, SceneKeyMakesTheBeamsFreeNodesMassless) {
  const Scene sc = massOnMasslessBeam();
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  const std::vector<int> mc = masslessCoordinates(as, p);
  ASSERT_EQ(mc.size(), 6u);  // n1, n2, n3 (x, y); the tip has the bar's mass
  for (int i : mc) EXPECT_NE(sc.model->coordinateLabel(i).find("(n"), std::string::npos);
  // Quasi-static start: the interior nodes move with the tip, v_i = v0 i / 4.
  const State s = consistentState(as, p);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(s.v[2 * i], kV0 * (i + 1) / 4.0, 1e-14);
  // Modes: one elastic mode (the tip's y is held by the bar to first order), six condensed.
  const ModalAnalysis a = analyzeModes(as, s, p, 1);
  EXPECT_EQ(a.massless, 6);
  ASSERT_EQ(a.modes.size(), 1u);
  // (to 1e-6: the tip's initial speed puts a centripetal force m v0^2 / R = 1e-4 N in the bar's
  // constraint, whose lambda Phi_qq term shifts omega by ~5e-7 relative)
  EXPECT_NEAR(a.modes[0].omega(), std::sqrt(kEA / kM), 1e-6 * kOmega);
}

TEST(Massless, SpringMassOscillationAndItsDerivativeMatchClosedForm) {
  const Scene sc = massOnMasslessBeam();
  const double T = 1.0, A = 1.0e-4;
  const double x = 1.0 + kV0 / kOmega * std::sin(kOmega * T);
  // d x / d A = v0 (T cos(w T) / w - sin(w T) / w^2) dw/dA, dw/dA = w / (2 A)   [m/m^2]
  const double dxdA = kV0 * (T * std::cos(kOmega * T) / kOmega - std::sin(kOmega * T) / (kOmega * kOmega)) *
                      kOmega / (2.0 * A);
  for (const char* type : {"idas", "trapezoidal"}) {
    IntegratorSettings set = integratorSettings(type, std::string(type) == "idas" ? 1e-9 : 1e-4, T);
    const StateWithSens f = runTo(sc, set);
    const int tip = sc.model->dof(sc.model->nodeIndex("tip"), 0);
    std::printf("  %-12s x_tip = %.10f (exact %.10f), dx/dA = %.6e (exact %.6e)\n", type, f.x.q[tip], x,
                f.dp[0].q[tip], dxdA);
    // amplitude 1e-3 m; the bar's circle adds ~ amplitude^2 / 2 = 5e-7 m of geometry
    EXPECT_NEAR(f.x.q[tip], x, 2e-6 * kV0 / kOmega * 1e3) << type;
    EXPECT_NEAR(f.dp[0].q[tip], dxdA, 2e-3 * std::abs(dxdA)) << type;
    // Central finite differences of whole runs: the fixed-step scheme's sensitivity is the exact
    // derivative of its discrete map (IDAS' adaptive steps would make run differences noisy).
    if (std::string(type) == "idas") continue;
    Scene plus = massOnMasslessBeam(), minus = massOnMasslessBeam();
    const double h = 1e-3 * A;  // truncation ~ (w T h / 2A)^2 = 2.5e-5, round-off ~1e-5 relative
    plus.model->parameters[0].nominal += h;
    minus.model->parameters[0].nominal -= h;
    const double fd = (runTo(plus, set).x.q[tip] - runTo(minus, set).x.q[tip]) / (2 * h);
    EXPECT_NEAR(f.dp[0].q[tip], fd, 1e-4 * std::abs(dxdA)) << type;
  }
}

namespace {

/// Massless positions-only cantilever (N segments of 1/N m, clamped by two ground nodes) with a
/// tip load (0, Fy), Fy = parameter 0 [N]. EI = 1 N m^2, EA = 1e4 N.
std::unique_ptr<Model> masslessCantilever(int N, std::shared_ptr<BeamSection>& sec) {
  auto m = std::make_unique<Model>();
  m->dim = 2;
  m->gravity = VecX::Zero(2);
  sec = std::make_shared<BeamSection>();
  sec->E.constant = 1e4;
  sec->area.constant = 1.0;
  sec->inertia.constant = 1e-4;
  sec->massless = true;
  const double h = 1.0 / N;
  auto node = [&](const std::string& name, double x, bool ground) {
    Node nd;
    nd.name = name;
    nd.position = (VecX(2) << x, 0.0).finished();
    nd.velocity = VecX::Zero(2);
    nd.ground = ground;
    m->nodes.push_back(nd);
  };
  node("ghost", -h, true);
  node("root", 0.0, true);
  for (int i = 1; i <= N; ++i) node("n" + std::to_string(i), i * h, false);
  for (int i = 0; i < N; ++i)
    m->elements.push_back(std::make_unique<BeamSegment>("beam.segment" + std::to_string(i),
                                                        std::vector<int>{i + 1, i + 2}, sec, h));
  for (int i = 0; i < N; ++i) {
    const std::vector<int> nd{i, i + 1, i + 2};
    VecX rest(6);
    for (int j = 0; j < 3; ++j) rest.segment<2>(2 * j) = m->nodes[nd[j]].position;
    m->elements.push_back(std::make_unique<BeamHinge>("beam.hinge" + std::to_string(i), nd, sec, rest,
                                                      i == 0 ? h / 2 : 0.0));
  }
  Quantity fx, fy;
  fy.param = 0;
  m->elements.push_back(std::make_unique<PointForce>("load", N + 1, std::vector<Quantity>{fx, fy}));
  m->parameters.push_back({"Fy", 0.5, "load.y"});
  m->finalize();
  return m;
}

}  // namespace

TEST(Massless, LoadedMasslessBeamInADynamicRunIsTheStaticSolution) {
  std::shared_ptr<BeamSection> sec;
  auto model = masslessCantilever(8, sec);
  Assembler as(*model);
  const VecX p = model->nominalParameters();  // Fy = 0.5 N: tip rotation ~0.24 rad
  StaticSettings ss;
  ss.paramsAt = linearLoadPath(VecX::Zero(1), p);
  const VecX qs = solveStatic(as, p, model->initialPositions(), ss);
  auto qStatic = [&](double Fy) {
    const VecX pp = VecX::Constant(1, Fy);
    StaticSettings s2;
    s2.paramsAt = linearLoadPath(VecX::Zero(1), pp);
    return solveStatic(as, pp, model->initialPositions(), s2);
  };
  const double h = 1e-6;
  const VecX dqFd = (qStatic(0.5 + h) - qStatic(0.5 - h)) / (2 * h);
  ASSERT_EQ(masslessCoordinates(as, p).size(), static_cast<size_t>(as.n()));
  {  // IDAS needs a differential variable: a model without any mass is refused, by name
    Recorder rec;
    EXPECT_THROW(integrate(as, p, initialState(as, p), integratorSettings("idas", 1e-8, 1.0), rec), InputError);
  }
  for (const char* type : {"bdf1", "trapezoidal"}) {
    const StateWithSens start = initialState(as, p);
    EXPECT_LT((start.x.q - qs).lpNorm<Eigen::Infinity>(), 1e-10) << "consistent start";
    Recorder rec;
    integrate(as, p, start, integratorSettings(type, 0.1, 1.0), rec);
    const StateWithSens& f = rec.frames.back();
    EXPECT_NEAR(f.x.t, 1.0, 1e-12);
    EXPECT_LT((f.x.q - qs).lpNorm<Eigen::Infinity>(), 1e-9) << type;
    EXPECT_LT((f.dp[0].q - dqFd).lpNorm<Eigen::Infinity>(), 1e-6 * dqFd.lpNorm<Eigen::Infinity>()) << type;
  }
}

TEST(Massless, NodeWithoutMassOrStiffnessIsANamedError) {
  // A two-node massless beam hanging from a ground node with a free end: the end has axial
  // stiffness only; nothing holds it transversally. The reader finds the null direction of
  // [K; C; Phi_q] on the massless coordinates (core/ModelChecks): an input error at the node,
  // raised by run, check and modes (the scene itself reads, for derivative-only uses).
  const Scene sc = readSceneText(R"(
dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: loose, position: [1, 0]}
elements:
  - {name: rope, type: beam, nodes: [A, loose], E: 1.0e6, inertia: none, section: {area: 1.0e-4, inertia: 1.0e-9}}
integrator: {type: bdf1, t_end: 1.0, dt: 0.01}
output: {directory: unused}
)", "loose.yaml");
  try {
    runScene(sc, testing::TempDir() + "flexsens_loose");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("loose.yaml:6:"), std::string::npos) << w;
    EXPECT_NE(w.find("y(loose)"), std::string::npos) << w;
  }
}

TEST(Massless, ExplicitSchemeRefusesMasslessParts) {
  const Scene sc = massOnMasslessBeam();
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  Recorder rec;
  EXPECT_THROW(integrate(as, p, initialState(as, p), integratorSettings("maggi_rk4", 1e-3, 0.01), rec),
               InputError);
}

// The stability measure of the run's health (masslessStability): a massless two-segment strut
// between a ground node and a massed tip, its middle node free. Pushing the tip in by delta
// compresses both segments by delta / 2 (axial force N = EA delta / (2 l)), which lowers the
// middle node's transverse stiffness by the geometric term 2 N / l: the strut buckles once
// that exceeds its bending stiffness. Reference: the stiffness by central differences of the
// assembled force, and the geometric term in closed form.
TEST(Massless, StabilityOfACompressedMasslessStrutMatchesFiniteDifferencesAndBuckles) {
  const Scene sc = readSceneText(R"(
dimension: 2
gravity: [0, 0]
nodes:
  - {name: root, position: [0, 0], ground: true}
  - {name: mid, position: [1, 0]}
  - {name: tip, position: [2, 0]}
  - {name: anchor, position: [2, -1], ground: true}
elements:
  - {name: strut, type: beam, nodes: [root, mid, tip], E: 1.0e6, inertia: none,
     section: {area: 1.0e-4, inertia: 1.0e-9}}
  - {name: mass, type: rigid_bar, nodes: [tip, anchor], mass: 3.0}
integrator: {type: idas, t_end: 1.0}
output: {directory: unused}
)", "strut.yaml");
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  const std::vector<int> mc = masslessCoordinates(as, p);
  ASSERT_EQ(mc.size(), 2u);  // mid's x and y
  const int tipX = sc.model->nodes[sc.model->nodeIndex("tip")].firstDof;
  auto stiffnessAt = [&](double delta, Eigen::Vector2d& eigFd, MasslessStability& ms) {
    State s;
    s.q = sc.model->initialPositions();
    s.q[tipX] -= delta;
    s.q[mc[0]] -= delta / 2;
    s.v = VecX::Zero(as.n());
    s.lambda = VecX::Zero(as.m());
    ms = masslessStability(as, s, p, mc);
    Eigen::Matrix2d K;
    const double h = 1e-7;
    for (int j = 0; j < 2; ++j) {
      VecX qp = s.q, qm = s.q;
      qp[mc[j]] += h;
      qm[mc[j]] -= h;
      const VecX dQ = (as.force(qp, s.v, p) - as.force(qm, s.v, p)) / (2 * h);
      for (int i = 0; i < 2; ++i) K(i, j) = -dQ[mc[i]];
    }
    eigFd = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(0.5 * (K + K.transpose())).eigenvalues();
    return K;
  };
  Eigen::Vector2d e0, e1;
  MasslessStability s0, s1;
  const Eigen::Matrix2d K0 = stiffnessAt(1e-7, e0, s0);
  const Eigen::Matrix2d K1 = stiffnessAt(1e-3, e1, s1);
  std::printf("  strut: transverse stiffness %.6g N/m (delta 1e-7 m), %.6g N/m (delta 1e-3 m); measure %.6g, %.6g\n",
              K0(1, 1), K1(1, 1), s0.minEigenvalue, s1.minEigenvalue);
  EXPECT_NEAR(s0.minEigenvalue, e0[0], 1e-6);  // [N/m], of ~4e-3 (bending) and 200 (axial)
  EXPECT_NEAR(s0.maxEigenvalue, e0[1], 1e-6 * e0[1]);
  EXPECT_NEAR(s1.minEigenvalue, e1[0], 1e-6);
  EXPECT_GT(s0.minEigenvalue, 0.0);  // nearly straight and unloaded: stable
  EXPECT_LT(s1.minEigenvalue, 0.0);  // compressed beyond the critical load: buckles
  EXPECT_EQ(s1.coordinate, sc.model->coordinateLabel(mc[1]));  // softest sideways (y)
  // The transverse stiffness dropped by the geometric term 2 N / l, N = EA (delta / 2) / l:
  // 100 N * 5e-4 * 2 / 1 m = 0.1 N/m (the bending part changes by O(delta) relative).
  EXPECT_NEAR(K0(1, 1) - K1(1, 1), 0.1, 0.002);
}
