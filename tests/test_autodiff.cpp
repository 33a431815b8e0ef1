// Sensitivity method "ad": the element and constraint derivatives by forward-mode automatic
// differentiation (Eigen's AutoDiffScalar) of the value templates must equal the hand-written
// analytic ones ("dd") to round-off, kernel by kernel and through the Assembler.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "constraints/Bilinear.hpp"
#include "constraints/Distance.hpp"
#include "core/Assembler.hpp"
#include "elements/Beam.hpp"
#include "elements/PlanarRigidBody.hpp"
#include "elements/PointForce.hpp"
#include "elements/RigidBar.hpp"
#include "elements/RigidBody.hpp"
#include "integrators/Idas.hpp"
#include "pim/Rigidization.hpp"

using namespace flexsens;
using flexsens::test::explicitParams;
using flexsens::test::explicitSection;
using flexsens::test::squareParams;
using flexsens::test::squareSection;

namespace {

constexpr double kTol = 1e-10;

/// Max-norm relative difference; 0 when both are exactly zero.
double rel(const MatX& a, const MatX& b) {
  EXPECT_EQ(a.rows(), b.rows());
  EXPECT_EQ(a.cols(), b.cols());
  if (a.rows() != b.rows() || a.cols() != b.cols()) return 1.0;
  const double scale = std::max(a.lpNorm<Eigen::Infinity>(), b.lpNorm<Eigen::Infinity>());
  return scale == 0.0 ? 0.0 : (a - b).lpNorm<Eigen::Infinity>() / scale;
}

/// dM / dJ as a full matrix (an empty matrix means "identically zero").
MatX full(const MatX& A, int rows, int cols) { return A.size() ? A : MatX(MatX::Zero(rows, cols)); }

VecX randomVec(int n, unsigned seed, double scale) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VecX r(n);
  for (int i = 0; i < n; ++i) r[i] = scale * u(rng);
  return r;
}

/// Local state with its own storage for p and gravity.
struct Local {
  VecX p, g;
  LocalState s;
  Local(int dim, VecX x, VecX v, VecX params) : p(std::move(params)) {
    g = VecX::Zero(dim);
    g[0] = 0.7;
    g[1] = -9.81;
    if (dim == 3) g[2] = 1.3;  // gravity not along an axis
    s.dim = dim;
    s.x = std::move(x);
    s.v = std::move(v);
    s.p = &p;
    s.gravity = &g;
  }
};

/// dQ/dq, dQ/dv and every parameter derivative (plus an unbound index) of an element,
/// analytic vs AD. `expectStiffness`: the check of dQ/dq is not vacuous.
void checkElement(const Element& e, const LocalState& s, int nParams, bool expectStiffness,
                  bool expectDamping) {
  SCOPED_TRACE(e.kind());
  const int n = static_cast<int>(s.x.size());
  MatX Kq, Kv, Kq2, Kv2;
  e.forceJacobian(s, Kq, Kv);
  e.forceJacobianAD(s, Kq2, Kv2);
  EXPECT_LT(rel(Kq2, Kq), kTol) << "dQ/dq";
  EXPECT_LT(rel(Kv2, Kv), kTol) << "dQ/dv";
  if (expectStiffness) EXPECT_GT(Kq.norm(), 0.0);
  if (expectDamping) EXPECT_GT(Kv.norm(), 0.0);
  // The declaration the assembly trusts (it skips such elements when only dQ/dv is wanted):
  // an element that says its forces never depend on v has dQ/dv = 0 by AD too.
  if (!e.velocityDependent()) EXPECT_EQ(Kv2.norm(), 0.0) << "declared velocity-independent";
  if (expectDamping) EXPECT_TRUE(e.velocityDependent());
  for (int k = 0; k <= nParams; ++k) {  // k = nParams: bound to nothing
    SCOPED_TRACE("parameter " + std::to_string(k));
    VecX dQ, dQ2;
    MatX dM, dM2;
    const bool dep = e.parameterDerivative(s, k, dQ, dM);
    const bool dep2 = e.parameterDerivativeAD(s, k, dQ2, dM2);
    ASSERT_EQ(dep, dep2);
    if (!dep) continue;
    EXPECT_LT(rel(dQ2, dQ), kTol) << "dQ/dp";
    EXPECT_LT(rel(full(dM2, n, n), full(dM, n, n)), kTol) << "dM/dp";
    EXPECT_GT(dQ.norm() + full(dM, n, n).norm(), 0.0);  // not vacuous
  }
}

/// Phi_q, every row's Hessian, Phi_p and Phi_qp, analytic vs AD.
void checkConstraint(const Constraint& c, const LocalState& s, int nParams, bool expectHessian) {
  SCOPED_TRACE(c.kind());
  const int n = static_cast<int>(s.x.size()), m = c.rows();
  MatX J, J2;
  c.jacobian(s, J);
  c.jacobianAD(s, J2);
  EXPECT_LT(rel(J2, J), kTol) << "Phi_q";
  EXPECT_GT(J.norm(), 0.0);
  double hsum = 0.0;
  for (int r = 0; r < m; ++r) {
    MatX H, H2;
    c.hessian(s, r, H);
    c.hessianAD(s, r, H2);
    EXPECT_LT(rel(H2, H), kTol) << "Hessian of row " << r;
    hsum += H.norm();
    if (c.constantHessian()) {  // as declared: AD's Hessian at another state is the same
      LocalState s2 = s;
      s2.x = s.x + randomVec(static_cast<int>(s.x.size()), 31 + r, 0.5);
      MatX H3;
      c.hessianAD(s2, r, H3);
      EXPECT_LT(rel(H3, H), kTol) << "constant Hessian of row " << r;
    }
  }
  if (expectHessian) EXPECT_GT(hsum, 0.0);
  for (int k = 0; k <= nParams; ++k) {
    SCOPED_TRACE("parameter " + std::to_string(k));
    VecX dphi, dphi2;
    MatX dJ, dJ2;
    const bool dep = c.parameterDerivative(s, k, dphi, dJ);
    const bool dep2 = c.parameterDerivativeAD(s, k, dphi2, dJ2);
    ASSERT_EQ(dep, dep2);
    if (!dep) continue;
    EXPECT_LT(rel(dphi2, dphi), kTol) << "Phi_p";
    EXPECT_LT(rel(full(dJ2, m, n), full(dJ, m, n)), kTol) << "Phi_qp";
    EXPECT_GT(dphi.norm(), 0.0);
  }
}

}  // namespace

// ---------------------------------------------------------------------------- elements
TEST(AutoDiff, RigidBar) {
  for (int dim : {2, 3}) {
    RigidBar e("bar", 0, 1, Quantity{0.0, 0});
    Local l(dim, randomVec(2 * dim, 1 + dim, 1.0), randomVec(2 * dim, 2, 1.0), VecX::Constant(1, 1.7));
    checkElement(e, l.s, 1, false, false);
    // force() is written for double apart from the value template: half the weight m g on
    // each end
    VecX Q;
    e.force(l.s, Q);
    EXPECT_LT(rel(Q, e.kernelForce(l.s)), 1e-14);
    VecX weight(2 * dim);
    weight << 0.5 * 1.7 * l.g, 0.5 * 1.7 * l.g;
    EXPECT_LT(rel(Q, weight), 1e-15);
  }
}

TEST(AutoDiff, SpringDamperWithDamping) {
  for (int dim : {2, 3}) {
    SpringDamper e("sd", 0, 1, Quantity{0.0, 0}, Quantity{0.0, 1}, Quantity{0.0, 2});
    Local l(dim, randomVec(2 * dim, 3 + dim, 1.0), randomVec(2 * dim, 4 + dim, 2.0),
            (VecX(3) << 50.0, 3.0, 0.4).finished());
    checkElement(e, l.s, 3, true, true);
    // force() is written for double apart from the value template; both against the tension
    // k (l - L0) + c dl/dt along the unit vector a -> b, pulling b back
    VecX Q;
    e.force(l.s, Q);
    EXPECT_LT(rel(Q, e.kernelForce(l.s)), 1e-14);
    const VecX dx = l.s.x.tail(dim) - l.s.x.head(dim), u = dx.normalized();
    const double tension = 50.0 * (dx.norm() - 0.4) + 3.0 * u.dot(l.s.v.tail(dim) - l.s.v.head(dim));
    EXPECT_LT(rel(Q.tail(dim), VecX(-tension * u)), 1e-13);
    EXPECT_LT(rel(Q.head(dim), VecX(tension * u)), 1e-13);
  }
}

TEST(AutoDiff, UndampedSpringIsVelocityIndependentUnlessItsDampingIsAParameter) {
  // Damping a constant 0: declared velocity-independent (the assembly then skips it when only
  // dQ/dv is wanted), and checkElement confirms dQ/dv = 0 by AD. Damping bound to a parameter
  // whose value is 0: its dQ/dc is not zero, so it stays velocity-dependent.
  for (int dim : {2, 3}) {
    SpringDamper e("sd", 0, 1, Quantity{0.0, 0}, Quantity{0.0, -1}, Quantity{0.0, 1});
    Local l(dim, randomVec(2 * dim, 7 + dim, 1.0), randomVec(2 * dim, 8 + dim, 2.0), (VecX(2) << 40.0, 0.6).finished());
    EXPECT_FALSE(e.velocityDependent());
    checkElement(e, l.s, 2, true, false);
    SpringDamper b("sd", 0, 1, Quantity{0.0, 0}, Quantity{0.0, 2}, Quantity{0.0, 1});
    Local lb(dim, randomVec(2 * dim, 7 + dim, 1.0), randomVec(2 * dim, 8 + dim, 2.0),
             (VecX(3) << 40.0, 0.6, 0.0).finished());
    EXPECT_TRUE(b.velocityDependent());
    checkElement(b, lb.s, 3, true, false);  // dQ/dc = l' u, not zero, against AD
  }
}

TEST(AutoDiff, SpringDamperPropertiesSharingAParameter) {
  // stiffness and damping bound to the same parameter: their partials add up
  SpringDamper e("sd", 0, 1, Quantity{0.0, 0}, Quantity{0.0, 0}, Quantity{0.0, 1});
  Local l(2, randomVec(4, 5, 1.0), randomVec(4, 6, 2.0), (VecX(2) << 20.0, 0.9).finished());
  checkElement(e, l.s, 2, true, true);
}

TEST(AutoDiff, BeamSegment2DAnd3D) {
  for (int dim : {2, 3}) {
    for (bool square : {true, false}) {
      SCOPED_TRACE("dim " + std::to_string(dim) + (square ? " square" : " explicit"));
      const double L = 0.7;
      BeamSegment e("seg", {0, 1}, square ? squareSection() : explicitSection(), L);
      VecX x = randomVec(2 * dim, 7 + dim, 1.0);
      const VecX d = randomVec(dim, 9 + dim, 1.0).normalized();
      x.tail(dim) = x.head(dim) + (square ? 1.3 : 0.6) * L * d;  // stretched / compressed
      Local l(dim, x, VecX::Zero(2 * dim), square ? squareParams() : explicitParams());
      checkElement(e, l.s, static_cast<int>(l.p.size()), true, false);
      // force() is written for double apart from the value template the AD kernels use
      VecX Q;
      e.force(l.s, Q);
      EXPECT_LT(rel(Q, e.kernelForce(l.s)), 1e-14);
      EXPECT_GT(Q.norm(), 0.0);
    }
  }
}

TEST(AutoDiff, BeamHinge) {
  {  // bent at rest, deformed further, unequal edges
    const VecX rest = (VecX(6) << 0, 0, 0.5, 0.1, 0.9, 0.4).finished();
    BeamHinge e("h", {0, 1, 2}, squareSection(), rest);
    Local l(2, (VecX(6) << 0.02, -0.03, 0.55, 0.08, 0.75, 0.6).finished(), VecX::Zero(6), squareParams());
    checkElement(e, l.s, 3, true, false);
  }
  {  // straight at rest, turning angle beyond pi/2, explicit section
    const VecX rest = (VecX(6) << 0, 0, 0.4, 0, 0.8, 0).finished();
    BeamHinge e("h", {0, 1, 2}, explicitSection(), rest);
    Local l(2, (VecX(6) << 0.1, 0.2, 0.5, 0.05, 0.15, -0.2).finished(), VecX::Zero(6), explicitParams());
    checkElement(e, l.s, 4, true, false);
  }
  {  // across the +-pi wrap of the deviation
    const double a0 = M_PI - 0.05, a1 = M_PI + 0.05;
    const VecX rest = (VecX(6) << -1, 0, 0, 0, std::cos(a0), std::sin(a0)).finished();
    BeamHinge e("h", {0, 1, 2}, squareSection(), rest);
    VecX x = rest;
    x.tail(2) << std::cos(a1), std::sin(a1);
    Local l(2, x, VecX::Zero(6), squareParams());
    checkElement(e, l.s, 3, true, false);
  }
}

TEST(AutoDiff, PointForce) {
  for (int dim : {2, 3}) {
    std::vector<Quantity> F;
    for (int c = 0; c < dim; ++c) F.push_back(Quantity{0.0, c});
    PointForce e("f", 0, F);
    Local l(dim, randomVec(dim, 11, 1.0), randomVec(dim, 12, 1.0), randomVec(dim, 13, 5.0));
    checkElement(e, l.s, dim, false, false);
  }
  // two components on one parameter, one constant
  PointForce e("f", 0, {Quantity{0.0, 0}, Quantity{2.5, -1}, Quantity{0.0, 0}});
  Local l(3, randomVec(3, 14, 1.0), VecX::Zero(3), VecX::Constant(1, -4.0));
  checkElement(e, l.s, 1, false, false);
}

TEST(AutoDiff, RigidBodies) {
  // The weight of a body in natural coordinates: no stiffness, no damping; velocities that
  // are not zero, so that the declared velocity independence is checked where it could fail.
  const VecX g3 = randomVec(12, 21, 1.0);
  Eigen::Matrix<double, 3, 4> X0;
  X0 << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  RigidBody body("body", {0, 1, 2, 3}, X0, Quantity{0.0, 0}, Eigen::Vector3d(0.3, 0.2, 0.1),
                 {Quantity{1.0, -1}, Quantity{1.2, -1}, Quantity{0.9, -1}, Quantity{0.1, -1}, Quantity{0.0, -1},
                  Quantity{0.05, -1}});
  Local l3(3, X0.reshaped(), randomVec(12, 22, 2.0), VecX::Constant(1, 3.5));
  checkElement(body, l3.s, 1, false, false);
  const VecX xA = (VecX(2) << 0.1, 0.2).finished(), xB = (VecX(2) << 1.1, 0.4).finished();
  const VecX com = (VecX(2) << 0.5, 0.4).finished();
  PlanarRigidBody planar("planar", 0, 1, xA, xB, com, Quantity{0.0, 0}, Quantity{0.2, 1});
  Local l2(2, (VecX(4) << xA, xB).finished(), randomVec(4, 23, 2.0), (VecX(2) << 2.0, 0.3).finished());
  checkElement(planar, l2.s, 2, false, false);
}

// -------------------------------------------------------------------------- constraints
TEST(AutoDiff, DistanceConstraint) {
  for (int dim : {2, 3}) {
    DistanceConstraint c("d", 0, 1, Quantity{0.0, 0});
    Local l(dim, randomVec(2 * dim, 15 + dim, 1.0), VecX::Zero(2 * dim), VecX::Constant(1, 1.3));
    checkConstraint(c, l.s, 1, true);
    // phi() is written for double apart from the value template: |x_b - x_a|^2 - L^2
    VecX phi;
    c.phi(l.s, phi);
    EXPECT_LT(rel(phi, c.kernelPhi(l.s)), 1e-14);
    ASSERT_EQ(phi.size(), 1);
    EXPECT_NEAR(phi[0], (l.s.x.tail(dim) - l.s.x.head(dim)).squaredNorm() - 1.3 * 1.3, 1e-14);
  }
}

TEST(AutoDiff, BilinearConstraints) {
  // a point on a plane fixed to a body (nodes: the body's 4 basic points, then the point) and
  // a perpendicularity of two node pairs
  Eigen::Matrix<double, 3, 4> X0;
  X0 << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  const auto plane = BilinearConstraint::pointOnBodyPlane("plane", {0, 1, 2, 3}, X0, 4, Eigen::Vector3d(0.2, 0.3, 0.1),
                                                          Eigen::Vector3d(0.3, -0.4, 0.8));
  Local l(3, randomVec(15, 25, 1.0), VecX::Zero(15), VecX::Constant(1, 1.0));
  checkConstraint(*plane, l.s, 1, true);
  const auto perp = BilinearConstraint::perpendicular("perp", {0, 1, 2, 3}, 0.0);
  Local l2(3, randomVec(12, 26, 1.0), VecX::Zero(12), VecX::Constant(1, 1.0));
  checkConstraint(*perp, l2.s, 1, true);
  // Phi itself (hand-written for double, apart from the AD kernel): the perpendicularity's
  // value (x_b - x_a) . (x_d - x_c), and central differences of it against Phi_q.
  VecX f;
  perp->phi(l2.s, f);
  const VecX& x = l2.s.x;
  EXPECT_NEAR(f[0], (x.segment<3>(3) - x.segment<3>(0)).dot(x.segment<3>(9) - x.segment<3>(6)), 1e-14);
  for (const auto* c : {static_cast<const Constraint*>(plane.get()), static_cast<const Constraint*>(perp.get())}) {
    LocalState s = c == perp.get() ? l2.s : l.s;
    MatX J;
    c->jacobian(s, J);
    const VecX x0 = s.x;
    for (Eigen::Index j = 0; j < x0.size(); ++j) {
      VecX fp, fm;
      s.x = x0;
      s.x[j] += 1e-6;
      c->phi(s, fp);
      s.x[j] -= 2e-6;
      c->phi(s, fm);
      EXPECT_NEAR((fp[0] - fm[0]) / 2e-6, J(0, j), 1e-8) << c->kind() << " coordinate " << j;
    }
  }
}

TEST(AutoDiff, FixedNodeConstraint) {
  for (int dim : {2, 3}) {
    FixedNodeConstraint c("fx", 0, randomVec(dim, 17, 1.0));
    Local l(dim, randomVec(dim, 18, 1.0), VecX::Zero(dim), VecX::Constant(2, 1.0));
    checkConstraint(c, l.s, 2, false);
    VecX phi;
    c.phi(l.s, phi);
    EXPECT_GT(phi.norm(), 0.0);
  }
}

TEST(AutoDiff, AttachedPointConstraint) {
  // nodes (A, B, C, i) in 2D and (A, B, C, D, i) in 3D with general coefficients
  for (int dim : {2, 3}) {
    const VecX coef = randomVec(dim, 19 + dim, 2.0);
    AttachedPointConstraint c("ap", [&] {
      std::vector<int> nd;
      for (int i = 0; i < dim + 2; ++i) nd.push_back(i);
      return nd;
    }(), coef, dim);
    Local l(dim, randomVec(dim * (dim + 2), 21, 1.0), VecX::Zero(dim * (dim + 2)), VecX::Constant(1, 1.0));
    checkConstraint(c, l.s, 1, false);
  }
}

TEST(AutoDiff, DefaultKernelsThrow) {
  struct NoAD : Element {
    NoAD() : Element("plain", {0}) {}
    std::string kind() const override { return "plain"; }
    void force(const LocalState& s, VecX& Q) const override { Q.setZero(s.x.size()); }
    void forceJacobian(const LocalState&, MatX&, MatX&) const override {}
    bool parameterDerivative(const LocalState&, int, VecX&, MatX&) const override { return false; }
    double potential(const LocalState&) const override { return 0.0; }
    std::vector<std::pair<std::string, Quantity*>> properties() override { return {}; }
  } e;
  LocalState s;
  MatX A, B;
  VecX v;
  EXPECT_THROW(e.forceJacobianAD(s, A, B), std::logic_error);
  EXPECT_THROW(e.parameterDerivativeAD(s, 0, v, A), std::logic_error);
}

// --------------------------------------------------------------------------- assembler
namespace {


/// A spatial model built in code with the kernels the scene reader cannot express: point
/// force, 3D beam segments with an explicit section, attached points, a fixed node.
std::unique_ptr<Model> spatialModel() {
  auto mp = std::make_unique<Model>();
  Model& m = *mp;
  m.dim = 3;
  m.gravity = (VecX(3) << 0.2, -9.81, 0.4).finished();
  m.gravityParam = {-1, 0, -1};  // g_y is parameter 0
  const double X[][3] = {{0, 0, 0}, {1, 0.1, -0.2}, {1.2, 1.1, 0.3}, {0.1, 0.9, 1.0},
                         {0.6, 0.5, 0.4}, {2.0, 0.2, -0.5}, {2.6, -0.4, -0.1}};
  for (int i = 0; i < 7; ++i) {
    Node nd;
    nd.name = "n" + std::to_string(i);
    nd.position = Eigen::Vector3d(X[i][0], X[i][1], X[i][2]);
    nd.velocity = VecX::Zero(3);
    nd.ground = i == 0;
    m.nodes.push_back(nd);
  }
  auto sec = std::make_shared<BeamSection>();
  sec->E.param = 1;
  sec->density.param = 2;
  sec->area.param = 3;
  sec->inertia = {1e-8, -1};
  m.elements.push_back(std::make_unique<RigidBar>("bar", 0, 1, Quantity{0.0, 4}));
  m.elements.push_back(std::make_unique<SpringDamper>("sd", 1, 2, Quantity{0.0, 5}, Quantity{0.0, 6},
                                                      Quantity{0.0, 7}));
  m.elements.push_back(std::make_unique<BeamSegment>("seg1", std::vector<int>{1, 5}, sec, 0.9));
  m.elements.push_back(std::make_unique<BeamSegment>("seg2", std::vector<int>{5, 6}, sec, 0.8));
  m.elements.push_back(std::make_unique<PointForce>(
      "push", 6, std::vector<Quantity>{Quantity{0.0, 8}, Quantity{-3.0, -1}, Quantity{0.0, 9}}));
  m.constraints.push_back(std::make_unique<DistanceConstraint>("d13", 1, 3, Quantity{0.0, 10}));
  m.constraints.push_back(std::make_unique<DistanceConstraint>("d23", 2, 3, Quantity{1.4, -1}));
  m.constraints.push_back(std::make_unique<FixedNodeConstraint>("fx", 3, m.nodes[3].position));
  m.constraints.push_back(std::make_unique<AttachedPointConstraint>(
      "ap", std::vector<int>{1, 2, 3, 0, 4}, (VecX(3) << 0.3, -0.4, 0.2).finished(), 3));
  const double nominal[] = {-9.81, 3e6, 900, 2e-4, 1.3, 40, 2.5, 1.0, 2.0, -1.5, 1.2};
  for (int k = 0; k < 11; ++k) m.parameters.push_back(Parameter{"p" + std::to_string(k), nominal[k], ""});
  m.finalize();
  return mp;
}

/// Every derivative entry point of the Assembler, analytic mode vs AD mode.
void compareAssemblers(const Model& model, const Assembler::ConstraintList* cons, unsigned seed,
                       bool everyParameterEnters = true) {
  Assembler an(model, cons);
  Assembler ad(model, cons, Derivatives::AutomaticDifferentiation);
  ASSERT_EQ(an.derivatives(), Derivatives::Analytic);
  ASSERT_EQ(ad.derivatives(), Derivatives::AutomaticDifferentiation);
  const int n = an.n(), m = an.m();
  const VecX p = model.nominalParameters();
  const VecX q = model.initialPositions() + randomVec(n, seed, 0.1);
  const VecX v = randomVec(n, seed + 1, 1.0), x = randomVec(n, seed + 2, 1.0);
  const VecX w = randomVec(m, seed + 3, 1.0), a = randomVec(n, seed + 4, 1.0);

  // values are the same path in both modes
  EXPECT_EQ(rel(ad.force(q, v, p), an.force(q, v, p)), 0.0);
  EXPECT_EQ(rel(ad.phi(q, p), an.phi(q, p)), 0.0);

  auto block = [&](const Assembler& as, int rows, int cols, auto add) {
    SparseAccumulator acc;
    acc.begin(rows, cols);
    add(as, acc);
    return MatX(acc.finish());
  };
  auto cmpBlock = [&](const char* what, int rows, int cols, auto add) {
    const MatX A = block(an, rows, cols, add), B = block(ad, rows, cols, add);
    EXPECT_LT(rel(B, A), kTol) << what;
    EXPECT_GT(A.norm(), 0.0) << what;
  };
  cmpBlock("dQ/dq", n, n, [&](const Assembler& as, SparseAccumulator& acc) {
    as.addForceJacobian(acc, q, v, p, -1.0, 0.0, 0, 0, 0); });
  cmpBlock("dQ/dv", n, n, [&](const Assembler& as, SparseAccumulator& acc) {
    as.addForceJacobian(acc, q, v, p, 0.0, -1.0, 0, 0, 0); });
  cmpBlock("[dQ/dq dQ/dv]", n, 2 * n, [&](const Assembler& as, SparseAccumulator& acc) {
    as.addForceJacobian(acc, q, v, p, 2.0, -3.0, 0, 0, n); });
  cmpBlock("Phi_q", m, n, [&](const Assembler& as, SparseAccumulator& acc) {
    as.addPhiQ(acc, q, p, 1.5, 0, 0, false); });
  cmpBlock("Phi_q^T", n, m, [&](const Assembler& as, SparseAccumulator& acc) {
    as.addPhiQ(acc, q, p, -1.0, 0, 0, true); });
  cmpBlock("sum w_i H_i", n, n, [&](const Assembler& as, SparseAccumulator& acc) {
    as.addHessian(acc, q, p, w, 1.0, 0, 0); });
  cmpBlock("rows H_i v", m, n, [&](const Assembler& as, SparseAccumulator& acc) {
    as.addHessianRows(acc, q, p, v, 1.0, 0, 0); });

  auto cmpVec = [&](const char* what, const VecX& A, const VecX& B) {
    EXPECT_LT(rel(B, A), kTol) << what;
    EXPECT_GT(A.norm(), 0.0) << what;
  };
  cmpVec("Phi_q x", an.phiQTimes(q, p, x), ad.phiQTimes(q, p, x));
  cmpVec("Phi_q^T w", an.phiQTransposeTimes(q, p, w), ad.phiQTransposeTimes(q, p, w));
  cmpVec("(v^T H_i v)_i", an.hessianQuadratic(q, p, v), ad.hessianQuadratic(q, p, v));
  cmpVec("(sum w_i H_i) x", an.hessianTimes(q, p, w, x), ad.hessianTimes(q, p, w, x));
  cmpVec("(v^T H_i x)_i", an.hessianRowsTimes(q, p, v, x), ad.hessianRowsTimes(q, p, v, x));
  EXPECT_LT(rel(ad.phiQDense(q, p), an.phiQDense(q, p)), kTol);

  int nonzero = 0;
  for (int k = 0; k < p.size(); ++k) {
    SCOPED_TRACE("parameter " + std::to_string(k));
    const VecX Qp = an.forceParamDerivative(q, v, p, k), Mp = an.massParamDerivativeTimes(p, k, a);
    const VecX Pp = an.phiParamDerivative(q, p, k), PQp = an.phiQParamDerivativeTimes(q, p, k, x);
    const VecX PQTp = an.phiQParamDerivativeTransposeTimes(q, p, k, w);
    EXPECT_LT(rel(ad.forceParamDerivative(q, v, p, k), Qp), kTol) << "Q_p";
    EXPECT_LT(rel(ad.massParamDerivativeTimes(p, k, a), Mp), kTol) << "M_p a";
    EXPECT_LT(rel(ad.phiParamDerivative(q, p, k), Pp), kTol) << "Phi_p";
    EXPECT_LT(rel(ad.phiQParamDerivativeTimes(q, p, k, x), PQp), kTol) << "Phi_qp x";
    EXPECT_LT(rel(ad.phiQParamDerivativeTransposeTimes(q, p, k, w), PQTp), kTol) << "Phi_qp^T w";
    if (Qp.norm() + Mp.norm() + Pp.norm() + PQp.norm() > 0) ++nonzero;
  }
  if (everyParameterEnters) EXPECT_EQ(nonzero, p.size());  // the check is not vacuous
  EXPECT_GT(nonzero, 0);
}

}  // namespace

TEST(AutoDiff, AssemblerMixedScene) {
  Scene sc = test::mixedScene();
  compareAssemblers(*sc.model, nullptr, 31);
}

TEST(AutoDiff, AssemblerMixedSceneWithRigidizationConstraints) {
  // The PIM's path: the Assembler over rigidization constraints Lambda (distances among the
  // basic points, attached points), here of the beam's node cloud plus n2.
  Scene sc = test::mixedScene();
  const Model& m = *sc.model;
  MatX X(m.dim, m.nodes.size());
  for (size_t i = 0; i < m.nodes.size(); ++i) X.col(i) = m.nodes[i].position;
  std::vector<int> cloud = {m.nodeIndex("n1"), m.nodeIndex("n5"), m.nodeIndex("n6"), m.nodeIndex("n2")};
  Rigidization R = rigidize("body", cloud, m, X, "test");
  ASSERT_GE(R.constraints.size(), 2u);
  compareAssemblers(m, &R.constraints, 41, false);  // L, Ld sit in replaced constraints
}

TEST(AutoDiff, AssemblerSpatialModel) {
  const auto model = spatialModel();
  compareAssemblers(*model, nullptr, 51);
}

TEST(AutoDiff, AssemblerModeSetterAndGglSystem) {
  Scene sc = test::mixedScene();
  Assembler as(*sc.model);
  EXPECT_EQ(as.derivatives(), Derivatives::Analytic);
  const int n = as.n(), m = as.m(), N = 2 * (n + m);
  const VecX p = sc.model->nominalParameters();
  const SpMat M = as.mass(p);
  VecX y = randomVec(N, 61, 1.0);
  y.head(n) = sc.model->initialPositions() + randomVec(n, 62, 0.1);
  const VecX yp = randomVec(N, 63, 1.0), s = randomVec(N, 64, 1.0), sd = randomVec(N, 65, 1.0);
  SparseAccumulator acc;
  const MatX Jan = MatX(gglJacobian(as, p, y, 37.0, acc));
  std::vector<VecX> ran;
  for (int k = 0; k < p.size(); ++k) ran.push_back(gglSensitivityResidual(as, p, M, y, yp, k, s, sd));
  as.setDerivatives(Derivatives::AutomaticDifferentiation);
  EXPECT_EQ(as.derivatives(), Derivatives::AutomaticDifferentiation);
  SparseAccumulator acc2;
  EXPECT_LT(rel(MatX(gglJacobian(as, p, y, 37.0, acc2)), Jan), kTol);
  for (int k = 0; k < p.size(); ++k)
    EXPECT_LT(rel(gglSensitivityResidual(as, p, M, y, yp, k, s, sd), ran[k]), kTol) << "parameter " << k;
}

// ------------------------------------------------------------------------- end to end
TEST(AutoDiff, RigidFivebarSensitivitiesMatchAnalyticMode) {
  // Whole run (consistent initial sensitivities, trapezoidal steps with their Newton and
  // sensitivity systems) with an AD-mode Assembler vs an analytic-mode one: the same
  // discrete scheme, so the sensitivities agree to the Newton tolerance.
  Scene sc = readScene(test::sourceDir() + "/examples/fivebar/rigid.yaml", "R1");
  const VecX p = sc.model->nominalParameters();
  IntegratorSettings set;
  set.type = "trapezoidal";
  set.dt = 1e-3;
  set.tEnd = 0.3;
  set.frameInterval = 0.1;
  set.newtonTol = 1e-14;
  test::Recorder runs[2];
  for (int mode = 0; mode < 2; ++mode) {
    const Assembler as(*sc.model, nullptr,
                       mode ? Derivatives::AutomaticDifferentiation : Derivatives::Analytic);
    integrate(as, p, initialState(as, p, sc.pimCase.get()), set, runs[mode]);
  }
  ASSERT_EQ(runs[0].frames.size(), runs[1].frames.size());
  ASSERT_GE(runs[0].frames.size(), 3u);
  for (size_t f = 0; f < runs[0].frames.size(); ++f) {
    const auto& a = runs[0].frames[f];
    const auto& b = runs[1].frames[f];
    ASSERT_EQ(a.dp.size(), static_cast<size_t>(p.size()));
    ASSERT_EQ(b.dp.size(), a.dp.size());
    EXPECT_LT(rel(b.x.q, a.x.q), 1e-12);
    for (size_t k = 0; k < a.dp.size(); ++k) {
      EXPECT_GT(a.dp[k].q.norm(), 0.0);
      EXPECT_LT(rel(b.dp[k].q, a.dp[k].q), 1e-9) << "t = " << a.x.t << ", parameter " << k;
      EXPECT_LT(rel(b.dp[k].v, a.dp[k].v), 1e-9) << "t = " << a.x.t << ", parameter " << k;
    }
  }
}

TEST(AutoDiff, AssemblerSpatialSceneWithRigidBodiesJointsAndPlanes) {
  Scene sc = test::mixedScene3D();
  compareAssemblers(*sc.model, nullptr, 71);
}
