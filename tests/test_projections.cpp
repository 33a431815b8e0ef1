// Velocity and acceleration projections of the fixed-step schemes (integrators/
// MotionProjection.hpp, `projections: true`): after each step Phi_q v + Phi_t = 0 and
// Phi_q a + (v^T H_i v)_i + g = 0 hold to round-off (without them only Phi = 0 does); the
// scheme stays second order (against a converged run of the same scheme); its dd sensitivities
// are the exact derivative of the projected discrete scheme (central differences of whole
// runs) for planar and spatial models, a driven mechanism (the drivers' time terms) and the
// massless satellite.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "TestModels.hpp"
#include "app/FiniteDifferences.hpp"
#include "integrators/InitialState.hpp"
#include "integrators/MotionProjection.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

/// A motor turns bar O-T about O (theta = 0.5 sin 3t: TestModels' motor bar) and bar T-U hangs
/// from T as a pendulum.
Scene drivenPendulum() {
  std::string text = kMotorBarScene;
  text.replace(text.find("elements:\n"), 10, "  - {name: U, position: [1.6, -0.8]}\nelements:\n");
  text.replace(text.find("constraints:\n"), 13, "  - {name: bar2, type: rigid_bar, nodes: [T, U], mass: 1.0}\nconstraints:\n");
  text += R"(parameters:
  - {name: A, of: motor, property: amplitude}
  - {name: L2, of: bar2, property: length}
integrator: {type: trapezoidal, t_end: 1, dt: 1.0e-3}
)";
  return readSceneText(text, "driven_pendulum.yaml");
}

/// max over frames after the first of |Phi_q v + Phi_t|_inf and |Phi_q a + v^T H v + g|_inf.
std::pair<double, double> constraintRates(const Assembler& as, const VecX& p, const Recorder& rec) {
  double dv = 0.0, da = 0.0;
  for (size_t i = 1; i < rec.frames.size(); ++i) {
    const State& x = rec.frames[i].x;
    as.setTime(x.t);
    dv = std::max(dv, (as.phiQTimes(x.q, p, x.v) + as.phiT(x.q, p)).lpNorm<Eigen::Infinity>());
    da = std::max(da, (as.phiQTimes(x.q, p, x.a) + as.hessianQuadratic(x.q, p, x.v) +
                       as.accelerationTimeTerms(x.q, x.v, p))
                          .lpNorm<Eigen::Infinity>());
  }
  return {dv, da};
}

}  // namespace

TEST(Projections, VelocitiesAndAccelerationsMeetTheirConstraintsOnlyWithThem) {
  // The seed-000 four-bar (3D rigid bodies in natural coordinates, joints) and the driven
  // pendulum (a rheonomic driver), trapezoidal rule, dt 2 ms, 0.5 s.
  for (const std::string name : {"four-bar 3D", "driven pendulum"}) {
    Scene sc = name == "four-bar 3D" ? readScene(sourceDir() + "/examples/seed000/four_bar.yaml") : drivenPendulum();
    Assembler as(*sc.model);
    const VecX p = sc.model->nominalParameters();
    StateWithSens start = initialState(as, p);
    start.dp.clear();
    IntegratorSettings set = integratorSettings("trapezoidal", 2e-3, 0.5);
    set.frameInterval = 0.05;
    Recorder plain, projected;
    integrate(as, p, start, set, plain);
    set.projections = true;
    integrate(as, p, start, set, projected);
    const auto [v0, a0] = constraintRates(as, p, plain);
    const auto [v1, a1] = constraintRates(as, p, projected);
    std::printf("  %s: |Phi_q v + Phi_t| %.2e -> %.2e, |d2Phi/dt2| %.2e -> %.2e with projections\n", name.c_str(), v0,
                v1, a0, a1);
    EXPECT_GT(v0, 1e-8) << name;  // the index-3 scheme leaves them (else this test shows nothing)
    EXPECT_GT(a0, 1e-6) << name;
    EXPECT_LT(v1, 1e-11) << name;
    EXPECT_LT(a1, 1e-9) << name;
  }
}

TEST(Projections, TheProjectedTrapezoidalRuleStaysSecondOrder) {
  // The driven pendulum's free angle at 1 s against the same scheme at dt 1e-4 s (converged to
  // ~1e-9): dt 4 and 2 ms give errors in the ratio 4.
  Scene sc = drivenPendulum();
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  StateWithSens start = initialState(as, p);
  start.dp.clear();
  const int ux = sc.model->dof(sc.model->nodeIndex("U"), 0);
  auto xAtOne = [&](double dt) {
    IntegratorSettings set = integratorSettings("trapezoidal", dt, 1.0);
    set.projections = true;
    Recorder rec;
    integrate(as, p, start, set, rec);
    return rec.at(1.0).x.q[ux];
  };
  const double ref = xAtOne(1e-4), e4 = std::abs(xAtOne(4e-3) - ref), e2 = std::abs(xAtOne(2e-3) - ref);
  std::printf("  x_U(1 s): error %.3e (dt 4 ms), %.3e (2 ms), ratio %.3f\n", e4, e2, e4 / e2);
  EXPECT_NEAR(e4 / e2, 4.0, 0.4);
  EXPECT_LT(e2, 1e-3);
}

TEST(Projections, SensitivitiesAreTheDerivativeOfTheProjectedScheme) {
  // dd against central differences (relative step 1e-5) of whole runs of the same projected
  // scheme, every parameter, positions and velocities at 0.5 s: the planar model with every 2D
  // element type (nine parameters: the converged point's matrix factorized), the seed-000
  // four-bar (GMRES), the driven pendulum; trapezoidal and generalized-alpha.
  struct Case {
    std::string name, type;
  };
  for (const Case c : {Case{"mixed 2D", "trapezoidal"}, Case{"four-bar 3D", "generalized_alpha"},
                       Case{"driven pendulum", "trapezoidal"}, Case{"driven pendulum", "generalized_alpha"}}) {
    Scene sc = c.name == "mixed 2D"      ? mixedScene()
               : c.name == "four-bar 3D" ? readScene(sourceDir() + "/examples/seed000/four_bar.yaml")
                                         : drivenPendulum();
    Assembler as(*sc.model);
    const VecX p = sc.model->nominalParameters();
    const StateWithSens start = initialState(as, p);
    IntegratorSettings set = integratorSettings(c.type, 2e-3, 0.5);
    set.rhoInf = 0.8;
    set.projections = true;
    Recorder dd, nd;
    integrate(as, p, start, set, dd);
    integrateFiniteDifferences(as, p, start, nullptr, set, {"central", 1e-5}, nd);
    ASSERT_EQ(dd.frames.size(), nd.frames.size());
    const auto& a = dd.frames.back().dp;
    const auto& b = nd.frames.back().dp;
    double wq = 0.0, wv = 0.0;
    for (size_t k = 0; k < a.size(); ++k) {
      wq = std::max(wq, relErr(a[k].q, b[k].q, 1.0));
      wv = std::max(wv, relErr(a[k].v, b[k].v, 1.0));
    }
    std::printf("  %s, %s: %zu parameters, max relative |dd - nd| at 0.5 s: dq/dp %.2e, dv/dp %.2e\n", c.name.c_str(),
                c.type.c_str(), a.size(), wq, wv);
    EXPECT_LT(wq, 1e-6) << c.name << " " << c.type;
    EXPECT_LT(wv, 1e-6) << c.name << " " << c.type;
  }
}

TEST(Projections, OnlyTheTrapezoidalRuleAndGeneralizedAlphaTakeThem) {
  std::string text = std::string(kMotorBarScene) + "integrator: {type: bdf1, t_end: 1, dt: 1.0e-3, projections: true}\n";
  try {
    readSceneText(text, "motor.yaml");
    ADD_FAILURE() << "bdf1 with projections was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("integrator.projections"), std::string::npos) << m;
    EXPECT_NE(m.find("not to bdf1"), std::string::npos) << m;
  }
}

TEST(Projections, ProjectionDerivativeMatchesCentralDifferences) {
  // The projection alone as a function of (q, v~, a~, p) along a random direction (dq, dv~,
  // da~) and parameter k: MotionProjection::sensitivity against central differences of
  // MotionProjection::project, for every parameter of the planar mixed model, the four-bar and
  // the driven pendulum (at t = 0.3 s: the driver's time terms).
  for (const std::string name : {"mixed 2D", "four-bar 3D", "driven pendulum"}) {
    Scene sc = name == "mixed 2D"      ? mixedScene()
               : name == "four-bar 3D" ? readScene(sourceDir() + "/examples/seed000/four_bar.yaml")
                                       : drivenPendulum();
    Assembler as(*sc.model);
    const VecX p = sc.model->nominalParameters();
    const StateWithSens start = initialState(as, p);
    const int n = as.n();
    std::srand(7);
    State x0 = start.x;
    x0.t = 0.3;
    as.setTime(x0.t);
    x0.v += 0.1 * VecX::Random(n);
    x0.a += VecX::Random(n);
    const VecX dq = VecX::Random(n), dv = VecX::Random(n), da = VecX::Random(n);
    double worst = 0.0;
    for (int k = 0; k < p.size(); ++k) {
      MotionProjection proj(as, p, {});
      State x = x0;
      proj.project(x, 0);
      State d;
      d.q = dq;
      d.v = dv;
      d.a = da;
      proj.sensitivity(x, k, d);
      const double h = 1e-6;
      State xs[2];
      for (int s = 0; s < 2; ++s) {
        const double sg = s == 0 ? 1.0 : -1.0;
        VecX pp = p;
        pp[k] += sg * h;
        MotionProjection pr(as, pp, {});
        xs[s] = x0;
        xs[s].q += sg * h * dq;
        xs[s].v += sg * h * dv;
        xs[s].a += sg * h * da;
        pr.project(xs[s], 0);
      }
      const VecX fv = (xs[0].v - xs[1].v) / (2 * h), fa = (xs[0].a - xs[1].a) / (2 * h);
      const double ev = relErr(d.v, fv, 1.0), ea = relErr(d.a, fa, 1.0);
      worst = std::max({worst, ev, ea});
    }
    std::printf("  %s: projected v and a, max relative |analytic - central difference| %.2e\n", name.c_str(), worst);
    EXPECT_LT(worst, 1e-7) << name;
  }
}
