// The four-panel satellite (examples/satellite): 3D rigid body, bent 3D beams released from
// their prestressed shape, point-on-plane constraints fixed to the moving cube, Gmsh-built
// geometry, and the PIM cases SAT1/SAT2.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "TestModels.hpp"
#include "app/FiniteDifferences.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

struct Satellite {
  Scene sc;
  std::unique_ptr<Assembler> as;
  VecX p;
  PimReport pim;
  StateWithSens start;
};

std::unique_ptr<Satellite> load(const std::string& caseName, const std::string& file = "satellite.yaml") {
  auto s = std::make_unique<Satellite>();
  s->sc = readScene(sourceDir() + "/examples/satellite/" + file, caseName);
  s->as = std::make_unique<Assembler>(*s->sc.model);
  s->p = s->sc.model->nominalParameters();
  s->start = initialState(*s->as, s->p, s->sc.pimCase.get(), &s->pim);
  return s;
}

IntegratorSettings bdf1(double tEnd) {
  IntegratorSettings set;
  set.type = "bdf1";
  set.dt = 0.02;
  set.tEnd = tEnd;
  set.frameInterval = 1.0;
  set.newtonTol = 1e-13;
  return set;
}

}  // namespace

TEST(Satellite, CountsOfTheModelAndOfThePimCases) {
  // 165 nodes: cube 9 (A1-A4, C1, S1-S4), springs 4 x 19 interior, panel beams 8 x 9 interior,
  // B1-B8: n = 495. m = cube 6 + 5 x 3 attached + 4 bars + 4 x 20 spring nodes on their
  // planes (S_i belongs to the cube) = 105. The PIM's rank-revealing count: 455 rigidization
  // equations generated, 75 implied by the constraints (out-of-plane rows of the planar
  // springs), m_r = 380, d - m_r = 10 = the SDOFs given.
  auto s = load("SAT1");
  EXPECT_EQ(s->pim.n, 495);
  EXPECT_EQ(s->pim.m, 105);
  EXPECT_EQ(s->pim.d, 390);
  EXPECT_EQ(s->pim.mr, 380);
  EXPECT_EQ(s->pim.ds, 10);
  EXPECT_LT(s->pim.condition, 1e5);
  // SAT1: every SDOF keeps its value; SAT2 pushes B2 out of the panel plane with dx/dp = 4.
  const Model& m = *s->sc.model;
  const int xB2 = m.dof(m.nodeIndex("B2"), 0);
  EXPECT_NEAR(s->start.dp[0].q[xB2], 0.0, 1e-12);
  auto s2 = load("SAT2");
  EXPECT_NEAR(s2->start.dp[0].q[xB2], 4.0, 1e-12);
  // Both start on the constraints and the bar length sensitivity: |B1 - B2| grows with p.
  const int B1 = m.nodeIndex("B1"), B2 = m.nodeIndex("B2");
  const Eigen::Vector3d d = m.nodes[B2].position - m.nodes[B1].position;
  const Eigen::Vector3d dd = s2->start.dp[0].q.segment<3>(m.dof(B2, 0)) - s2->start.dp[0].q.segment<3>(m.dof(B1, 0));
  EXPECT_NEAR(d.normalized().dot(dd), 1.0, 1e-9);  // d|B1B2|/dL = 1
}

// The non-flat variant (satellite_nonflat.yaml: B3, B5, B8 lifted 5 cm out of their panels'
// planes): each rigidized panel truss is then rigid at first order, so the rank-revealing count
// leaves exactly the paper's 7 SDOFs (cube 6 + x_B2), with x_B2's sensitivity 0 (SAT1) and 4
// (SAT2) at t = 0, and the initial sensitivities on the constraints: Phi_q q_p + Phi_p = 0.
TEST(Satellite, NonFlatPanelsNeedExactlyThePapersSevenSdofs) {
  for (const char* name : {"SAT1", "SAT2"}) {
    auto s = load(name, "satellite_nonflat.yaml");
    EXPECT_EQ(s->pim.d - s->pim.mr, 7) << name;
    EXPECT_EQ(s->pim.ds, 7) << name;
    const Model& m = *s->sc.model;
    const int xB2 = m.dof(m.nodeIndex("B2"), 0);
    EXPECT_NEAR(s->start.dp[0].q[xB2], std::string(name) == "SAT1" ? 0.0 : 4.0, 1e-12) << name;
    const VecX r = s->as->phiQTimes(s->start.x.q, s->p, s->start.dp[0].q) + s->as->phiParamDerivative(s->start.x.q, s->p, 0);
    EXPECT_LT(r.lpNorm<Eigen::Infinity>(), 1e-9) << name;
    EXPECT_GT((m.nodes[m.nodeIndex("B3")].position - m.nodes[m.nodeIndex("B7")].position).norm(), 0.04);
  }
}

// The ANCF version (satellite_ancf.yaml: panel beams and springs as ANCF cables, the pins
// between chains as separate nodes with spherical joints) next to the positions-only one:
// the same d - m_r and SDOFs, and q_p0, v_p0 equal on every shared coordinate (both are the
// rigid-body kinematics of the same rigidized panels, springs and cube); the slopes carry the rest.
TEST(Satellite, AncfVersionHasThePositionsOnlyCountsAndInitialSensitivities) {
  for (const char* name : {"SAT1", "SAT2"}) {
    auto a = load(name, "satellite_ancf.yaml"), b = load(name);
    EXPECT_EQ(a->pim.d - a->pim.mr, b->pim.d - b->pim.mr) << name;
    EXPECT_EQ(a->pim.ds, b->pim.ds) << name;
    const Model &ma = *a->sc.model, &mb = *b->sc.model;
    const double scale = std::max(1.0, b->start.dp[0].q.lpNorm<Eigen::Infinity>());
    std::map<std::string, int> inA;
    for (int j = 0; j < ma.n; ++j) inA[ma.coordinateLabel(j)] = j;
    int shared = 0;
    double worst = 0;
    for (int i = 0; i < mb.n; ++i) {
      const auto it = inA.find(mb.coordinateLabel(i));
      if (it == inA.end()) continue;
      worst = std::max({worst, std::abs(a->start.dp[0].q[it->second] - b->start.dp[0].q[i]),
                        std::abs(a->start.dp[0].v[it->second] - b->start.dp[0].v[i])});
      ++shared;
    }
    std::printf("  %s: n = %d (ANCF) vs %d, %d shared coordinates, max |q_p0, v_p0 difference| = %.2e\n", name,
                ma.n, mb.n, shared, worst);
    EXPECT_EQ(shared, mb.n) << name;
    EXPECT_LT(worst, 1e-10 * scale) << name;
  }
}

// BDF-1's discrete sensitivities of the ANCF satellite are the exact derivative of its
// discrete solution: central differences of the same scheme, SAT2, t = 0.5 and 1 s, 1e-6.
TEST(Satellite, AncfBdf1SensitivitiesMatchCentralDifferences) {
  auto s = load("SAT2", "satellite_ancf.yaml");
  IntegratorSettings set = bdf1(1.0);
  set.frameInterval = 0.5;
  Recorder dd, nd;
  const auto st = integrate(*s->as, s->p, s->start, set, dd);
  EXPECT_LT(st.maxConstraintViolation, 1e-10);
  integrateFiniteDifferences(*s->as, s->p, s->start, s->sc.pimCase.get(), set, {"central", 1e-5}, nd);
  for (double t : {0.5, 1.0}) {
    const double e = relErr(dd.at(t).dp[0].q, nd.at(t).dp[0].q, 1e-12);
    std::printf("  ANCF SAT2 t = %.1f s: max relative |dd - nd| = %.2e\n", t, e);
    EXPECT_LT(e, 1e-6) << "t = " << t;
  }
}

TEST(Satellite, Bdf1SensitivitiesMatchCentralDifferencesAt1_5_10s) {
  // BDF-1's discrete sensitivities are the exact derivative of the discrete solution: central
  // differences of the same scheme from PIM-consistent perturbed starts must agree to 1e-6
  // relative (all coordinates), t = 1, 5, 10 s, SAT1 and SAT2. The cube stays rigid.
  for (const char* name : {"SAT1", "SAT2"}) {
    auto s = load(name);
    const auto set = bdf1(10.0);
    Recorder dd, nd;
    const auto st = integrate(*s->as, s->p, s->start, set, dd);
    EXPECT_LT(st.maxConstraintViolation, 1e-10) << name;
    integrateFiniteDifferences(*s->as, s->p, s->start, s->sc.pimCase.get(), set, {"central", 1e-5}, nd);
    const int xB2 = s->sc.model->dof(s->sc.model->nodeIndex("B2"), 0);
    for (double t : {1.0, 5.0, 10.0}) {
      const auto &a = dd.at(t), &b = nd.at(t);
      const double e = relErr(a.dp[0].q, b.dp[0].q, 1e-12);
      std::printf("  %s t = %4.1f s: dx_B2/dp dd %+.9f nd %+.9f; max relative |dd - nd| = %.2e\n", name, t,
                  a.dp[0].q[xB2], b.dp[0].q[xB2], e);
      EXPECT_LT(e, 1e-6) << name << " t = " << t;
    }
  }
}

TEST(Satellite, GeneralizedAlphaSensitivitiesMatchCentralDifferences) {
  // The low-dissipation run of figure 12 (generalized-alpha, rho_inf 0.5, dt = 1 ms):
  // its dd sensitivities are the derivative of its discrete solution, SAT2 to 0.5 s, central
  // differences of the same scheme within 1e-6 relative (all coordinates).
  auto s = load("SAT2");
  IntegratorSettings set = bdf1(0.5);
  set.type = "generalized_alpha";
  set.rhoInf = 0.5;
  set.dt = 1e-3;
  set.frameInterval = 0.25;
  const auto st = expectDdMatchesCentralDifferences(*s->as, s->p, s->start, s->sc.pimCase.get(), set, 1e-5,
                                                    {0.25, 0.5}, 1e-6, "SAT2 generalized-alpha");
  EXPECT_LT(st.maxConstraintViolation, 1e-10);
}

TEST(Satellite, IdasSensitivitiesMatchCentralDifferencesOverTheFirstMillisecond) {
  // IDAS at rtol 1e-8 resolves the light springs' axial vibrations (~4e5 rad/s, started by
  // the release at ~1e6 m/s^2): ~5e3 steps per millisecond, so 10 s are out of reach and the
  // check covers the violent first millisecond of SAT2. dd against central differences of
  // IDAS runs (relative step 1e-4: truncation ~1e-8, tolerance noise ~rtol / 1e-4 = 1e-4 of
  // the step's effect): 1e-4 relative, all coordinates.
  auto s = load("SAT2");
  IntegratorSettings set = s->sc.integrator;
  set.type = "idas";
  set.rtol = 1e-8;
  set.dt = 0.0;
  set.tEnd = 1e-3;
  set.frameInterval = 5e-4;
  expectDdMatchesCentralDifferences(*s->as, s->p, s->start, s->sc.pimCase.get(), set, 1e-4, {5e-4, 1e-3}, 1e-4,
                                    "SAT2 IDAS rtol 1e-8");
}
