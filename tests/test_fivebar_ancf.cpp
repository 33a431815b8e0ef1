// The flexible five-bar with its beam 1-2 as ANCF cable elements (examples/fivebar/
// flexible_ancf.yaml) next to the positions-only version (flexible.yaml): PIM counts, initial
// sensitivities equal on the shared coordinates (both come from the same rigid-body
// kinematics of the rigidized bodies), and the trapezoidal rule's discrete sensitivities
// against central differences of the same scheme started from the perturbed initial models.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "core/Assembler.hpp"
#include "integrators/InitialState.hpp"
#include "pim/Pim.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

struct CaseRun {
  Scene sc;
  std::unique_ptr<Assembler> as;
  PimReport rep;
  StateWithSens start;
};

std::unique_ptr<CaseRun> load(const std::string& file, const std::string& name) {
  auto r = std::make_unique<CaseRun>();
  r->sc = readScene(sourceDir() + "/examples/fivebar/" + file, name);
  r->as = std::make_unique<Assembler>(*r->sc.model);
  r->start = initialState(*r->as, r->sc.model->nominalParameters(), r->sc.pimCase.get(), &r->rep);
  return r;
}

const char* kCases[] = {"F1", "F2", "F3", "F4", "F5", "F6", "F1R", "F2R", "F3R", "F4R", "F5R", "F6R"};

}  // namespace

// Rigidizing the ANCF beam adds one equation per free slope component (3 nodes x 2), the
// F-R twins' rigid model 6 constraints: d - m_r and d_s are those of the positions-only model.
TEST(FivebarAncf, CountsFollowThePositionsOnlyModel) {
  for (const char* name : kCases) {
    auto a = load("flexible_ancf.yaml", name), b = load("flexible.yaml", name);
    const bool twin = std::string(name).back() == 'R';
    EXPECT_EQ(a->rep.n, b->rep.n + 6) << name;
    EXPECT_EQ(a->rep.m, b->rep.m + (twin ? 6 : 0)) << name;
    EXPECT_EQ(a->rep.d - a->rep.mr, b->rep.d - b->rep.mr) << name;
    EXPECT_EQ(a->rep.ds, b->rep.ds) << name;
  }
}

// q_p0 and v_p0 of every case equal the positions-only version's on the shared coordinates
// (labels x(n1), z(n1), ...); the slopes' q_p0 turn with the rigidized beam.
TEST(FivebarAncf, InitialSensitivitiesEqualThePositionsOnlyModel) {
  for (const char* name : kCases) {
    auto a = load("flexible_ancf.yaml", name), b = load("flexible.yaml", name);
    const Model &ma = *a->sc.model, &mb = *b->sc.model;
    const double scale = std::max(1.0, b->start.dp[0].q.lpNorm<Eigen::Infinity>());
    int shared = 0;
    for (int i = 0; i < mb.n; ++i)
      for (int j = 0; j < ma.n; ++j)
        if (ma.coordinateLabel(j) == mb.coordinateLabel(i)) {
          EXPECT_NEAR(a->start.dp[0].q[j], b->start.dp[0].q[i], 1e-10 * scale) << name << " " << mb.coordinateLabel(i);
          EXPECT_NEAR(a->start.dp[0].v[j], b->start.dp[0].v[i], 1e-10 * scale) << name << " " << mb.coordinateLabel(i);
          ++shared;
        }
    EXPECT_EQ(shared, mb.n) << name;
  }
}

// dz2/dp of the trapezoidal rule (dt 1 ms) against central differences (h = 1e-5) of the same
// scheme from the perturbed initial models at p +/- h, every F case, to 1e-6 relative.
TEST(FivebarAncf, DiscreteSensitivitiesMatchCentralDifferencesOfTheScheme) {
  IntegratorSettings set;
  set.type = "trapezoidal";
  set.dt = 1e-3;
  set.tEnd = 1.0;
  set.frameInterval = 0.5;
  set.newtonTol = 1e-14;
  const std::vector<double> times = {0.5, 1.0};
  const double h = 1e-5;
  for (const char* name : {"F1", "F2", "F3", "F4", "F5", "F6"}) {
    auto r = load("flexible_ancf.yaml", name);
    const Model& m = *r->sc.model;
    const int z2 = m.dof(m.nodeIndex("n2"), 1);
    const VecX p0 = m.nominalParameters();
    Recorder rec;
    integrate(*r->as, p0, r->start, set, rec);
    std::vector<double> fd(times.size(), 0.0);
    for (int sgn : {1, -1}) {
      VecX p = p0;
      p[0] += sgn * h;
      StateWithSens st;
      st.x.q = perturbedConfiguration(*r->as, *r->sc.pimCase, r->start.x.q, p0, p, 0);
      st.x.v = VecX::Zero(st.x.q.size());  // q'_0 = 0 and z'_p0 = 0 in every F case
      solveAccelerations(*r->as, st.x, p);
      Recorder rp;
      integrate(*r->as, p, st, set, rp);
      for (size_t i = 0; i < times.size(); ++i) fd[i] += sgn * rp.at(times[i]).x.q[z2] / (2 * h);
    }
    for (size_t i = 0; i < times.size(); ++i) {
      const double dd = rec.at(times[i]).dp[0].q[z2];
      std::printf("  %s t = %.1f s: dz2/dp = %+.10e (dd)  %+.10e (central FD)  rel. diff %.1e\n", name, times[i], dd,
                  fd[i], std::abs(dd - fd[i]) / std::abs(fd[i]));
      EXPECT_LE(std::abs(dd - fd[i]), 1e-6 * std::abs(fd[i])) << name << " t = " << times[i];
    }
  }
}
