// Modified Newton (integrator.newton: modified) against full Newton on the flexible five-bar
// (examples/fivebar/flexible.yaml: a steel beam between rigid bars, stiff: its axial mode is
// far above 1/h) with BDF-1 and the trapezoidal rule: the same positions to the Newton
// tolerance, the same sensitivities (both exact derivatives of the discrete step, solved with
// the kept LU as a GMRES preconditioner) to 1e-8 relative, and far fewer factorizations.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "core/Assembler.hpp"
#include "integrators/AndersonMixing.hpp"
#include "integrators/InitialState.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

struct Result {
  Recorder rec;
  IntegratorStats stats;
};

constexpr double kNewtonTol = 1e-13;

Result simulate(const std::string& type, const std::string& newton, const char* caseName) {
  const Scene sc = readScene(sourceDir() + "/examples/fivebar/flexible.yaml", caseName);
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  IntegratorSettings set = sc.integrator;
  set.type = type;
  set.dt = 1e-3;
  set.tEnd = 0.3;
  set.frameInterval = 0.1;
  set.newtonTol = kNewtonTol;
  set.newton = newton;
  Result r;
  r.stats = integrate(as, p, initialState(as, p, sc.pimCase.get()), set, r.rec);
  return r;
}

}  // namespace

TEST(ModifiedNewton, SamePositionsAndSensitivitiesAsFullNewtonWithFewerFactorizations) {
  for (const char* type : {"bdf1", "trapezoidal"})
    for (const char* caseName : {"F1", "F4"}) {  // a bar length, a spring's natural length
      SCOPED_TRACE(std::string(type) + " " + caseName);
      const Result full = simulate(type, "full", caseName);
      const Result mod = simulate(type, "modified", caseName);
      ASSERT_EQ(full.rec.frames.size(), mod.rec.frames.size());
      ASSERT_EQ(full.stats.steps, 300);
      for (size_t f = 0; f < full.rec.frames.size(); ++f) {
        const StateWithSens& a = full.rec.frames[f];
        const StateWithSens& b = mod.rec.frames[f];
        // Each step converges to the tolerance on the scaled update (modified Newton leaves up
        // to about that error, full Newton's quadratic convergence far less): over the steps
        // taken so far the differences add up to at most steps x tolerance.
        const double steps = std::round(a.x.t / 1e-3);
        EXPECT_LE((a.x.q - b.x.q).lpNorm<Eigen::Infinity>(), steps * kNewtonTol * (1 + a.x.q.lpNorm<Eigen::Infinity>()))
            << "t = " << a.x.t;
        ASSERT_EQ(a.dp.size(), 1u);
        EXPECT_LT(relErr(b.dp[0].q, a.dp[0].q), 1e-8) << "t = " << a.x.t;
        EXPECT_LT(relErr(b.dp[0].v, a.dp[0].v), 1e-8) << "t = " << a.x.t;
      }
      // Every factorization is counted: full Newton factorizes once per iteration. In most
      // steps its last one is of the converged point to round-off (the last update below
      // 1e-13 relative), which the sensitivity solve takes as is: no assembly, no iteration;
      // the other steps assemble the matrix there. Either way the sensitivities above equal
      // modified Newton's, whose GMRES works with the matrix assembled at the converged point.
      EXPECT_EQ(full.stats.factorizations, full.stats.newtonIterations + full.stats.sensitivityFactorizations);
      EXPECT_EQ(full.stats.jacobianEvaluations,
                full.stats.newtonIterations + full.stats.steps - full.stats.sensitivityReusedLu);
      EXPECT_GT(full.stats.sensitivityReusedLu, 0.9 * double(full.stats.steps));  // measured 295 of 300
      EXPECT_EQ(mod.stats.sensitivityFactorizations, 0);  // GMRES converged
      EXPECT_GT(mod.stats.sensitivityIterations, mod.stats.steps);
      // Modified Newton: measured 0.017-0.037 factorizations per step (F1, F4, bdf1 and
      // trapezoidal at newton_tol 1e-13); full Newton takes 2.9-3 per step.
      const double perStep = double(mod.stats.factorizations) / mod.stats.steps;
      std::cout << "  " << type << " " << caseName << ": full " << double(full.stats.factorizations) / full.stats.steps
                << " factorizations/step, " << double(full.stats.newtonIterations) / full.stats.steps
                << " iterations/step; modified " << perStep << " factorizations/step, "
                << double(mod.stats.newtonIterations) / mod.stats.steps << " iterations/step, "
                << double(mod.stats.sensitivityIterations) / mod.stats.steps << " sensitivity iterations/step\n";
      EXPECT_LT(perStep, 0.2);
      EXPECT_EQ(mod.stats.convergenceFailures, 0);
    }
}

TEST(ModifiedNewton, AndersonMixingAcceleratesALinearFixedPointIteration) {
  // x <- x + f(x), f(x) = B (b - A x) with B a poor approximate inverse (the chord of a stale
  // matrix): the plain iteration contracts by ~0.9 per step; type-II Anderson with depth >= dim
  // is GMRES on this linear problem (Walker and Ni 2011), so it reaches the solution in dim + 1
  // steps up to the accuracy of its least-squares fit: by normal equations (what the Newton
  // iteration needs, cheaply) 2e-4 here, where a QR of the differences gives 1.6e-10.
  const int dim = 6;
  std::srand(3);
  const MatX A = MatX::Identity(dim, dim) + 0.3 * MatX::Random(dim, dim);
  const MatX B = 0.1 * A.inverse() + 0.02 * MatX::Random(dim, dim);
  const VecX b = VecX::Random(dim), exact = A.lu().solve(b);
  auto f = [&](const VecX& x) { return VecX(B * (b - A * x)); };
  VecX plain = VecX::Zero(dim), acc = VecX::Zero(dim);
  AndersonMixing aa(AndersonMixing::kMaxDepth, dim, dim);
  for (int k = 0; k < dim + 1; ++k) {
    plain += f(plain);
    acc += aa.step(acc, f(acc));
  }
  const double ePlain = (plain - exact).norm() / exact.norm(), eAcc = (acc - exact).norm() / exact.norm();
  std::cout << "  after " << dim + 1 << " steps: plain error " << ePlain << ", Anderson " << eAcc << "\n";
  EXPECT_GT(ePlain, 0.1);
  EXPECT_LT(eAcc, 1e-3);
}

TEST(ModifiedNewton, AcceleratedOnTheSatelliteSameMotionAndSensitivitiesAsFullNewton) {
  // The massed satellite (SAT1, BDF-1 at 0.02 s, 1 s): its chord contracts slowly (the light
  // spring nodes turn within a step), so modified Newton accelerates it (kAndersonAbove: most
  // iterations); the positions stay within the Newton tolerance of full Newton's per step and
  // the sensitivities (exact derivatives of the same discrete step) within 1e-7. Fewer
  // factorizations per step than full Newton's (over this first second, ~3 against ~6; over
  // the 10 s, 1.44 against 4.32: bench/satellite/speedup.md).
  const Scene sc = readScene(sourceDir() + "/examples/satellite/satellite.yaml", "SAT1");
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  const StateWithSens start = initialState(as, p, sc.pimCase.get());
  IntegratorSettings set = sc.integrator;
  set.type = "bdf1";
  set.dt = 0.02;
  set.tEnd = 1.0;
  set.frameInterval = 0.5;
  set.newtonTol = 1e-12;
  Recorder full, mod;
  const IntegratorStats sf = integrate(as, p, start, set, full);
  set.newton = "modified";
  const IntegratorStats sm = integrate(as, p, start, set, mod);
  ASSERT_EQ(full.frames.size(), mod.frames.size());
  for (size_t i = 0; i < full.frames.size(); ++i) {
    const auto& a = full.frames[i];
    const auto& b = mod.frames[i];
    EXPECT_LE((a.x.q - b.x.q).lpNorm<Eigen::Infinity>(), 50 * 1e-12 * (1 + a.x.q.lpNorm<Eigen::Infinity>()))
        << "t = " << a.x.t;
    EXPECT_LT(relErr(b.dp[0].q, a.dp[0].q), 1e-7) << "t = " << a.x.t;
  }
  const double perStep = double(sm.factorizations) / double(sm.steps);
  std::cout << "  satellite SAT1, 1 s: full " << double(sf.factorizations) / double(sf.steps)
            << " factorizations/step; modified " << perStep << " (" << double(sm.newtonIterations) / double(sm.steps)
            << " iterations/step, " << sm.acceleratedIterations << " of " << sm.newtonIterations << " accelerated)\n";
  EXPECT_LT(perStep, 0.6 * double(sf.factorizations) / double(sf.steps));
  EXPECT_GT(sm.acceleratedIterations, sm.newtonIterations / 2);
  EXPECT_EQ(sm.convergenceFailures, 0);
}
