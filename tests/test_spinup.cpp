// Spin-up beam (examples/spinup/spinup.yaml, Simo and Vu-Quoc's classic): a flexible beam
// whose root segment follows a prescribed hub angle (motor + spin_up). The test runs it with
// a faster spin-up (omega = 6 rad/s reached in 1 s instead of 15 s, so that one second of
// simulation bends the beam) and checks: the root segment's angle equals the prescribed one;
// the sensitivities to E and to the spin rate omega equal central differences of two whole
// runs (trapezoidal: the exact derivative of the discrete scheme, so the match is tight).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "TestModels.hpp"
#include "app/Run.hpp"

using namespace flexsens;

namespace {
struct Last : Observer {
  StateWithSens s;
  void frame(const StateWithSens& x) override { s = x; }
};

Scene fastSpinUp() {
  std::ifstream in(test::sourceDir() + "/examples/spinup/spinup.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const std::string from = "duration: 15", to = "duration: 1";
  text.replace(text.find(from), from.size(), to);
  Scene sc = readSceneText(text, "spinup.yaml");
  sc.integrator.type = "trapezoidal";
  sc.integrator.dt = 1e-3;
  sc.integrator.tEnd = 1.0;
  sc.integrator.frameInterval = 1.0;
  sc.integrator.newtonTol = 1e-13;
  return sc;
}
}  // namespace

TEST(SpinUpBeam, SensitivitiesToEAndSpinRateMatchCentralDifferences) {
  const Scene sc = fastSpinUp();
  const Model& m = *sc.model;
  ASSERT_EQ(m.parameters.size(), 2u);
  Assembler as(m);
  const VecX p = m.nominalParameters();
  Last nominal;
  integrate(as, p, initialState(as, p), sc.integrator, nominal);
  ASSERT_NEAR(nominal.s.x.t, 1.0, 1e-12);
  // Hub angle at t = 1 s (spin_up, T = 1): (omega/T)(t^2/2 + (T/2pi)^2 (cos(2 pi t/T) - 1)) = omega/2.
  const VecX& q = nominal.s.x.q;
  const double angle = std::atan2(q[1], q[0]);  // node n1 is the first free node
  EXPECT_NEAR(angle, 3.0 - 2 * M_PI * std::round(3.0 / (2 * M_PI)), 1e-9);
  const int tip = static_cast<int>(q.size()) - 2;
  // The beam bends behind the hub: the tip lags the root segment's line.
  const double lag = std::atan2(q[tip + 1], q[tip]) - std::atan2(q[1], q[0]);
  EXPECT_GT(std::abs(lag), 1e-3);
  std::printf("spin-up beam at t = 1 s: tip lag behind the root segment %.4e rad\n", lag);
  for (int k = 0; k < 2; ++k) {
    const double h = 1e-5 * std::abs(p[k]);
    VecX qs[2];
    for (int s = 0; s < 2; ++s) {
      VecX pk = p;
      pk[k] += (s == 0 ? h : -h);
      Last run;
      StateWithSens start = initialState(as, pk);
      start.dp.clear();
      integrate(as, pk, start, sc.integrator, run);
      qs[s] = run.s.x.q;
    }
    const VecX fd = (qs[0] - qs[1]) / (2 * h);
    const VecX dd = nominal.s.dp[k].q;
    EXPECT_GT(dd.norm(), 0.0) << m.parameters[k].name;
    std::printf("spin-up beam: d q/d %s, |dd - fd|_inf / |fd|_inf = %.2e (|fd|_inf = %.3e)\n",
                m.parameters[k].name.c_str(), (dd - fd).lpNorm<Eigen::Infinity>() / fd.lpNorm<Eigen::Infinity>(),
                fd.lpNorm<Eigen::Infinity>());
    EXPECT_LT((dd - fd).lpNorm<Eigen::Infinity>(), 1e-5 * fd.lpNorm<Eigen::Infinity>())
        << m.parameters[k].name << "\n dd " << dd.transpose() << "\n fd " << fd.transpose();
  }
}
