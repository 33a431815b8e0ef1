// Sensitivity methods on the same case and outputs: dd (analytic direct differentiation),
// dq (IDAS' internal difference quotients), nd (finite differences of perturbed runs).
// Each is compared with a reference it cannot share errors with, within the accuracy the
// method can reach (bounds stated per test).
#include <gtest/gtest.h>

#include <cmath>

#include "TestModels.hpp"
#include "app/FiniteDifferences.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

struct Case {
  Scene sc;
  std::unique_ptr<Assembler> as;
  VecX p;
  StateWithSens start;
  int z2;
};

std::unique_ptr<Case> load(const std::string& file, const std::string& name) {
  auto c = std::make_unique<Case>();
  c->sc = readScene(sourceDir() + "/examples/fivebar/" + file, name);
  c->as = std::make_unique<Assembler>(*c->sc.model);
  c->p = c->sc.model->nominalParameters();
  c->start = initialState(*c->as, c->p, c->sc.pimCase.get());
  const Model& m = *c->sc.model;
  c->z2 = m.dof(m.nodeIndex("n2"), 1);
  return c;
}


double dz2(const Recorder& r, const Case& c, double t) { return r.at(t).dp[0].q[c.z2]; }

}  // namespace

TEST(Methods, NumericalDifferencesMatchDirectDifferentiationOfTheSameScheme) {
  // The trapezoidal rule's dd sensitivities are the exact derivative of the discrete
  // scheme, so central nd (relative step 1e-5) of the same scheme must agree up to its
  // truncation and round-off: 1e-5 relative (rigid R1 to 1 s, flexible F1 and F4 to 2 s).
  for (const auto& [file, name, tEnd] : {std::tuple<std::string, std::string, double>{"rigid.yaml", "R1", 1.0},
                                         {"flexible.yaml", "F1", 2.0}, {"flexible.yaml", "F4", 2.0}}) {
    auto c = load(file, name);
    const auto set = integratorSettings("trapezoidal", 1e-3, tEnd);
    Recorder dd, nd;
    integrate(*c->as, c->p, c->start, set, dd);
    integrateFiniteDifferences(*c->as, c->p, c->start, c->sc.pimCase.get(), set, {"central", 1e-5}, nd);
    ASSERT_EQ(dd.frames.size(), nd.frames.size());
    for (size_t f = 1; f < dd.frames.size(); ++f) {
      const double t = dd.frames[f].x.t, a = dz2(dd, *c, t), b = dz2(nd, *c, t);
      std::printf("  %s t = %.1f s: dd %+.9e  nd %+.9e\n", name.c_str(), t, a, b);
      EXPECT_LE(std::abs(a - b), 1e-5 * std::abs(a) + 1e-8) << name << " t = " << t;
    }
  }
}

TEST(Methods, ForwardDifferencesAreFirstOrderInTheStep) {
  // Forward nd error ~ h: halving the step halves the error (against dd of the same scheme).
  auto c = load("flexible.yaml", "F1");
  const auto set = integratorSettings("trapezoidal", 1e-3, 0.5);
  Recorder dd;
  integrate(*c->as, c->p, c->start, set, dd);
  std::vector<double> err;
  for (double h : {1e-3, 5e-4}) {
    Recorder nd;
    integrateFiniteDifferences(*c->as, c->p, c->start, c->sc.pimCase.get(), set, {"forward", h}, nd);
    err.push_back(std::abs(dz2(nd, *c, 0.5) - dz2(dd, *c, 0.5)));
  }
  std::printf("  forward nd error %.3e (h = 1e-3) -> %.3e (h = 5e-4)\n", err[0], err[1]);
  EXPECT_NEAR(err[0] / err[1], 2.0, 0.2);
}

TEST(Methods, IdasDifferenceQuotientsWorkAtLooseToleranceOnly) {
  // At rtol 1e-4, dd and dq both approximate the converged sensitivity (dd at rtol 1e-10)
  // to what that tolerance allows: at t = 1 s the error depends on which steps IDAS' error
  // test accepted, which round-off decides: with four variants of the sparse LU (orderings,
  // pivot tolerances, refinement) dd was off by 7.5e-5 .. 5.7e-3 and dq by 1.1e-3 .. 2.1e-3
  // relative (at t = 0.5 s: 4.5e-4 and 1.1e-4 every time); a fifth (the constant Hessians'
  // zeros out of the matrix pattern, so another AMD ordering) put dd 1.7e-2 off at t = 1 s
  // (dq 7.8e-3; 5.1e-4 and 1.5e-4 at 0.5 s). Bound 1e-2 = 100 rtol, dd at t = 1 s 3e-2: the
  // rigid five-bar amplifies what rtol 1e-4 lets through. Tighter tolerances make the difference-quotient residual
  // too inaccurate for the corrector: IDAS may stop with IDA_CONV_FAIL (the CLI run of R1
  // at rtol 1e-6 stops near t = 0.55 s with that diagnostic), never writing wrong numbers.
  auto c = load("rigid.yaml", "R1");
  Recorder ref, dq, dd;
  integrate(*c->as, c->p, c->start, integratorSettings("idas", 1e-10, 1.0), ref);
  auto loose = integratorSettings("idas", 1e-4, 1.0);
  integrate(*c->as, c->p, c->start, loose, dd);
  loose.sensitivityMethod = "dq";
  integrate(*c->as, c->p, c->start, loose, dq);
  for (double t : {0.5, 1.0}) {
    const double r = dz2(ref, *c, t);
    std::printf("  t = %.1f s: reference %+.9e  dd(1e-4) %+.9e  dq(1e-4) %+.9e\n", t, r, dz2(dd, *c, t), dz2(dq, *c, t));
    EXPECT_LE(std::abs(dz2(dq, *c, t) - r), 1e-2 * std::abs(r));
    EXPECT_LE(std::abs(dz2(dd, *c, t) - r), (t < 0.75 ? 1e-2 : 3e-2) * std::abs(r));
  }
}

TEST(Methods, AutomaticDifferentiationReproducesDirectDifferentiation) {
  // ad and dd solve the same tangent linear model; only the partials' source differs
  // (AD of the kernels versus hand-written derivatives), so they agree to round-off with a
  // fixed-step integrator (bound 1e-9 relative) and to the tolerance's control with IDAS.
  auto c = load("flexible.yaml", "F2");
  Assembler adAs(*c->sc.model, Derivatives::AutomaticDifferentiation);
  const StateWithSens adStart = initialState(adAs, c->p, c->sc.pimCase.get());
  const auto set = integratorSettings("trapezoidal", 1e-3, 1.0);
  Recorder dd, ad;
  integrate(*c->as, c->p, c->start, set, dd);
  integrate(adAs, c->p, adStart, set, ad);
  for (double t : {0.5, 1.0}) {
    std::printf("  F2 t = %.1f s: dd %+.12e  ad %+.12e\n", t, dz2(dd, *c, t), dz2(ad, *c, t));
    EXPECT_LE(std::abs(dz2(dd, *c, t) - dz2(ad, *c, t)), 1e-9 * std::abs(dz2(dd, *c, t)));
  }
  auto r = load("rigid.yaml", "R1");
  Assembler adR(*r->sc.model, Derivatives::AutomaticDifferentiation);
  const auto iset = integratorSettings("idas", 1e-8, 1.0);
  Recorder idd, iad;
  integrate(*r->as, r->p, r->start, iset, idd);
  integrate(adR, r->p, initialState(adR, r->p, r->sc.pimCase.get()), iset, iad);
  for (double t : {0.5, 1.0}) EXPECT_LE(std::abs(dz2(idd, *r, t) - dz2(iad, *r, t)), 1e-6 * std::abs(dz2(idd, *r, t)));
}
