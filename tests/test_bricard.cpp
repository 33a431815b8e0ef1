// Bricard's mechanism (IFToMM benchmark A04, examples/iftomm/bricard.yaml): five rods and six
// revolute joints, an overconstrained loop (Grubler 0, mobility 1) that every run used to stop
// on at t = 0 ("augmented matrix singular"). With the dependent row left out it runs 10 s on
// each integrator; the checks are independent of the code: every constraint row (the left-out
// one included) below 1e-8, energy conserved (no damping, no loads but gravity), the schemes
// agreeing with IDAS at tight tolerance, and the sensitivity against central differences.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "core/RedundantRows.hpp"
#include "integrators/InitialState.hpp"
#include "output/Energy.hpp"

using namespace flexsens;

namespace {

const std::string kScene = std::string(FLEXSENS_SOURCE_DIR) + "/examples/iftomm/bricard.yaml";

struct Watch : Observer {
  const Model* m = nullptr;
  const Assembler* as = nullptr;
  const VecX* p = nullptr;
  const EnergyMeter* meter = nullptr;
  double maxPhi = 0, maxLeftOut = 0, e0 = 0, maxRise = 0, maxFall = 0;
  bool first = true;
  VecX qEnd, qpEnd;
  void frame(const StateWithSens& s) override {
    maxPhi = std::max(maxPhi, as->phi(s.x.q, *p).lpNorm<Eigen::Infinity>());
    maxLeftOut = std::max(maxLeftOut, leftOutViolation(*m, *as, s.x.q, *p));
    const double e = meter->at(s.x.q, s.x.v).total();
    if (first) e0 = e, first = false;
    maxRise = std::max(maxRise, e - e0);
    maxFall = std::max(maxFall, e0 - e);
    qEnd = s.x.q;
    if (!s.dp.empty()) qpEnd = s.dp[0].q;
  }
};

Watch runBricard(const Scene& sc, const std::string& type, double dtOrTol, double tEnd, double mass3) {
  const Model& m = *sc.model;
  Assembler as(m);
  VecX p = m.nominalParameters();
  p[0] = mass3;
  const EnergyMeter meter(as, p);
  Watch w;
  w.m = &m, w.as = &as, w.p = &p, w.meter = &meter;
  IntegratorSettings set = test::integratorSettings(type, dtOrTol, tEnd);
  set.frameInterval = 0.1;
  integrate(as, p, initialState(as, p), set, w);
  return w;
}

}  // namespace

TEST(Bricard, LeftOutRowAndOneDegreeOfFreedom) {
  const Scene sc = readScene(kScene);
  EXPECT_EQ(sc.model->n, 24);
  EXPECT_EQ(sc.model->n - sc.model->m, 1);  // mobility 1, as the geometry gives
  EXPECT_EQ(sc.model->redundantRows.size(), 1u);
}

// 10 s on the implicit schemes and IDAS; energy scale: the potential swing is ~4.6 J.
TEST(Bricard, RunsTenSecondsOnEveryIntegratorWithConstraintsAndEnergyKept) {
  const Scene sc = readScene(kScene);
  const int y3 = sc.model->nodes[sc.model->nodeIndex("P3")].firstDof + 1;
  const Watch ref = runBricard(sc, "idas", 1e-10, 10.0, 1.0);
  EXPECT_LT(ref.maxPhi, 1e-8);
  EXPECT_LT(ref.maxLeftOut, 1e-8);
  EXPECT_LT(std::max(ref.maxRise, ref.maxFall), 1e-6);
  struct Case { const char* type; double dt, energyBound, position; };
  for (const Case& c : {Case{"trapezoidal", 1e-3, 1e-5, 1e-6}, Case{"generalized_alpha", 1e-3, 1e-5, 1e-6},
                        Case{"bdf1", 1e-3, 0.3, 0.05}}) {
    const Watch w = runBricard(sc, c.type, c.dt, 10.0, 1.0);
    EXPECT_LT(w.maxPhi, 1e-8) << c.type;
    EXPECT_LT(w.maxLeftOut, 1e-8) << c.type;
    EXPECT_LT(w.maxRise, 1e-5) << c.type << ": gained energy";  // trapezoidal 8.2e-7 J measured
    EXPECT_LT(w.maxFall, c.energyBound) << c.type;  // BDF-1's numerical damping: 0.21 J measured
    EXPECT_LT((w.qEnd - ref.qEnd).lpNorm<Eigen::Infinity>(), c.position) << c.type;
  }
  // maggi_rk4 (12 factorizations a step): 2 s, against IDAS over the same span.
  const Watch m2 = runBricard(sc, "maggi_rk4", 1e-3, 2.0, 1.0);
  const Watch r2 = runBricard(sc, "idas", 1e-10, 2.0, 1.0);
  EXPECT_LT(m2.maxPhi, 1e-8);
  EXPECT_LT((m2.qEnd - r2.qEnd).lpNorm<Eigen::Infinity>(), 1e-7);
  // The sensitivity to rod 3's mass against central differences of IDAS runs (3 s). Step
  // 1e-3: IDAS at rtol 1e-10 carries errors of ~1e-8 that change with round-off (the LU's
  // ordering), which a step of 1e-4 turned into differences of 1e-5 (the bound); the
  // truncation error of 1e-3 is ~1e-6.
  const double h = 1e-3;
  const Watch nom = runBricard(sc, "idas", 1e-10, 3.0, 1.0);
  const Watch up = runBricard(sc, "idas", 1e-10, 3.0, 1.0 + h), dn = runBricard(sc, "idas", 1e-10, 3.0, 1.0 - h);
  const VecX cd = (up.qEnd - dn.qEnd) / (2 * h);
  ASSERT_EQ(nom.qpEnd.size(), cd.size());
  EXPECT_GT(std::abs(cd[y3]), 1e-3);  // the mass does move the mechanism
  EXPECT_LT((nom.qpEnd - cd).lpNorm<Eigen::Infinity>(), 1e-5 * std::max(1.0, cd.lpNorm<Eigen::Infinity>()));
}
