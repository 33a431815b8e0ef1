// Curved and twisted rest shapes of the spatial ANCF beam (elements/AncfBeam3D): the rest
// shape is stress-free under any rigid motion, every derivative against central differences
// and AD, the rest length against the arc's, the chain's default tangents against a circle's,
// the Bathe-Bolourchi 45-degree bend against its published tip, and static sensitivities of a
// curved cantilever against central differences of whole solutions.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "StaticChecks.hpp"
#include "TestModels.hpp"
#include "core/Assembler.hpp"
#include "elements/AncfBeam3D.hpp"
#include "integrators/Static.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;
using flexsens::test::fdJacobian;
using flexsens::test::relMax;

namespace {

/// Rest coordinates of one element on a helix-like arc: the axis turns by `bend` [rad] about z
/// over radius R [m] and the section twists by `twist` [rad] about the axis.
VecX arcElement(double R, double bend, double twist) {
  VecX e(24);
  for (int end = 0; end < 2; ++end) {
    const double th = end * bend, tw = end * twist;
    const Eigen::Vector3d r(R * std::sin(th), R * (1 - std::cos(th)), 0.1 * R * end * bend);
    const Eigen::Vector3d t = Eigen::Vector3d(R * std::cos(th), R * std::sin(th), 0.1 * R).normalized();
    const Eigen::Vector3d n0 = Eigen::Vector3d(-std::sin(th), std::cos(th), 0.0);
    const Eigen::Vector3d y0 = (n0 - n0.dot(t) * t).normalized(), z0 = t.cross(y0);
    const Eigen::Vector3d y = std::cos(tw) * y0 + std::sin(tw) * z0, z = t.cross(y);
    e.segment<12>(12 * end) << r, t, y, z;
  }
  return e;
}

std::shared_ptr<AncfBeamSection> boundSection() {
  auto s = std::make_shared<AncfBeamSection>();
  s->E.param = 0;
  s->nu.param = 1;
  s->density.param = 2;
  s->width.param = 3;
  s->height.param = 4;
  return s;
}

/// x's 24 coordinates moved rigidly: positions by R x + c, gradients by R g.
VecX moved(const VecX& x, const Eigen::Matrix3d& R, const Eigen::Vector3d& c) {
  VecX y = x;
  for (int i = 0; i < 8; ++i) y.segment<3>(3 * i) = R * x.segment<3>(3 * i) + (i == 0 || i == 4 ? c : Eigen::Vector3d::Zero());
  return y;
}

struct CurvedElement {
  VecX rest = arcElement(0.8, 0.5, 0.4);
  VecX p = (VecX(5) << 5.0e6, 0.3, 1100.0, 0.03, 0.012).finished();
  VecX g = VecX(Eigen::Vector3d(0.7, -9.81, 1.3));
  AncfBeam3D e{"b", {0, 1}, boundSection(), AncfBeam3D::restLength(rest), AncfBeam3D::kNormalPoints,
               AncfBeam3D::kShearPoints, &rest};
  LocalState at(const VecX& x, bool gravity) const {
    LocalState s;
    s.dim = 3;
    s.gradients = 3;
    s.x = x;
    s.v = VecX::Zero(24);
    s.p = &p;
    s.gravity = gravity ? &g : nullptr;
    return s;
  }
};

}  // namespace

// At a deformed state of a curved, twisted element: dQ/dq analytic vs AD (1e-10) and central
// FD (1e-6), -dU/dq vs Q, the value template vs the hand-coded force, and dQ/dp, dM/dp for E,
// nu, density, width, height (the rest metric moves with the section) vs AD and FD.
TEST(AncfBeamCurved, DerivativesMatchFiniteDifferencesAndAD) {
  CurvedElement c;
  std::srand(11);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const LocalState s = c.at(moved(c.rest, R, {0.1, 0.2, -0.3}) + 0.05 * VecX::Random(24), true);
  MatX Kv, Kvad;
  const MatX K = test::expectConservativeKernels(c.e, s, c.p, 5, Kv, Kvad);
  EXPECT_LT(relMax(K, K.transpose()), 1e-12) << "conservative: symmetric stiffness";
  VecX Q, Qt;
  c.e.force(s, Q);
  static_cast<const KernelElement<AncfBeam3D>&>(c.e).KernelElement<AncfBeam3D>::force(s, Qt);
  EXPECT_LT(relMax(Qt, Q), 1e-12) << "value template vs hand-coded force";
}

// The rest shape carries no stress, moved rigidly or not (forces of order E A = 1800 N would
// show any rest strain); its stiffness has exactly the 6 zero eigenvalues of the rigid motions.
TEST(AncfBeamCurved, RestShapeIsStressFreeUnderRigidMotion) {
  CurvedElement c;
  for (const double angle : {0.0, 0.9, 2.5}) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, Eigen::Vector3d(-1, 0.5, 2).normalized()).toRotationMatrix();
    const LocalState s = c.at(moved(c.rest, R, {1.0, -2.0, 0.5}), false);
    VecX Q;
    c.e.force(s, Q);
    EXPECT_LT(Q.lpNorm<Eigen::Infinity>(), 1e-9) << "rotation " << angle;
    MatX K, Kv;
    c.e.forceJacobian(s, K, Kv);
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<MatX>(-K).eigenvalues();
    int zeros = 0;
    for (int i = 0; i < ev.size(); ++i) zeros += std::abs(ev[i]) < 1e-9 * ev.cwiseAbs().maxCoeff();
    EXPECT_EQ(zeros, 6) << "rotation " << angle;
    EXPECT_GT(ev.minCoeff(), -1e-9 * ev.cwiseAbs().maxCoeff()) << "stable rest shape";
  }
}

// A circular arc of radius R and angle a with unit end tangents: the cubic Hermite axis's arc
// length converges to R a at O(a^4) as a -> 0 (measured 1.4e-3 a^4).
TEST(AncfBeamCurved, RestLengthIsTheArcLength) {
  for (const double a : {0.1, 0.3, 0.785}) {
    const double L = AncfBeam3D::restLength(arcElement(2.0, a, 0.0)), arc = 2.0 * a * std::sqrt(1.01);
    std::printf("arc angle %.3f: rest length / arc length - 1 = %.2e\n", a, L / arc - 1.0);
    EXPECT_LT(std::abs(L / arc - 1.0), 2e-3 * std::pow(a, 4));
  }
}

namespace {

/// The Bathe-Bolourchi bend (Bathe & Bolourchi 1979; Simo & Vu-Quoc 1986): a 45-degree arc of
/// radius 100 in the x-y plane from the origin (tangent +x), clamped there, unit square section,
/// E = 1e7, nu = 0, a dead load 600 along z at the tip, in `steps` load steps; N elements.
std::string batheBolourchi(int N, double load, int steps, const std::string& extra = "") {
  std::string nodes, names;
  for (int j = 0; j <= N; ++j) {
    const double th = M_PI / 4 * j / N;
    char buf[200];
    std::snprintf(buf, sizeof buf, "  - {name: n%d, position: [%.17g, %.17g, 0]%s}\n", j, 100 * std::sin(th),
                  100 * (1 - std::cos(th)), j == 0 ? ", ground: true, clamped: true" : "");
    nodes += buf;
    names += (j ? ", n" : "n") + std::to_string(j);
  }
  return "dimension: 3\nnodes:\n" + nodes + "elements:\n  - {name: bend, type: ancf_beam, nodes: [" + names +
         "], E: 1.0e7, nu: 0.0, density: 1.0,\n     section: {side: 1.0}, y_axis: [0, 0, 1]}\n"
         "  - {name: load, type: point_force, node: n" + std::to_string(N) + ", force: [0, 0, " + std::to_string(load) +
         "]}\n" + extra + "static: {load_steps: " + std::to_string(steps) + "}\n";
}

}  // namespace

// The chain's default frames on a uniformly divided arc: every tangent (bisector inside, the
// reflected chord at the ends) is the circle's, r_y the given y_axis.
TEST(AncfBeamCurved, DefaultTangentsOfAnArcAreTheCircles) {
  const Scene sc = readSceneText(batheBolourchi(8, 600, 20), "bend.yaml");
  for (int j = 0; j <= 8; ++j) {
    const double th = M_PI / 4 * j / 8;
    const VecX& g = sc.model->nodes[j].slope;
    EXPECT_LT((g.head<3>() - Eigen::Vector3d(std::cos(th), std::sin(th), 0)).norm(), 1e-12) << "node " << j;
    EXPECT_LT((g.segment<3>(3) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12) << "node " << j;
  }
}

// Published tip (47.23, 15.79, 53.37) (Simo & Vu-Quoc 1986): within 1% of the tip's
// displacement with 8 and with 16 elements, starting from the curved rest shape.
TEST(AncfBeamCurved, BatheBolourchiBendWithinOnePercent) {
  const Eigen::Vector3d published(47.23, 15.79, 53.37), start(100 * std::sin(M_PI / 4), 100 * (1 - std::cos(M_PI / 4)), 0);
  for (const int N : {8, 16}) {
    const Scene sc = readSceneText(batheBolourchi(N, 600, 20), "bend.yaml");
    const Model& m = *sc.model;
    Assembler as(m);
    StaticSettings set;
    set.steps = 20;
    const VecX q = solveStatic(as, VecX::Zero(0), m.initialPositions(), set);
    const Eigen::Vector3d tip(q[m.dof(N, 0)], q[m.dof(N, 1)], q[m.dof(N, 2)]);
    const double err = (tip - published).norm() / (published - start).norm();
    std::printf("Bathe-Bolourchi N = %d: tip (%.3f, %.3f, %.3f), error / |u| = %.2e\n", N, tip[0], tip[1], tip[2], err);
    EXPECT_LT(err, 0.01) << "N = " << N;
  }
}

// The curved cantilever under a moderate tip load (nonlinear): dq/dp of E, density and the
// side from staticSensitivities against central differences of whole static solutions.
TEST(AncfBeamCurved, StaticSensitivitiesMatchCentralDifferences) {
  const Scene sc = readSceneText(batheBolourchi(4, 100, 4,
                                                "parameters:\n  - {name: E, of: bend, property: E}\n"
                                                "  - {name: side, of: bend, property: side}\n"),
                                 "bend.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = m.nominalParameters();
  StaticSettings set;
  set.steps = 4;
  set.stepLoadFactor = true;
  StaticReport rep;
  const VecX q = solveStatic(as, p, m.initialPositions(), set, &rep);
  EXPECT_GT(q[m.dof(4, 2)], 10.0) << "a large deflection";
  const StaticSensitivity d = staticSensitivities(as, q, rep.lambda, p);
  test::expectStaticSensitivitiesMatchCentralDifferences(as, m, p, q, d.qp, 1e-6);
}

namespace {

/// Every ancf_beam node's r_x equals the curve's unit tangent at its position (to Gmsh's
/// derivative, ~1e-8); `count` such nodes.
template <class Tangent>
void expectTangents(const Model& m, int count, Tangent exact) {
  int checked = 0;
  for (const Node& nd : m.nodes) {
    if (nd.slope.size() != 9) continue;
    EXPECT_LT((nd.slope.head<3>() - exact(nd.position)).norm(), 1e-7) << nd.name;
    ++checked;
  }
  EXPECT_EQ(checked, count);
}

}  // namespace

// examples/frames/bathe_bolourchi.yaml: the arc meshed by Gmsh from bend.geo; its nodes take
// the circle's own tangents (to Gmsh's derivative, ~1e-8), and the tip lands within 1% of the
// published displacement.
TEST(AncfBeamCurved, GmshArcTakesTheCirclesTangents) {
  const Scene sc = readScene(test::sourceDir() + "/examples/frames/bathe_bolourchi.yaml");
  const Model& m = *sc.model;
  expectTangents(m, 9, [](const VecX& x) {
    const double th = std::atan2(x[0], 100.0 - x[1]);  // angle about the centre (0, 100)
    return Eigen::Vector3d(std::cos(th), std::sin(th), 0);
  });
  Assembler as(m);
  StaticSettings set;
  set.steps = 20;
  const VecX q = solveStatic(as, VecX::Zero(0), m.initialPositions(), set);
  const int tip = m.nodeIndex("tip");
  const Eigen::Vector3d x(q[m.dof(tip, 0)], q[m.dof(tip, 1)], q[m.dof(tip, 2)]), published(47.23, 15.79, 53.37);
  const Eigen::Vector3d start(100 * std::sin(M_PI / 4), 100 * (1 - std::cos(M_PI / 4)), 0);
  EXPECT_LT((x - published).norm() / (published - start).norm(), 0.01);
}

// A quarter ellipse x = 20 cos t, y = 10 sin t from Gmsh: every node's r_x is the ellipse's
// unit tangent (-2 sin t, cos t) / |.| (~1e-8), where tangents fitted to the chords would be off by
// ~1e-2 at the ends (checked: the reflected end chord's error printed).
TEST(AncfBeamCurved, GmshCurveTangentsOnAnEllipse) {
  const Scene sc = readScene(test::sourceDir() + "/tests/scenes/gmsh/ellipse_beam.yaml");
  const Model& m = *sc.model;
  expectTangents(m, 7, [](const VecX& x) {
    const double t = std::atan2(x[1] / 10.0, x[0] / 20.0);
    return Eigen::Vector3d(Eigen::Vector3d(-2 * std::sin(t), std::cos(t), 0).normalized());
  });
  // the fitted end tangent (the first chord reflected about the bisector at node 1)
  const Eigen::Vector3d x0 = m.nodes[m.nodeIndex("start")].position, x1 = m.nodes[m.nodeIndex("quarter.1")].position;
  const Eigen::Vector3d x2 = m.nodes[m.nodeIndex("quarter.2")].position;
  const Eigen::Vector3d d0 = (x1 - x0).normalized(), t1 = (d0 + (x2 - x1).normalized()).normalized();
  const Eigen::Vector3d fitted = 2.0 * t1.dot(d0) * d0 - t1;
  std::printf("ellipse start: fitted tangent off by %.2e\n", (fitted - Eigen::Vector3d(0, 1, 0)).norm());
  EXPECT_GT((fitted - Eigen::Vector3d(0, 1, 0)).norm(), 1e-3);
}
