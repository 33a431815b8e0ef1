// General planar rigid body (elements/PlanarRigidBody.hpp), checked against independent
// references: the mass matrix against the sum over a cloud of point masses of N^T N m_k
// (and the kinetic energy 1/2 m v_G^2 + 1/2 I_G w^2 of any rigid motion), the release of an
// off-centre compound pendulum against alpha = -m g x_G / I_O, AD against the analytic
// parameter derivatives, parameter derivatives against central differences, and a four-bar of
// uniform planar bodies against the same four-bar of rigid bars.
#include <gtest/gtest.h>

#include <random>

#include "app/Run.hpp"
#include "elements/PlanarRigidBody.hpp"
#include "integrators/FixedStep.hpp"

using namespace flexsens;

namespace {

struct Cloud {
  std::vector<Eigen::Vector2d> x;
  std::vector<double> m;
  double mass = 0, IG = 0;
  Eigen::Vector2d com = Eigen::Vector2d::Zero();
};

/// An irregular cloud of point masses (the "body"), its mass, centre of mass, polar moment.
Cloud cloud() {
  Cloud c;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), w(0.1, 2.0);
  for (int k = 0; k < 40; ++k) {
    c.x.push_back(Eigen::Vector2d(0.8 + 0.6 * u(rng), 0.3 + 0.4 * u(rng)));
    c.m.push_back(w(rng));
  }
  for (size_t k = 0; k < c.x.size(); ++k) c.mass += c.m[k], c.com += c.m[k] * c.x[k];
  c.com /= c.mass;
  for (size_t k = 0; k < c.x.size(); ++k) c.IG += c.m[k] * (c.x[k] - c.com).squaredNorm();
  return c;
}

/// Local state of the body's two basic points at xA, xB with parameters p and gravity g.
struct Local {
  VecX p, g;
  LocalState s;
  Local(const VecX& xA, const VecX& xB, VecX params) : p(std::move(params)), g(Eigen::Vector2d(0.3, -9.81)) {
    s.dim = 2;
    s.x = (VecX(4) << xA, xB).finished();
    s.v = VecX::Zero(4);
    s.p = &p;
    s.gravity = &g;
  }
};

}  // namespace

TEST(PlanarRigidBody, MassMatrixEqualsPointMassSumAndKineticEnergy) {
  const Cloud c = cloud();
  const VecX xA = Eigen::Vector2d(0.1, -0.2), xB = Eigen::Vector2d(1.3, 0.4);
  PlanarRigidBody body("b", 0, 1, xA, xB, c.com, {c.mass, -1}, {c.IG, -1});
  Local l(xA, xB, VecX());
  MatX M;
  ASSERT_TRUE(body.mass(l.s, M));
  MatX ref = MatX::Zero(4, 4);
  Eigen::Matrix2d R;
  R << 0, -1, 1, 0;
  for (size_t k = 0; k < c.x.size(); ++k) {
    const Eigen::Vector2d bc = PlanarRigidBody::bodyCoordinates(xA, xB, c.x[k]);
    MatX N(2, 4);
    N << (1 - bc[0]) * Eigen::Matrix2d::Identity() - bc[1] * R, bc[0] * Eigen::Matrix2d::Identity() + bc[1] * R;
    ref += c.m[k] * N.transpose() * N;
  }
  EXPECT_LT((M - ref).lpNorm<Eigen::Infinity>(), 1e-12 * ref.lpNorm<Eigen::Infinity>());
  // Rigid motion: v_P = v_A + w R (x_P - x_A)
  const Eigen::Vector2d vA(0.7, -1.1);
  const double w = 2.3;
  VecX v(4);
  v << vA, vA + w * R * (xB - xA);
  const Eigen::Vector2d vG = vA + w * R * (c.com - xA);
  EXPECT_NEAR(0.5 * v.dot(M * v), 0.5 * c.mass * vG.squaredNorm() + 0.5 * c.IG * w * w, 1e-12 * c.mass);
  // gravity: total force m g, potential -m g . r_G
  VecX Q;
  body.force(l.s, Q);
  EXPECT_LT((Q.head(2) + Q.tail(2) - c.mass * l.g).norm(), 1e-12 * c.mass);
  EXPECT_NEAR(body.potential(l.s), -c.mass * l.g.dot(c.com), 1e-12 * c.mass);
}

TEST(PlanarRigidBody, AnalyticParameterDerivativesMatchAdAndCentralDifferences) {
  const VecX xA = Eigen::Vector2d(0.1, -0.2), xB = Eigen::Vector2d(1.3, 0.4), com = Eigen::Vector2d(0.9, 0.5);
  PlanarRigidBody body("b", 0, 1, xA, xB, com, {0.0, 0}, {0.0, 1});
  Local l(xA, xB, Eigen::Vector2d(3.0, 0.4));
  for (int k = 0; k < 2; ++k) {
    VecX dQ, dQad;
    MatX dM, dMad;
    ASSERT_TRUE(body.parameterDerivative(l.s, k, dQ, dM));
    ASSERT_TRUE(body.parameterDerivativeAD(l.s, k, dQad, dMad));
    EXPECT_LT((dM - dMad).lpNorm<Eigen::Infinity>(), 1e-10 * dM.lpNorm<Eigen::Infinity>());
    EXPECT_LT((dQ - dQad).lpNorm<Eigen::Infinity>(), 1e-10 * (1 + dQ.lpNorm<Eigen::Infinity>()));
    const double h = 1e-6;
    VecX pp = l.p, pm = l.p;
    pp[k] += h;
    pm[k] -= h;
    MatX Mp, Mm;
    VecX Qp, Qm;
    l.s.p = &pp;
    body.mass(l.s, Mp);
    body.force(l.s, Qp);
    l.s.p = &pm;
    body.mass(l.s, Mm);
    body.force(l.s, Qm);
    l.s.p = &l.p;
    EXPECT_LT((dM - (Mp - Mm) / (2 * h)).lpNorm<Eigen::Infinity>(), 1e-8 * dM.lpNorm<Eigen::Infinity>());
    EXPECT_LT((dQ - (Qp - Qm) / (2 * h)).lpNorm<Eigen::Infinity>(), 1e-8 * (1 + dQ.lpNorm<Eigen::Infinity>()));
  }
  VecX dQ;
  MatX dM;
  EXPECT_FALSE(body.parameterDerivative(l.s, 2, dQ, dM));
}

// Compound pendulum pinned at ground node O, released at rest: every point accelerates as
// a_P = alpha R (x_P - x_O), alpha = ((x_G - x_O) x m g) / I_O, I_O = I_G + m |x_G - x_O|^2.
TEST(PlanarRigidBody, ReleasedCompoundPendulumAcceleratesAsTheoryGives) {
  const char* text = R"(dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: O, position: [0, 0], ground: true}
  - {name: B, position: [1.2, 0.3]}
  - {name: P, position: [0.4, -0.7]}
elements:
  - {name: body, type: planar_rigid_body, nodes: [O, B, P], mass: 2.5, center_of_mass: [0.5, 0.35], inertia: 0.4}
integrator: {type: trapezoidal, t_end: 0.1, dt: 0.001}
)";
  const Scene sc = readSceneText(text, "pendulum.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  const State s = consistentState(as, m.nominalParameters());
  const Eigen::Vector2d G(0.5, 0.35), g(0, -9.81);
  const double IO = 0.4 + 2.5 * G.squaredNorm();
  const double alpha = (G[0] * 2.5 * g[1] - G[1] * 2.5 * g[0]) / IO;
  Eigen::Matrix2d R;
  R << 0, -1, 1, 0;
  for (const char* name : {"B", "P"}) {
    const int id = m.nodeIndex(name);
    const Eigen::Vector2d x = m.nodes[id].position;
    const Eigen::Vector2d a = s.a.segment(m.dof(id, 0), 2);
    EXPECT_LT((a - alpha * R * x).norm(), 1e-10 * std::abs(alpha)) << name << ": " << a.transpose();
  }
}

// A four-bar of uniform planar bodies (centre of mass at mid-length, I_G = m L^2 / 12) is the
// four-bar of rigid bars: same mass matrices, so the trapezoidal runs agree to round-off.
TEST(PlanarRigidBody, FourBarOfUniformBodiesEqualsFourBarOfRigidBars) {
  const std::string nodes = R"(dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: D, position: [2, 0], ground: true}
  - {name: B, position: [0.3, 1.0], velocity: [1.0, -0.3]}
  - {name: C, position: [1.9, 1.2]}
integrator: {type: trapezoidal, t_end: 1.0, dt: 0.001}
)";
  auto bodyLine = [](const std::string& n, const std::string& a, const std::string& b, double m,
                     const Eigen::Vector2d& xa, const Eigen::Vector2d& xb) {
    const Eigen::Vector2d c = 0.5 * (xa + xb);
    const double L2 = (xb - xa).squaredNorm();
    std::ostringstream os;
    os.precision(17);
    os << "  - {name: " << n << ", type: planar_rigid_body, nodes: [" << a << ", " << b << "], mass: " << m
       << ", center_of_mass: [" << c[0] << ", " << c[1] << "], inertia: " << m * L2 / 12 << "}\n";
    return os.str();
  };
  const Eigen::Vector2d A(0, 0), D(2, 0), B(0.3, 1.0), C(1.9, 1.2);
  const std::string bars = nodes + "elements:\n"
                           "  - {name: AB, type: rigid_bar, nodes: [A, B], mass: 1}\n"
                           "  - {name: BC, type: rigid_bar, nodes: [B, C], mass: 2}\n"
                           "  - {name: CD, type: rigid_bar, nodes: [C, D], mass: 1.5}\n";
  const std::string bodies = nodes + "elements:\n" + bodyLine("AB", "A", "B", 1, A, B) + bodyLine("BC", "B", "C", 2, B, C) +
                             bodyLine("CD", "C", "D", 1.5, C, D);
  struct Last : Observer {
    VecX q;
    void frame(const StateWithSens& s) override { q = s.x.q; }
  };
  VecX out[2];
  int i = 0;
  for (const std::string& text : {bars, bodies}) {
    const Scene sc = readSceneText(text, "fourbar.yaml");
    Assembler as(*sc.model);
    const VecX p = sc.model->nominalParameters();
    Last last;
    integrate(as, p, initialState(as, p), sc.integrator, last);
    out[i++] = last.q;
  }
  ASSERT_EQ(out[0].size(), out[1].size());
  const double moved = (out[0] - readSceneText(bars, "x.yaml").model->initialPositions()).norm();
  EXPECT_GT(moved, 0.1);  // the mechanism did move
  EXPECT_LT((out[0] - out[1]).lpNorm<Eigen::Infinity>(), 1e-10) << out[0].transpose() << "\n" << out[1].transpose();
}
