// Velocity outputs (`quantity: velocity` in `outputs`): a node's velocity component and a
// joint angle's rate, with their sensitivities, in series.csv. Checked against the closed form
// of a motor-driven bar (value and d/dA) and, for the angle rate's derivative, against central
// differences of the value along a random direction (dq, dv).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;

namespace {

// theta = A sin(3t), A = 0.5: tip T at (cos theta, sin theta).
const std::string kMotorBar = std::string(test::kMotorBarScene) + R"(parameters:
  - {name: A, of: motor, property: amplitude}
integrator: {type: idas, t_end: 1, frame_interval: 0.1, rtol: 1e-10, atol: 1e-12}
outputs:
  - {name: yT, node: T, component: y}
  - {name: vyT, node: T, component: y, quantity: velocity}
  - {name: vyX, node: X, component: y, quantity: velocity}
output: {vtk: false, plots: false}
)";

std::vector<std::vector<double>> readCsv(const std::string& path, std::string& header) {
  std::ifstream in(path);
  std::getline(in, header);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<double> r;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) r.push_back(std::stod(c));
    rows.push_back(r);
  }
  return rows;
}

}  // namespace

TEST(VelocityOutputs, NodeVelocityAndItsSensitivityMatchTheClosedForm) {
  const Scene sc = readSceneText(kMotorBar, "motor.yaml");
  const std::string dir = ::testing::TempDir() + "/flexsens_velocity_outputs";
  std::filesystem::remove_all(dir);
  runScene(sc, dir);
  std::string header;
  const auto rows = readCsv(dir + "/series.csv", header);
  ASSERT_EQ(header.rfind("t,yT,vyT,vyX,dyT/dA,dvyT/dA,dvyX/dA,", 0), 0u) << header;
  ASSERT_EQ(rows.size(), 11u);
  for (const auto& r : rows) {
    const double t = r[0], A = 0.5, s = std::sin(3 * t), c = std::cos(3 * t);
    const double th = A * s, thd = 3 * A * c;
    EXPECT_NEAR(r[1], std::sin(th), 1e-8) << t;
    EXPECT_NEAR(r[2], thd * std::cos(th), 1e-7) << t;  // d/dt sin(theta)
    EXPECT_EQ(r[3], 0.0);                             // a ground node
    EXPECT_NEAR(r[4], s * std::cos(th), 1e-7) << t;
    // d/dA (theta' cos theta) = 3 cos(3t) cos(theta) - theta' sin(theta) sin(3t)
    EXPECT_NEAR(r[5], 3 * c * std::cos(th) - thd * std::sin(th) * s, 1e-6) << t;
    EXPECT_EQ(r[6], 0.0);
  }
  std::filesystem::remove_all(dir);
}

// The angle rate theta' = grad theta . v and its derivative v^T H q_p + grad theta . v_p
// (OutputSpec::derivative) against central differences of the value along (dq, dv).
TEST(VelocityOutputs, AngleRateDerivativeMatchesFiniteDifferences) {
  const char* kChain = R"(dimension: 3
gravity: [0, 0, -9.81]
nodes:
  - {name: O, position: [0, 0, 0], ground: true}
  - {name: P, position: [0, 0, 1]}
  - {name: Q, position: [1, 0, 1]}
  - {name: R, position: [1, 1, 1.2]}
elements:
  - {name: b1, type: rigid_bar, nodes: [O, P], mass: 1}
  - {name: b2, type: rigid_bar, nodes: [P, Q], mass: 1}
  - {name: b3, type: rigid_bar, nodes: [Q, R], mass: 1}
integrator: {type: trapezoidal, t_end: 1, dt: 0.01}
outputs:
  - {name: th, angle: {axis: [O, P], from: [P, Q], to: [Q, R]}}
  - {name: thd, angle: {axis: [O, P], from: [P, Q], to: [Q, R]}, quantity: velocity}
)";
  const Scene sc = readSceneText(kChain, "chain.yaml");
  const Model& m = *sc.model;
  ASSERT_EQ(sc.outputs.size(), 2u);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto random = [&](double scale) {
    VecX r(m.n);
    for (int i = 0; i < m.n; ++i) r[i] = scale * u(rng);
    return r;
  };
  for (int trial = 0; trial < 5; ++trial) {
    State x, dx;
    x.q = m.initialPositions() + random(0.1);
    x.v = random(2.0);
    dx.q = random(1.0);
    dx.v = random(1.0);
    const double h = 1e-6;
    for (const auto& o : sc.outputs) {
      State xp = x, xm = x;
      xp.q += h * dx.q, xp.v += h * dx.v;
      xm.q -= h * dx.q, xm.v -= h * dx.v;
      const double fd = (o.value(m, xp) - o.value(m, xm)) / (2 * h);
      EXPECT_NEAR(o.derivative(m, x, dx), fd, 1e-7 * std::max(1.0, std::abs(fd))) << o.name << " trial " << trial;
    }
    // The rate is the time derivative of the angle: central difference along (v, a = 0).
    State xp = x, xm = x;
    xp.q += h * x.v;
    xm.q -= h * x.v;
    EXPECT_NEAR(sc.outputs[1].value(m, x), (sc.outputs[0].value(m, xp) - sc.outputs[0].value(m, xm)) / (2 * h), 1e-7);
  }
}

TEST(VelocityOutputs, UnknownQuantityIsAnInputErrorWithItsLine) {
  std::string text = kMotorBar;
  const std::string from = "quantity: velocity}";
  text.replace(text.find(from), from.size(), "quantity: speed}");
  try {
    readSceneText(text, "motor.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("motor.yaml:16"), std::string::npos) << w;
    EXPECT_NE(w.find("outputs[1].quantity"), std::string::npos) << w;
    EXPECT_NE(w.find("expected position, velocity or displacement"), std::string::npos) << w;
  }
}
