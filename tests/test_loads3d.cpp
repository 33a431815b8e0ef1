// Spatial loads: point_torque in 3D (elements/SpatialTorque.hpp; two or three nodes,
// space-fixed or follower) and the 3D follower point_force (elements/SpatialFollowerForce.hpp).
// Checked against independent references: the couple's resultant and moment against the
// torque (computed here from the inputs), the follower vectors on a rigidly rotated
// configuration against R V0, dQ/dq and dQ/dp against central finite differences, AD against
// the analytic derivatives; then whole runs against rigid-body mechanics: a free body under a
// torque about a principal axis through its centre of mass, theta = T t^2 / (2 I), with a
// space-fixed and a follower torque; a body pinned at a point under a follower force; a
// pinned bar under a two-node torque, and the planar scene against the same scene in 3D; a
// clamped beam bent by an end couple into a circular arc (static); the run sensitivities.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "core/TimeFunction.hpp"
#include "elements/SpatialFollowerForce.hpp"
#include "elements/SpatialTorque.hpp"
#include "integrators/InitialState.hpp"
#include "integrators/Static.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

/// Harmonic f(t) with its constants bound to parameters 0..3, the three components to 4..6.
struct LoadParams {
  std::unique_ptr<TimeFunction> f;
  std::vector<Quantity> comps;
  VecX p;
};

LoadParams loadParams(const Eigen::Vector3d& V0) {
  LoadParams lp;
  lp.f = makeHarmonic(0.5, 3.0, 0.1, 1.0);
  auto props = lp.f->properties();
  lp.p.resize(7);
  for (int i = 0; i < 4; ++i) {
    lp.p[i] = props[i].second->constant;
    props[i].second->param = i;
  }
  for (int c = 0; c < 3; ++c) {
    lp.p[4 + c] = V0[c];
    lp.comps.push_back(Quantity{V0[c], 4 + c});
  }
  return lp;
}

/// f(t) of loadParams at t = 0.4, from its definition.
double factorAt04() { return 1.0 + 0.5 * std::sin(3.0 * 0.4 + 0.1); }

Eigen::Vector3d node(const VecX& x, int k) { return x.segment<3>(3 * k); }

/// Checks dQ/dq (analytic and AD) and dQ/dp (analytic and AD) of e at s against central
/// differences; parameters 0..np-1.
void checkDerivatives(const Element& e, const LocalState& s, int np, const std::string& what) {
  auto Q = [&](const VecX& x, const VecX& pp) {
    LocalState l = s;
    l.x = x;
    l.p = &pp;
    VecX r;
    e.force(l, r);
    return r;
  };
  const VecX& p = *s.p;
  MatX K, C, Kad, Cad;
  e.forceJacobian(s, K, C);
  e.forceJacobianAD(s, Kad, Cad);
  const MatX Kfd = fdJacobian([&](const VecX& x) { return Q(x, p); }, s.x);
  EXPECT_GT(Kfd.norm(), 1e-3) << what;  // the load does depend on q
  EXPECT_LT(relErr(K, Kfd), 1e-6) << what << "\nK\n" << K << "\nFD\n" << Kfd;
  EXPECT_LT(relErr(Kad, K), 1e-12) << what;
  EXPECT_EQ(C.norm(), 0.0) << what;
  EXPECT_EQ(Cad.norm(), 0.0) << what;
  for (int k = 0; k < np; ++k) {
    VecX dQ, dQad;
    MatX dM, dMad;
    ASSERT_TRUE(e.parameterDerivative(s, k, dQ, dM)) << what << " k " << k;
    ASSERT_TRUE(e.parameterDerivativeAD(s, k, dQad, dMad)) << what << " k " << k;
    VecX pp = p, pm = p;
    pp[k] += 1e-6;
    pm[k] -= 1e-6;
    const VecX fd = (Q(s.x, pp) - Q(s.x, pm)) / 2e-6;
    EXPECT_GT(fd.norm(), 1e-3) << what << " k " << k;
    EXPECT_LT(relErr(dQ, fd), 1e-6) << what << " k " << k;
    EXPECT_LT(relErr(dQad, dQ), 1e-12) << what << " k " << k;
  }
  VecX dQ;
  MatX dM;
  EXPECT_FALSE(e.parameterDerivative(s, np, dQ, dM)) << what;
  EXPECT_FALSE(e.parameterDerivativeAD(s, np, dQ, dM)) << what;
}

/// Resultant and moment about the origin of the nodal forces Q at positions x.
void resultant(const VecX& x, const VecX& Q, Eigen::Vector3d& F, Eigen::Vector3d& M) {
  F.setZero();
  M.setZero();
  for (int k = 0; k < x.size() / 3; ++k) {
    F += node(Q, k);
    M += node(x, k).cross(node(Q, k));
  }
}

/// A random non-degenerate state of n nodes (positions spread over ~1 m).
VecX randomPositions(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VecX x(3 * n);
  for (int i = 0; i < x.size(); ++i) x[i] = u(rng);
  return x;
}

}  // namespace

TEST(Loads3dTorque, ThreeNodeCoupleHasTheTorqueAsMomentAndMatchesFiniteDifferences) {
  const Eigen::Vector3d T0(0.7, -1.3, 2.1);
  for (bool follower : {false, true}) {
    LoadParams lp = loadParams(T0);
    MatX X0(3, 3);
    X0 << 0.1, 1.2, 0.3,  //
        -0.2, 0.1, 0.9,   //
        0.3, 0.4, -0.1;
    SpatialTorque tq("tq", {0, 1, 2}, lp.comps, std::move(lp.f), follower, X0);
    LocalState s;
    s.dim = 3;
    s.p = &lp.p;
    s.t = 0.4;
    s.v = VecX::Zero(9);
    const double fac = factorAt04();
    const std::string what = follower ? "follower" : "space-fixed";
    // A general (non-rigid) state: no net force; moment = T(q), T = f T0 or, following,
    // f (a1 d1 + a2 d2 + a3 n) with a solved here from T0 = E0 a.
    s.x = randomPositions(3, 7);
    VecX Q;
    tq.force(s, Q);
    Eigen::Vector3d F, M, T = fac * T0;
    if (follower) {
      Eigen::Matrix3d E0, E;
      const Eigen::Vector3d a1 = X0.col(1) - X0.col(0), a2 = X0.col(2) - X0.col(0);
      const Eigen::Vector3d b1 = node(s.x, 1) - node(s.x, 0), b2 = node(s.x, 2) - node(s.x, 0);
      E0 << a1, a2, a1.cross(a2);
      E << b1, b2, b1.cross(b2);
      T = fac * E * E0.fullPivLu().solve(T0);
    }
    resultant(s.x, Q, F, M);
    EXPECT_LT(F.norm(), 1e-12 * Q.norm()) << what;
    EXPECT_LT((M - T).norm(), 1e-12 * T.norm()) << what << ": " << M.transpose() << " vs " << T.transpose();
    // Power on a rigid motion v_k = v0 + omega x x_k is T . omega.
    const Eigen::Vector3d v0(0.3, -0.5, 0.8), om(-1.1, 0.4, 0.6);
    double power = 0;
    for (int k = 0; k < 3; ++k) power += Q.segment<3>(3 * k).dot(v0 + om.cross(node(s.x, k)));
    EXPECT_NEAR(power, T.dot(om), 1e-12 * T.norm()) << what;
    checkDerivatives(tq, s, 7, what);
    // A rigid motion of the initial nodes: the follower torque is R T0 f, the space-fixed T0 f.
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
    for (int k = 0; k < 3; ++k) s.x.segment<3>(3 * k) = R * X0.col(k) + Eigen::Vector3d(0.2, -0.4, 1.0);
    tq.force(s, Q);
    resultant(s.x, Q, F, M);
    const Eigen::Vector3d expect = follower ? Eigen::Vector3d(fac * R * T0) : Eigen::Vector3d(fac * T0);
    EXPECT_LT((M - expect).norm(), 1e-12 * expect.norm()) << what;
    checkDerivatives(tq, s, 7, what + " rotated");
  }
}

TEST(Loads3dTorque, TwoNodeCoupleActsWithThePerpendicularPart) {
  const Eigen::Vector3d T0(0.0, -1.3, 2.1);  // perpendicular to the initial A-B = x axis
  LoadParams lp = loadParams(T0);
  MatX X0(3, 2);
  X0 << 0, 1.5, 0, 0, 0, 0;
  SpatialTorque tq("tq", {0, 1}, lp.comps, std::move(lp.f), false, X0);
  LocalState s;
  s.dim = 3;
  s.p = &lp.p;
  s.t = 0.4;
  s.v = VecX::Zero(6);
  s.x = randomPositions(2, 11);
  VecX Q;
  tq.force(s, Q);
  // Moment = the part of T perpendicular to d (a couple of two forces cannot have more).
  const Eigen::Vector3d d = node(s.x, 1) - node(s.x, 0), T = factorAt04() * T0;
  const Eigen::Vector3d Tperp = T - d * T.dot(d) / d.squaredNorm();
  Eigen::Vector3d F, M;
  resultant(s.x, Q, F, M);
  EXPECT_LT(F.norm(), 1e-14);
  EXPECT_LT((M - Tperp).norm(), 1e-12 * T.norm());
  checkDerivatives(tq, s, 7, "two nodes");
  // Two nodes cannot carry a follower torque.
  LoadParams l2 = loadParams(T0);
  EXPECT_THROW(SpatialTorque("t2", {0, 1}, l2.comps, std::move(l2.f), true, X0), std::invalid_argument);
}

TEST(Loads3dFollowerForce, TurnsWithTheBodyAndMatchesFiniteDifferences) {
  const Eigen::Vector3d F0(1.1, -0.4, 0.9);
  LoadParams lp = loadParams(F0);
  Eigen::Matrix3d X0;
  X0 << 0.1, 1.2, 0.3,  //
      -0.2, 0.1, 0.9,   //
      0.3, 0.4, -0.1;
  // P is node 3 of the local state; the body A, B, C are 0, 1, 2 (global numbering here).
  SpatialFollowerForce ff("ff", 3, 0, 1, 2, X0, lp.comps, std::move(lp.f));
  LocalState s;
  s.dim = 3;
  s.p = &lp.p;
  s.t = 0.4;
  s.v = VecX::Zero(12);
  const double fac = factorAt04();
  // Local order: P, A, B, C. At t = 0 positions the force is F0 f; rotated rigidly, R F0 f.
  const Eigen::Vector3d P0(0.5, 0.5, 0.5);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-1.7, Eigen::Vector3d(0.3, -1, 0.4).normalized()).toRotationMatrix();
  for (int rotated = 0; rotated < 2; ++rotated) {
    const Eigen::Matrix3d Rr = rotated ? R : Eigen::Matrix3d::Identity();
    s.x.resize(12);
    s.x.segment<3>(0) = Rr * P0;
    for (int k = 0; k < 3; ++k) s.x.segment<3>(3 + 3 * k) = Rr * X0.col(k) + Eigen::Vector3d(-0.3, 0.2, 0.7);
    VecX Q;
    ff.force(s, Q);
    EXPECT_LT((Q.head<3>() - fac * Rr * F0).norm(), 1e-13) << rotated;
    EXPECT_EQ(Q.tail<9>().norm(), 0.0);
    checkDerivatives(ff, s, 7, rotated ? "follower force rotated" : "follower force");
  }
  // A general (deformed) state: derivatives again.
  s.x = randomPositions(4, 3);
  checkDerivatives(ff, s, 7, "follower force deformed");
  Eigen::Matrix3d line = X0;
  line.col(2) = 2.0 * X0.col(1) - X0.col(0);  // C on the line A-B
  LoadParams l2 = loadParams(F0);
  EXPECT_THROW(SpatialFollowerForce("f2", 3, 0, 1, 2, line, l2.comps, std::move(l2.f)), std::invalid_argument);
}

namespace {

/// Runs a scene with its own integrator settings and returns the last frame's state.
StateWithSens runToEnd(const std::string& text, Derivatives mode = Derivatives::Analytic) {
  const Scene sc = readSceneText(text, "loads3d.yaml");
  Assembler as(*sc.model, mode);
  const VecX p = sc.model->nominalParameters();
  Recorder rec;
  integrate(as, p, initialState(as, p), sc.integrator, rec);
  if (rec.frames.empty()) throw std::runtime_error("no frames");
  return rec.frames.back();
}

/// Largest distance of the nodes `names` from their initial positions turned by theta about
/// the z axis through `pivot`.
double offRotation(const Scene& sc, const StateWithSens& st, const std::vector<std::string>& names, double theta,
                   const Eigen::Vector3d& pivot) {
  const Model& m = *sc.model;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  double worst = 0;
  for (const auto& n : names) {
    const int id = m.nodeIndex(n);
    const Eigen::Vector3d X = m.nodes[id].position, expect = pivot + R * (X - pivot);
    Eigen::Vector3d x;
    for (int c = 0; c < 3; ++c) x[c] = m.dof(id, c) >= 0 ? st.x.q[m.dof(id, c)] : X[c];
    worst = std::max(worst, (x - expect).norm());
  }
  return worst;
}

// A free rigid body (no gravity), centre of mass at the origin, inertia diag(0.3, 0.35, 0.4)
// about it (z the largest: rotation about z is stable), at rest. A torque tau = 0.4 N m about
// z turns it about the z axis through the centre of mass with theta'' = tau / Izz = 1 rad/s^2.
const char* kFreeBody = R"(
dimension: 3
gravity: [0, 0, 0]
nodes:
  - {name: A, position: [0.2, -0.1, 0.1]}
  - {name: B, position: [1.0, 0.1, -0.2]}
  - {name: C, position: [0.1, 0.9, 0.2]}
  - {name: D, position: [-0.1, 0.2, 0.8]}
elements:
  - {name: body, type: rigid_body, nodes: [A, B, C, D], mass: 2, center_of_mass: [0, 0, 0], inertia: [0.3, 0.35, 0.4]}
)";
const char* kRun = "integrator: {type: trapezoidal, t_end: 1, dt: 0.001, frame_interval: 1}\n";

}  // namespace

TEST(Loads3dPhysics, FreeBodyUnderTorqueAboutAPrincipalAxisTurnsAsTauTSquaredOver2I) {
  // Space-fixed and follower give the same motion: the rotation stays about z, so the
  // follower torque R T0 = T0. Analytic theta(1 s) = 0.4 * 1 / (2 * 0.4) = 0.5 rad.
  for (const std::string extra : {"", ", follower: true"}) {
    const std::string text =
        std::string(kFreeBody) + "  - {name: tq, type: point_torque, nodes: [A, B, C], torque: [0, 0, 0.4]" + extra + "}\n" + kRun;
    const Scene sc = readSceneText(text, "free.yaml");
    const StateWithSens st = runToEnd(text);
    ASSERT_NEAR(st.x.t, 1.0, 1e-12);
    const double err = offRotation(sc, st, {"A", "B", "C", "D"}, 0.5, Eigen::Vector3d::Zero());
    // Trapezoidal rule at dt = 1e-3: O(dt^2) position error, here ~1e-7 m.
    EXPECT_LT(err, 1e-6) << "torque" << extra;
    // A wrong torque (e.g. 1 % off) would be 5e-3 rad x ~1 m away.
    EXPECT_GT(offRotation(sc, st, {"B"}, 0.505, Eigen::Vector3d::Zero()), 1e-3);
  }
}

TEST(Loads3dPhysics, FollowerForceOnAPinnedBodyActsAsAConstantTorque) {
  // Body pinned at the ground node O (a spherical joint: the shared node), centre of mass
  // G = (0.5, 0, 0), inertia diag(0.1, 0.2, 0.25) about G: about O, I_O = I_G + m (|r|^2 1 -
  // r r^T), r = G - O, is diagonal with Izz_O = 0.25 + 2 * 0.25 = 0.75 (the largest). The
  // follower force F0 = (0, 0.75, 0) at B = (1, 0, 0) stays perpendicular to OB in the plane
  // of rotation: moment 0.75 N m about z, theta'' = 1 rad/s^2, theta(1 s) = 0.5 rad.
  const std::string text = R"(
dimension: 3
gravity: [0, 0, 0]
nodes:
  - {name: O, position: [0, 0, 0], ground: true}
  - {name: B, position: [1, 0, 0]}
  - {name: C, position: [0.5, 0.5, 0]}
  - {name: D, position: [0.5, 0, 0.5]}
elements:
  - {name: body, type: rigid_body, nodes: [O, B, C, D], mass: 2, center_of_mass: [0.5, 0, 0], inertia: [0.1, 0.2, 0.25]}
  - {name: push, type: point_force, node: B, force: [0, 0.75, 0], follower: true, body: [O, B, C]}
integrator: {type: trapezoidal, t_end: 1, dt: 0.001, frame_interval: 1}
)";
  const Scene sc = readSceneText(text, "pinned.yaml");
  const StateWithSens st = runToEnd(text);
  ASSERT_NEAR(st.x.t, 1.0, 1e-12);
  EXPECT_LT(offRotation(sc, st, {"B", "C", "D"}, 0.5, Eigen::Vector3d::Zero()), 1e-6);
  // The same force as a dead load would give a different angle (its moment falls as cos theta).
  EXPECT_GT(offRotation(sc, st, {"B"}, 0.49, Eigen::Vector3d::Zero()), 5e-3);
}

TEST(Loads3dPhysics, TwoNodeTorqueOnAPinnedBarAndThePlanarSceneAgree) {
  // A uniform bar (m = 1.5 kg, L = 1.2 m) pinned at O, no gravity, torque 0.6 N m about z:
  // theta'' = tau / (m L^2 / 3) = 0.6 / 0.72 rad/s^2. The planar scene and the 3D one (the
  // bar in the plane z = 0, the torque about z through the two nodes) give the same steps.
  const std::string planar = R"(
dimension: 2
gravity: [0, 0]
nodes:
  - {name: O, position: [0, 0], ground: true}
  - {name: T, position: [1.2, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [O, T], mass: 1.5}
  - {name: tq, type: point_torque, nodes: [O, T], torque: 0.6}
integrator: {type: trapezoidal, t_end: 1, dt: 0.001, frame_interval: 1}
)";
  const std::string spatial = R"(
dimension: 3
gravity: [0, 0, 0]
nodes:
  - {name: O, position: [0, 0, 0], ground: true}
  - {name: T, position: [1.2, 0, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [O, T], mass: 1.5}
  - {name: tq, type: point_torque, nodes: [O, T], torque: [0, 0, 0.6]}
integrator: {type: trapezoidal, t_end: 1, dt: 0.001, frame_interval: 1}
)";
  const StateWithSens a = runToEnd(planar), b = runToEnd(spatial);
  ASSERT_EQ(a.x.q.size(), 2);
  ASSERT_EQ(b.x.q.size(), 3);
  EXPECT_LT(std::abs(a.x.q[0] - b.x.q[0]), 1e-10);
  EXPECT_LT(std::abs(a.x.q[1] - b.x.q[1]), 1e-10);
  EXPECT_LT(std::abs(b.x.q[2]), 1e-12);
  const double theta = 0.5 * (0.6 / 0.72) * 1.0;
  const Scene sc = readSceneText(spatial, "bar.yaml");
  EXPECT_LT(offRotation(sc, b, {"T"}, theta, Eigen::Vector3d::Zero()), 1e-6);
}

TEST(Loads3dPhysics, EndCoupleBendsAClampedBeamIntoACircularArc) {
  // A clamped 3D beam (L = 1 m, EI = E a^4/12) under a torque M = (pi/2) EI / L about z
  // through its last two nodes: the bending moment is M all along, the beam a quarter circle
  // of radius R = EI / M, tip at (R sin(L/R), R (1 - cos(L/R)), 0) = (2/pi, 2/pi, 0) L. The
  // discrete beam (hinges with the half-cell clamp) converges to it as N grows.
  const double E = 2.1e11, a = 1e-3, EI = E * std::pow(a, 4) / 12.0, M = M_PI / 2 * EI;
  double prev = 0;
  for (int N : {16, 32, 64}) {
    std::ostringstream os;
    os.precision(17);
    os << "dimension: 3\ngravity: [0, 0, 0]\nnodes:\n  - {name: root, position: [0, 0, 0], ground: true}\n";
    for (int i = 1; i <= N; ++i) os << "  - {name: n" << i << ", position: [" << double(i) / N << ", 0, 0]}\n";
    os << "elements:\n  - {name: beam, type: beam, clamp: start, E: " << E << ", density: 7800, section: {side: " << a
       << "}, nodes: [root";
    for (int i = 1; i <= N; ++i) os << ", n" << i;
    os << "]}\n  - {name: tq, type: point_torque, nodes: [n" << N - 1 << ", n" << N << "], torque: [0, 0, " << M
       << "]}\nstatic: {load_steps: 10}\n";
    const Scene sc = readSceneText(os.str(), "arc.yaml");
    const Model& m = *sc.model;
    Assembler as(m);
    StaticSettings set;
    set.steps = 10;
    set.stepLoadFactor = true;
    const VecX q = solveStatic(as, m.nominalParameters(), m.initialPositions(), set, nullptr);
    const int tip = m.nodeIndex("n" + std::to_string(N));
    const Eigen::Vector3d x(q[m.dof(tip, 0)], q[m.dof(tip, 1)], q[m.dof(tip, 2)]);
    const double err = (x - Eigen::Vector3d(2 / M_PI, 2 / M_PI, 0)).norm();
    std::printf("  N = %d: tip error %.3e m\n", N, err);
    EXPECT_LT(err, 1.0 / (N * N)) << N;
    if (prev > 0) EXPECT_GT(std::log2(prev / err), 1.8) << N;
    prev = err;
  }
}

TEST(Loads3dScene, ComponentsAndFunctionConstantsAreBindableParameters) {
  // Each component by its axis name, the function's constants by theirs; the sensitivities
  // (dd and ad) of a short run to the torque's z component, the ramp's slope and the follower
  // force's y component against central differences of two runs.
  auto scene = [](double tz, double slope) {
    std::ostringstream os;
    os.precision(17);
    os << kFreeBody << "  - {name: tq, type: point_torque, nodes: [A, B, C], torque: [0.05, -0.02, " << tz
       << "], follower: true, function: {type: ramp, slope: " << slope << "}}\n"
       << "  - {name: push, type: point_force, node: D, force: [0.1, 0.2, -0.1], follower: true, body: [A, B, C]}\n"
       << kRun << "parameters:\n  - {name: Tz, of: tq, property: z}\n  - {name: s, of: tq, property: slope}\n"
       << "  - {name: Fy, of: push, property: y}\n";
    return os.str();
  };
  // Fy: the force's y component in the text.
  auto withFy = [&](double fy) {
    std::string t = scene(0.4, 2);
    const std::string from = "force: [0.1, 0.2, -0.1]";
    std::ostringstream os;
    os.precision(17);
    os << "force: [0.1, " << fy << ", -0.1]";
    t.replace(t.find(from), from.size(), os.str());
    return t;
  };
  const double h = 1e-4;
  const VecX fd[3] = {(runToEnd(scene(0.4 + h, 2)).x.q - runToEnd(scene(0.4 - h, 2)).x.q) / (2 * h),
                      (runToEnd(scene(0.4, 2 + h)).x.q - runToEnd(scene(0.4, 2 - h)).x.q) / (2 * h),
                      (runToEnd(withFy(0.2 + h)).x.q - runToEnd(withFy(0.2 - h)).x.q) / (2 * h)};
  for (const Derivatives mode : {Derivatives::Analytic, Derivatives::AutomaticDifferentiation}) {
    const std::string method = mode == Derivatives::Analytic ? "dd" : "ad";
    const StateWithSens st = runToEnd(scene(0.4, 2), mode);
    ASSERT_EQ(st.dp.size(), 3u);
    for (int k = 0; k < 3; ++k) {
      EXPECT_GT(fd[k].norm(), 1e-2) << k;
      EXPECT_LT(relErr(st.dp[k].q, fd[k]), 1e-6) << method << " p" << k << "\n" << st.dp[k].q.transpose() << "\n" << fd[k].transpose();
    }
  }
}
