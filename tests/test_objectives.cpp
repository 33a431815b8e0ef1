// Objectives of a scene (scene/Objective.hpp, app/Objectives.hpp): reading, and the discrete
// objectives on the step grid against closed forms of sampled polynomials (the trapezoidal
// rule's known error h^2/12 (f'(b) - f'(a)), linear interpolation, the KS bounds).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "app/Objectives.hpp"
#include "scene/Scene.hpp"

namespace flexsens {
namespace {

const char* kBar = R"(dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: tip, position: [1, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [A, tip], mass: 1.0}
integrator: {type: trapezoidal, t_end: 1.0, dt: 0.01}
outputs:
  - {name: tip_x, node: tip, component: x}
  - {name: tip_y, node: tip, component: y}
)";

/// One objective read from `objectives` text appended to kBar.
std::vector<ObjectiveSpec> objectivesOf(const std::string& objectives) {
  return readSceneText(std::string(kBar) + "objectives:\n" + objectives, "objectives.yaml").objectives;
}

/// Samples o_n = f(t_n) in column `col` of a two-output sample matrix on grid g.
MatX sampled(const StepGrid& g, int col, double (*f)(double)) {
  MatX s = MatX::Zero(g.steps + 1, 2);
  for (long n = 0; n <= g.steps; ++n) s(n, col) = f(g.time(n));
  return s;
}

double square(double t) { return t * t; }
double cube(double t) { return t * t * t; }

TEST(Objectives, ReadsEveryKindWithItsDefaults) {
  const auto obj = objectivesOf(R"(  - {name: e, terminal: {output: tip_y}}
  - {name: i, integral: {output: tip_x, power: 2, from: 0.25}}
  - {name: k, max: {output: tip_y, rho: 30, to: 0.5}}
  - {name: r, tracking: {output: tip_y, target: {type: linear, slope: 2, offset: 1}}}
  - {name: s, sum: [{objective: e, weight: 2}, {objective: k}]}
)");
  ASSERT_EQ(obj.size(), 5u);
  EXPECT_EQ(obj[0].kind, "terminal");
  EXPECT_EQ(obj[0].output, 1);
  EXPECT_LT(obj[0].at, 0.0);  // t_end
  EXPECT_EQ(obj[1].output, 0);
  EXPECT_EQ(obj[1].power, 2);
  EXPECT_DOUBLE_EQ(obj[1].from, 0.25);
  EXPECT_LT(obj[1].to, 0.0);
  EXPECT_DOUBLE_EQ(obj[2].rho, 30.0);
  EXPECT_DOUBLE_EQ(obj[2].to, 0.5);
  EXPECT_DOUBLE_EQ(obj[3].targetAt(0.5), 2.0);  // 1 + 2 t
  ASSERT_EQ(obj[4].terms.size(), 2u);
  EXPECT_EQ(obj[4].terms[0], std::make_pair(0, 2.0));
  EXPECT_EQ(obj[4].terms[1], std::make_pair(2, 1.0));
}

TEST(Objectives, TrackingTargetFromCsvInterpolatesItsRows) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "flexsens_objective_csv";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "target.csv") << "t, value\n# a comment\n0, 1\n0.5, 2\n1.0, 0\n";
  std::ofstream(dir / "scene.yaml") << kBar << "objectives:\n  - {name: r, tracking: {output: tip_y, csv: target.csv}}\n";
  const Scene sc = readScene((dir / "scene.yaml").string());
  const ObjectiveSpec& o = sc.objectives.at(0);
  EXPECT_DOUBLE_EQ(o.targetAt(0.25), 1.5);
  EXPECT_DOUBLE_EQ(o.targetAt(0.75), 1.0);
  EXPECT_DOUBLE_EQ(o.targetAt(1.0), 0.0);
  std::filesystem::remove_all(dir);
}

TEST(Objectives, IntegralIsTheTrapezoidalRuleOnTheStepTimes) {
  // Composite trapezoidal rule of t^2 on [0, 1] with step h: 1/3 + h^2/6 exactly
  // (error h^2/12 (f'(1) - f'(0))); its derivative with respect to each sample is its weight.
  const std::vector<ObjectiveSpec> obj = objectivesOf("  - {name: i, integral: {output: tip_x}}\n");
  const StepGrid g{0.0, 0.01, 1.0, 100};
  const MatX s = sampled(g, 0, square);
  EXPECT_NEAR(objectiveValue(obj, 0, g, s), 1.0 / 3.0 + 1e-4 / 6.0, 1e-15);
  MatX dJ = MatX::Zero(s.rows(), s.cols());
  addObjectiveDerivative(obj, 0, g, s, 1.0, dJ);
  EXPECT_NEAR(dJ(0, 0), 0.005, 1e-17);
  EXPECT_NEAR(dJ(50, 0), 0.01, 1e-16);
  EXPECT_NEAR(dJ(100, 0), 0.005, 1e-16);
  EXPECT_EQ(dJ.col(1).norm(), 0.0);
}

TEST(Objectives, WindowInsideStepsIntegratesTheInterpolant) {
  // Samples of a linear function: the interpolant is the function itself, so any window,
  // cutting steps or not, integrates exactly: int_0.123^0.777 (3 t) dt = 1.5 (0.777^2 - 0.123^2).
  const std::vector<ObjectiveSpec> obj = objectivesOf("  - {name: i, integral: {output: tip_x, from: 0.123, to: 0.777}}\n");
  const StepGrid g{0.0, 0.01, 1.0, 100};
  MatX s = MatX::Zero(101, 2);
  for (long n = 0; n <= 100; ++n) s(n, 0) = 3.0 * g.time(n);
  EXPECT_NEAR(objectiveValue(obj, 0, g, s), 1.5 * (0.777 * 0.777 - 0.123 * 0.123), 1e-14);
}

TEST(Objectives, PowerAndTrackingIntegrands) {
  // int_0^1 (t^3)^2 = 1/7 and int_0^1 (t^3 - t)^2 = 1/7 - 2/5 + 1/3, by the trapezoidal rule
  // with h = 1e-3: error h^2/12 (f'(1) - f'(0)) = h^2/12 * 6 and h^2/12 * (6 - 8 + 2) = 0.
  const std::vector<ObjectiveSpec> obj = objectivesOf(R"(  - {name: p, integral: {output: tip_x, power: 2}}
  - {name: r, tracking: {output: tip_x, target: {type: linear, slope: 1}}}
)");
  const StepGrid g{0.0, 1e-3, 1.0, 1000};
  const MatX s = sampled(g, 0, cube);
  EXPECT_NEAR(objectiveValue(obj, 0, g, s), 1.0 / 7.0 + 1e-6 / 2.0, 1e-10);
  EXPECT_NEAR(objectiveValue(obj, 1, g, s), 1.0 / 7.0 - 0.4 + 1.0 / 3.0, 1e-10);
  MatX dJ = MatX::Zero(s.rows(), s.cols());
  addObjectiveDerivative(obj, 1, g, s, 1.0, dJ);  // w_n 2 (o_n - t_n): at t = 0.5, 1e-3 * 2 (1/8 - 1/2)
  EXPECT_NEAR(dJ(500, 0), 1e-3 * 2.0 * (0.125 - 0.5), 1e-15);
}

TEST(Objectives, TerminalInterpolatesBetweenSteps) {
  const std::vector<ObjectiveSpec> obj = objectivesOf(R"(  - {name: e, terminal: {output: tip_y}}
  - {name: m, terminal: {output: tip_y, at: 0.505}}
)");
  const StepGrid g{0.0, 0.01, 1.0, 100};
  const MatX s = sampled(g, 1, square);
  EXPECT_DOUBLE_EQ(objectiveValue(obj, 0, g, s), 1.0);
  EXPECT_NEAR(objectiveValue(obj, 1, g, s), 0.5 * (0.25 + 0.2601), 1e-15);
}

TEST(Objectives, KsAggregateBoundsTheMaximumAndSumsWeight) {
  // o_n = t_n^2 on [0, 0.5]: max 0.25 at t = 0.5; KS within [max, max + ln(51)/rho]; its
  // derivatives are weights that sum to 1, largest at the maximum.
  const std::vector<ObjectiveSpec> obj = objectivesOf(R"(  - {name: k, max: {output: tip_x, rho: 200, to: 0.5}}
  - {name: s, sum: [{objective: k, weight: 3}]}
)");
  const StepGrid g{0.0, 0.01, 1.0, 100};
  const MatX s = sampled(g, 0, square);
  const double ks = objectiveValue(obj, 0, g, s);
  EXPECT_GE(ks, 0.25);
  EXPECT_LE(ks, 0.25 + std::log(51.0) / 200.0);
  MatX dJ = MatX::Zero(s.rows(), s.cols());
  addObjectiveDerivative(obj, 0, g, s, 1.0, dJ);
  EXPECT_NEAR(dJ.sum(), 1.0, 1e-14);
  EXPECT_EQ(dJ.bottomRows(50).norm(), 0.0);  // t > 0.5: outside the window
  Eigen::Index where;
  dJ.col(0).maxCoeff(&where);
  EXPECT_EQ(where, 50);
  EXPECT_DOUBLE_EQ(objectiveValue(obj, 1, g, s), 3.0 * ks);
}

TEST(Objectives, TimesBeyondAShortenedRunAreNamed) {
  const std::vector<ObjectiveSpec> obj = objectivesOf("  - {name: m, terminal: {output: tip_y, at: 0.8}}\n");
  try {
    checkObjectiveTimes(obj[0], 0.5);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("objectives.yaml:"), std::string::npos) << what;
    EXPECT_NE(what.find("objectives[0]"), std::string::npos) << what;
    EXPECT_NE(what.find("--t-end"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace flexsens
