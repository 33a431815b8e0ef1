// A driver's initial speed (its function's slope at t = 0) and the scene's given initial
// velocities: a slider-crank whose crank turns at w = 10 rad/s from t = 0 (`linear`) with the
// matching velocities runs with no projection and no jump (the crank tip's velocity is the
// closed-form -w r sin(theta0 + w t) at every frame) and a complete energy audit; the same
// velocities with a `ramp` (at rest at t = 0) are refused naming both speeds.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "app/Run.hpp"
#include "core/Types.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;
namespace fs = std::filesystem;

namespace {

constexpr double kCrank = 0.1, kCoupler = 0.3, kTheta0 = M_PI / 3, kOmega = 10.0;

/// Crank O-A (ground O), coupler A-B, slider B on y = 0; crank angle theta0, the velocities of
/// A and B those of the crank turning at kOmega (B's from (B - A).(v_B - v_A) = 0, v_B = (u, 0)).
std::string sliderCrank(const std::string& function) {
  const double ax = kCrank * std::cos(kTheta0), ay = kCrank * std::sin(kTheta0);
  const double bx = ax + std::sqrt(kCoupler * kCoupler - ay * ay);
  const double vax = -kOmega * ay, vay = kOmega * ax;
  const double u = vax - (-ay) * (0.0 - vay) / (bx - ax);  // (bx-ax)(u-vax) + (-ay)(0-vay) = 0
  std::ostringstream s;
  s << std::setprecision(17) << "dimension: 2\ngravity: [0, -9.81]\nnodes:\n"
    << "  - {name: O, position: [0, 0], ground: true}\n"
    << "  - {name: X, position: [1, 0], ground: true}\n"
    << "  - {name: A, position: [" << ax << ", " << ay << "], velocity: [" << vax << ", " << vay << "]}\n"
    << "  - {name: B, position: [" << bx << ", 0], velocity: [" << u << ", 0]}\n"
    << "elements:\n"
    << "  - {name: crank, type: rigid_bar, nodes: [O, A], mass: 1.0}\n"
    << "  - {name: coupler, type: rigid_bar, nodes: [A, B], mass: 2.0}\n"
    << "constraints:\n"
    << "  - {name: drive, type: motor, nodes: [O, X, O, A], function: " << function << "}\n"
    << "  - {name: slider, type: prescribed_coordinate, node: B, axis: y, function: {type: constant, value: 0}}\n"
    << "integrator: {type: trapezoidal, t_end: 0.5, dt: 0.001, frame_interval: 0.01}\n"
    << "outputs:\n  - {name: vAx, node: A, component: x, quantity: velocity}\n"
    << "output: {vtk: false, plots: false}\n";
  return s.str();
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST(DriverInitialSpeed, LinearFunctionWithMatchingVelocitiesRunsWithoutJump) {
  const Scene sc = readSceneText(sliderCrank("{type: linear, slope: 10}"), "slider_crank.yaml");
  const std::string dir = ::testing::TempDir() + "/flexsens_slider_crank_linear";
  fs::remove_all(dir);
  const RunResult res = runScene(sc, dir);
  EXPECT_TRUE(res.suspect.empty()) << res.suspect;
  const std::string js = slurp(fs::path(dir) / "summary.json");
  EXPECT_NE(js.find("\"judged\": true"), std::string::npos) << js;
  // No projection: the given velocities were already the drivers'.
  const size_t k = js.find("\"initial_velocity_change\": ");
  ASSERT_NE(k, std::string::npos);
  EXPECT_LT(std::stod(js.substr(k + 27)), 1e-9);
  // The crank tip's x velocity at every frame against -w r sin(theta0 + w t).
  std::ifstream csv(fs::path(dir) / "series.csv");
  std::string line;
  std::getline(csv, line);
  std::istringstream head(line);
  std::string col;
  int tCol = -1, vCol = -1;
  for (int i = 0; std::getline(head, col, ','); ++i) {
    if (col == "t") tCol = i;
    if (col == "vAx") vCol = i;
  }
  ASSERT_GE(tCol, 0);
  ASSERT_GE(vCol, 0);
  int rows = 0;
  double worst = 0.0;
  while (std::getline(csv, line)) {
    std::istringstream row(line);
    std::vector<double> v;
    while (std::getline(row, col, ',')) v.push_back(std::stod(col));
    const double t = v[tCol];
    worst = std::max(worst, std::abs(v[vCol] + kOmega * kCrank * std::sin(kTheta0 + kOmega * t)));
    ++rows;
  }
  EXPECT_EQ(rows, 51);
  // Observed 1.6e-5 m/s (the trapezoidal velocities hold the driver to O(dt^2)); a jump to speed
  // in the first step (the ramp's case) is of the order of the speed itself, w r = 1 m/s.
  EXPECT_LT(worst, 1e-4);
  fs::remove_all(dir);
}

TEST(DriverInitialSpeed, RampFromRestWithGivenSpeedIsRefusedNamingBoth) {
  try {
    readSceneText(sliderCrank("{type: ramp, slope: 10}"), "slider_crank.yaml");
    FAIL() << "a ramp (at rest at t = 0) with the crank given 10 rad/s was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("slider_crank.yaml:12:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("key 'constraints[0].function'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("is 0 rad/s"), std::string::npos) << msg;
    EXPECT_NE(msg.find("at 10 rad/s"), std::string::npos) << msg;
    EXPECT_NE(msg.find("nodes[2].velocity"), std::string::npos) << msg;
  }
}

TEST(DriverInitialSpeed, HarmonicSpeedAtZeroIsChecked) {
  // amplitude 2, omega 5: f'(0) = 10 rad/s with phase 0 (accepted), 0 with phase pi/2 (refused).
  EXPECT_NO_THROW(readSceneText(sliderCrank("{type: harmonic, amplitude: 2, omega: 5}"), "a.yaml"));
  EXPECT_THROW(readSceneText(sliderCrank("{type: harmonic, amplitude: 2, omega: 5, phase: 1.5707963267948966, offset: -2}"),
                             "b.yaml"),
               InputError);
}

// prescribed_distance: the rate (x_b - x_a) . (v_b - v_a) / |x_b - x_a| of the given velocities
// against f'(0); and a driver without a given velocity on its nodes is not checked (the
// initial state derives the velocities from the drivers).
TEST(DriverInitialSpeed, DistanceDriverRateAgainstItsFunction) {
  auto scene = [](const std::string& velocity, const std::string& function) {
    return "dimension: 2\nnodes:\n  - {name: O, position: [0, 0], ground: true}\n"
           "  - {name: P, position: [0.6, 0.8]" + velocity + "}\n  - {name: Q, position: [0.6, 1.8]}\n"
           "elements:\n  - {name: mass, type: rigid_bar, nodes: [P, Q], mass: 1}\n"
           "constraints:\n  - {name: pull, type: prescribed_distance, nodes: [O, P], function: " + function + "}\n"
           "integrator: {type: trapezoidal, t_end: 0.1, dt: 0.01}\n";
  };
  // v = (0.3, 0.4): radial rate 0.6 * 0.3 + 0.8 * 0.4 = 0.5 m/s
  EXPECT_NO_THROW(readSceneText(scene(", velocity: [0.3, 0.4]", "{type: linear, slope: 0.5}"), "a.yaml"));
  try {
    readSceneText(scene(", velocity: [0.3, 0.4]", "{type: linear, slope: 0.25}"), "b.yaml");
    ADD_FAILURE() << "a distance driver at 0.25 m/s with the node given 0.5 m/s was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("is 0.25 m/s"), std::string::npos) << msg;
    EXPECT_NE(msg.find("at 0.5 m/s"), std::string::npos) << msg;
  }
  EXPECT_NO_THROW(readSceneText(scene("", "{type: linear, slope: 0.25}"), "c.yaml"));
}
