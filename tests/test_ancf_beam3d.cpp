// Fully parameterized spatial ANCF beam (elements/AncfBeam3D, the 3243 element): derivatives
// against central finite differences and AD, rigid-motion invariance and the zero-energy modes,
// the uniform-stretch patch test against the St. Venant-Kirchhoff axial force, the linear
// cantilever (P L^3 / 3EI plus the shear term) and the twisted shaft (T L / (G J)) with their
// convergence, the scene (clamp, pin, default gradients).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "StaticChecks.hpp"
#include "TestModels.hpp"
#include "core/Assembler.hpp"
#include "elements/AncfBeam3D.hpp"
#include "elements/PointForce.hpp"
#include "integrators/Static.hpp"
#include "pim/Rigidization.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;
using flexsens::test::fdJacobian;
using flexsens::test::relMax;

namespace {

/// A section whose every entry is a parameter: p = (E, nu, density, width, height) or, square,
/// (E, nu, density, side). Soft material so that strains of a few percent give forces of order 1.
std::shared_ptr<AncfBeamSection> section(bool square) {
  auto s = std::make_shared<AncfBeamSection>();
  s->E.param = 0;
  s->nu.param = 1;
  s->density.param = 2;
  s->square = square;
  if (square) s->side.param = 3;
  else {
    s->width.param = 3;
    s->height.param = 4;
  }
  return s;
}
VecX params(bool square) {
  return square ? (VecX(4) << 5.0e6, 0.3, 1100.0, 0.02).finished()
                : (VecX(5) << 5.0e6, 0.3, 1100.0, 0.03, 0.012).finished();
}

struct Local {
  VecX p, g;
  LocalState s;
  Local(VecX x, VecX params, bool gravity = true) : p(std::move(params)) {
    g = gravity ? VecX(Eigen::Vector3d(0.7, -9.81, 1.3)) : VecX(VecX::Zero(3));
    s.dim = 3;
    s.gradients = 3;
    s.v = VecX::Zero(x.size());
    s.x = std::move(x);
    s.p = &p;
    s.gravity = &g;
  }
};

/// Coordinates of a straight element of length L placed by rotation R and translation c,
/// its positions and gradients stretched by F (F = I: the rest state): r(X) = c + R F X.
VecX placed(double L, const Eigen::Matrix3d& R, const Eigen::Vector3d& c, const Eigen::Matrix3d& F = Eigen::Matrix3d::Identity()) {
  const Eigen::Matrix3d J = R * F;
  VecX x(24);
  x << c, J.col(0), J.col(1), J.col(2), c + L * J.col(0), J.col(0), J.col(1), J.col(2);
  return x;
}
Eigen::Matrix3d rotation(double a, double b, double c) {
  return (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(c, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

}  // namespace

// Every derivative at a deformed state (a rotated rest state plus 5% noise on all 24
// coordinates): dQ/dq analytic vs AD (1e-10) and vs central FD; -dU/dq vs Q; dQ/dp, dM/dp for
// E, nu, density, width, height (or side) analytic vs AD and vs central FD in p; also with
// separate Gauss rules for the two strain groups (the constructor's option).
TEST(AncfBeam3D, DerivativesMatchFiniteDifferencesAndAD) {
  for (int rule = 0; rule < 3; ++rule) {
    const bool square = rule == 1;  // rule 2: separate Gauss rules for the normal and shear strains
    SCOPED_TRACE(rule == 0 ? "width x height" : rule == 1 ? "square section" : "rules 4 / 2");
    const double L = 0.4;
    AncfBeam3D e("b", {0, 1}, section(square), L, rule == 2 ? 4 : AncfBeam3D::kNormalPoints,
                 rule == 2 ? 2 : AncfBeam3D::kShearPoints);
    std::srand(7);
    Local Lc(placed(L, rotation(0.3, -0.5, 0.8), {0.1, -0.2, 0.3}) + 0.05 * VecX::Random(24), params(square));
    const LocalState& s = Lc.s;
    MatX Kv, Kvad;
    const MatX K = test::expectConservativeKernels(e, s, Lc.p, static_cast<int>(Lc.p.size()), Kv, Kvad);
    EXPECT_EQ(Kv.norm(), 0.0);
    EXPECT_EQ(Kvad.norm(), 0.0);
    EXPECT_FALSE(e.velocityDependent());  // as declared (the assembly skips it for dQ/dv alone)
    EXPECT_LT(relMax(K, K.transpose()), 1e-13) << "conservative: symmetric stiffness";
    VecX Q, Qt;
    e.force(s, Q);
    static_cast<const KernelElement<AncfBeam3D>&>(e).KernelElement<AncfBeam3D>::force(s, Qt);
    EXPECT_LT(relMax(Qt, Q), 1e-12) << "value template vs hand-coded force";
  }
}

// Any rigid motion of the rest state (rotation + translation, large angles) leaves no elastic
// force; the stiffness there has exactly the 6 zero eigenvalues of the rigid motions (the
// selective reduced integration adds no spurious zero-energy mode).
TEST(AncfBeam3D, RigidMotionGivesZeroElasticForce) {
  const double L = 0.4;
  AncfBeam3D e("b", {0, 1}, section(false), L);
  const VecX p = params(false);
  for (int trial = 0; trial < 4; ++trial) {
    const Eigen::Matrix3d R = rotation(1.1 * trial, -0.7 + 0.9 * trial, 2.0 - trial);
    Local Lc(placed(L, R, Eigen::Vector3d(0.3 * trial, -1.0, 2.0)), p, false);
    VecX Q;
    e.force(Lc.s, Q);
    // scale: the force of a 1% stretch, E A 0.01
    EXPECT_LT(Q.lpNorm<Eigen::Infinity>(), 1e-13 * p[0] * p[3] * p[4] * 0.01) << "trial " << trial;
    MatX K, Kv;
    e.forceJacobian(Lc.s, K, Kv);
    Eigen::SelfAdjointEigenSolver<MatX> es(-K);
    const VecX ev = es.eigenvalues();
    const double top = ev.maxCoeff();
    int zeros = 0;
    for (int i = 0; i < ev.size(); ++i) {
      EXPECT_GT(ev[i], -1e-12 * top);
      if (ev[i] < 1e-10 * top) ++zeros;
    }
    EXPECT_EQ(zeros, 6) << "trial " << trial << ", smallest nonzero " << ev[6] / top;
  }
}

// A uniform axial stretch r = c + R diag(1 + eps, 1, 1) X: Green strain E_xx = ((1 + eps)^2 - 1) / 2,
// S_xx = E E_xx, no lateral stress (the normal stresses are uncoupled), so the axial force is
// N = A P_xx = A (1 + eps) E E_xx along the axis: -N R e_1 on the end node b, +N R e_1 on a,
// nothing on the gradients (int dS_b/dx dx = 1, int dS_{r_x,b}/dx dx = 0).
TEST(AncfBeam3D, UniformStretchGivesAxialForce) {
  const double L = 0.4;
  AncfBeam3D e("b", {0, 1}, section(false), L);
  const VecX p = params(false);
  const Eigen::Matrix3d R = rotation(0.4, 0.9, -1.3);
  for (double eps : {1e-3, 0.05, -0.2, 0.5}) {
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    F(0, 0) = 1.0 + eps;
    Local Lc(placed(L, R, Eigen::Vector3d(1, 2, 3), F), p, false);
    VecX Q;
    e.force(Lc.s, Q);
    const double Exx = 0.5 * ((1 + eps) * (1 + eps) - 1.0);
    const double N = p[3] * p[4] * (1 + eps) * p[0] * Exx;  // [N]
    VecX ref = VecX::Zero(24);
    ref.segment<3>(0) = N * R.col(0);
    ref.segment<3>(12) = -N * R.col(0);
    EXPECT_LT((Q - ref).lpNorm<Eigen::Infinity>(), 1e-12 * std::abs(N)) << "eps = " << eps;
  }
}

// ------------------------------------------------------------- cantilever and torsion
namespace {

/// A tip torque T about +x on a node's gradients: Q(r_y) = fy T e_z, Q(r_z) = -fz T e_y (the
/// virtual work of the section rotation dtheta about x, r_y' = dtheta e_z, r_z' = -dtheta e_y,
/// is (fy + fz) T dtheta, fy + fz = 1). The shear traction of uniform torsion, G theta' (-z, y),
/// puts the shares fy = int y^2 dA / I_p, fz = int z^2 dA / I_p on r_y and r_z. A dead load for
/// the small twists of the test.
class TipTorque : public Element {
 public:
  TipTorque(int node, double T, double fy) : Element("tip_torque", {node}), T_(T), fy_(fy) {}
  std::string kind() const override { return "tip_torque"; }
  int gradients() const override { return 3; }
  bool isLoad() const override { return true; }
  void force(const LocalState&, VecX& Q) const override {
    Q = VecX::Zero(12);
    Q[3 + 3 + 2] = fy_ * T_;
    Q[3 + 6 + 1] = -(1.0 - fy_) * T_;
  }
  void forceJacobian(const LocalState&, MatX& dQdq, MatX& dQdv) const override {
    dQdq.setZero(12, 12);
    dQdv.setZero(12, 12);
  }
  bool parameterDerivative(const LocalState&, int, VecX&, MatX&) const override { return false; }
  double potential(const LocalState& s) const override {
    VecX Q;
    force(s, Q);
    return -Q.dot(s.x);
  }
  std::vector<std::pair<std::string, Quantity*>> properties() override { return {}; }

 private:
  double T_, fy_;
};

struct Shaft {
  std::unique_ptr<Model> model;
  int tip = 0;
};

/// A straight beam along x of length L in N elements, node 0 ground and clamped; a tip force
/// (Fy, Fz) on the last node's position and a tip torque T.
Shaft buildShaft(int N, double L, std::shared_ptr<AncfBeamSection> sec, Eigen::Vector3d tipForce, double T,
                 int shearPoints = AncfBeam3D::kShearPoints) {
  Shaft sh;
  sh.model = std::make_unique<Model>();
  Model& m = *sh.model;
  m.dim = 3;
  m.gravity = VecX::Zero(3);
  for (int i = 0; i <= N; ++i) {
    Node nd;
    nd.name = "n" + std::to_string(i);
    nd.position = Eigen::Vector3d(i * L / N, 0, 0);
    nd.velocity = VecX::Zero(3);
    nd.slope = (VecX(9) << 1, 0, 0, 0, 1, 0, 0, 0, 1).finished();
    nd.ground = nd.clamped = i == 0;
    m.nodes.push_back(nd);
  }
  for (int i = 0; i < N; ++i)
    m.elements.push_back(std::make_unique<AncfBeam3D>("e" + std::to_string(i), std::vector<int>{i, i + 1}, sec, L / N,
                                                        AncfBeam3D::kNormalPoints, shearPoints));
  sh.tip = N;
  std::vector<Quantity> f(3);
  for (int c = 0; c < 3; ++c) f[c].constant = tipForce[c];
  m.elements.push_back(std::make_unique<PointForce>("tip_force", N, f));
  if (T != 0.0) {
    const double w = sec->width.constant, h = sec->height.constant;
    m.elements.push_back(std::make_unique<TipTorque>(N, T, w * w / (w * w + h * h)));  // int y^2 / I_p
  }
  m.finalize();
  return sh;
}

std::shared_ptr<AncfBeamSection> steel(double w, double h) {
  auto s = std::make_shared<AncfBeamSection>();
  s->E.constant = 2.0e11;
  s->nu.constant = 0.3;
  s->density.constant = 7850;
  s->width.constant = w;
  s->height.constant = h;
  return s;
}

VecX solve(const Shaft& sh) {
  Assembler as(*sh.model);
  StaticSettings set;
  set.steps = 1;
  return solveStatic(as, VecX::Zero(0), sh.model->initialPositions(), set);
}

}  // namespace

// Linear cantilever, clamped (all gradients fixed), tip load P along z, square section, a
// small load (tip deflection 1e-5 L), L/h = 20 and 100. The element has shear deformation with
// plane sections (uniform shear strain, shear coefficient 1), so its limit is Timoshenko's
// P L^3/(3EI) + P L/(G A) (3 E I/(G A L^2) = 1.6e-3 and 6.5e-5 above Euler-Bernoulli's). The
// sections' rotation is linear in each element, the curvature constant, so the error falls at
// O(h^2); the same at L/h = 100 as at 20: no shear locking. The limit is checked by Richardson
// extrapolation of N = 16, 32.
TEST(AncfBeam3DCantilever, TipDeflectionConverges) {
  const double L = 1.0, E = 2.0e11, G = E / 2.6;
  for (double a : {0.05, 0.01}) {
    const double A = a * a, I = a * a * a * a / 12;
    const double P = 1e-5 * 3 * E * I / (L * L * L);  // tip deflection ~ 1e-5 L [N]
    const double eb = P * L * L * L / (3 * E * I), timo = eb + P * L / (G * A);
    std::printf("cantilever, L/h = %g: Timoshenko (k = 1) / Euler-Bernoulli = %.6f\n", L / a, timo / eb);
    double prev = 0.0, wPrev = 0.0, w = 0.0;
    for (int N : {1, 2, 4, 8, 16, 32}) {
      const Shaft sh = buildShaft(N, L, steel(a, a), Eigen::Vector3d(0, 0, P), 0.0);
      const VecX q = solve(sh);
      wPrev = w;
      w = q[sh.model->dof(sh.tip, 2)];
      const double err = std::abs(w / timo - 1.0);
      std::printf("  N = %2d: w/EB = %.6f, error vs Timoshenko %.3e, rate %.2f\n", N, w / eb, err,
                  prev > 0 ? std::log2(prev / err) : 0.0);
      if (N >= 4) EXPECT_GT(std::log2(prev / err), 1.95) << "N = " << N;
      if (N == 32) EXPECT_LT(err, 2.6e-4);
      prev = err;
    }
    const double extrapolated = w + (w - wPrev) / 3.0;  // O(h^2)
    std::printf("  Richardson (16, 32): w/Timoshenko - 1 = %.2e\n", extrapolated / timo - 1.0);
    EXPECT_NEAR(extrapolated / timo, 1.0, 2e-5);
  }
}

// Clamped shaft under a tip torque T: without warping the sections turn rigidly, the shear
// strains are -theta' z and theta' y, and the torsion constant is the polar moment
// I_p = (w h^3 + h w^3) / 12 (square: a^4 / 6); the twist is T L / (G I_p) for every N
// (a uniform twist rate is exact). Saint-Venant's J of the square, 0.140577 a^4, is smaller:
// the element is 1.186 times too stiff in torsion.
TEST(AncfBeam3DTorsion, TwistIsTLOverGIp) {
  const double L = 1.0, E = 2.0e11, G = E / 2.6;
  for (auto [w, h] : {std::pair<double, double>{0.05, 0.05}, {0.06, 0.02}}) {
    const double Ip = (w * h * h * h + h * w * w * w) / 12;
    const double T = 1e-6 * G * Ip / L;  // twist ~ 1e-6 rad [N m]
    for (int N : {1, 3, 8}) {
      const Shaft sh = buildShaft(N, L, steel(w, h), Eigen::Vector3d::Zero(), T);
      const VecX q = solve(sh);
      const Model& m = *sh.model;
      const Eigen::Vector3d ry(q[m.dof(sh.tip, 6)], q[m.dof(sh.tip, 7)], q[m.dof(sh.tip, 8)]);
      const double theta = std::atan2(ry[2], ry[1]);
      const double ref = T * L / (G * Ip);
      std::printf("torsion %g x %g, N = %d: theta / (T L / (G I_p)) = %.9f\n", w, h, N, theta / ref);
      EXPECT_NEAR(theta / ref, 1.0, 1e-5) << "N = " << N;  // the twist is ~1e-6: geometric terms ~1e-6
      if (w == h && N == 8) {
        const double Jsv = 0.140577 * w * w * w * w;  // Saint-Venant, square (Timoshenko & Goodier)
        std::printf("square: element J / Saint-Venant J = %.4f\n", (T * L / (G * theta)) / Jsv);
      }
    }
  }
}

// ------------------------------------------------------------------------------ scenes
namespace {

std::string beamScene(bool clamped, const std::string& extraNode = "", const std::string& extraElement = "") {
  return "dimension: 3\n"
         "gravity: [0, 0, -9.81]\n"
         "nodes:\n"
         "  - {name: A, position: [0, 0, 0], ground: true" + std::string(clamped ? ", clamped: true" : "") + "}\n"
         "  - {name: n1, position: [0.5, 0, 0]" + extraNode + "}\n"
         "  - {name: n2, position: [1, 0, 0]}\n"
         "elements:\n"
         "  - {name: b, type: ancf_beam, nodes: [A, n1, n2], E: 2.0e11, nu: 0.3, density: 7850,\n"
         "     section: {width: 0.02, height: 0.01}" + extraElement + "}\n"
         "integrator: {type: trapezoidal, t_end: 0.1, dt: 0.01}\n";
}

}  // namespace

// Default gradients (r_x along the chain, r_y the least aligned axis, r_z = r_x x r_y); a
// clamped ground node has no coordinates, a pinned one keeps its 9 gradient coordinates;
// labels; the weight of the body.
TEST(AncfBeam3DScene, GradientsClampAndPin) {
  const Scene clamped = readSceneText(beamScene(true), "beam.yaml");
  const Model& m = *clamped.model;
  EXPECT_EQ(m.n, 2 * 12);
  const VecX frame = (VecX(9) << 1, 0, 0, 0, 1, 0, 0, 0, 1).finished();
  for (int i = 0; i < 3; ++i) EXPECT_EQ((m.nodes[i].slope - frame).norm(), 0.0);
  EXPECT_EQ(m.coordinateLabel(0), "x(n1)");
  EXPECT_EQ(m.coordinateLabel(3), "x_x(n1)");
  EXPECT_EQ(m.coordinateLabel(7), "y_y(n1)");
  EXPECT_EQ(m.coordinateLabel(11), "z_z(n1)");
  const Scene pinned = readSceneText(beamScene(false), "beam.yaml");
  const Model& mp = *pinned.model;
  EXPECT_EQ(mp.n, 2 * 12 + 9);
  EXPECT_EQ(mp.dof(0, 0), -1);
  EXPECT_EQ(mp.dof(0, 3), 0);
  EXPECT_EQ(mp.coordinateLabel(0), "x_x(A)");
  // Weight: gravity on a body is M times a translation; its z forces on the positions of a
  // free body sum to -rho A L g, its x forces to 0.
  const Scene freeBody = readSceneText(
      "dimension: 3\ngravity: [0, 0, -9.81]\nnodes:\n"
      "  - {name: a, position: [0, 0, 0]}\n  - {name: b, position: [0.3, 0, 0]}\n  - {name: c, position: [1, 0, 0]}\n"
      "elements:\n  - {type: ancf_beam, nodes: [a, b, c], E: 2.0e11, nu: 0.3, density: 7850, section: {side: 0.01}}\n"
      "integrator: {type: trapezoidal, t_end: 0.1, dt: 0.01}\n",
      "free.yaml");
  const Model& mf = *freeBody.model;
  const VecX Qf = Assembler(mf).force(mf.initialPositions(), VecX::Zero(mf.n), mf.nominalParameters());
  double fz = 0, fx = 0;
  for (int i = 0; i < 3; ++i) {
    fz += Qf[mf.dof(i, 2)];
    fx += Qf[mf.dof(i, 0)];
  }
  const double W = 7850 * 1e-4 * 1.0 * 9.81;
  EXPECT_NEAR(fz / -W, 1.0, 1e-13);
  EXPECT_NEAR(fx, 0.0, 1e-13 * W);
}

// Given gradients: a y_axis / gradients key sets the section's orientation; a node with a
// cable slope on an ancf_beam is an input error. A chain that starts twisted (n1's section
// turned by 90 degrees about x) is at rest there by default (no elastic force at the start,
// a straight rest gives forces of kN there); `rest_shape: straight` makes it spring back.
TEST(AncfBeam3DScene, GivenGradients) {
  const std::string turned = ", gradients: [[1, 0, 0], [0, 0, 1], [0, -1, 0]]";
  auto elasticForce = [](const Scene& sc) {  // the largest elastic force entry of any element [N]
    const Model& m = *sc.model;
    Assembler as(m);
    const VecX q = m.initialPositions(), v = VecX::Zero(m.n), p = m.nominalParameters();
    double largest = 0.0;
    for (const auto& el : m.elements) {
      LocalState s = as.localState(*el, q, v, p);
      s.gravity = nullptr;
      VecX Q;
      el->force(s, Q);
      largest = std::max(largest, Q.lpNorm<Eigen::Infinity>());
    }
    return largest;
  };
  const Scene atRest = readSceneText(beamScene(true, turned), "beam.yaml");
  EXPECT_LT(elasticForce(atRest), 1e-6);
  const Scene sc = readSceneText(beamScene(true, turned, ", rest_shape: straight"), "beam.yaml");
  EXPECT_GT(elasticForce(sc), 1e3);
  const VecX g = sc.model->nodes[1].slope;
  EXPECT_EQ((g - (VecX(9) << 1, 0, 0, 0, 0, 1, 0, -1, 0).finished()).norm(), 0.0);
  EXPECT_THROW(readSceneText(beamScene(true, ", slope: [1, 0, 0]"), "beam.yaml"), InputError);
  EXPECT_THROW(readSceneText(beamScene(true, ", gradients: [[1, 0, 0], [0, 1, 0], [0, 1, 0]]"), "beam.yaml"),
               InputError);
}

// ------------------------------------------------------------------------ PIM: gradients
namespace {

/// Rigid velocities of a model with ancf_beam nodes: v_i = u + w x r_i on positions, w x g on
/// every free gradient g; one column per motion (3 translations, 3 rotations).
MatX rigidVelocities(const Model& m, const VecX& q) {
  MatX V = MatX::Zero(m.n, 6);
  for (int k = 0; k < 6; ++k) {
    const Eigen::Vector3d u = k < 3 ? Eigen::Vector3d(Eigen::Vector3d::Unit(k)) : Eigen::Vector3d(Eigen::Vector3d::Zero());
    const Eigen::Vector3d w = k < 3 ? Eigen::Vector3d(Eigen::Vector3d::Zero()) : Eigen::Vector3d(Eigen::Vector3d::Unit(k - 3));
    for (int i = 0; i < static_cast<int>(m.nodes.size()); ++i) {
      if (m.dof(i, 0) >= 0) {
        const Eigen::Vector3d r(q[m.dof(i, 0)], q[m.dof(i, 1)], q[m.dof(i, 2)]);
        V.block<3, 1>(m.dof(i, 0), k) = u + w.cross(r);
      }
      for (int g = 0; g < 3; ++g)
        if (m.dof(i, 3 + 3 * g) >= 0) {
          const int d = m.dof(i, 3 + 3 * g);
          V.block<3, 1>(d, k) = w.cross(Eigen::Vector3d(q.segment<3>(d)));
        }
    }
  }
  return V;
}

}  // namespace

// Rigidizing an undeformed ancf_beam body also fixes its gradients as directions in the body
// (a straight chain's frame is completed by A's r_y, r_z): what is left are the 6 rigid
// motions of a free body, 3 (rotations about A) when A is a pinned ground node, none when it
// is clamped. Phi = 0 at the undeformed state, no redundant row, Phi_q against central FD, and
// every rigid velocity in its null space.
TEST(AncfBeam3DRigidization, LeavesTheRigidMotions) {
  struct Case {
    std::string name, groundKeys;
    bool kinked;
    int motions;
  };
  for (const Case& c : {Case{"free straight", "", false, 6}, Case{"free kinked", "", true, 6},
                        Case{"pinned", ", ground: true", false, 3}, Case{"clamped", ", ground: true, clamped: true", false, 0}}) {
    SCOPED_TRACE(c.name);
    const std::string text =
        "dimension: 3\nnodes:\n"
        "  - {name: A, position: [0.1, 0.2, 0.3]" + c.groundKeys + "}\n"
        "  - {name: n1, position: [0.5, 0.6, 0.5]}\n"
        "  - {name: n2, position: [" + std::string(c.kinked ? "0.7, 1.3, 0.4" : "0.9, 1.0, 0.7") + "]}\n"
        "  - {name: n3, position: [" + std::string(c.kinked ? "0.6, 1.5, 1.0" : "1.3, 1.4, 0.9") + "]}\n"
        "elements:\n"
        "  - {name: b, type: ancf_beam, nodes: [A, n1, n2, n3], E: 2.0e11, nu: 0.3, density: 7850,\n"
        "     section: {width: 0.02, height: 0.01}, rest_shape: straight}\n"  // kinked: starts bent
        "integrator: {type: trapezoidal, t_end: 0.1, dt: 0.01}\n";
    const Scene sc = readSceneText(text, "body.yaml");
    const Model& m = *sc.model;
    const std::vector<int> all = {0, 1, 2, 3};
    MatX X(3, 4);
    for (int i = 0; i < 4; ++i) X.col(i) = m.nodes[i].position;
    RigidizeOptions withSlopes;
    withSlopes.slopes = true;  // an ANCF body
    Rigidization R = rigidize("b", all, m, X, "test", nullptr, withSlopes);
    Assembler as(m, &R.constraints);
    const VecX q = m.initialPositions(), p = m.nominalParameters();
    EXPECT_LT(as.phi(q, p).lpNorm<Eigen::Infinity>(), 1e-12);
    const MatX J = as.phiQDense(q, p);
    EXPECT_LT(relMax(fdJacobian([&](const VecX& x) { return as.phi(x, p); }, q), J), 1e-8);
    Eigen::FullPivLU<MatX> lu(J);
    lu.setThreshold(1e-10);
    EXPECT_EQ(m.n - lu.rank(), c.motions);
    EXPECT_EQ(lu.rank(), J.rows());  // no redundant equation
    if (c.motions == 6) EXPECT_LT((J * rigidVelocities(m, q)).lpNorm<Eigen::Infinity>(), 1e-12);
  }
}

// A PIM case rigidizes a pinned ancf_beam (gradients included): 3 motions are left, the
// rotations about A, named by the tip's y and z and a gradient component ("z_y": r_y's z, the
// twist about the axis, which no position of a straight beam shows).
TEST(AncfBeam3DRigidization, SceneCaseWithGradientSdof) {
  const std::string text = beamScene(false) +
                           "parameters:\n  - {name: E_b, of: b, property: E}\n"
                           "cases:\n  - {name: S1, parameters: [E_b], rigidize: [b], sdofs: [{node: n2, component: y}, "
                           "{node: n2, component: z}, {node: n2, component: z_y}]}\n";
  const Scene sc = readSceneText(text, "case.yaml", "S1");
  ASSERT_TRUE(sc.pimCase);
  ASSERT_EQ(sc.pimCase->sdofs.size(), 3u);
  EXPECT_EQ(sc.pimCase->sdofs[2]->name, "z_y(n2)");
  int rows = 0;
  for (const auto& c : sc.pimCase->lambda) rows += c->rows();
  EXPECT_EQ(rows, sc.model->n - 3);
}

// The bad ancf_beam scenes' exact messages (tests/test_bad_scenes.cpp checks file, line and
// key of every bad scene through the command line).
TEST(AncfBeam3DScene, BadScenesSayWhatIsWrong) {
  const std::pair<const char*, const char*> cases[] = {
      {"bad_ancf_beam_zero_length.yaml",
       ":8:50: key 'elements[0].nodes[2]': coincides with the previous node: zero element length"},
      {"bad_ancf_beam_gradient_size.yaml", ":5:62: key 'nodes[1].gradients[1]': expected a list of 3 numbers"},
      {"bad_ancf_beam_gradient_count.yaml",
       ":5:50: key 'nodes[1].gradients': expected three vectors r_x, r_y, r_z (a right-handed orthonormal frame); got 2"},
      {"bad_ancf_beam_cable_slope.yaml",
       ":5:46: key 'nodes[1].slope': node 'n1' carries one slope (ancf_cable); an ancf_beam node takes gradients "
       "(r_x, r_y, r_z)"},
      {"bad_ancf_beam_planar.yaml", ":7:24: key 'elements[0].type': ancf_beam needs a spatial scene (dimension 3)"},
      {"bad_ancf_beam_y_axis.yaml",
       ":8:14: key 'elements[0].y_axis': is along the beam at node 'A': expected a direction across it"},
      {"bad_ancf_beam_rest_frame.yaml",
       ":8:53: key 'elements[0].nodes[1]': ancf_beam beam.element0: its rest shape folds over at xi = 0.5 (det "
       "dr0/dX = 0): the rest axis turns back or the gradients (r_x, r_y, r_z) are not a right-handed frame there; "
       "give the nodes' gradients along the chain"},
      {"bad_ancf_cable_gradients.yaml",
       ":5:50: key 'nodes[1].gradients': node 'n1' carries the three gradients of an ancf_beam; an ancf_cable node "
       "has one slope"},
  };
  for (const auto& [file, tail] : cases) {
    const std::string path = test::sourceDir() + "/tests/scenes/bad/" + file;
    try {
      readScene(path);
      ADD_FAILURE() << file << " was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), path + tail);
    }
  }
}

// Two chains welded at an angle: the remedy names the key each element has, `gradients` for
// ancf_beam nodes (ancf_beam refuses `slope`) and `slope` for ancf_cable nodes.
TEST(AncfBeam3DScene, SharedNodeErrorNamesTheElementsOwnKey) {
  auto message = [](const char* file) {
    try {
      readScene(test::sourceDir() + "/tests/scenes/bad/" + file);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string beam = message("bad_ancf_beam_shared_gradients.yaml");
  EXPECT_NE(beam.find("give the node its 'gradients' (r_x, r_y, r_z)"), std::string::npos) << beam;
  EXPECT_EQ(beam.find("'slope'"), std::string::npos) << beam;
  const std::string cable = message("bad_ancf_shared_slope.yaml");
  EXPECT_NE(cable.find("give the node a 'slope'"), std::string::npos) << cable;
}

// ---------------------------------------------------------------- static sensitivities
// A clamped ancf_beam under gravity and a tip force across it, deflected ~5% of L (nonlinear):
// dq/dp from staticSensitivities for E, nu, density, width and height against central
// differences of whole static solutions (relative step 1e-4).
TEST(AncfBeam3DStatic, SensitivitiesMatchCentralDifferences) {
  const Scene sc = readSceneText(
      "dimension: 3\ngravity: [0, 0, -9.81]\nnodes:\n"
      "  - {name: A, position: [0, 0, 0], ground: true, clamped: true}\n"
      "  - {name: n1, position: [0.4, 0, 0]}\n  - {name: n2, position: [0.8, 0, 0]}\n  - {name: tip, position: [1.2, 0, 0]}\n"
      "elements:\n"
      "  - {name: b, type: ancf_beam, nodes: [A, n1, n2, tip], E: 2.0e9, nu: 0.3, density: 7850,\n"
      "     section: {width: 0.03, height: 0.02}}\n"
      "  - {name: load, type: point_force, node: tip, force: [0, 6, 0]}\n"
      "parameters:\n  - {name: E, of: b, property: E}\n  - {name: nu, of: b, property: nu}\n"
      "  - {name: rho, of: b, property: density}\n  - {name: w, of: b, property: width}\n"
      "  - {name: h, of: b, property: height}\n"
      "static: {load_steps: 5}\n",
      "static.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = m.nominalParameters();
  StaticSettings set;
  set.stepLoadFactor = true;
  StaticReport rep;
  const VecX q = solveStatic(as, p, m.initialPositions(), set, &rep);
  const int tip = m.nodeIndex("tip");
  std::printf("tip (y, z) = (%.4f, %.4f) m\n", q[m.dof(tip, 1)], q[m.dof(tip, 2)]);
  EXPECT_GT(q[m.dof(tip, 1)], 0.03);
  const StaticSensitivity d = staticSensitivities(as, q, rep.lambda, p);
  test::expectStaticSensitivitiesMatchCentralDifferences(as, m, p, q, d.qp, 1e-6);
}

// Initial gradient rates from the nodes' velocities: a chain turning rigidly with w about an
// axis across it gives every free gradient the rate w x g (and no stretch rate).
TEST(AncfBeam3DScene, GradientRatesOfARigidTurn) {
  const Eigen::Vector3d w(0.0, 0.3, 2.0);  // [rad/s], normal to the chain (along x)
  std::string nodes;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d r(0.5 * i, 0, 0), v = w.cross(r);
    char buf[200];
    std::snprintf(buf, sizeof buf, "  - {name: n%d, position: [%g, 0, 0], velocity: [%.17g, %.17g, %.17g]}\n", i,
                  r[0], v[0], v[1], v[2]);
    nodes += buf;
  }
  const Scene sc = readSceneText("dimension: 3\nnodes:\n" + nodes +
                                     "elements:\n  - {type: ancf_beam, nodes: [n0, n1, n2], E: 2.0e11, nu: 0.3, "
                                     "density: 7850, section: {side: 0.01}}\n"
                                     "integrator: {type: trapezoidal, t_end: 0.1, dt: 0.01}\n",
                                 "turn.yaml");
  for (const Node& nd : sc.model->nodes) {
    ASSERT_EQ(nd.slopeRate.size(), 9) << nd.name;
    for (int g = 0; g < 3; ++g)
      EXPECT_LT((Eigen::Vector3d(nd.slopeRate.segment<3>(3 * g)) - w.cross(Eigen::Vector3d(nd.slope.segment<3>(3 * g)))).norm(),
                1e-14)
          << nd.name << " gradient " << g;
  }
}

// F-R twin: `rigid_model: [b]` makes an ancf_beam body rigid with its own consistent mass.
// A pinned horizontal rod (A at the origin, along x) released under gravity -g e_z: 3 motions
// are left, and its initial angular acceleration is the rigid body's, alpha = m g L/2 / I_A,
// I_A = rho (A L^3/3 + L w h^3/12) (the section's own z^2 inertia included), so the tip's
// acceleration is -alpha L e_z, from the constrained equations M a + Phi_q^T lambda = Q, Phi_q a = 0.
TEST(AncfBeam3DRigidization, RigidTwinSwingsAsARigidRod) {
  const std::string text = beamScene(false) + "parameters:\n  - {name: rho, of: b, property: density}\n" +
                           "cases:\n  - {name: R1, parameters: [rho], rigid_model: [b]}\n";
  const Scene sc = readSceneText(text, "twin.yaml", "R1");
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX q = m.initialPositions(), v = VecX::Zero(m.n), p = m.nominalParameters();
  const MatX J = as.phiQDense(q, p), M = MatX(as.mass(p));
  Eigen::FullPivLU<MatX> lu(J);
  lu.setThreshold(1e-10);
  EXPECT_EQ(m.n - lu.rank(), 3);
  MatX K = MatX::Zero(m.n + J.rows(), m.n + J.rows());
  K.topLeftCorner(m.n, m.n) = M;
  K.topRightCorner(m.n, J.rows()) = J.transpose();
  K.bottomLeftCorner(J.rows(), m.n) = J;
  VecX rhs = VecX::Zero(K.rows());
  rhs.head(m.n) = as.force(q, v, p);
  const VecX a = K.fullPivLu().solve(rhs);
  const double L = 1.0, w = 0.02, h = 0.01, rho = 7850, g = 9.81;
  const double mass = rho * w * h * L, IA = rho * (w * h * L * L * L / 3 + L * w * h * h * h / 12);
  const double alpha = mass * g * L / 2 / IA;
  const int tip = m.nodeIndex("n2");
  EXPECT_NEAR(a[m.dof(tip, 2)] / (-alpha * L), 1.0, 1e-10);
  EXPECT_NEAR(a[m.dof(tip, 0)], 0.0, 1e-10);
}

// The first bending frequency of the clamped cantilever (L/h = 100, square, linearized at the
// straight state with the consistent mass) against Euler-Bernoulli's beta_1 L = 1.8751040687:
// from above at O(h^2) (the sections' rotation is linear per element), its Richardson limit
// within the shear and rotary-inertia corrections (~1e-4 at L/h = 100) of the reference.
TEST(AncfBeam3DCantilever, FirstFrequencyConverges) {
  const double L = 1.0, a = 0.01, E = 2.0e11, rho = 7850;
  const double bL = 1.8751040687;
  const double ref = bL * bL / (L * L) * std::sqrt(E * a * a * a * a / 12 / (rho * a * a));  // [rad/s]
  double prev = 0.0, wPrev = 0.0, w = 0.0;
  for (int N : {2, 4, 8, 16}) {
    const Shaft sh = buildShaft(N, L, steel(a, a), Eigen::Vector3d::Zero(), 0.0);
    const Model& m = *sh.model;
    Assembler as(m);
    const VecX p = VecX::Zero(0), q = m.initialPositions();
    SparseAccumulator acc;
    acc.begin(m.n, m.n);
    as.addForceJacobian(acc, q, VecX::Zero(m.n), p, 1.0, 0.0, 0, 0, 0);  // adds -dQ/dq
    const MatX K = MatX(acc.finish()), M = MatX(as.mass(p));
    Eigen::GeneralizedSelfAdjointEigenSolver<MatX> es(K, M);
    wPrev = w;
    w = std::sqrt(es.eigenvalues()[0]);  // the two first bending modes (y, z) coincide
    const double err = w / ref - 1.0;
    std::printf("N = %2d: omega_1 / EB - 1 = %.3e, rate %.2f\n", N, err, prev > 0 ? std::log2(prev / err) : 0.0);
    EXPECT_GT(err, 0.0);
    if (prev > 0) EXPECT_GT(std::log2(prev / err), 1.9);
    prev = err;
  }
  const double lim = w + (w - wPrev) / 3.0;
  std::printf("Richardson (8, 16): omega_1 / EB - 1 = %.2e\n", lim / ref - 1.0);
  EXPECT_NEAR(lim / ref, 1.0, 2e-4);
}
