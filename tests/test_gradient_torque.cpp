// point_torque through the slope coordinates of an ANCF node (elements/GradientTorque.hpp):
// its dQ/dq and dQ/dp against central differences (planar cable, spatial cable, ancf_beam with
// a fixed and a follower torque), AD against analytic, the virtual work against T . delta phi
// of a small rotation; then cantilevers against the analytic answers: tip rotation M L / EI in
// the linear range, and the roll-up (M = 2 pi EI / L closes the cantilever into a circle, the
// tip back at the clamp), ancf_cable with `node:` beside the positions-only beam at equal N;
// the static sensitivity of the tip rotation to M against central differences of two solves.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "TestModels.hpp"
#include "elements/GradientTorque.hpp"
#include "elements/PlanarTorque.hpp"
#include "elements/SpatialTorque.hpp"
#include "integrators/Static.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

struct Case {
  const char* what;
  int dim, gradients;
  bool follower;
};

/// The element on node 0 with its torque bound to parameters 0.. (planar: tau; spatial: x, y, z).
std::unique_ptr<GradientTorque> makeTorque(const Case& c, const LocalState& s) {
  std::unique_ptr<Element> inner;
  if (c.dim == 2) {
    inner = std::make_unique<PlanarTorque>("t", 0, 0, Quantity{0.0, 0});
  } else {
    const int used = c.gradients == 1 ? 1 : 2;
    MatX X0 = MatX::Zero(3, used + 1);
    const int first = c.gradients == 3 ? 1 : 0;  // ancf_beam: r_y, r_z
    for (int k = 0; k < used; ++k) X0.col(k + 1) = s.x.segment(3 * (k + 1 + first), 3);
    std::vector<Quantity> comps{{0.0, 0}, {0.0, 1}, {0.0, 2}};
    inner = std::make_unique<SpatialTorque>("t", std::vector<int>(used + 1, 0), comps, nullptr, c.follower, X0);
  }
  return std::make_unique<GradientTorque>("t", 0, c.gradients, std::move(inner));
}

LocalState stateOf(const Case& c) {
  LocalState s;
  s.dim = c.dim;
  s.gradients = c.gradients;
  if (c.dim == 2) {
    s.x.resize(4);
    s.x << 0.3, -0.2, 0.8, 0.7;  // r, r' (not unit: a stretched cable)
  } else if (c.gradients == 1) {
    s.x.resize(6);
    s.x << 0.3, -0.2, 0.1, 0.8, 0.7, -0.3;
  } else {
    s.x.resize(12);  // r, then a sheared and stretched r_x, r_y, r_z
    s.x << 0.3, -0.2, 0.1, 1.1, 0.2, -0.1, -0.15, 0.9, 0.3, 0.05, -0.2, 1.05;
  }
  s.v = VecX::Zero(s.x.size());
  return s;
}

VecX torqueParams(const Case& c, const LocalState& s) {
  if (c.dim == 2) return VecX::Constant(1, 2.5);
  Eigen::Vector3d T(0.4, -1.3, 0.9);
  if (c.gradients == 1) {  // perpendicular to the slope, as the reader requires
    const Eigen::Vector3d r = s.x.segment<3>(3);
    T -= r * T.dot(r) / r.squaredNorm();
  }
  return T;
}

const Case kCases[] = {{"planar cable", 2, 1, false},
                       {"spatial cable", 3, 1, false},
                       {"ancf_beam", 3, 3, false},
                       {"ancf_beam follower", 3, 3, true}};

}  // namespace

TEST(GradientTorque, JacobianAndParameterDerivativesMatchFiniteDifferences) {
  for (const Case& c : kCases) {
    LocalState s = stateOf(c);
    const auto el = makeTorque(c, s);
    VecX p = torqueParams(c, s);
    s.p = &p;
    auto Q = [&](const VecX& x, const VecX& pp) {
      LocalState t = s;
      t.x = x;
      t.p = &pp;
      VecX q;
      el->force(t, q);
      return q;
    };
    VecX q0;
    el->force(s, q0);
    EXPECT_TRUE(q0.head(c.dim).isZero()) << c.what << ": a couple, no force on the position";
    EXPECT_GT(q0.norm(), 0.1) << c.what;
    MatX K, C, Kad, Cad;
    el->forceJacobian(s, K, C);
    el->forceJacobianAD(s, Kad, Cad);
    const MatX Kfd = fdJacobian([&](const VecX& x) { return Q(x, p); }, s.x);
    EXPECT_LT((K - Kfd).norm(), 1e-7 * (1 + Kfd.norm())) << c.what << "\n" << K << "\n\n" << Kfd;
    EXPECT_LT((Kad - K).norm(), 1e-12 * (1 + K.norm())) << c.what;
    for (int k = 0; k < p.size(); ++k) {
      VecX dQ, dQad;
      MatX dM;
      ASSERT_TRUE(el->parameterDerivative(s, k, dQ, dM)) << c.what;
      ASSERT_TRUE(el->parameterDerivativeAD(s, k, dQad, dM)) << c.what;
      VecX pp = p, pm = p;
      pp[k] += 1e-6;
      pm[k] -= 1e-6;
      const VecX fd = (Q(s.x, pp) - Q(s.x, pm)) / 2e-6;
      EXPECT_LT((dQ - fd).norm(), 1e-7 * (1 + fd.norm())) << c.what << " k " << k;
      EXPECT_LT((dQad - dQ).norm(), 1e-12 * (1 + dQ.norm())) << c.what << " k " << k;
    }
  }
}

// Q . delta r = T . delta phi for a small rotation delta phi of the gradients (delta r_i =
// delta phi x r_i; planar: delta r' = delta theta R90 r'): the torque's work, independent of the
// stretch and shear of the gradients. With a cable's one slope only the part of T across the
// slope does work (the twist is not a coordinate): T is across it here.
TEST(GradientTorque, VirtualWorkIsTheTorqueTimesTheRotation) {
  for (const Case& c : kCases) {
    LocalState s = stateOf(c);
    const auto el = makeTorque(c, s);
    VecX p = torqueParams(c, s);
    s.p = &p;
    VecX Q;
    el->force(s, Q);
    const int n = (s.x.size() / c.dim) - 1;  // gradient vectors
    if (c.dim == 2) {
      VecX dr = VecX::Zero(4);
      dr.segment<2>(2) = Eigen::Vector2d(-s.x[3], s.x[2]);  // delta theta = 1
      EXPECT_NEAR(Q.dot(dr), p[0], 1e-12) << c.what;
      continue;
    }
    const Eigen::Vector3d T = p;
    for (const Eigen::Vector3d dphi : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1)}) {
      VecX dr = VecX::Zero(s.x.size());
      for (int i = 0; i < n; ++i) dr.segment<3>(3 * (i + 1)) = dphi.cross(Eigen::Vector3d(s.x.segment<3>(3 * (i + 1))));
      if (c.gradients == 3) {  // the torque sees only the section vectors r_y, r_z
        VecX q;
        el->force(s, q);
        EXPECT_TRUE(q.segment<3>(3).isZero()) << c.what << ": nothing on r_x";
      }
      double expected = T.dot(dphi);
      if (c.gradients == 1) {  // the rotation about the slope moves nothing
        const Eigen::Vector3d r = s.x.segment<3>(3);
        expected = T.dot(dphi - r * dphi.dot(r) / r.squaredNorm());
      }
      EXPECT_NEAR(Q.dot(dr), expected, 1e-12) << c.what;
    }
  }
}

namespace {

constexpr double kEI = 1.0, kL = 1.0;  // E 1e6 Pa, I 1e-6 m^4, A 1e-2 m^2 (L / r = 100)

/// A planar cantilever of N elements along x, clamped at A, end moment M at the tip (bound to
/// parameter M): ancf_cable with the torque through the tip's slope, or the positions-only
/// beam (clamp: start) with the couple on its end segment.
std::string cantilever(bool ancf, int N, double M) {
  std::ostringstream s;
  s.precision(17);
  s << "dimension: 2\nnodes:\n  - {name: A, position: [0, 0], ground: true" << (ancf ? ", clamped: true" : "") << "}\n";
  for (int i = 1; i <= N; ++i) s << "  - {name: n" << i << ", position: [" << kL * i / N << ", 0]}\n";
  s << "elements:\n  - {name: bar, type: " << (ancf ? "ancf_cable" : "beam") << ", E: 1.0e6, density: 1000,"
    << " section: {area: 1.0e-2, inertia: 1.0e-6}" << (ancf ? "" : ", clamp: start") << ", nodes: [A";
  for (int i = 1; i <= N; ++i) s << ", n" << i;
  s << "]}\n  - {name: moment, type: point_torque, torque: " << M;
  if (ancf) s << ", node: n" << N << "}\n";
  else s << ", nodes: [n" << N - 1 << ", n" << N << "]}\n";
  s << "parameters:\n  - {name: M, of: moment, property: torque}\nstatic: {load_steps: 1}\n";
  return s.str();
}

struct Tip {
  double x, y, rotation;  ///< [m], [m], [rad] (unwrapped along the load steps)
  VecX q, lambda;
};

Tip solveCantilever(const Scene& sc, bool ancf, int steps, const VecX* pOverride = nullptr) {
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = pOverride ? *pOverride : m.nominalParameters();
  int tip = -1, maxIndex = 0;  // node nN, N the largest (a clamp adds a ghost node after them)
  for (int i = 0; i < static_cast<int>(m.nodes.size()); ++i)
    if (m.nodes[i].name[0] == 'n' && std::stoi(m.nodes[i].name.substr(1)) > maxIndex)
      maxIndex = std::stoi(m.nodes[i].name.substr(1)), tip = i;
  Tip r;
  double unwrapped = 0.0;
  auto angle = [&](const VecX& q) {
    if (ancf) return std::atan2(q[m.dof(tip, 3)], q[m.dof(tip, 2)]);
    return std::atan2(q[m.dof(tip, 1)] - m.coordinate(q, tip - 1, 1), q[m.dof(tip, 0)] - m.coordinate(q, tip - 1, 0));
  };
  StaticSettings set;
  set.steps = steps;
  set.stepLoadFactor = true;
  set.onStep = [&](int, double, const VecX& q, const VecX&) {
    const double a = angle(q);
    unwrapped += std::remainder(a - unwrapped, 2 * M_PI);
  };
  StaticReport rep;
  r.q = solveStatic(as, p, m.initialPositions(), set, &rep);
  r.lambda = rep.lambda;
  r.x = r.q[m.dof(tip, 0)];
  r.y = r.q[m.dof(tip, 1)];
  r.rotation = unwrapped;
  return r;
}

}  // namespace

// Linear range: M = 1e-4 EI / L, tip rotation M L / EI, deflection M L^2 / (2 EI).
TEST(GradientTorque, CantileverTipRotationIsMLOverEI) {
  const double M = 1e-4 * kEI / kL;
  for (bool ancf : {true, false}) {
    const Scene sc = readSceneText(cantilever(ancf, 8, M), "cantilever.yaml");
    const Tip t = solveCantilever(sc, ancf, 1);
    std::printf("%s N = 8: tip rotation %.6e (M L / EI = %.6e), deflection %.6e (M L^2 / 2 EI = %.6e)\n",
                ancf ? "ancf_cable" : "beam", t.rotation, M * kL / kEI, t.y, M * kL * kL / (2 * kEI));
    // ANCF cubic elements hold a constant curvature exactly; the positions-only beam's last
    // segment's direction lags the tip tangent by half a segment's turn (M L / EI / (2 N)).
    const double rotTol = ancf ? 1e-3 : 0.07;
    EXPECT_NEAR(t.rotation, M * kL / kEI, rotTol * M * kL / kEI) << ancf;
    EXPECT_NEAR(t.y, M * kL * kL / (2 * kEI), (ancf ? 1e-3 : 2e-2) * M * kL * kL / (2 * kEI)) << ancf;
  }
}

// The roll-up: M = 2 pi EI / L bends the cantilever into a full circle of radius R = L / (2 pi),
// node n_i (arc length s_i = i L / N) at R (sin(s_i/R), 1 - cos(s_i/R)), the tip back at the
// clamp turned by 2 pi. At equal N: the largest nodal distance from the circle / L and the tip's.
// Observed: N = 8 ancf_cable 1.39e-3 (tip 1.38e-3), beam 8.33e-3 (tip 2e-16: the beam's nodes
// lie on a closed regular polygon of too large a radius); N = 16 ancf_cable 9.57e-5, beam 2.06e-3.
TEST(GradientTorque, RollUpClosesTheCircle) {
  const double M = 2 * M_PI * kEI / kL, R = kL / (2 * M_PI);
  double previous = 1.0;
  for (int N : {8, 16}) {
    double err[2];
    for (bool ancf : {true, false}) {
      const Scene sc = readSceneText(cantilever(ancf, N, M), "rollup.yaml");
      const Model& m = *sc.model;
      const Tip t = solveCantilever(sc, ancf, 40);
      err[ancf] = 0.0;
      for (int i = 1; i <= N; ++i) {
        int id = 0;
        while (m.nodes[id].name != "n" + std::to_string(i)) ++id;
        const double si = kL * i / N;
        err[ancf] = std::max(err[ancf], std::hypot(t.q[m.dof(id, 0)] - R * std::sin(si / R),
                                                   t.q[m.dof(id, 1)] - R * (1 - std::cos(si / R))) / kL);
      }
      std::printf("roll-up N = %d %s: largest nodal error / L %.3e, tip (%.3e, %.3e), rotation/(2 pi) %.6f\n", N,
                  ancf ? "ancf_cable" : "beam", err[ancf], t.x, t.y, t.rotation / (2 * M_PI));
      if (ancf) EXPECT_NEAR(t.rotation, 2 * M_PI, 10.0 / std::pow(N, 4) * 2 * M_PI) << N;
    }
    EXPECT_LE(err[1], err[0]) << "N = " << N << ": the ANCF cable less accurate than the beam";
    EXPECT_LT(err[1], previous / 8) << "N = " << N << ": the ANCF cable does not converge";
    previous = err[1];
  }
}

// d(tip rotation)/dM and d(tip x)/dM from staticSensitivities against central differences of
// two static solves, in the nonlinear range (M = 0.3 of the roll-up moment).
TEST(GradientTorque, StaticSensitivityMatchesCentralDifferences) {
  const Scene sc = readSceneText(cantilever(true, 6, 0.3 * 2 * M_PI), "sens.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = m.nominalParameters();
  const Tip t = solveCantilever(sc, true, 10);
  const StaticSensitivity sens = staticSensitivities(as, t.q, t.lambda, p);
  const double h = 1e-5 * p[0];
  VecX pp = p, pm = p;
  pp[0] += h;
  pm[0] -= h;
  const Tip a = solveCantilever(sc, true, 10, &pp), b = solveCantilever(sc, true, 10, &pm);
  const VecX fd = (a.q - b.q) / (2 * h);
  EXPECT_LT((sens.qp.col(0) - fd).norm(), 1e-6 * fd.norm()) << sens.qp.col(0).transpose() << "\n" << fd.transpose();
  EXPECT_GT(fd.norm(), 0.1);
}

// Spatial cantilevers (x axis, clamped at A) under an end moment about z through `node:` of the
// tip: an ancf_cable's slope and an ancf_beam's section (r_y; fixed and follower torque) turn by
// M L / EI in the linear range (M = 1e-4 EI / L); a torque along a cable's slope is refused.
TEST(GradientTorque, SpatialCantileversTurnByMLOverEI) {
  const double side = 0.1, E = 1.0e6, EI = E * std::pow(side, 4) / 12, M = 1e-4 * EI;
  for (const std::string kind : {"ancf_cable", "ancf_beam", "ancf_beam follower"}) {
    const bool beam = kind != "ancf_cable";
    std::ostringstream s;
    s.precision(17);
    s << "dimension: 3\nnodes:\n  - {name: A, position: [0, 0, 0], ground: true, clamped: true}\n";
    for (int i = 1; i <= 4; ++i) s << "  - {name: n" << i << ", position: [" << 0.25 * i << ", 0, 0]}\n";
    s << "elements:\n  - {name: bar, type: " << (beam ? "ancf_beam" : "ancf_cable") << ", E: " << E
      << (beam ? ", nu: 0" : "") << ", density: 1000, section: {side: " << side << "}, nodes: [A, n1, n2, n3, n4]}\n"
      << "  - {name: moment, type: point_torque, node: n4, torque: [0, 0, " << M << "]"
      << (kind == "ancf_beam follower" ? ", follower: true" : "") << "}\nstatic: {load_steps: 1}\n";
    const Scene sc = readSceneText(s.str(), "spatial.yaml");
    const Model& m = *sc.model;
    Assembler as(m);
    StaticSettings set;
    set.steps = 1;
    set.stepLoadFactor = true;
    const VecX q = solveStatic(as, m.nominalParameters(), m.initialPositions(), set);
    int tip = 0;
    while (m.nodes[tip].name != "n4") ++tip;
    // r' (cable) or the section vector r_y (ancf_beam) turned about z
    const double rot = beam ? std::atan2(-q[m.dof(tip, 6)], q[m.dof(tip, 7)]) : std::atan2(q[m.dof(tip, 4)], q[m.dof(tip, 3)]);
    std::printf("%s: tip rotation %.6e (M L / EI = %.6e)\n", kind.c_str(), rot, M / EI);
    EXPECT_NEAR(rot, M / EI, 1e-3 * M / EI) << kind;
  }
  const std::string along = "dimension: 3\nnodes:\n  - {name: A, position: [0, 0, 0], ground: true, clamped: true}\n"
                            "  - {name: B, position: [1, 0, 0]}\nelements:\n"
                            "  - {name: bar, type: ancf_cable, E: 1.0e6, density: 1000, section: {side: 0.1}, nodes: [A, B]}\n"
                            "  - {name: twist, type: point_torque, node: B, torque: [1, 0, 0]}\nstatic: {load_steps: 1}\n";
  try {
    readSceneText(along, "twist.yaml");
    ADD_FAILURE() << "a twist on a cable's slope was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("twist.yaml:7:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("key 'elements[1].torque'"), std::string::npos) << e.what();
  }
}
