// Generalized-alpha (Arnold-Bruls index-3 form, Chung-Hulbert parameters from rho_inf):
// second-order accuracy against the analytic oscillator, numerical dissipation at high
// frequency equal to rho_inf per step (its definition), none worth mentioning at low
// frequency, and dd sensitivities that are the exact derivative of the discrete scheme
// (central differences of whole perturbed runs).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "TestModels.hpp"
#include "app/FiniteDifferences.hpp"
#include "output/Energy.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

// A 2 kg rigid bar between two springs of k = 50 N/m along x (natural length 100 m: the
// springs' spurious Newton root, a node on its anchor, is then far away), released
// x0 off equilibrium: pure translation x(t) = x0 cos(w t), w = sqrt(2k/m) = sqrt(50) rad/s.
// The bar's length constraint carries no force, the springs act along x only.
Scene oscillator(double x0) {
  std::string text = R"(
dimension: 2
plane: xy
gravity: [0, 0]
nodes:
  - {name: A, position: [-100, 0], ground: true}
  - {name: B, position: [102, 0], ground: true}
  - {name: n1, position: [X1, 0]}
  - {name: n2, position: [X2, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [n1, n2], mass: 2.0}
  - {name: s1, type: spring_damper, nodes: [A, n1], stiffness: 50, natural_length: 100.0}
  - {name: s2, type: spring_damper, nodes: [n2, B], stiffness: 50, natural_length: 100.0}
integrator: {type: generalized_alpha, t_end: 1, dt: 1.0e-3}
)";
  text.replace(text.find("X1"), 2, std::to_string(x0));
  text.replace(text.find("X2"), 2, std::to_string(2.0 + x0));
  return readSceneText(text, "oscillator.yaml");
}

const double kOmega = std::sqrt(50.0);  // [rad/s]

struct Motion {
  std::vector<double> t, x, v, energy;  // x, v of n1 about equilibrium [m, m/s], energy [J]
};

Motion runOscillator(double rhoInf, double dt, long steps, double x0 = 0.1,
                     const std::string& type = "generalized_alpha") {
  Scene sc = oscillator(x0);
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  IntegratorSettings set = integratorSettings(type, dt, dt * steps);
  set.rhoInf = rhoInf;
  set.frameInterval = dt;
  Recorder rec;
  integrate(as, p, initialState(as, p), set, rec);
  const int ix = sc.model->dof(sc.model->nodeIndex("n1"), 0);
  Motion r;
  for (const auto& f : rec.frames) {
    const double x = f.x.q[ix], v = f.x.v[ix];
    r.t.push_back(f.x.t);
    r.x.push_back(x);
    r.v.push_back(v);
    r.energy.push_back(0.5 * 2.0 * v * v + 0.5 * 100.0 * x * x);  // m = 2 kg, 2k = 100 N/m
  }
  return r;
}

}  // namespace

TEST(GeneralizedAlpha, SecondOrderForEveryRhoInf) {
  // Error of x(1 s) against 0.1 cos(w t) at dt = 2e-3 and 1e-3 s: ratio 4 for second order.
  for (double rho : {0.0, 0.5, 0.8, 1.0}) {
    std::vector<double> err;
    for (double dt : {2e-3, 1e-3}) {
      const Motion r = runOscillator(rho, dt, std::lround(1.0 / dt));
      err.push_back(std::abs(r.x.back() - 0.1 * std::cos(kOmega * r.t.back())));
    }
    std::printf("  rho_inf %.1f: error %.3e (dt 2 ms) -> %.3e (1 ms), ratio %.3f\n", rho, err[0], err[1], err[0] / err[1]);
    EXPECT_NEAR(err[0] / err[1], 4.0, 0.3) << "rho_inf " << rho;
    EXPECT_LT(err[1], 1e-4) << "rho_inf " << rho;
  }
}

TEST(GeneralizedAlpha, HighFrequenciesDecayByRhoInfPerStep) {
  // w h = 1000: the step's spectral radius tends to rho_inf (a double eigenvalue, so the
  // measured ratio approaches it from above like rho (1 + 1/n)); energy = amplitude^2 falls
  // by ~rho_inf^2 per step; rho_inf = 1 keeps it (the trapezoidal rule's spectrum).
  const double dt = 1000.0 / kOmega;
  for (double rho : {0.5, 0.8, 1.0}) {
    const Motion r = runOscillator(rho, dt, 40, 1e-4);
    const double perStep = std::pow(r.energy[40] / r.energy[30], 1.0 / 20.0);  // amplitude ratio
    std::printf("  rho_inf %.1f at w h = 1000: measured amplitude ratio per step %.4f, E40/E0 = %.3e\n", rho,
                perStep, r.energy[40] / r.energy[0]);
    EXPECT_NEAR(perStep, rho, 0.04) << "rho_inf " << rho;
  }
}

TEST(GeneralizedAlpha, LowFrequenciesKeepTheirEnergy) {
  // w h = 0.01 (628 steps per period), 10 periods: the algorithmic damping ratio is
  // O((w h)^3), so even rho_inf = 0 loses under 1e-4 of the energy, while BDF-1 (damping
  // ratio ~ w h / 2) loses about 1 - exp(-2 * 0.005 * w * t) = 47% in the same run.
  const double dt = 0.01 / kOmega;
  const long steps = std::lround(10 * 2 * M_PI / kOmega / dt);
  for (double rho : {0.0, 0.8}) {
    const Motion r = runOscillator(rho, dt, steps);
    const double loss = 1.0 - r.energy.back() / r.energy.front();
    std::printf("  rho_inf %.1f at w h = 0.01: energy lost in 10 periods %.3e\n", rho, loss);
    EXPECT_LT(std::abs(loss), 1e-4) << "rho_inf " << rho;
  }
  const Motion b = runOscillator(0.0, dt, steps, 0.1, "bdf1");
  const double loss = 1.0 - b.energy.back() / b.energy.front();
  std::printf("  bdf1 at w h = 0.01: energy lost in 10 periods %.3f (expected 1 - exp(-2 pi 0.01 10) = 0.467)\n", loss);
  EXPECT_NEAR(loss, 1.0 - std::exp(-2.0 * M_PI * 0.01 * 10.0), 0.02);
}

TEST(GeneralizedAlpha, SensitivitiesAreTheDerivativeOfTheDiscreteScheme) {
  // dd against central differences (relative step 1e-5) of the same scheme, every coordinate
  // and parameter: the planar model holding every 2D element type, and the seed-000 four-bar
  // (3D rigid bodies, joints, rotational spring-damper). The three paths of the fixed-step
  // sensitivity solve: full Newton ends each step with an LU of the converged point (its last
  // update at round-off), which the solve takes as is; with modified Newton's older LU the
  // planar model's nine parameters factor the converged point's matrix (fewer flops than one
  // GMRES per parameter) and the four-bar's four try GMRES preconditioned by it, which falls
  // back to factoring (test_modified_newton has GMRES converge).
  for (const std::string name : {"mixed 2D", "four-bar 3D"})
    for (const std::string newton : {"full", "modified"}) {
    SCOPED_TRACE(name + ", " + newton + " Newton");
    Scene sc = name == "mixed 2D" ? mixedScene() : readScene(sourceDir() + "/examples/seed000/four_bar.yaml");
    Assembler as(*sc.model);
    const VecX p = sc.model->nominalParameters();
    const StateWithSens start = initialState(as, p);
    IntegratorSettings set = integratorSettings("generalized_alpha", 2e-3, 0.5);
    set.rhoInf = 0.7;
    set.newton = newton;
    Recorder dd, nd;
    const IntegratorStats st = integrate(as, p, start, set, dd);
    integrateFiniteDifferences(as, p, start, nullptr, set, {"central", 1e-5}, nd);
    ASSERT_EQ(dd.frames.size(), nd.frames.size());
    if (newton == "full") {
      EXPECT_EQ(st.sensitivityReusedLu, st.steps);
      EXPECT_EQ(st.sensitivityFactorizations + st.sensitivityIterations, 0);
      EXPECT_EQ(st.jacobianEvaluations, st.newtonIterations);  // no assembly for the sensitivities
    } else {  // the matrix assembled at the converged point: factored, or GMRES that fell back to it
      EXPECT_GT(st.sensitivityFactorizations, st.steps / 2);
      EXPECT_LT(st.sensitivityReusedLu, st.steps / 2);
      if (name == "four-bar 3D") EXPECT_GT(st.sensitivityIterations, 0);
    }
    const auto& a = dd.frames.back().dp;
    const auto& b = nd.frames.back().dp;
    double worst = 0.0;
    for (size_t k = 0; k < a.size(); ++k)
      worst = std::max(worst, relErr(a[k].q, b[k].q, 1.0));
    std::printf("  %s, %s Newton: %zu parameters, max relative |dd - nd| of dq/dp at 0.5 s: %.2e\n", name.c_str(),
                newton.c_str(), a.size(), worst);
    EXPECT_LT(worst, 1e-6) << name;
    }
}

// The first step's overshoot on a stiff mode released out of equilibrium (the satellite's
// massed springs: kinetic 0 -> 23 kJ in the first 1-ms step at rho_inf 0.5). Started with the
// consistent a_0 and w_0 = a_0 (Chung-Hulbert, Arnold-Bruls), the scheme gives a mode with
// Omega = omega h >> 1 the velocity v_1 -> (1 - rho_inf)^2 / 4 h a_0 (from the recurrence:
// v_1 / h = (gamma / (2 beta) - 1)(-a_0) + O(a_0 / Omega^2), gamma / (2 beta) = (3 - rho)(1 + rho) / 4)
// instead of at most omega x_0: E_1 / E_0 grows as ((1 - rho)^2 Omega / 4)^2 (626 at rho 0.5,
// Omega 400), then decays by ~rho^2 per step. Expected here: E_1 / E_0 from the scheme's 3x3
// recurrence for x'' = -omega^2 x written in the classical (x, v, w) form, solved in the test.
TEST(GeneralizedAlpha, FirstStepOvershootOfAStiffModeFollowsTheRecurrence) {
  const double x0 = 0.1;
  for (double rho : {0.5, 0.8, 1.0})
    for (double Omega : {0.5, 10.0, 400.0}) {
      const double h = Omega / kOmega, w2 = kOmega * kOmega;
      const double am = (2 * rho - 1) / (rho + 1), af = rho / (rho + 1);
      const double gamma = 0.5 + af - am, beta = 0.25 * (1 + af - am) * (1 + af - am);
      // L (x1, v1, w1) = R (x0, v0, w0): the Newmark updates and the alpha-averaged equilibrium
      // (1 - am) w1 + am w0 = (1 - af) a1 + af a0 with a = -omega^2 x.
      Eigen::Matrix3d L, R;
      L << 1, 0, -h * h * beta, 0, 1, -h * gamma, (1 - af) * w2, 0, 1 - am;
      R << 1, h, h * h * (0.5 - beta), 0, 1, h * (1 - gamma), -af * w2, 0, -am;
      const Eigen::Vector3d y1 = L.partialPivLu().solve(R * Eigen::Vector3d(x0, 0.0, -w2 * x0));
      const double expected = (y1[1] * y1[1] + w2 * y1[0] * y1[0]) / (w2 * x0 * x0);
      const Motion r = runOscillator(rho, h, 1, x0);
      const double measured = r.energy[1] / r.energy[0];
      const double vRatio = r.v[1] / (h * -w2 * x0);  // v1 / (h a0)
      std::printf("  rho_inf %.1f, omega h = %5.1f: E1/E0 %.6g (amplification matrix %.6g), v1 / (h a0) %.5f\n", rho,
                  Omega, measured, expected, vRatio);
      EXPECT_NEAR(measured / expected, 1.0, 1e-8) << "rho_inf " << rho << ", omega h " << Omega;
      if (Omega == 400.0)  // the asymptote v1 -> (1 - rho)^2 / 4 h a0, up to O(1 / Omega^2)
        EXPECT_NEAR(vRatio, std::pow(1 - rho, 2) / 4, 10.0 / (Omega * Omega)) << "rho_inf " << rho;
      if (rho == 1.0) EXPECT_NEAR(measured, 1.0, 1e-9);  // the trapezoidal rule: no overshoot
    }
}

// The satellite's springs start in their drawn arcs, not their equilibrium shapes: their
// modes up to 4.4e5 rad/s (omega h = 440 at h = 1 ms) start out of equilibrium, with
// |a_0|_inf = 2.4e7 m/s^2. The overshoot law above, summed over them, predicts the first step's
// energy gain E_1 - E_0 ~ (1 - rho_inf)^4 h^2 / 32 a_0^T M a_0 (each mode's v_1 = (1 - rho)^2 / 4
// h a_0): measured 0.86 and 0.88 of it at h = 1e-3 and 5e-4 s (11056 and 2821 J; 0.94, 0.85 at
// 2.5e-4, 1e-4 s); the rest is the modes' finite omega h and their potential's change.
TEST(GeneralizedAlpha, SatelliteFirstStepGainIsTheOvershootOfItsSprings) {
  Scene sc = readScene(sourceDir() + "/examples/satellite/satellite.yaml");
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  StateWithSens start = initialState(as, p);
  start.dp.clear();  // the motion only
  const EnergyMeter meter(as, p);
  const double aMa = start.x.a.dot(as.mass(p) * start.x.a);  // [kg m^2 / s^4]
  const double e0 = meter.at(start.x.q, start.x.v).total();
  std::vector<double> gain;
  for (double h : {1e-3, 5e-4}) {
    IntegratorSettings set = integratorSettings("generalized_alpha", h, h);
    set.rhoInf = 0.5;
    set.frameInterval = h;
    set.newtonTol = 1e-10;
    Recorder rec;
    integrate(as, p, start, set, rec);
    gain.push_back(meter.at(rec.frames.back().x.q, rec.frames.back().x.v).total() - e0);
    const double law = std::pow(0.5, 4) * h * h / 32 * aMa;
    std::printf("  h = %.0e s: E1 - E0 = %.1f J, (1 - rho)^4 h^2 / 32 a0^T M a0 = %.1f J, ratio %.3f\n", h,
                gain.back(), law, gain.back() / law);
    EXPECT_GT(gain.back() / law, 0.75) << "h " << h;
    EXPECT_LT(gain.back() / law, 1.05) << "h " << h;
  }
  EXPECT_NEAR(gain[0] / gain[1], 4.0, 0.5);  // the overshoot's h^2
}

// A light ANCF cable (20 elements, 0.047 kg) straight at rest, bent into a 270-degree arc of
// radius 1 m and released, one end pinned: its slopes' fast modes (omega h >> 1) leave
// velocities that put the predictor q_n + h v_n out of Newton's reach at the second step (it
// failed there before Newton also tried q_n; the positions-only beam at the third). The run
// must now reach 0.03 s, and its dd sensitivity to E must still be the derivative of the
// discrete scheme (central differences of whole runs: the perturbed runs take the same starts).
TEST(GeneralizedAlpha, ReleasedPrestressedArcRunsAndKeepsExactSensitivities) {
  for (const std::string kind : {"ancf_cable", "beam"}) {
    std::string text = "dimension: 2\ngravity: [0, 0]\nnodes:\n";
    const int n = 20;
    for (int i = 0; i <= n; ++i) {
      const double t = 1.5 * M_PI * i / n;
      char line[160];
      std::snprintf(line, sizeof line, "  - {name: n%d, position: [%.17g, %.17g]%s}\n", i, std::sin(t),
                    1.0 - std::cos(t), i == 0 ? ", ground: true" : "");
      text += line;
    }
    text += "elements:\n  - {name: s, type: " + kind + ", rest_shape: straight, E: 1.0e9, density: 1.0,\n"
            "     section: {area: 0.01, inertia: 7.9577472e-6}, nodes: [n0";
    for (int i = 1; i <= n; ++i) text += ", n" + std::to_string(i);
    text += "]}\nparameters:\n  - {name: E, of: s, property: E}\n"
            "integrator: {type: generalized_alpha, rho_inf: 0.5, t_end: 0.03, dt: 1.0e-3}\n";
    Scene sc = readSceneText(text, "arc.yaml");
    Assembler as(*sc.model);
    const VecX p = sc.model->nominalParameters();
    const StateWithSens start = initialState(as, p);
    IntegratorSettings set = integratorSettings("generalized_alpha", 1e-3, 0.03);
    set.rhoInf = 0.5;
    set.frameInterval = 0.01;
    Recorder dd, nd;
    const IntegratorStats st = integrate(as, p, start, set, dd);
    EXPECT_EQ(st.steps, 30) << kind;
    integrateFiniteDifferences(as, p, start, nullptr, set, {"central", 1e-5}, nd);
    ASSERT_EQ(dd.frames.size(), nd.frames.size());
    const double e = relErr(dd.frames.back().dp[0].q, nd.frames.back().dp[0].q, 1e-12);
    std::printf("  %s arc: %ld Newton iterations in %ld steps; dq/dE at 0.03 s, max relative |dd - nd| = %.2e\n",
                kind.c_str(), st.newtonIterations, st.steps, e);
    EXPECT_LT(e, 1e-6) << kind;
  }
}

TEST(GeneralizedAlpha, RhoInfOutsideZeroToOneSaysWhatWasExpected) {
  // File, line, key, exit status and "nothing written" are checked for the CLI by the bad
  // scene tests/scenes/bad/bad_rho_inf.yaml; here the message's expectation.
  std::string text = R"(
dimension: 2
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: n1, position: [1, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [A, n1], mass: 1.0}
integrator: {type: generalized_alpha, t_end: 1, dt: 1.0e-3, rho_inf: 1.5}
)";
  try {
    readSceneText(text, "bad_rho.yaml");
    FAIL() << "rho_inf 1.5 was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad_rho.yaml:8"), std::string::npos) << msg;
    EXPECT_NE(msg.find("integrator.rho_inf"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[0, 1]"), std::string::npos) << msg;
  }
}
