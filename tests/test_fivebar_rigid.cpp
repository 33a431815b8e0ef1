// Rigid five-bar (examples/fivebar/rigid.yaml): IDAS against the trapezoidal rule,
// second-order convergence of the trapezoidal rule, energy conservation, constraints.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "core/Assembler.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {


struct Run {
  Scene scene;
  std::unique_ptr<Assembler> as;
  Recorder rec;
  IntegratorStats stats;
};

std::unique_ptr<Run> simulate(const std::string& type, double dt, double rtol = 1e-10,
                              double tEnd = 2.0, double frame = 0.5) {
  auto r = std::make_unique<Run>();
  r->scene = readScene(sourceDir() + "/examples/fivebar/rigid.yaml");
  auto& s = r->scene.integrator;
  s.type = type;
  s.dt = dt;
  s.rtol = rtol;
  s.atol = rtol;  // positions ~1 m: absolute and relative tolerances alike
  s.tEnd = tEnd;
  s.frameInterval = frame;
  s.newtonTol = 1e-13;
  r->as = std::make_unique<Assembler>(*r->scene.model);
  const VecX p = r->scene.model->nominalParameters();
  StateWithSens start = initialState(*r->as, p);
  start.dp.clear();  // dynamics only: sensitivities are tested with the PIM cases
  r->stats = integrate(*r->as, p, start, s, r->rec);
  return r;
}

double z2(const Run& r, double t) {
  const Model& m = *r.scene.model;
  return r.rec.at(t).x.q[m.dof(m.nodeIndex("n2"), 1)];
}

double energy(const Run& r, const State& s) {
  const VecX p = r.scene.model->nominalParameters();
  return 0.5 * s.v.dot(r.as->mass(p) * s.v) + r.as->potentialEnergy(s.q, p);
}

}  // namespace

TEST(FivebarRigid, IdasAndTrapezoidalAgreeOnZ2) {
  const auto idas = simulate("idas", 0.0, 1e-10);
  const auto trap = simulate("trapezoidal", 2.5e-5);
  for (double t : {0.5, 1.0, 1.5, 2.0}) {
    SCOPED_TRACE("t = " + std::to_string(t));
    EXPECT_NEAR(z2(*idas, t), z2(*trap, t), 1e-6);
  }
  EXPECT_LT(idas->stats.maxConstraintViolation, 1e-8);
  EXPECT_LT(trap->stats.maxConstraintViolation, 1e-10);
}

TEST(FivebarRigid, TrapezoidalIsSecondOrder) {
  // Errors against a much finer trapezoidal reference; the observed order from halving dt.
  const auto ref = simulate("trapezoidal", 1e-5, 1e-10, 1.0, 1.0);
  std::vector<double> err;
  for (double dt : {4e-3, 2e-3, 1e-3}) {
    const auto r = simulate("trapezoidal", dt, 1e-10, 1.0, 1.0);
    err.push_back(std::abs(z2(*r, 1.0) - z2(*ref, 1.0)));
  }
  for (size_t i = 1; i < err.size(); ++i) {
    const double order = std::log2(err[i - 1] / err[i]);
    std::printf("  trapezoidal z2(1 s) error %.3e -> %.3e: order %.3f\n", err[i - 1], err[i], order);
    EXPECT_NEAR(order, 2.0, 0.15);
  }
}

TEST(FivebarRigid, TrapezoidalConservesEnergyBetterAsDtShrinks) {
  // The rigid five-bar has no damping: the total energy is conserved exactly. The
  // trapezoidal rule keeps it to O(dt^2); we state the bound 2e-3 J * (dt / 1e-3 s)^2
  // over 2 s and check that halving dt cuts the drift by about four.
  std::vector<double> drift;
  for (double dt : {2e-3, 1e-3, 5e-4}) {
    const auto r = simulate("trapezoidal", dt, 1e-10, 2.0, 0.01);
    const double E0 = energy(*r, r->rec.frames.front().x);
    double worst = 0.0;
    for (const auto& f : r->rec.frames) worst = std::max(worst, std::abs(energy(*r, f.x) - E0));
    std::printf("  dt = %.1e s: max |E - E0| = %.3e J (E0 = %.4f J), max |Phi| = %.2e\n", dt,
                worst, E0, r->stats.maxConstraintViolation);
    EXPECT_LT(worst, 2e-3 * std::pow(dt / 1e-3, 2));
    EXPECT_LT(r->stats.maxConstraintViolation, 1e-10);
    drift.push_back(worst);
  }
  EXPECT_GT(drift[0] / drift[1], 3.0);
  EXPECT_GT(drift[1] / drift[2], 3.0);
}

TEST(FivebarRigid, Bdf1IsFirstOrderAndDissipative) {
  const auto ref = simulate("trapezoidal", 1e-5, 1e-10, 1.0, 1.0);
  const auto a = simulate("bdf1", 1e-3, 1e-10, 1.0, 1.0);
  const auto b = simulate("bdf1", 5e-4, 1e-10, 1.0, 1.0);
  const double ea = std::abs(z2(*a, 1.0) - z2(*ref, 1.0)), eb = std::abs(z2(*b, 1.0) - z2(*ref, 1.0));
  EXPECT_NEAR(std::log2(ea / eb), 1.0, 0.2);
  EXPECT_LT(energy(*a, a->rec.frames.back().x), energy(*a, a->rec.frames.front().x));
}
