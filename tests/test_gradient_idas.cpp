// flexsens gradient on integrator idas (app/IdasGradient.hpp, integrators/IdasAdjoint.hpp): the
// continuous adjoint against IDAS' forward sensitivities (the same continuous objectives, to a
// tolerance tied to rtol) and against central differences of whole IDAS runs at a tighter
// tolerance whose objectives the test integrates itself (Simpson's rule on 1 ms frames), for a
// rigid pendulum whose PIM case gives non-zero initial sensitivities and an ANCF cable pendulum;
// terminal objectives at t_end (the adjoint's terminal condition); and the refusals (a
// terminal objective before t_end, massless coordinates).
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include "GradientChecks.hpp"
#include "app/Gradient.hpp"
#include "app/ParameterValues.hpp"
#include "integrators/Idas.hpp"

namespace flexsens {
namespace {

const char* kPendulum = R"(dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: A,   position: [0, 0], ground: true}
  - {name: tip, position: [0.8, 0.6]}
  - {name: B,   position: [0.5, -0.5], ground: true}
elements:
  - {name: bar, type: rigid_bar, nodes: [A, tip], mass: 1.0}
  - {name: spring, type: spring_damper, nodes: [B, tip], stiffness: 20.0, damping: 0.3}
parameters:
  - {name: L, of: bar, property: length}
  - {name: k, of: spring, property: stiffness}
cases:
  - name: same_x
    parameters: [L, k]
    sdofs: [{node: tip, component: x}]
integrator: {type: idas, t_end: 1.0, rtol: 1.0e-8, atol: 1.0e-10, frame_interval: 1.0e-3}
outputs:
  - {name: tip_x, node: tip, component: x}
  - {name: tip_y, node: tip, component: y}
  - {name: tip_vy, node: tip, component: y, quantity: velocity}
objectives:
  - {name: y_sq, integral: {output: tip_y, power: 2}}
  - {name: x_track, tracking: {output: tip_x, target: {type: linear, slope: 0.2}, from: 0.2, to: 0.8}}
  - {name: y_low, max: {output: tip_y, rho: 10}}
  - {name: mix, sum: [{objective: y_sq, weight: 2}, {objective: y_low, weight: -1}]}
)";

GradientResult gradients(const Scene& sc, const std::string& method, const std::string& objective = "") {
  return test::gradients(sc, method, 0, objective);
}
using test::worstRelative;

/// The outputs at every frame of a plain IDAS run.
class Frames : public Observer {
 public:
  explicit Frames(const Scene& sc) : sc_(sc) {}
  void frame(const StateWithSens& s) override {
    times.push_back(s.x.t);
    std::vector<double> row;
    for (const auto& o : sc_.outputs) row.push_back(o.value(*sc_.model, s.x));
    values.push_back(row);
  }
  std::vector<double> times;
  std::vector<std::vector<double>> values;

 private:
  const Scene& sc_;
};

/// Simpson's rule of f over the frames i0 ... i1 (an even count of equal intervals h).
struct FrameTable {
  std::vector<double> times;
  std::vector<std::vector<double>> values;  ///< per frame, the outputs
};

template <class F>
double simpson(const FrameTable& fr, size_t i0, size_t i1, F f) {
  const double h = (fr.times[i1] - fr.times[i0]) / double(i1 - i0);
  double s = f(i0) + f(i1);
  for (size_t i = i0 + 1; i < i1; ++i) s += (i - i0) % 2 ? 4 * f(i) : 2 * f(i);
  return s * h / 3;
}

/// The pendulum's outputs at the 1 ms frames of a whole IDAS run at parameter k moved by d
/// (rtol 1e-11).
FrameTable accurateRun(const std::string& caseName, int k, double d) {
  Scene sc = readSceneText(kPendulum, "pendulum.yaml", caseName);
  const VecX p0 = sc.model->nominalParameters();
  applyParameterValues(sc, {{sc.model->parameters[size_t(k)].name, p0[k] + d}});
  sc.integrator.rtol = 1e-11;
  sc.integrator.atol = 1e-13;
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  StateWithSens start;
  start.x = initialState(as, p, sc.pimCase.get()).x;
  Frames fr(sc);
  integrateIdas(as, p, start, sc.integrator, fr);
  return {fr.times, fr.values};
}

/// The pendulum's four objectives from a whole IDAS run at parameter k moved by d (rtol 1e-11),
/// integrated here from the 1 ms frames: y_sq, x_track, y_low (the KS mean), mix.
std::vector<double> objectivesOfRun(const std::string& caseName, int k, double d) {
  const FrameTable fr = accurateRun(caseName, k, d);
  EXPECT_EQ(fr.times.size(), 1001u);
  const auto& v = fr.values;
  const double ySq = simpson(fr, 0, 1000, [&](size_t i) { return v[i][1] * v[i][1]; });
  const double track = simpson(fr, 200, 800, [&](size_t i) {
    const double e = v[i][0] - 0.2 * fr.times[i];
    return e * e;
  });
  double m = -1e300;
  for (const auto& row : v) m = std::max(m, row[1]);
  const double ks = m + std::log(simpson(fr, 0, 1000, [&](size_t i) { return std::exp(10 * (v[i][1] - m)); })) / 10;
  return {ySq, track, ks, 2 * ySq - ks};
}

/// Output `output` at frame `frame` of a whole IDAS run at parameter k moved by d (rtol 1e-11).
double outputAtFrame(const std::string& caseName, int k, double d, size_t frame, size_t output) {
  return accurateRun(caseName, k, d).values.at(frame)[output];
}

void checkPendulum(const std::string& caseName) {
  const Scene sc = readSceneText(kPendulum, "pendulum.yaml", caseName);
  const GradientResult fw = gradients(sc, "forward"), adj = gradients(sc, "adjoint");
  ASSERT_EQ(adj.objectives.size(), 4u);
  // The two runs step differently (the forward one's error test includes the sensitivities):
  // values and gradients agree to the integration tolerance (rtol 1e-8), not to round-off.
  for (size_t i = 0; i < 4; ++i) EXPECT_NEAR(adj.objectives[i].value, fw.objectives[i].value, 1e-7 * std::abs(fw.objectives[i].value));
  EXPECT_LT(worstRelative(adj, fw, 1e-3), 100 * sc.integrator.rtol) << caseName;
  EXPECT_GT(adj.adjoint.backwardSteps, 0);
  EXPECT_GE(adj.adjoint.checkpoints, 1);
  // Relative step 3e-5: the central difference's truncation error was 7e-4 at 1e-3 and 7e-6 at
  // 1e-4 (O(d^2)); the runs' own error, ~rtol 1e-11, adds ~1e-11 / d.
  for (int k = 0; k < 2; ++k) {
    const double d = 3e-5 * sc.model->nominalParameters()[k];
    const std::vector<double> plus = objectivesOfRun(caseName, k, d), minus = objectivesOfRun(caseName, k, -d);
    for (size_t i = 0; i < 4; ++i) {
      const double nd = (plus[i] - minus[i]) / (2 * d);
      EXPECT_NEAR(adj.objectives[i].gradient[k], nd, 1e-5 * std::max(std::abs(nd), 1e-2))
          << caseName << " " << adj.objectives[i].name << " d/d" << sc.model->parameters[size_t(k)].name;
    }
  }
}

// The PIM case moves the start along the motion (the tip's x kept, dq0/dL not along the bar):
// the initial-condition term (F_y'^T yB)(t0) . dy0/dp is part of the gradient; the least-norm
// rule moves it along the bar, where the adjoint is orthogonal to it (Phi_q yB_q = 0).
TEST(GradientIdas, PendulumAdjointEqualsForwardAndDifferencesPimCase) { checkPendulum("same_x"); }
TEST(GradientIdas, PendulumAdjointEqualsForwardAndDifferencesLeastNorm) { checkPendulum(""); }

TEST(GradientIdas, CheckpointsEveryFewStepsGiveTheSameGradient) {
  // Every 20 IDAS steps a checkpoint (IDAS recomputes each interval from its checkpoint in the
  // backward pass) against one interval for the whole run. A checkpoint changes IDAS' forward
  // steps (441 steps against 529 here), so the gradients agree to the tolerance (measured
  // 2.7e-7 at rtol 1e-8), not to round-off.
  const Scene sc = readSceneText(kPendulum, "pendulum.yaml", "same_x");
  GradientRequest req;
  const GradientResult whole = computeGradients(sc, req);
  req.checkpointEvery = 20;
  const GradientResult every20 = computeGradients(sc, req);
  EXPECT_EQ(whole.adjoint.checkpoints, 1);
  EXPECT_EQ(every20.adjoint.checkpointEvery, 20);
  EXPECT_GT(every20.adjoint.checkpoints, every20.steps / 20 - 1);
  EXPECT_LT(worstRelative(every20, whole, 1e-3), 100 * sc.integrator.rtol);
}

TEST(GradientIdas, AncfCablePendulumAdjointEqualsForward) {
  // The flexible cable of examples/ancf/pendulum.yaml (E, density) for 0.3 s at rtol 1e-8.
  std::ifstream in(std::string(FLEXSENS_SOURCE_DIR) + "/examples/ancf/pendulum.yaml");
  std::stringstream text;
  text << in.rdbuf();
  Scene sc = readSceneText(text.str() + R"(
parameters:
  - {name: E, of: rod, property: E}
  - {name: rho, of: rod, property: density}
objectives:
  - {name: y_sq, integral: {output: y_tip, power: 2}}
  - {name: x_track, tracking: {output: x_tip, target: {type: linear, slope: 0.2}, from: 0.1, to: 0.25}}
  - {name: y_low, max: {output: y_tip, rho: 10}}
  - {name: y_end, terminal: {output: y_tip}}
)", "pendulum.yaml", "");
  RunOptions opt;
  opt.integrator = "idas";
  opt.tEnd = 0.3;
  applyOptions(sc, opt);
  const GradientResult fw = gradients(sc, "forward"), adj = gradients(sc, "adjoint");
  ASSERT_EQ(adj.objectives.size(), 4u);
  EXPECT_LT(worstRelative(adj, fw, 1e-12), 100 * sc.integrator.rtol);
  for (const auto& o : adj.objectives) EXPECT_NE(o.gradient[0], 0.0) << o.name;  // E matters
  // A checkpoint every 50 steps (this segfaulted inside IDASolveB while frames stopped the
  // forward pass's steps: a recomputed interval took more steps than IDAS had stored).
  GradientRequest req;
  req.checkpointEvery = 50;
  const GradientResult every50 = computeGradients(sc, req);
  EXPECT_GT(every50.adjoint.checkpoints, 20);
  EXPECT_LT(worstRelative(every50, fw, 1e-12), 100 * sc.integrator.rtol);
}

TEST(GradientIdas, TerminalObjectivesAtTheEndByBothMethodsBeforeItByForwardOnly) {
  const std::string text = std::string(kPendulum) + "  - {name: y_end, terminal: {output: tip_y}}\n"
                                                    "  - {name: x_end, terminal: {output: tip_x}}\n"
                                                    "  - {name: vy_end, terminal: {output: tip_vy}}\n"
                                                    "  - {name: x_mid, terminal: {output: tip_x, at: 0.5}}\n"
                                                    "  - {name: both, sum: [{objective: y_end, weight: 2}, {objective: y_sq, weight: -1}]}\n";
  const Scene sc = readSceneText(text, "pendulum.yaml", "same_x");
  // Forward: the outputs' sensitivities at t_end and 0.5 s; the adjoint at t_end (its terminal
  // condition: the projections onto the constraints' null space); both against central
  // differences of the frames there (rtol 1e-11 runs).
  for (const auto& [name, frame, output] : {std::tuple{"y_end", 1000, 1}, std::tuple{"x_end", 1000, 0},
                                           std::tuple{"vy_end", 1000, 2}, std::tuple{"x_mid", 500, 0}}) {
    const GradientResult fw = gradients(sc, "forward", name);
    const bool atEnd = frame == 1000;
    const GradientResult adj = atEnd ? gradients(sc, "adjoint", name) : fw;
    for (int k = 0; k < 2; ++k) {
      const double d = 3e-5 * sc.model->nominalParameters()[k];
      const double nd = (outputAtFrame("same_x", k, d, frame, output) - outputAtFrame("same_x", k, -d, frame, output)) / (2 * d);
      EXPECT_NEAR(fw.objectives[0].gradient[k], nd, 1e-5 * std::max(std::abs(nd), 1e-2)) << name << " " << k;
      EXPECT_NEAR(adj.objectives[0].gradient[k], nd, 1e-5 * std::max(std::abs(nd), 1e-2)) << name << " adjoint " << k;
    }
  }
  const GradientResult fw = gradients(sc, "forward", "both"), adj = gradients(sc, "adjoint", "both");
  EXPECT_LT(worstRelative(adj, fw, 1e-2), 1e-5);
  // Before t_end the adjoint refuses, naming the alternatives.
  try {
    gradients(sc, "adjoint");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("objective 'x_mid'"), std::string::npos) << what;
    EXPECT_NE(what.find("use --method forward, or a fixed-step integrator"), std::string::npos) << what;
  }
}

// A body's mass (objective kind mass) has no part in the motion: on idas it is the explicit
// term alone, m with dm/dm = 1, and in a sum beside an integral the sum of the two gradients.
TEST(GradientIdas, MassObjectiveBesideAnIntegral) {
  std::string text = kPendulum;
  text.replace(text.find("  - {name: L, of: bar"), 0, "  - {name: m, of: bar, property: mass}\n");
  text += "  - {name: m_bar, mass: {of: bar}}\n  - {name: m_and_y, sum: [{objective: m_bar, weight: 3}, {objective: y_sq, weight: 1}]}\n";
  const Scene sc = readSceneText(text, "pendulum_mass.yaml");
  for (const std::string method : {"adjoint", "forward"}) {
    const GradientResult r = gradients(sc, method);
    const auto& y = r.objectives[0];
    const auto& mass = r.objectives[4];
    const auto& both = r.objectives[5];
    ASSERT_EQ(mass.name, "m_bar");
    EXPECT_DOUBLE_EQ(mass.value, 1.0) << method;
    EXPECT_DOUBLE_EQ(mass.gradient[0], 1.0) << method;
    EXPECT_EQ(mass.gradient.tail(2).norm(), 0.0) << method;
    EXPECT_NEAR(both.value, 3.0 + y.value, 1e-14 * both.value) << method;
    EXPECT_LT((both.gradient - (3.0 * mass.gradient + y.gradient)).norm(), 1e-12 * both.gradient.norm()) << method;
  }
}

TEST(GradientIdas, MasslessCoordinatesAreRefusedByTheAdjoint) {
  const char* massless = R"(dimension: 2
gravity: [0, -2]
nodes:
  - {name: root, position: [0, 0], ground: true}
  - {name: n1, position: [0.5, 0]}
  - {name: tip, position: [1, 0]}
  - {name: anchor, position: [1, -1], ground: true}
elements:
  - {name: spring, type: beam, nodes: [root, n1, tip], E: 1.0e6, inertia: none, section: {area: 1.0e-4, inertia: 1.0e-9}}
  - {name: mass, type: rigid_bar, nodes: [tip, anchor], mass: 3.0}
parameters:
  - {name: A, of: spring, property: area}
integrator: {type: idas, t_end: 0.1}
outputs:
  - {name: x_tip, node: tip, component: x}
objectives:
  - {name: x_sq, integral: {output: x_tip, power: 2}}
)";
  const Scene sc = readSceneText(massless, "massless.yaml", "");
  try {
    gradients(sc, "adjoint");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("massless coordinates (inertia: none); use --method forward"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(gradients(sc, "forward").objectives.size(), 1u);
}

/// Runs `flexsens <args>` with stderr into dir/err.txt; returns the exit status.
int flexsensCli(const std::string& args, const std::string& dir, std::string& err) {
  const std::string cmd = std::string(FLEXSENS_EXE) + " " + args + " >" + dir + "/out.txt 2>" + dir + "/err.txt";
  const int st = std::system(cmd.c_str());
  std::ifstream in(dir + "/err.txt");
  std::stringstream ss;
  ss << in.rdbuf();
  err = ss.str();
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

TEST(GradientIdasCli, AdjointWritesGradientJsonAndRefusesATerminalObjectiveBeforeWriting) {
  const std::string dir = testing::TempDir() + "flexsens_gradient_idas_cli";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/p.yaml") << kPendulum << "  - {name: y_mid, terminal: {output: tip_y, at: 0.5}}\n";
  std::string err;
  EXPECT_EQ(flexsensCli("gradient " + dir + "/p.yaml --out " + dir + "/h", dir, err), 1);
  EXPECT_NE(err.find("p.yaml:"), std::string::npos) << err;  // the objective's file and line
  EXPECT_NE(err.find("a terminal objective before t_end (at) has no continuous adjoint on integrator idas"), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/h"));
  ASSERT_EQ(flexsensCli("gradient " + dir + "/p.yaml --objective y_sq --out " + dir + "/g", dir, err), 0) << err;
  std::ifstream in(dir + "/g/gradient.json");
  std::stringstream json;
  json << in.rdbuf();
  EXPECT_NE(json.str().find("\"method\": \"adjoint\""), std::string::npos) << json.str();
  EXPECT_NE(json.str().find("\"checkpoints\": 1"), std::string::npos) << json.str();
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace flexsens
