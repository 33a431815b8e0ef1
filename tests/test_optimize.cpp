// `flexsens optimize` (app/Optimize.hpp) on problems whose optimum is known in closed form,
// and the mass objective (app/BodyMass.hpp) against the plate's analytic mass and central
// differences.
//
// The bar problem: a free rigid bar of mass m pushed by 1 N at each end from rest moves as
// y(t) = t^2 / m (constant acceleration 2 N / m; the trapezoidal rule integrates a constant
// acceleration exactly, so the discrete y_n = t_n^2 / m to round-off). The tracking objective's
// target is t^2 / 4 at the step times, so J(m) = C (1/m - 1/4)^2 is least at m* = 4 kg. With
// y(1 s) = 1/m >= 0.5 m the constrained optimum is m = 2 kg (the bound active); with
// y(1 s) <= 0.2 m it is m = 5 kg.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/BodyMass.hpp"
#include "app/Optimize.hpp"
#include "core/Interrupt.hpp"
#include "scene/Scene.hpp"

namespace fs = std::filesystem;
using namespace flexsens;

namespace {

const char* kBar = R"(dimension: 2
nodes:
  - {name: A, position: [0, 0]}
  - {name: B, position: [1, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [A, B], mass: START}  # the start [kg]
  - {name: fA, type: point_force, node: A, force: [0, 1.0]}
  - {name: fB, type: point_force, node: B, force: [0, 1.0]}
parameters:
  - {name: m, of: bar, property: mass}
integrator: {type: trapezoidal, t_end: 1.0, dt: 0.1}
outputs:
  - {name: yA, node: A, component: y}
objectives:
  - {name: fit, tracking: {output: yA, csv: target.csv}}
  - {name: y_end, terminal: {output: yA}}
  - {name: mass, mass: {of: bar}}
optimize:
  objective: fit
  algorithm: ALGORITHM
  variables: [{parameter: m, lower: 0.5, upper: 10}]
  tolerance: 1e-12
CONSTRAINTS
output: {vtk: false}
)";

std::string replaced(std::string text, const std::string& key, const std::string& value) {
  const size_t at = text.find(key);
  return text.replace(at, key.size(), value);
}

/// A fresh folder with target.csv (y* = t^2/4 at the step times) and the bar scene.
fs::path barScene(const std::string& name, const std::string& algorithm, const std::string& constraints,
                  double start = 2.0) {
  const fs::path dir = fs::temp_directory_path() / ("flexsens_optimize_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream csv(dir / "target.csv");
  csv.precision(17);
  for (int n = 0; n <= 10; ++n) csv << 0.1 * n << "," << (0.1 * n) * (0.1 * n) / 4.0 << "\n";
  std::ostringstream startText;
  startText << start;
  std::string text = replaced(kBar, "START", startText.str());
  text = replaced(replaced(text, "ALGORITHM", algorithm), "CONSTRAINTS", constraints);
  std::ofstream(dir / "bar.yaml") << text;
  return dir;
}

OptimizeResult optimizeBar(const fs::path& dir) {
  OptimizeRequest req;
  req.scenePath = (dir / "bar.yaml").string();
  req.outDir = (dir / "out").string();
  req.plots = false;
  return optimizeCommand(req);
}

double bestMass(const OptimizeResult& r) { return r.history.at(size_t(r.best)).x[0]; }

std::string fileText(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST(Optimize, ReachesTheClosedFormOptimumWithEachAlgorithm) {
  for (const std::string algorithm : {"mma", "slsqp", "lbfgs"}) {
    const fs::path dir = barScene("free_" + algorithm, algorithm, "");
    const OptimizeResult r = optimizeBar(dir);
    EXPECT_EQ(r.status, "converged") << algorithm << " " << r.nloptResult;
    EXPECT_EQ(r.exitCode(), 0) << algorithm;
    ASSERT_GE(r.best, 0) << algorithm;
    EXPECT_NEAR(bestMass(r), 4.0, 4e-6) << algorithm;  // 1e-6 relative
    // The optimized scene holds the optimum: read back, its parameter is the best point's.
    // (read as if beside bar.yaml: it names target.csv relative to the scene's folder)
    const Scene back = readSceneText(fileText(dir / "out" / "optimized.yaml"), (dir / "optimized.yaml").string());
    EXPECT_EQ(back.model->parameters[0].nominal, bestMass(r)) << algorithm;
    EXPECT_NE(fileText(dir / "out" / "optimized.yaml").find("# the start [kg]"), std::string::npos);  // comments kept
    fs::remove_all(dir);
  }
}

TEST(Optimize, ForwardGradientsReachTheSameOptimum) {
  const fs::path dir = barScene("forward", "slsqp", "  gradient: forward");
  const OptimizeResult r = optimizeBar(dir);
  EXPECT_EQ(r.status, "converged") << r.nloptResult;
  EXPECT_EQ(r.gradient, "forward");
  ASSERT_GE(r.best, 0);
  EXPECT_NEAR(bestMass(r), 4.0, 4e-6);
  fs::remove_all(dir);
}

TEST(Optimize, ConstraintsActiveAtTheirBounds) {
  struct Case {
    std::string algorithm, constraint;
    double mass;   // the analytic constrained optimum [kg]
    double start;  // [kg]
  };
  // Feasible starts: MMA from an infeasible start can stop early (docs/known-limits.md).
  for (const Case& c : {Case{"mma", "{objective: y_end, min: 0.5}", 2.0, 1.0},
                        Case{"slsqp", "{objective: y_end, min: 0.5}", 2.0, 1.0},
                        Case{"mma", "{objective: y_end, max: 0.2}", 5.0, 8.0},
                        Case{"slsqp", "{objective: mass, min: 4.5}", 4.5, 8.0}}) {
    const fs::path dir = barScene("constrained_" + c.algorithm, c.algorithm, "  constraints: [" + c.constraint + "]", c.start);
    const OptimizeResult r = optimizeBar(dir);
    EXPECT_EQ(r.status, "converged") << c.algorithm << " " << c.constraint << " " << r.nloptResult;
    ASSERT_GE(r.best, 0);
    EXPECT_NEAR(bestMass(r), c.mass, 1e-6 * c.mass) << c.algorithm << " " << c.constraint;
    EXPECT_LT(r.kktResidual, 1e-6) << c.algorithm << " " << c.constraint;
    fs::remove_all(dir);
  }
}

TEST(Optimize, AStalledStopIsNotCalledConverged) {
  // MMA from the infeasible start m = 3 kg (y(1 s) = 1/3 < 0.5 m) jumps to 1.69 kg and then to
  // the bound 0.5 kg and stops with XTOL_REACHED after 3 evaluations; the best point (1.69 kg,
  // the constraint inactive) has a gradient far from zero: stalled, not converged.
  const fs::path dir = barScene("stalled", "mma", "  constraints: [{objective: y_end, min: 0.5}]", 3.0);
  const OptimizeResult r = optimizeBar(dir);
  EXPECT_EQ(r.nloptResult, "XTOL_REACHED");
  EXPECT_EQ(r.status, "stalled");
  EXPECT_EQ(r.exitCode(), 5);
  EXPECT_GT(r.kktResidual, 0.1);
  fs::remove_all(dir);
}

TEST(Optimize, FailingEvaluationStopsWithTheReportAndExitCode2) {
  // A pendulum with a 5-iteration Newton: the optimizer pushes the load up to where the first
  // step cannot converge.
  const fs::path dir = fs::temp_directory_path() / ("flexsens_optimize_fail_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "fail.yaml") << R"(dimension: 2
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: B, position: [1, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [A, B], mass: 1.0}
  - {name: push, type: point_force, node: B, force: [0, -1.0]}
parameters:
  - {name: F, of: push, property: y}
integrator: {type: trapezoidal, t_end: 1.0, dt: 0.1, max_newton_iterations: 5}
outputs:
  - {name: yB, node: B, component: y}
objectives:
  - {name: drop, terminal: {output: yB, at: 0.3}}
optimize:
  objective: drop
  variables: [{parameter: F, lower: -1.0e6, upper: 0.0}]
output: {vtk: false}
)";
  const std::string cmd = std::string(FLEXSENS_EXE) + " optimize " + (dir / "fail.yaml").string() + " --out " +
                          (dir / "out").string() + " --no-plots > " + (dir / "log").string() + " 2>&1";
  const int st = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(st));
  EXPECT_EQ(WEXITSTATUS(st), 2);
  const std::string log = fileText(dir / "log"), json = fileText(dir / "out" / "optimize.json");
  EXPECT_NE(log.find("evaluation 2 failed at F = "), std::string::npos) << log;
  EXPECT_NE(log.find("Newton did not converge"), std::string::npos) << log;
  EXPECT_NE(json.find("\"status\": \"failed\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"failure\": {\"evaluation\": 2"), std::string::npos) << json;
  EXPECT_NE(json.find("\"optimum\": {\"evaluation\": 1"), std::string::npos) << json;  // the best so far
  // The scene at the best point: the force's y component is the start's -1 (the best so far).
  EXPECT_NE(fileText(dir / "out" / "optimized.yaml").find("force: [0, -1]"), std::string::npos);
  fs::remove_all(dir);
}

TEST(Optimize, InterruptKeepsWhatWasDone) {
  const fs::path dir = barScene("interrupt", "mma", "");
  requestInterrupt(SIGINT);
  const OptimizeResult r = optimizeBar(dir);
  clearInterrupt();
  EXPECT_EQ(r.status, "interrupted");
  EXPECT_EQ(r.exitCode(), 130);
  EXPECT_TRUE(fs::exists(dir / "out" / "optimize.json"));
  fs::remove_all(dir);
}

TEST(Optimize, MassOfAPlateAndItsPerElementGradient) {
  // rho t L H = 1000 kg/m^3 * 0.01 m * 1 m * 0.05 m = 0.5 kg; dm/dt_i = rho A_i sums to rho L H.
  const std::string text = R"(dimension: 2
elements:
  - {name: plate, type: solid, mesh: plate.geo, group: plate, size: 0.05, E: 2.0e6, nu: 0.3, density: 1000,
     thickness: 0.01, ground: [root]}
parameters:
  - {name: t, of: plate, property: thickness, per: element}
  - {name: rho, of: plate, property: density}
integrator: {type: trapezoidal, t_end: 0.01, dt: 0.01}
objectives:
  - {name: mass, mass: {of: plate}}
)";
  const Scene sc = readSceneText(text, std::string(FLEXSENS_SOURCE_DIR) + "/tests/scenes/solid/mass.yaml");
  const Model& m = *sc.model;
  const VecX p = m.nominalParameters();
  const ExplicitObjective mass = explicitObjective(m, sc.objectives, 0, p);
  EXPECT_NEAR(mass.value, 0.5, 1e-12);
  const Eigen::Index np = p.size(), cells = np - 1;
  ASSERT_GT(cells, 10);
  EXPECT_NEAR(mass.gradient.head(cells).sum(), 1000.0 * 0.05, 1e-9);
  EXPECT_NEAR(mass.gradient[np - 1], 0.5 / 1000.0, 1e-15);  // dm/drho = m / rho
  for (Eigen::Index k : {Eigen::Index(0), cells / 2, cells - 1, np - 1}) {
    const double h = 1e-4 * p[k];
    VecX plus = p, minus = p;
    plus[k] += h;
    minus[k] -= h;
    const double fd = (bodyMass(m, sc.objectives[0].elements, plus).value -
                       bodyMass(m, sc.objectives[0].elements, minus).value) / (2 * h);
    EXPECT_NEAR(mass.gradient[k], fd, 1e-9 * std::abs(fd)) << k;
  }
}

TEST(Optimize, FiveBarExampleRecoversTheLinkLengthsOfItsPath) {
  // examples/optimize/fivebar_path.yaml: the path is the five-bar's own at L_A1 = 1.5 m,
  // L_3B = 1.3 m (make_fivebar_path.py); from sqrt(2) m each the optimizer finds them again.
  const fs::path out = fs::temp_directory_path() / ("flexsens_optimize_fivebar_" + std::to_string(::getpid()));
  OptimizeRequest req;
  req.scenePath = std::string(FLEXSENS_SOURCE_DIR) + "/examples/optimize/fivebar_path.yaml";
  req.outDir = out.string();
  req.plots = false;
  const OptimizeResult r = optimizeCommand(req);
  EXPECT_EQ(r.status, "converged") << r.nloptResult;
  ASSERT_GE(r.best, 0);
  EXPECT_NEAR(r.history[size_t(r.best)].x[0], 1.5, 1.5e-6);
  EXPECT_NEAR(r.history[size_t(r.best)].x[1], 1.3, 1.3e-6);
  fs::remove_all(out);
}

/// The relative differences |dJ/dx_k - central difference| / |central difference| of the
/// evaluations' gradients at x, k = 0 ... size - 1 (step h relative to x_k).
std::vector<double> gradientMismatch(Scene& sc, const VecX& x, double h) {
  std::vector<VecX> points{x};
  for (Eigen::Index k = 0; k < x.size(); ++k)
    for (double s : {1.0, -1.0}) {
      points.push_back(x);
      points.back()[k] += s * h * x[k];
    }
  const std::vector<OptimizeEvaluation> e = evaluatePoints(sc, points);
  std::vector<double> mismatch;
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    const double fd = (e.at(size_t(1 + 2 * k)).objective - e.at(size_t(2 + 2 * k)).objective) / (2 * h * x[k]);
    mismatch.push_back(std::abs(e[0].gradient[k] - fd) / std::abs(fd));
  }
  return mismatch;
}

TEST(Optimize, EvaluationGradientsEqualCentralDifferences) {
  // The bar's mass does not move its start: the gradient is the evaluations' derivative
  // (measured 3.2e-10 relative, the central difference's round-off).
  const fs::path dir = barScene("fd", "mma", "");
  Scene bar = readScene((dir / "bar.yaml").string());
  VecX m(1);
  m << 3.0;
  EXPECT_LT(gradientMismatch(bar, m, 1e-6)[0], 1e-8) << gradientMismatch(bar, m, 1e-6)[0];
  fs::remove_all(dir);
  // The five-bar's lengths do: away from the scene's values the start is the scene's start
  // projected onto the constraints at the new lengths, and the gradient takes its least-norm
  // sensitivity there, not the projection's derivative (docs/known-limits.md): measured 6.5e-5
  // and 5.9e-5 relative at lengths 2.5% and 4% from the scene's. Held to 1e-4 so that it does
  // not grow unnoticed.
  Scene fivebar = readScene(std::string(FLEXSENS_SOURCE_DIR) + "/examples/optimize/fivebar_path.yaml");
  VecX x(2);
  x << 1.45, 1.36;
  for (double mismatch : gradientMismatch(fivebar, x, 1e-6)) EXPECT_LT(mismatch, 1e-4) << mismatch;
}
