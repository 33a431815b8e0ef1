// Time functions, drivers (rheonomic constraints) and time-dependent loads: every new
// derivative against central finite differences computed here (f', f'' and d/dp of the time
// functions; Phi_t, Phi_qt, Phi_tt + 2 Phi_qt v and its q-derivative, Phi_p, Phi_tp, g_p of
// each driver; the planar torque's dQ/dq and dQ/dp); then whole runs against analytic
// solutions: a pendulum driven by a motor (angle, reaction torque) with each integrator, and
// the reaction's sensitivity against central differences of two runs.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "constraints/Driver.hpp"
#include "core/TimeFunction.hpp"
#include "elements/PlanarFollowerForce.hpp"
#include "elements/PlanarTorque.hpp"
#include "elements/PointForce.hpp"
#include "integrators/InitialState.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

std::vector<std::unique_ptr<TimeFunction>> allFunctions(const std::string& dir) {
  std::vector<std::unique_ptr<TimeFunction>> r;
  r.push_back(makeConstant(1.7));
  r.push_back(makeRamp(0.8, 0.1, -0.3));
  r.push_back(makeLinear(1.9, 0.25));
  r.push_back(makeSmoothStep(0.05, 0.9, 0.2, 1.4));
  r.push_back(makeHarmonic(0.7, 5.3, 0.4, 0.1));
  r.push_back(makeSpinUp(4.0, 0.6));
  r.push_back(makeTable({0.0, 0.2, 0.5, 1.0}, {0.0, 1.0, 0.5, 2.0}, 1.3));
  (void)dir;
  return r;
}

/// Binds every constant of f to its own parameter (p = nominal values).
VecX bindAll(TimeFunction& f) {
  auto props = f.properties();
  VecX p(props.size());
  for (size_t i = 0; i < props.size(); ++i) {
    p[i] = props[i].second->constant;
    props[i].second->param = static_cast<int>(i);
  }
  return p;
}

}  // namespace

TEST(TimeFunction, TimeAndParameterDerivativesMatchFiniteDifferences) {
  const double h = 1e-6;
  for (auto& f : allFunctions("")) {
    const VecX p = bindAll(*f);
    // Away from the kinks of ramp and table (0.1, 0.2, 0.5): inside segments f is smooth.
    for (double t : {0.07, 0.33, 0.45, 0.71, 0.95}) {
      const TimeValue v = f->at(t, p), a = f->at(t + h, p), b = f->at(t - h, p);
      EXPECT_NEAR(v.df, (a.f - b.f) / (2 * h), 1e-6 * (1 + std::abs(v.df))) << f->kind() << " t = " << t;
      EXPECT_NEAR(v.ddf, (a.df - b.df) / (2 * h), 1e-5 * (1 + std::abs(v.ddf))) << f->kind() << " t = " << t;
      for (int k = 0; k < p.size(); ++k) {
        TimeValue d;
        ASSERT_TRUE(f->parameterDerivative(t, p, k, d)) << f->kind();
        VecX pp = p, pm = p;
        pp[k] += h;
        pm[k] -= h;
        const TimeValue fp = f->at(t, pp), fm = f->at(t, pm);
        EXPECT_NEAR(d.f, (fp.f - fm.f) / (2 * h), 1e-6 * (1 + std::abs(d.f))) << f->kind() << " k " << k;
        EXPECT_NEAR(d.df, (fp.df - fm.df) / (2 * h), 1e-6 * (1 + std::abs(d.df))) << f->kind() << " k " << k;
        EXPECT_NEAR(d.ddf, (fp.ddf - fm.ddf) / (2 * h), 1e-5 * (1 + std::abs(d.ddf))) << f->kind() << " k " << k;
      }
      TimeValue none;
      EXPECT_FALSE(f->parameterDerivative(t, p, static_cast<int>(p.size()), none));
    }
  }
}

TEST(TimeFunction, ClosedFormValues) {
  const VecX p;
  // Smooth step: halfway at the midpoint, ends held; spin-up: omega (t - T/2) after T.
  auto s = makeSmoothStep(1.0, 3.0, 2.0, 6.0);
  EXPECT_DOUBLE_EQ(s->at(2.0, p).f, 4.0);
  EXPECT_DOUBLE_EQ(s->at(0.5, p).f, 2.0);
  EXPECT_DOUBLE_EQ(s->at(3.5, p).f, 6.0);
  EXPECT_DOUBLE_EQ(s->at(3.5, p).df, 0.0);
  auto su = makeSpinUp(6.0, 15.0);
  EXPECT_NEAR(su->at(20.0, p).f, 6.0 * (20.0 - 7.5), 1e-12);
  EXPECT_NEAR(su->at(15.0 - 1e-9, p).df, 6.0, 1e-8);  // reaches omega continuously
  auto tab = makeTable({0.0, 1.0, 3.0}, {0.0, 2.0, 1.0}, 2.0);
  EXPECT_DOUBLE_EQ(tab->at(2.0, p).f, 3.0);   // 2 * 1.5
  EXPECT_DOUBLE_EQ(tab->at(2.0, p).df, -1.0); // 2 * (-0.5)
  EXPECT_DOUBLE_EQ(tab->at(9.0, p).f, 2.0);   // held
  auto hm = makeHarmonic(2.0, 3.0, 0.5, 1.0);
  EXPECT_DOUBLE_EQ(hm->at(0.7, p).f, 1.0 + 2.0 * std::sin(3.0 * 0.7 + 0.5));
}

namespace {

/// A driver with a harmonic function whose constants are parameters 0..3, at a random state.
struct DriverCase {
  std::unique_ptr<Driver> d;
  VecX p, x, v;
};

DriverCase driverCase(int which) {
  DriverCase c;
  auto f = makeHarmonic(0.3, 4.0, 0.2, 0.1);
  c.p = bindAll(*f);
  if (which == 0) {
    c.d = std::make_unique<CoordinateDriver>("dc", 0, 2, 1, 0.4, std::move(f));
    c.x = Eigen::Vector2d(0.3, 0.9);
    c.v = Eigen::Vector2d(-0.7, 1.1);
  } else if (which == 1) {
    c.d = std::make_unique<DistanceDriver>("dd", 0, 1, 3, 1.2, std::move(f));
    c.x = (VecX(6) << 0.1, -0.2, 0.3, 1.0, 0.7, -0.4).finished();
    c.v = (VecX(6) << 0.5, -1.0, 0.2, -0.3, 0.8, 1.4).finished();
  } else {
    c.d = std::make_unique<AngleDriver>("m", std::vector<int>{0, 1, 2, 3}, 0.6, std::move(f));
    c.x = (VecX(8) << 0.1, -0.2, 1.0, 0.3, 0.4, 0.5, 0.2, 1.6).finished();
    c.v = (VecX(8) << 0.5, -1.0, 0.2, -0.3, 0.8, 1.4, -0.6, 0.9).finished();
  }
  return c;
}

LocalState state(const DriverCase& c, double t, const VecX& x, const VecX& p) {
  LocalState s;
  s.dim = c.d->kind() == "prescribed_distance" ? 3 : 2;
  s.x = x;
  s.v = c.v;
  s.p = &p;
  s.t = t;
  return s;
}

}  // namespace

TEST(Driver, TimeAndStateDerivativesMatchFiniteDifferences) {
  const double h = 1e-6, t = 0.37;
  for (int which = 0; which < 3; ++which) {
    const DriverCase c = driverCase(which);
    const Driver& d = *c.d;
    auto phiAt = [&](double tt, const VecX& x, const VecX& p) {
      VecX r;
      d.phi(state(c, tt, x, p), r);
      return r;
    };
    auto timeAt = [&](double tt, const VecX& x, const VecX& p, VecX& pt, MatX& pqt, VecX& g, MatX& dg) {
      d.timeDerivatives(state(c, tt, x, p), pt, pqt, g, dg);
    };
    const LocalState s = state(c, t, c.x, c.p);
    MatX J, H, pqt, dg;
    VecX pt, g;
    d.jacobian(s, J);
    d.hessian(s, 0, H);
    timeAt(t, c.x, c.p, pt, pqt, g, dg);
    const std::string k = d.kind();
    // Phi_q, Hessian
    EXPECT_LT(relErr(J, fdJacobian([&](const VecX& x) { return phiAt(t, x, c.p); }, c.x)), 1e-7) << k;
    EXPECT_LT(relErr(H, fdJacobian([&](const VecX& x) {
                       MatX Jx;
                       d.jacobian(state(c, t, x, c.p), Jx);
                       return VecX(Jx.row(0).transpose());
                     }, c.x)), 1e-7) << k;
    // Phi_t, Phi_qt
    const VecX ptFd = (phiAt(t + h, c.x, c.p) - phiAt(t - h, c.x, c.p)) / (2 * h);
    EXPECT_NEAR(pt[0], ptFd[0], 1e-6 * (1 + std::abs(pt[0]))) << k;
    MatX Jp, Jm;
    d.jacobian(state(c, t + h, c.x, c.p), Jp);
    d.jacobian(state(c, t - h, c.x, c.p), Jm);
    EXPECT_LT(relErr(pqt, (Jp - Jm) / (2 * h)), 1e-6) << k;
    // g = Phi_tt + 2 Phi_qt v, Phi_tt from the FD of Phi_t
    VecX ptp, ptm, gp_, gm_;
    MatX a1, a2, b1, b2;
    timeAt(t + h, c.x, c.p, ptp, a1, gp_, b1);
    timeAt(t - h, c.x, c.p, ptm, a2, gm_, b2);
    const double phiTT = (ptp[0] - ptm[0]) / (2 * h);
    EXPECT_NEAR(g[0], phiTT + 2.0 * pqt.row(0).dot(c.v), 1e-5 * (1 + std::abs(g[0]))) << k;
    // Independent check of g: d2/dt2 Phi(x + v t + a t^2/2, t) = Phi_q a + v^T H v + g (a = 0).
    auto along = [&](double tau) { return phiAt(t + tau, VecX(c.x + tau * c.v), c.p)[0]; };
    const double h2 = 1e-4;
    const double d2 = (along(h2) - 2 * along(0) + along(-h2)) / (h2 * h2);
    EXPECT_NEAR(d2, c.v.dot(H * c.v) + g[0], 1e-5 * (1 + std::abs(d2))) << k;
    // dg/dq
    EXPECT_LT(relErr(dg, fdJacobian([&](const VecX& x) {
                        VecX a, gg;
                        MatX b, e;
                        timeAt(t, x, c.p, a, b, gg, e);
                        return gg;
                      }, c.x)), 1e-6) << k;
    // Parameter derivatives: Phi_p, Phi_qp, Phi_tp, g_p for each function constant
    for (int kk = 0; kk < c.p.size(); ++kk) {
      VecX dphi, dpt, dgp;
      MatX dJ;
      ASSERT_TRUE(d.parameterDerivative(s, kk, dphi, dJ)) << k;
      ASSERT_TRUE(d.timeParameterDerivative(s, kk, dpt, dgp)) << k;
      VecX pp = c.p, pm = c.p;
      pp[kk] += h;
      pm[kk] -= h;
      EXPECT_NEAR(dphi[0], (phiAt(t, c.x, pp)[0] - phiAt(t, c.x, pm)[0]) / (2 * h), 1e-6) << k << " p" << kk;
      MatX Jpp, Jpm;
      d.jacobian(state(c, t, c.x, pp), Jpp);
      d.jacobian(state(c, t, c.x, pm), Jpm);
      EXPECT_LT(relErr(dJ, (Jpp - Jpm) / (2 * h)), 1e-6) << k << " p" << kk;
      VecX q1, q2, g1, g2;
      MatX r1, r2, s1, s2;
      timeAt(t, c.x, pp, q1, r1, g1, s1);
      timeAt(t, c.x, pm, q2, r2, g2, s2);
      EXPECT_NEAR(dpt[0], (q1[0] - q2[0]) / (2 * h), 1e-6 * (1 + std::abs(dpt[0]))) << k << " p" << kk;
      EXPECT_NEAR(dgp[0], (g1[0] - g2[0]) / (2 * h), 1e-5 * (1 + std::abs(dgp[0]))) << k << " p" << kk;
    }
    // Reaction scale: its gradient
    VecX grad;
    d.reactionScale(c.x, &grad);
    const MatX gfd = fdJacobian([&](const VecX& x) { return VecX::Constant(1, d.reactionScale(x, nullptr)); }, c.x);
    EXPECT_LT(relErr(grad.transpose(), gfd), 1e-7) << k;
  }
}

TEST(PlanarTorque, ForceJacobianAndParameterDerivativesMatchFiniteDifferences) {
  auto f = makeHarmonic(0.5, 3.0, 0.1, 1.0);
  VecX p = bindAll(*f);
  p.conservativeResize(5);
  p[4] = 2.5;  // the torque [N m]
  PlanarTorque tq("tq", 0, 1, Quantity{2.5, 4}, std::move(f));
  LocalState s;
  s.dim = 2;
  s.x = (VecX(4) << 0.2, -0.1, 1.1, 0.6).finished();
  s.v = VecX::Zero(4);
  s.p = &p;
  s.t = 0.4;
  auto Q = [&](const VecX& x, const VecX& pp) {
    LocalState l = s;
    l.x = x;
    l.p = &pp;
    VecX r;
    tq.force(l, r);
    return r;
  };
  MatX K, C;
  tq.forceJacobian(s, K, C);
  EXPECT_LT(relErr(K, fdJacobian([&](const VecX& x) { return Q(x, p); }, s.x)), 1e-7);
  // A couple: no net force, moment about any point = tau f(t).
  const VecX q = Q(s.x, p);
  EXPECT_NEAR(q[0] + q[2], 0.0, 1e-14);
  const double moment = s.x[0] * q[1] - s.x[1] * q[0] + s.x[2] * q[3] - s.x[3] * q[2];
  EXPECT_NEAR(moment, 2.5 * (1.0 + 0.5 * std::sin(3.0 * 0.4 + 0.1)), 1e-12);
  for (int k = 0; k < 5; ++k) {
    VecX dQ;
    MatX dM;
    ASSERT_TRUE(tq.parameterDerivative(s, k, dQ, dM));
    VecX pp = p, pm = p;
    pp[k] += 1e-6;
    pm[k] -= 1e-6;
    EXPECT_LT(relErr(dQ, (Q(s.x, pp) - Q(s.x, pm)) / 2e-6), 1e-7) << k;
  }
}

TEST(PointForce, TimeFunctionScalesTheLoadAndItsParameterDerivatives) {
  auto f = makeRamp(2.0, 0.1, 0.5);
  VecX p = bindAll(*f);  // slope, start, offset = parameters 0, 1, 2
  p.conservativeResize(4);
  p[3] = -3.0;  // F_y [N]
  PointForce pf("pf", 0, {Quantity{1.5, -1}, Quantity{-3.0, 3}}, std::move(f));
  LocalState s;
  s.dim = 2;
  s.x = VecX::Zero(2);
  s.v = VecX::Zero(2);
  s.p = &p;
  s.t = 0.6;
  VecX Q;
  pf.force(s, Q);
  const double fac = 0.5 + 2.0 * 0.5;
  EXPECT_DOUBLE_EQ(Q[0], 1.5 * fac);
  EXPECT_DOUBLE_EQ(Q[1], -3.0 * fac);
  EXPECT_TRUE(pf.externalWork());
  for (int k = 0; k < 4; ++k) {
    VecX dQ, dQad;
    MatX dM, dMad;
    ASSERT_TRUE(pf.parameterDerivative(s, k, dQ, dM));
    ASSERT_TRUE(pf.parameterDerivativeAD(s, k, dQad, dMad));
    VecX pp = p, pm = p, Qp, Qm;
    pp[k] += 1e-6;
    pm[k] -= 1e-6;
    LocalState a = s, b = s;
    a.p = &pp;
    b.p = &pm;
    pf.force(a, Qp);
    pf.force(b, Qm);
    EXPECT_LT(relErr(dQ, (Qp - Qm) / 2e-6), 1e-8) << k;
    EXPECT_LT(relErr(dQad, dQ), 1e-14) << k;
  }
}

namespace {

/// A uniform bar (m = 2 kg, L = 1 m) pinned at the ground node O, its angle from the x axis
/// driven by a motor: theta(t) = A sin(omega t), A = 0.5 rad (parameter), omega = 3 rad/s.
/// The motor's torque on the bar is I_O theta'' + m g (L/2) cos(theta), I_O = m L^2/3.
const std::string kMotorBar = std::string(test::kMotorBarScene) + R"(parameters:
  - {name: A, of: motor, property: amplitude}
integrator: {type: idas, t_end: 1}
)";

struct Frames : Observer {
  std::vector<StateWithSens> f;
  void frame(const StateWithSens& s) override { f.push_back(s); }
};

double motorTorque(double t, double A) {
  const double th = A * std::sin(3 * t), thdd = -9.0 * A * std::sin(3 * t);
  return 2.0 / 3.0 * thdd + 2.0 * 9.81 * 0.5 * std::cos(th);
}

}  // namespace

TEST(Driver, MotorDrivenBarFollowsTheAngleWithEachIntegrator) {
  for (const std::string type : {"idas", "trapezoidal", "bdf1", "generalized_alpha", "maggi_rk4"}) {
    Scene sc = readSceneText(kMotorBar, "motor.yaml");
    sc.integrator = integratorSettings(type, type == "idas" ? 1e-10 : 1e-3, 1.0);
    sc.integrator.frameInterval = 0.25;
    Assembler as(*sc.model);
    const VecX p = sc.model->nominalParameters();
    Frames fr;
    integrate(as, p, initialState(as, p), sc.integrator, fr);
    ASSERT_EQ(fr.f.size(), 5u) << type;
    for (const auto& s : fr.f) {
      const double t = s.x.t, th = 0.5 * std::sin(3 * t);
      // Positions: index-3 schemes hold Phi(q, t_{n+1}) = 0 exactly; Maggi/RK4 integrates them.
      EXPECT_NEAR(s.x.q[0], std::cos(th), 1e-8) << type << " t = " << t;
      EXPECT_NEAR(s.x.q[1], std::sin(th), 1e-8) << type << " t = " << t;
      // Velocity: theta' (-sin, cos) (IDAS and Maggi satisfy Phi_q v + Phi_t = 0 at each time).
      if (type == "idas" || type == "maggi_rk4") {
        const double thd = 1.5 * std::cos(3 * t);
        EXPECT_NEAR(s.x.v[0], -thd * std::sin(th), 1e-7) << type << " t = " << t;
        EXPECT_NEAR(s.x.v[1], thd * std::cos(th), 1e-7) << type << " t = " << t;
      }
      // Sensitivity to the amplitude: d theta/dA = sin(omega t).
      ASSERT_EQ(s.dp.size(), 1u);
      const double dth = std::sin(3 * t);
      EXPECT_NEAR(s.dp[0].q[0], -std::sin(th) * dth, 1e-7) << type << " t = " << t;
      EXPECT_NEAR(s.dp[0].q[1], std::cos(th) * dth, 1e-7) << type << " t = " << t;
    }
  }
}

TEST(Driver, MotorReactionAndItsSensitivityInSeriesCsv) {
  const Scene sc = readSceneText(kMotorBar + "output: {vtk: false, plots: false}\n", "motor.yaml");
  const std::string dir = ::testing::TempDir() + "/flexsens_motor_run";
  std::filesystem::remove_all(dir);
  const RunResult res = runScene(sc, dir);
  EXPECT_TRUE(res.suspect.empty());
  std::ifstream csv(dir + "/series.csv");
  std::string header, line, last;
  std::getline(csv, header);
  while (std::getline(csv, line)) last = line;
  std::vector<std::string> cols;
  std::vector<double> vals;
  {
    std::stringstream h(header), v(last);
    std::string c;
    while (std::getline(h, c, ',')) cols.push_back(c);
    while (std::getline(v, c, ',')) vals.push_back(std::stod(c));
  }
  auto col = [&](const std::string& name) {
    for (size_t i = 0; i < cols.size(); ++i)
      if (cols[i] == name) return vals.at(i);
    ADD_FAILURE() << "no column " << name << " in " << header;
    return 0.0;
  };
  const double t = col("t");
  EXPECT_NEAR(t, 1.0, 1e-12);
  // Torque against the closed form; its derivative against a central difference of it.
  EXPECT_NEAR(col("motor.reaction_Nm"), motorTorque(t, 0.5), 1e-5);
  const double h = 1e-4;
  EXPECT_NEAR(col("dmotor.reaction_Nm/dA"), (motorTorque(t, 0.5 + h) - motorTorque(t, 0.5 - h)) / (2 * h), 1e-4);
  // The audit judges a driven model too: the motor's work is in its balance (test_energy_audit).
  std::ifstream js(dir + "/summary.json");
  const std::string summary((std::istreambuf_iterator<char>(js)), std::istreambuf_iterator<char>());
  EXPECT_NE(summary.find("\"judged\": true"), std::string::npos);
  EXPECT_NE(summary.find("\"status\": \"complete\""), std::string::npos);
}

TEST(FollowerForce, TurnsWithTheBodyAndItsJacobianMatchesFiniteDifferences) {
  auto f = makeHarmonic(0.5, 3.0, 0.1, 1.0);
  VecX p = bindAll(*f);  // amplitude, omega, phase, offset: parameters 0..3
  p.conservativeResize(6);
  p[4] = 2.0;   // F0_x [N]
  p[5] = -1.5;  // F0_y [N]
  const VecX d0 = Eigen::Vector2d(0.8, 0.3);
  PlanarFollowerForce ff("ff", 0, 1, 2, d0, {Quantity{2.0, 4}, Quantity{-1.5, 5}}, std::move(f));
  LocalState s;
  s.dim = 2;
  s.v = VecX::Zero(6);
  s.p = &p;
  s.t = 0.3;
  const double fac = 1.0 + 0.5 * std::sin(3.0 * 0.3 + 0.1);
  // At the initial configuration the force is F0 f(t); turned by 90 degrees it is R90 F0 f(t).
  s.x = (VecX(6) << 0.4, 0.2, 0.1, -0.1, 0.1 + d0[0], -0.1 + d0[1]).finished();
  VecX Q;
  ff.force(s, Q);
  EXPECT_NEAR(Q[0], 2.0 * fac, 1e-14);
  EXPECT_NEAR(Q[1], -1.5 * fac, 1e-14);
  s.x.segment<2>(4) = s.x.segment<2>(2) + Eigen::Vector2d(-d0[1], d0[0]);
  ff.force(s, Q);
  EXPECT_NEAR(Q[0], 1.5 * fac, 1e-14);
  EXPECT_NEAR(Q[1], 2.0 * fac, 1e-14);
  // A general configuration: dQ/dq and dQ/dp against central differences.
  s.x = (VecX(6) << 0.4, 0.2, -0.3, 0.5, 0.6, -0.2).finished();
  auto Qat = [&](const VecX& x, const VecX& pp) {
    LocalState l = s;
    l.x = x;
    l.p = &pp;
    VecX r;
    ff.force(l, r);
    return r;
  };
  MatX K, C;
  ff.forceJacobian(s, K, C);
  EXPECT_GT(K.norm(), 0.0);
  EXPECT_LT(relErr(K, fdJacobian([&](const VecX& x) { return Qat(x, p); }, s.x)), 1e-8);
  for (int k = 0; k < 6; ++k) {
    VecX dQ;
    MatX dM;
    ASSERT_TRUE(ff.parameterDerivative(s, k, dQ, dM)) << k;
    VecX pp = p, pm = p;
    pp[k] += 1e-6;
    pm[k] -= 1e-6;
    EXPECT_LT(relErr(dQ, (Qat(s.x, pp) - Qat(s.x, pm)) / 2e-6), 1e-7) << k;
  }
}

TEST(Driver, PrescribedCoordinateMovesABarAndItsReactionBalancesTheInertia) {
  // A uniform bar (1 kg, 1 m) pinned at O, no gravity; its tip's y follows 0.3 sin(2t), so
  // theta = asin(y) and the driver's vertical force F on the tip satisfies I_O theta'' = F x_T.
  const char* text = R"(
dimension: 2
gravity: [0, 0]
nodes:
  - {name: O, position: [0, 0], ground: true}
  - {name: T, position: [1, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [O, T], mass: 1.0}
constraints:
  - {name: lift, type: prescribed_coordinate, node: T, axis: y, function: {type: harmonic, amplitude: 0.3, omega: 2}}
integrator: {type: idas, t_end: 1}
)";
  auto theta = [](double t) { return std::asin(0.3 * std::sin(2 * t)); };
  for (const std::string type : {"idas", "bdf1"}) {
    Scene sc = readSceneText(text, "lift.yaml");
    sc.integrator = integratorSettings(type, type == "idas" ? 1e-10 : 1e-3, 1.0);
    sc.integrator.frameInterval = 0.5;
    Assembler as(*sc.model);
    const VecX p = sc.model->nominalParameters();
    Frames fr;
    integrate(as, p, initialState(as, p), sc.integrator, fr);
    for (const auto& s : fr.f) {
      const double t = s.x.t, y = 0.3 * std::sin(2 * t);
      EXPECT_NEAR(s.x.q[1], y, 1e-9) << type << " t = " << t;
      EXPECT_NEAR(s.x.q[0], std::sqrt(1 - y * y), 1e-9) << type << " t = " << t;
      if (type != "idas") continue;
      // The driver's force on the tip is -lambda (row 1: the bar's own length is row 0).
      const double h = 1e-4, thdd = (theta(t + h) - 2 * theta(t) + theta(t - h)) / (h * h);
      EXPECT_NEAR(-s.x.lambda[1], thdd / 3.0 / std::sqrt(1 - y * y), 1e-5) << t;
    }
  }
}
