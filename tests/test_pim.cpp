// PIM module: the paper's Table 1 and printed q_p0 vectors, finite-difference checks of the
// PIM system (eq. 8), of SDOF and rigidization derivatives, and of the sensitivities along the
// whole motion against central differences of perturbed simulations.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "core/Assembler.hpp"
#include "integrators/InitialState.hpp"
#include "pim/Pim.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

std::string rigidScene() { return sourceDir() + "/examples/fivebar/rigid.yaml"; }
std::string flexScene() { return sourceDir() + "/examples/fivebar/flexible.yaml"; }
std::string sceneOf(const std::string& c) { return c[0] == 'R' ? rigidScene() : flexScene(); }


/// IDAS at rtol = atol = 1e-10 to tEnd, frames every 0.5 s.
IntegratorSettings idasSettings(double tEnd) {
  IntegratorSettings set;
  set.type = "idas";
  set.rtol = set.atol = 1e-10;
  set.dt = 0.0;
  set.tEnd = tEnd;
  set.frameInterval = 0.5;
  return set;
}

struct CaseRun {
  Scene sc;
  std::unique_ptr<Assembler> as;
  PimReport rep;
};

std::unique_ptr<CaseRun> load(const std::string& name) {
  auto r = std::make_unique<CaseRun>();
  r->sc = readScene(sceneOf(name), name);
  r->as = std::make_unique<Assembler>(*r->sc.model);
  return r;
}

int z2dof(const Model& m) { return m.dof(m.nodeIndex("n2"), 1); }

/// z2 at the given times from a simulation started at `start` (no sensitivities).
std::vector<double> z2Series(const CaseRun& r, const VecX& p, StateWithSens start,
                             const IntegratorSettings& set, const std::vector<double>& times) {
  Recorder rec;
  start.dp.clear();
  integrate(*r.as, p, start, set, rec);
  std::vector<double> out;
  for (double t : times) out.push_back(rec.at(t).x.q[z2dof(*r.sc.model)]);
  return out;
}

/// Checks dz2/dp of `set`'s integrator against central differences of simulations from the
/// nonlinear perturbed initial configurations at p +/- h.
void checkAgainstFiniteDifferences(const std::string& name, IntegratorSettings set,
                                   const std::vector<double>& times, double h, double rel, double abs) {
  auto r = load(name);
  const VecX p0 = r->sc.model->nominalParameters();
  const StateWithSens start = initialState(*r->as, p0, r->sc.pimCase.get(), &r->rep);
  Recorder rec;
  integrate(*r->as, p0, start, set, rec);
  std::vector<double> fd(times.size(), 0.0);
  for (int sgn : {1, -1}) {
    VecX p = p0;
    p[0] += sgn * h;
    State s;
    s.q = perturbedConfiguration(*r->as, *r->sc.pimCase, start.x.q, p0, p, 0);
    s.v = VecX::Zero(s.q.size());  // q'_0 = 0 and z'_p0 = 0 in every case of Table 1
    auto z = [&] {
      StateWithSens st;
      st.x = s;
      solveAccelerations(*r->as, st.x, p);
      return z2Series(*r, p, st, set, times);
    }();
    for (size_t i = 0; i < times.size(); ++i) fd[i] += sgn * z[i] / (2 * h);
  }
  for (size_t i = 0; i < times.size(); ++i) {
    const double dd = rec.at(times[i]).dp[0].q[z2dof(*r->sc.model)];
    std::printf("  %-4s t = %.2f s: dz2/dp = %+.9e (sensitivity)  %+.9e (central FD)\n", name.c_str(),
                times[i], dd, fd[i]);
    EXPECT_LE(std::abs(dd - fd[i]), std::max(rel * std::abs(fd[i]), abs)) << name << " t = " << times[i];
  }
}

}  // namespace

TEST(Pim, TableOneSizes) {
  // The paper's Table 1: n, m, d, m_r, d_s per case.
  struct Row { const char* name; int n, m, d, mr, ds; };
  for (const Row& row : {Row{"R1", 6, 4, 2, 0, 2}, Row{"R2", 6, 4, 2, 0, 2}, Row{"R3", 6, 4, 2, 0, 2},
                         Row{"F1", 8, 3, 5, 5, 0}, Row{"F2", 8, 3, 5, 3, 2}, Row{"F3", 8, 3, 5, 4, 1},
                         Row{"F4", 8, 3, 5, 5, 0}, Row{"F5", 8, 3, 5, 4, 1}, Row{"F6", 8, 3, 5, 4, 1}}) {
    auto r = load(row.name);
    initialState(*r->as, r->sc.model->nominalParameters(), r->sc.pimCase.get(), &r->rep);
    EXPECT_EQ(r->rep.n, row.n) << row.name;
    EXPECT_EQ(r->rep.m, row.m) << row.name;
    EXPECT_EQ(r->rep.d, row.d) << row.name;
    EXPECT_EQ(r->rep.mr, row.mr) << row.name;
    EXPECT_EQ(r->rep.ds, row.ds) << row.name;
  }
}

TEST(Pim, PrintedInitialSensitivitiesOfR1AndF1AndNullF5) {
  auto qp = [](const std::string& c) {
    auto r = load(c);
    initialState(*r->as, r->sc.model->nominalParameters(), r->sc.pimCase.get(), &r->rep);
    return VecX(r->rep.qp.col(0));
  };
  VecX r1(6), f1(8);
  r1 << -0.5657, -0.8485, 0, 0, 0, 0;                                   // paper, eq. (A.4)
  f1 << 1.4142, -2.8284, 2.8284, -0.7071, 1.4142, 1.4142, 2.1213, -1.7678;  // paper, eq. (A.13)
  EXPECT_LT((qp("R1") - r1).lpNorm<Eigen::Infinity>(), 1e-4);
  EXPECT_LT((qp("F1") - f1).lpNorm<Eigen::Infinity>(), 1e-4);
  EXPECT_LT(qp("F5").lpNorm<Eigen::Infinity>(), 1e-12);
  // Physical expectations stated in the paper: R2 raises z2's sensitivity, R3 lowers it.
  EXPECT_GT(qp("R2")[3], 0.0);
  EXPECT_LT(qp("R3")[3], 0.0);
}

TEST(Pim, InitialSensitivitiesAreDerivativesOfThePerturbedInitialModel) {
  // Eq. (8) checked against central differences of the nonlinear PIM assembly, every case.
  for (const char* name : {"R1", "R2", "R3", "F1", "F2", "F3", "F4", "F5", "F6", "F2R", "F6R"}) {
    auto r = load(name);
    const VecX p0 = r->sc.model->nominalParameters();
    const StateWithSens s = initialState(*r->as, p0, r->sc.pimCase.get(), &r->rep);
    const double h = 1e-6;
    VecX pp = p0, pm = p0;
    pp[0] += h;
    pm[0] -= h;
    const VecX fd = (perturbedConfiguration(*r->as, *r->sc.pimCase, s.x.q, p0, pp, 0) -
                     perturbedConfiguration(*r->as, *r->sc.pimCase, s.x.q, p0, pm, 0)) / (2 * h);
    EXPECT_LT((s.dp[0].q - fd).lpNorm<Eigen::Infinity>(), 1e-8) << name;
  }
}

TEST(Pim, SdofAndRigidizationDerivativesMatchFiniteDifferences) {
  auto r = load("F2");
  const Model& m = *r->sc.model;
  const VecX p = m.nominalParameters();
  std::srand(3);
  const VecX q = m.initialPositions() + 0.05 * VecX::Random(m.n);
  for (const auto& z : r->sc.pimCase->sdofs) {
    const MatX g = fdJacobian([&](const VecX& x) { return VecX::Constant(1, z->value(m, x)); }, q);
    EXPECT_LT(relErr(z->gradient(m, q), VecX(g.transpose())), 1e-8) << z->name;
    const MatX H = fdJacobian([&](const VecX& x) { return z->gradient(m, x); }, q);
    EXPECT_LT(relErr(z->hessian(m, q), H), 1e-7) << z->name;
  }
  const Assembler lam(m, &r->sc.pimCase->lambda);
  ASSERT_EQ(lam.m(), 3);
  SparseAccumulator acc;
  acc.begin(lam.m(), m.n);
  lam.addPhiQ(acc, q, p, 1.0, 0, 0, false);
  EXPECT_LT(relErr(MatX(acc.finish()), fdJacobian([&](const VecX& x) { return lam.phi(x, p); }, q)), 1e-8);
}

TEST(Pim, TrapezoidalDiscreteSensitivitiesMatchFiniteDifferencesForEveryCase) {
  IntegratorSettings set;
  set.type = "trapezoidal";
  set.dt = 1e-3;
  set.frameInterval = 0.5;
  set.newtonTol = 1e-14;
  // Rigid cases to 1 s: beyond, their finite differences stop converging (see below).
  set.tEnd = 1.0;
  for (const char* name : {"R1", "R2", "R3"}) checkAgainstFiniteDifferences(name, set, {0.5, 1.0}, 1e-5, 1e-5, 1e-7);
  set.tEnd = 2.0;
  for (const char* name : {"F1", "F2", "F3", "F4", "F5", "F6", "F1R", "F2R", "F3R", "F4R", "F5R", "F6R"})
    checkAgainstFiniteDifferences(name, set, {0.5, 1.0, 2.0}, 1e-5, 1e-5, 1e-7);
}

namespace {

/// Central difference (step h in p) of z2 from trapezoidal simulations (step dt) of the
/// nonlinear perturbed initial models.
std::vector<double> referenceDerivative(const std::string& name, const std::vector<double>& times,
                                        double dt, double h) {
  auto r = load(name);
  const VecX p0 = r->sc.model->nominalParameters();
  const StateWithSens start = initialState(*r->as, p0, r->sc.pimCase.get());
  std::vector<double> out(times.size(), 0.0);
  {
    const double step = dt;
    IntegratorSettings set;
    set.type = "trapezoidal";
    set.dt = step;
    set.tEnd = times.back();
    set.frameInterval = 0.5;
    set.newtonTol = 1e-14;
    const double w = 1.0;
    for (int sgn : {1, -1}) {
      VecX p = p0;
      p[0] += sgn * h;
      StateWithSens st;
      st.x.q = perturbedConfiguration(*r->as, *r->sc.pimCase, start.x.q, p0, p, 0);
      st.x.v = VecX::Zero(st.x.q.size());
      solveAccelerations(*r->as, st.x, p);
      const auto z = z2Series(*r, p, st, set, times);
      for (size_t i = 0; i < times.size(); ++i) out[i] += w * sgn * z[i] / (2 * h);
    }
  }
  return out;
}

void checkIdasCase(const std::string& name, const std::vector<double>& times, double dt,
                   double rel, double abs = 1e-7) {
  auto r = load(name);
  const VecX p0 = r->sc.model->nominalParameters();
  const IntegratorSettings set = idasSettings(times.back());
  Recorder rec;
  integrate(*r->as, p0, initialState(*r->as, p0, r->sc.pimCase.get()), set, rec);
  const auto ref = referenceDerivative(name, times, dt, 1e-5);
  for (size_t i = 0; i < times.size(); ++i) {
    const double dd = rec.at(times[i]).dp[0].q[z2dof(*r->sc.model)];
    std::printf("  %-4s t = %.2f s: dz2/dp = %+.9e (IDAS rtol 1e-10)  %+.9e (central FD)  rel. diff %.1e\n",
                name.c_str(), times[i], dd, ref[i], std::abs(dd - ref[i]) / std::abs(ref[i]));
    EXPECT_LE(std::abs(dd - ref[i]), std::max(rel * std::abs(ref[i]), abs)) << name << " t = " << times[i];
  }
}

}  // namespace

// Central differences of perturbed simulations are limited by the mechanism itself: the
// symmetric rigid motion amplifies perturbations, so z2(p) computed with any integrator
// carries noise that the difference quotient magnifies. Measured for R1 at t = 1 s, trapezoidal
// dt = 1e-4 s: h = 4e-5 ... 1e-6 give -0.152712, -0.152707, -0.152701, -0.152710, -0.152725,
// -0.152711 around the converged sensitivity -0.1527058 (spread ~1.5e-4 relative); at t = 2 s
// they do not converge at all (h = 1e-4 ... 1e-7: -0.455, 0.025, 0.054, 0.054 vs 0.054). Hence
// 1e-5 at t = 0.5 s, 1e-4 at t = 1 s, and the converged-reference test below for all times.
TEST(Pim, IdasSensitivitiesMatchFiniteDifferencesRigidCases) {
  for (const char* name : {"R1", "R2", "R3"}) {
    checkIdasCase(name, {0.5}, 1e-4, 1e-5);
    checkIdasCase(name, {1.0}, 1e-4, 1e-4);
  }
}

// Flexible cases, all six to 2 s. The references carry noise of their own: the trapezoidal
// rule does not damp the beam's axial vibration (period ~1.5 ms), which round-off keeps
// excited, so even its discrete sensitivities scatter by ~1e-4 relative as dt shrinks (F5 at
// t = 2 s: dt = 1e-4, 5e-5, 2.5e-5, 1.25e-5 give 0.133659, 0.133662, 0.133663, 0.133650),
// while IDAS converges in rtol (1e-9, 1e-10, 1e-11 give 0.13363737, 0.13363742, 0.13363742).
// Measured agreement with the dt = 1e-4 references: 1e-6 ... 5e-5 relative, 1.8e-5 absolute
// on F2's near-zero value at 2 s and 1.9e-5 on F5 at 2 s. The bound must cover the
// references' own scatter, up to 2.6e-5 absolute (F5 above): 1e-4 relative or 3e-5 absolute.
TEST(Pim, IdasSensitivitiesMatchFiniteDifferencesFlexibleCases) {
  for (const char* name : {"F1", "F2", "F3", "F4", "F5", "F6"})
    checkIdasCase(name, {0.5, 1.0, 2.0}, 1e-4, 1e-4, 3e-5);
}

// Converged reference: the trapezoidal rule's exact discrete sensitivities at dt = 5e-5 s
// (measured to converge to IDAS: R1 at t = 1 s, dt = 1e-3, 2e-4, 1e-4, 5e-5 give -0.1527124,
// -0.1527061, -0.15270588, -0.15270582 against IDAS -0.15270585).
TEST(Pim, IdasSensitivitiesMatchConvergedTrapezoidalSensitivities) {
  for (const char* name : {"R1", "R2", "R3"}) {
    auto r = load(name);
    const VecX p0 = r->sc.model->nominalParameters();
    const StateWithSens start = initialState(*r->as, p0, r->sc.pimCase.get());
    IntegratorSettings set = idasSettings(2.0);
    Recorder idas, trap;
    integrate(*r->as, p0, start, set, idas);
    set.type = "trapezoidal";
    set.dt = 5e-5;
    set.newtonTol = 1e-14;
    integrate(*r->as, p0, start, set, trap);
    for (double t : {0.5, 1.0, 2.0}) {
      const double a = idas.at(t).dp[0].q[z2dof(*r->sc.model)], b = trap.at(t).dp[0].q[z2dof(*r->sc.model)];
      // At t = 2 s dz2/dp is a small difference of large coordinate sensitivities (|q_p| up
      // to ~3e4: the horizontal sensitivities grow through the symmetric motion): measure it
      // against the size of q_p there.
      const double scale = t < 1.5 ? std::abs(b) : trap.at(t).dp[0].q.lpNorm<Eigen::Infinity>();
      std::printf("  %s t = %.1f s: dz2/dp IDAS %+.9e  trapezoidal(5e-5) %+.9e  |q_p|_inf %.3e\n", name, t,
                  a, b, trap.at(t).dp[0].q.lpNorm<Eigen::Infinity>());
      EXPECT_LE(std::abs(a - b), std::max((t < 1.5 ? 1e-5 : 1e-4) * scale, 1e-7)) << name << " t = " << t;
    }
  }
}

TEST(Pim, TrapezoidalSensitivitiesConvergeToIdasAtOrderTwo) {
  auto r = load("R1");
  const VecX p0 = r->sc.model->nominalParameters();
  const StateWithSens start = initialState(*r->as, p0, r->sc.pimCase.get());
  IntegratorSettings set = idasSettings(2.0);
  Recorder idas;
  integrate(*r->as, p0, start, set, idas);
  std::vector<double> err;
  for (double dt : {2e-3, 1e-3, 5e-4}) {
    set.type = "trapezoidal";
    set.dt = dt;
    set.newtonTol = 1e-14;
    Recorder trap;
    integrate(*r->as, p0, start, set, trap);
    double e = 0.0;
    for (double t : {0.5, 1.0, 1.5, 2.0})
      e = std::max(e, (trap.at(t).dp[0].q - idas.at(t).dp[0].q).lpNorm<Eigen::Infinity>());
    err.push_back(e);
  }
  for (size_t i = 1; i < err.size(); ++i) {
    const double order = std::log2(err[i - 1] / err[i]);
    std::printf("  max |q_p(trapezoidal) - q_p(IDAS)| %.3e -> %.3e: order %.2f\n", err[i - 1], err[i], order);
    EXPECT_NEAR(order, 2.0, 0.25);
  }
}
