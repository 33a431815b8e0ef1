// Andrews' squeezing mechanism (examples/andrews/andrews.yaml: seven planar rigid bodies, a
// constant driving torque, a spring) against the reference solution of the IVP test set at
// t = 0.03 s: problem "andrews" of the Test Set for IVP Solvers (F. Mazzia, C. Magherini,
// Univ. of Bari; src/problems/andrews.f, subroutine andsoln: PSIDE at rtol = atol = 1e-14),
// the model of Hairer and Wanner, Solving Ordinary Differential Equations II, section VII.7.
// The node positions at 0.03 s are compared with those the reference angles give, through
// the test set's own kinematic relations (its constraint functions g):
//   P = rr e(beta), E = P - d e(beta + Theta), Q = A + zt e(delta), R = A + u (sin eps, -cos eps),
//   D = B + sd e(gamma) + sc (sin gamma, -cos gamma), E = Q + e (sin(Phi + delta), -cos(Phi + delta)),
//   E = R + zf e(Omega + eps),       e(a) = (cos a, sin a),
// so every one of the seven angles is checked.
#include <gtest/gtest.h>

#include <cmath>

#include "TestModels.hpp"
#include "app/Run.hpp"

using namespace flexsens;

namespace {
struct Last : Observer {
  StateWithSens s;
  void frame(const StateWithSens& x) override { s = x; }
};
Eigen::Vector2d e(double a) { return {std::cos(a), std::sin(a)}; }
}  // namespace

TEST(Andrews, PositionsAtThreeHundredthsOfASecondMatchTheTestSetReference) {
  Scene sc = readScene(test::sourceDir() + "/examples/andrews/andrews.yaml");
  ASSERT_EQ(sc.integrator.type, "idas");
  ASSERT_EQ(sc.integrator.rtol, 1e-10);
  sc.integrator.frameInterval = 0.03;
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  Last last;
  integrate(as, p, initialState(as, p), sc.integrator, last);
  ASSERT_NEAR(last.s.x.t, 0.03, 1e-15);

  // andsoln, y(1..7) at t = 0.03 s [rad]
  const double be = 0.1581077119629904e+2, th = -0.1575637105984298e+2, ga = 0.4082224013073101e-1,
               ph = -0.5347301163226948e+0, de = 0.5244099658805304e+0, om = 0.5347301163226948e+0,
               ep = 0.1048080741042263e+1;
  const double rr = 7e-3, d = 28e-3, zt = 4e-2, u = 4e-2, sd = 2e-2, sc_ = 18e-3, ee = 2e-2, zf = 2e-2;
  const Eigen::Vector2d A(-0.06934, -0.00227), B(-0.03635, 0.03273);
  const Eigen::Vector2d P = rr * e(be), E = P - d * e(be + th), Q = A + zt * e(de);
  const Eigen::Vector2d R = A + u * Eigen::Vector2d(std::sin(ep), -std::cos(ep));
  const Eigen::Vector2d D = B + sd * e(ga) + sc_ * Eigen::Vector2d(std::sin(ga), -std::cos(ga));
  // The reference angles close the loops to round-off (a check of the formulas above).
  EXPECT_LT((Q + ee * Eigen::Vector2d(std::sin(ph + de), -std::cos(ph + de)) - E).norm(), 1e-12);
  EXPECT_LT((R + zf * e(om + ep) - E).norm(), 1e-12);

  const Model& m = *sc.model;
  auto node = [&](const char* name) {
    for (size_t i = 0; i < m.nodes.size(); ++i)
      if (m.nodes[i].name == name) return Eigen::Vector2d(last.s.x.q.segment(m.nodes[i].firstDof, 2));
    throw std::runtime_error(std::string("no node ") + name);
  };
  const double tol = 1e-7;  // [m]; the mechanism is ~0.1 m across
  double worst = 0.0;
  for (const auto& [name, ref] : {std::pair{"P", P}, {"E", E}, {"Q", Q}, {"R", R}, {"D", D}}) {
    const double err = (node(name) - ref).norm();
    worst = std::max(worst, err);
    EXPECT_LT(err, tol) << name << ": " << node(name).transpose() << " vs " << ref.transpose();
  }
  RecordProperty("worst_position_error_m", std::to_string(worst));
  std::printf("Andrews at t = 0.03 s: worst node position error %.3e m\n", worst);
}
