// `flexsens modes` (src/app/Modes.*): the constrained linearized eigenproblem against
//  (a) a fixed-fixed spring-mass chain (closed form of the tridiagonal pencil),
//  (b) the five-bar's tangent stiffness by finite differences of the residual Phi_q^T lambda - Q,
//      and its eigenvalues against the pencil built from that finite-difference matrix,
//  (c) the command line: report contents, JSON, and the error for redundant constraints.
// The cantilever's beta_n L check lives in test_cantilever.cpp (it reuses that fixture).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "TestModels.hpp"
#include "app/Modes.hpp"
#include "app/Run.hpp"
#include "elements/RigidBar.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

/// N point masses (rigid_bar of mass 3 Mp to a ground node: M = Mp on the free node) on the
/// x axis at 1 m spacing between two ground nodes, N + 1 springs k [N/m] at natural length.
std::unique_ptr<Model> springChain(int N, double k, double Mp) {
  auto m = std::make_unique<Model>();
  m->dim = 2;
  m->gravity = VecX::Zero(2);
  auto node = [&](const std::string& name, double x, double y, bool ground) {
    Node nd;
    nd.name = name;
    nd.position = (VecX(2) << x, y).finished();
    nd.velocity = VecX::Zero(2);
    nd.ground = ground;
    m->nodes.push_back(nd);
    return static_cast<int>(m->nodes.size()) - 1;
  };
  std::vector<int> chain{node("left", 0, 0, true)};
  for (int i = 1; i <= N; ++i) chain.push_back(node("n" + std::to_string(i), i, 0, false));
  chain.push_back(node("right", N + 1, 0, true));
  for (int i = 1; i <= N; ++i) {
    const int anchor = node("g" + std::to_string(i), i, -1, true);
    m->elements.push_back(std::make_unique<RigidBar>("mass" + std::to_string(i), chain[i], anchor,
                                                     Quantity{3.0 * Mp, -1}));
  }
  for (int i = 0; i <= N; ++i)
    m->elements.push_back(std::make_unique<SpringDamper>("spring" + std::to_string(i), chain[i], chain[i + 1],
                                                         Quantity{k, -1}, Quantity{0.0, -1}, Quantity{1.0, -1}));
  m->finalize();
  return m;
}

}  // namespace

// (a) omega_j = 2 sqrt(k/M) sin(j pi / (2 (N + 1))): the axial modes. The transverse (y)
// directions carry mass but no stiffness at natural length: N zero modes, reported rigid.
// Energy: each eigenmode holds as much strain as kinetic energy (springs vs masses).
TEST(Modes, SpringMassChainMatchesClosedForm) {
  const int N = 7;
  const double k = 250.0, Mp = 2.0;
  auto model = springChain(N, k, Mp);
  Assembler as(*model);
  const VecX p(0);
  const State s = consistentState(as, p);
  const ModalAnalysis a = analyzeModes(as, s, p, N);
  ASSERT_EQ(static_cast<int>(a.modes.size()), 2 * N);
  EXPECT_EQ(a.tangent, 2 * N);
  EXPECT_EQ(a.massless, 0);
  for (int j = 0; j < N; ++j) {
    EXPECT_TRUE(a.modes[j].rigid);
    EXPECT_NEAR(a.modes[j].omega2, 0.0, 1e-9);
  }
  for (int j = 1; j <= N; ++j) {
    const Mode& md = a.modes[N + j - 1];
    const double exact = 2.0 * std::sqrt(k / Mp) * std::sin(j * M_PI / (2.0 * (N + 1)));
    EXPECT_NEAR(md.omega(), exact, 1e-9 * exact) << "mode " << j;
    double strain = 0, kinetic = 0;
    for (const auto& sh : md.parts) {
      strain += sh.strain;
      kinetic += sh.kinetic;
      if (sh.part.rfind("spring", 0) == 0) EXPECT_EQ(sh.kinetic, 0.0);
      if (sh.part.rfind("mass", 0) == 0) EXPECT_NEAR(sh.strain, 0.0, 1e-12);
    }
    EXPECT_NEAR(strain, 0.5, 1e-9);
    EXPECT_NEAR(kinetic, 0.5, 1e-9);
  }
  // The lowest axial mode is symmetric: the middle mass carries the largest kinetic share.
  const EnergyShare* most = nullptr;
  for (const auto& sh : a.modes[N].parts)
    if (!most || sh.kinetic > most->kinetic) most = &sh;
  ASSERT_NE(most, nullptr);
  EXPECT_EQ(most->part, "mass" + std::to_string((N + 1) / 2));
}

// (b) The five-bar (flexible: beam, springs, rigid bars, gravity, n = 8, m = 3) at its initial
// state, which is not an equilibrium (lambda != 0 from gravity).
TEST(Modes, FiveBarLinearizationMatchesFiniteDifferencesOfTheResidual) {
  Scene sc = readScene(sourceDir() + "/examples/fivebar/flexible.yaml");
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  const State s = consistentState(as, p);
  ASSERT_GT(s.lambda.norm(), 1.0);  // the multiplier term is exercised
  // Residual of the equations of motion at fixed v, lambda: R(q) = Phi_q^T lambda - Q(q, v).
  auto R = [&](const VecX& q) -> VecX {
    return as.phiQTransposeTimes(q, p, s.lambda) - as.force(q, s.v, p);
  };
  const MatX Kfd = fdJacobian(R, s.q, 1e-6);
  const MatX K = tangentStiffness(as, s, p);
  EXPECT_LT((K - Kfd).norm(), 1e-6 * K.norm()) << "K:\n" << K << "\nFD:\n" << Kfd;
  // Eigenvalues from the finite-difference matrix on the null space of Phi_q (an SVD basis).
  Eigen::JacobiSVD<MatX> svd(as.phiQDense(s.q, p), Eigen::ComputeFullV);
  const MatX Nb = svd.matrixV().rightCols(as.n() - as.m());
  const MatX Kr = Nb.transpose() * (0.5 * (Kfd + Kfd.transpose())) * Nb;
  const MatX Mr = Nb.transpose() * MatX(as.mass(p)) * Nb;
  Eigen::GeneralizedSelfAdjointEigenSolver<MatX> ges(Kr, Mr);
  const ModalAnalysis a = analyzeModes(as, s, p, 2);
  ASSERT_EQ(static_cast<int>(a.modes.size()), as.n() - as.m());
  for (int j = 0; j < ges.eigenvalues().size(); ++j) {
    std::printf("  mode %d: omega^2 = %.10e (FD pencil %.10e)\n", j + 1, a.modes[j].omega2, ges.eigenvalues()[j]);
    EXPECT_NEAR(a.modes[j].omega2, ges.eigenvalues()[j], 1e-6 * ges.eigenvalues().cwiseAbs().maxCoeff());
  }
}

// ---------------------------------------------------------------------- (c) command line
namespace {
struct Cli {
  int status = -1;
  std::string out, err;
};
Cli runModes(const std::string& args) {
  const std::string base = testing::TempDir() + "flexsens_modes_" + std::to_string(::getpid());
  const std::string cmd = std::string(FLEXSENS_EXE) + " modes " + args + " >" + base + ".out 2>" + base + ".err";
  Cli r;
  const int st = std::system(cmd.c_str());
  r.status = (st != -1 && WIFEXITED(st)) ? WEXITSTATUS(st) : -1;
  auto slurp = [](const std::string& f) {
    std::ifstream in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    std::remove(f.c_str());
    return ss.str();
  };
  r.out = slurp(base + ".out");
  r.err = slurp(base + ".err");
  return r;
}
}  // namespace

TEST(ModesCli, ReportsFrequenciesTimeStepsAndParts) {
  const Cli r = runModes(sourceDir() + "/examples/fivebar/flexible.yaml --count 2");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* s : {"n = 8 coordinates, m = 3", "lowest elastic modes:", "highest modes:",
                        "maggi_rk4 (explicit RK4) is stable for dt <", "beam_12", "suggestion:"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s << " missing in:\n" << r.out;
  const Cli j = runModes(sourceDir() + "/examples/fivebar/flexible.yaml --json");
  ASSERT_EQ(j.status, 0) << j.err;
  EXPECT_NE(j.out.find("\"maggi_rk4_dt_max\""), std::string::npos) << j.out;
  EXPECT_EQ(j.out.find("lowest elastic modes"), std::string::npos);
}

// Redundant constraints: the reader leaves the dependent row out (core/RedundantRows), so the
// pendulum held twice is a pendulum; `modes` says which row went. Its one mode: the bar
// (mass 1 kg, L = 1 m, horizontal, released) has K = lambda Phi_qq on the tangent space.
TEST(ModesCli, RedundantConstraintsAreLeftOutAndNamed) {
  const Cli r = runModes(sourceDir() + "/tests/scenes/modes/redundant_constraints.yaml");
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.err.find("left out:"), std::string::npos) << r.err;
  EXPECT_TRUE(r.err.find("again") != std::string::npos || r.err.find("bar") != std::string::npos) << r.err;
}
