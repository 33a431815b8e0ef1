// Continuum elements (elements/Solid.hpp): triangles 3/6 (plane stress, plane strain) and
// tetrahedra 4/10, St. Venant-Kirchhoff and neo-Hookean. References independent of the code
// under test: finite differences (force Jacobian, parameter derivatives, potential gradient),
// the AD kernels (equal to the analytic ones to 1e-10), closed-form stresses of homogeneous
// deformations written here from the laws' textbook formulas (patch tests), zero force under
// rigid motion, and exact areas, volumes and centroids of straight elements (mass).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>

#include "TestModels.hpp"
#include "elements/Solid.hpp"

using namespace flexsens;
using flexsens::test::fdJacobian;
using flexsens::test::relMax;

namespace {

struct Case {
  Simplex shape;
  Law law;
  PlanarState planar;
  std::string label() const {
    return simplexName(shape) + (law == Law::NeoHookean ? " neo-Hookean" : " SVK") +
           (planar == PlanarState::PlaneStress ? " plane stress" : planar == PlanarState::PlaneStrain ? " plane strain" : "");
  }
};

std::vector<Case> allCases() {
  std::vector<Case> c;
  for (Simplex s : {Simplex::Tri3, Simplex::Tri6})
    for (Law l : {Law::SaintVenantKirchhoff, Law::NeoHookean})
      for (PlanarState p : {PlanarState::PlaneStress, PlanarState::PlaneStrain}) c.push_back({s, l, p});
  for (Simplex s : {Simplex::Tet4, Simplex::Tet10})
    for (Law l : {Law::SaintVenantKirchhoff, Law::NeoHookean}) c.push_back({s, l, PlanarState::None});
  return c;
}

/// Every property bound: p = (E, nu, density, thickness, alpha, beta).
std::shared_ptr<SolidProperties> boundProps(const Case& c) {
  auto pr = std::make_shared<SolidProperties>();
  pr->dim = simplexDim(c.shape);
  pr->law = {c.law, c.planar};
  pr->E = {0, 0};
  pr->nu = {0, 1};
  pr->density = {0, 2};
  pr->thickness = pr->dim == 2 ? Quantity{0, 3} : Quantity{1.0, -1};
  pr->alpha = {0, 4};
  pr->beta = {0, 5};
  return pr;
}
VecX params() {
  VecX p(6);
  p << 1000.0, 0.3, 7.0, 0.1, 0.3, 0.05;
  return p;
}

/// Rest positions (dim x nodes) of a skewed simplex; quadratic nodes at the edge midpoints,
/// moved by `curve` (0: straight element) to make it curved.
MatX restOf(Simplex s, double curve = 0.0) {
  const int d = simplexDim(s), n = simplexNodes(s);
  MatX X(d, n);
  if (d == 2) X.leftCols(3) << 0.1, 1.2, 0.3, -0.2, 0.1, 0.9;
  else X.leftCols(4) << 0.1, 1.1, 0.2, 0.3, -0.2, 0.1, 0.9, 0.2, 0.0, 0.2, 0.1, 1.0;
  const auto edges = simplexEdges(s);
  for (size_t k = 0; k < edges.size(); ++k) {
    X.col(d + 1 + k) = 0.5 * (X.col(edges[k].first) + X.col(edges[k].second));
    X.col(d + 1 + k) += curve * VecX::Unit(d, k % d) * (k % 2 ? -1.0 : 1.0);
  }
  return X;
}

VecX flat(const MatX& X) { return Eigen::Map<const VecX>(X.data(), X.size()); }

struct Local {
  VecX p, g;
  LocalState s;
  Local(int d, const VecX& x, const VecX& v, bool gravity) : p(params()) {
    g = VecX::Zero(d);
    if (gravity) {
      g[0] = 0.7;
      g[1] = -9.81;
    }
    s.dim = d;
    s.x = x;
    s.v = v;
    s.p = &p;
    s.gravity = &g;
  }
};

/// The second Piola-Kirchhoff stress of a homogeneous deformation F from the laws' textbook
/// formulas, written here independently of elements/Material.hpp (plane stress neo-Hookean:
/// C33 by bisection on S33 = 0).
MatX expectedS(const Case& c, const MatX& F, double E0, double nu) {
  const int d = static_cast<int>(F.rows());
  const double mu = E0 / (2 * (1 + nu)), lam = E0 * nu / ((1 + nu) * (1 - 2 * nu));
  const MatX C = F.transpose() * F, I = MatX::Identity(d, d), E = 0.5 * (C - I);
  if (c.law == Law::SaintVenantKirchhoff) {
    const double l = c.planar == PlanarState::PlaneStress ? E0 * nu / (1 - nu * nu) : lam;
    return l * E.trace() * I + 2 * mu * E;
  }
  const MatX Ci = C.inverse();
  double c33 = 1.0;
  if (c.planar == PlanarState::PlaneStress) {  // S33 = mu (1 - 1/c) + lambda ln J / c = 0
    auto s33 = [&](double cc) { return mu * (1 - 1 / cc) + lam * 0.5 * std::log(C.determinant() * cc) / cc; };
    double lo = 1e-3, hi = 10.0;
    for (int i = 0; i < 200; ++i) {
      const double m = 0.5 * (lo + hi);
      (s33(m) > 0 ? hi : lo) = m;
    }
    c33 = 0.5 * (lo + hi);
  }
  const double lnJ = 0.5 * std::log(C.determinant() * c33);
  return mu * (I - Ci) + lam * lnJ * Ci;
}

MatX homogeneousF(int d) {
  MatX A(d, d);
  if (d == 2) A << 1.08, 0.12, -0.05, 0.93;
  else A << 1.08, 0.12, 0.03, -0.05, 0.93, 0.07, 0.02, -0.04, 1.05;
  return A;
}

}  // namespace

TEST(Solid, DerivativesAgainstFiniteDifferencesAndAD) {
  for (const Case& c : allCases()) {
    SCOPED_TRACE(c.label());
    const int d = simplexDim(c.shape), n = simplexNodes(c.shape);
    const MatX X = restOf(c.shape, simplexOrder(c.shape) == 2 ? 0.03 : 0.0);
    std::vector<int> nodes(n);
    Solid e("e", nodes, boundProps(c), c.shape, X);
    std::srand(7);
    const VecX x = flat(X) + 0.06 * VecX::Random(d * n);
    const VecX v = 0.5 * VecX::Random(d * n);
    Local L(d, x, v, true);
    MatX K, Kv, Kad, Kvad;
    e.forceJacobian(L.s, K, Kv);
    e.forceJacobianAD(L.s, Kad, Kvad);
    EXPECT_LT(relMax(Kad, K), 1e-10);
    EXPECT_LT(relMax(Kvad, Kv), 1e-10);
    auto fq = [&](const VecX& q) { LocalState s = L.s; s.x = q; VecX Q; e.force(s, Q); return Q; };
    auto fv = [&](const VecX& w) { LocalState s = L.s; s.v = w; VecX Q; e.force(s, Q); return Q; };
    EXPECT_LT(relMax(fdJacobian(fq, x), K), 1e-6);
    EXPECT_LT(relMax(fdJacobian(fv, v), Kv), 1e-6);
    EXPECT_GT(K.norm(), 0.0);
    flexsens::test::expectForceMatchesTemplate(e, L.s);
    // -dU/dq = Q at rest velocity (potential: elastic + gravity)
    {
      Local L0(d, x, VecX::Zero(d * n), true);
      VecX Q;
      e.force(L0.s, Q);
      auto U = [&](const VecX& q) { LocalState s = L0.s; s.x = q; VecX r(1); r[0] = e.potential(s); return r; };
      EXPECT_LT(relMax(-fdJacobian(U, x).transpose(), Q), 1e-6);
    }
    // parameters
    for (int k = 0; k < 6; ++k) {
      SCOPED_TRACE("parameter " + std::to_string(k));
      VecX dQ, dQad;
      MatX dM, dMad;
      const bool has = e.parameterDerivative(L.s, k, dQ, dM);
      EXPECT_EQ(has, d == 2 || k != 3);
      if (!has) continue;
      ASSERT_TRUE(e.parameterDerivativeAD(L.s, k, dQad, dMad));
      EXPECT_LT(relMax(dQad, dQ), 1e-10);
      EXPECT_LT(relMax(dMad, dM), 1e-10);
      auto fp = [&](const VecX& pk) { VecX p = L.p; p[k] = pk[0]; LocalState s = L.s; s.p = &p; VecX Q; e.force(s, Q); return Q; };
      auto mp = [&](const VecX& pk) {
        VecX p = L.p; p[k] = pk[0]; LocalState s = L.s; s.p = &p; MatX M; e.mass(s, M);
        return VecX(Eigen::Map<VecX>(M.data(), M.size()));
      };
      const VecX pk = L.p.segment(k, 1);
      EXPECT_LT(relMax(fdJacobian(fp, pk, 1e-5), dQ), 1e-6);
      const VecX dMf = Eigen::Map<const VecX>(dM.data(), dM.size());
      if (k == 2 || k == 3) EXPECT_LT(relMax(fdJacobian(mp, pk, 1e-5), dMf), 1e-8);
      else EXPECT_EQ(dM.norm(), 0.0);
    }
  }
}

TEST(Solid, RigidMotionGivesZeroForce) {
  for (const Case& c : allCases()) {
    SCOPED_TRACE(c.label());
    const int d = simplexDim(c.shape), n = simplexNodes(c.shape);
    const MatX X = restOf(c.shape, simplexOrder(c.shape) == 2 ? 0.03 : 0.0);
    auto pr = boundProps(c);
    Solid e("e", std::vector<int>(n), pr, c.shape, X);
    MatX R;
    VecX w;
    if (d == 2) {
      const double a = 0.7;
      R.resize(2, 2);
      R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    } else {
      R = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
      w = Eigen::Vector3d(0.3, -1.1, 0.4);
    }
    const MatX x = (R * X).colwise() + VecX::Constant(d, 0.37);
    MatX v(d, n);  // rigid velocity omega x (x - x0)
    for (int i = 0; i < n; ++i) {
      const VecX r = x.col(i) - x.col(0);
      if (d == 2) v.col(i) = 1.3 * Eigen::Vector2d(-r[1], r[0]);
      else v.col(i) = Eigen::Vector3d(w).cross(Eigen::Vector3d(r));
    }
    Local L(d, flat(x), flat(v), false);
    L.p[4] = 0.0;  // alpha damps rigid motion by design; beta (Kelvin-Voigt) does not
    VecX Q;
    e.force(L.s, Q);
    // scale: E times the element's measure over its size ~ 1000 * 0.5 N
    EXPECT_LT(Q.lpNorm<Eigen::Infinity>(), 1e-10 * L.p[0]) << Q.transpose();
  }
}

TEST(Solid, ConstantStrainPatchOneElement) {
  // x = A X + b on a straight element: sum_i Q_i = 0 and sum_i Q_i X_i^T = -t V P with
  // P = F S(F) the stress of the homogeneous deformation (textbook formula, expectedS).
  for (const Case& c : allCases()) {
    SCOPED_TRACE(c.label());
    const int d = simplexDim(c.shape), n = simplexNodes(c.shape);
    const MatX X = restOf(c.shape);
    Solid e("e", std::vector<int>(n), boundProps(c), c.shape, X);
    const MatX A = homogeneousF(d);
    const MatX x = (A * X).colwise() + VecX::Constant(d, -0.2);
    Local L(d, flat(x), VecX::Zero(d * n), false);
    VecX Q;
    e.force(L.s, Q);
    MatX sumQ = MatX::Zero(d, 1), QX = MatX::Zero(d, d);
    for (int i = 0; i < n; ++i) {
      sumQ += Q.segment(i * d, d);
      QX += Q.segment(i * d, d) * X.col(i).transpose();
    }
    MatX J0(d, d);
    for (int k = 0; k < d; ++k) J0.col(k) = X.col(k + 1) - X.col(0);
    const double V = std::abs(J0.determinant()) / (d == 2 ? 2.0 : 6.0), t = d == 2 ? L.p[3] : 1.0;
    const MatX P = A * expectedS(c, A, L.p[0], L.p[1]);
    EXPECT_LT(sumQ.norm(), 1e-12 * P.norm() * V);
    EXPECT_LT(relMax(QX, -t * V * P), 1e-12);
    MatX Es, S, sigma;
    double vm;
    e.centroidStress(L.s, Es, S, sigma, vm);
    EXPECT_LT(relMax(Es, 0.5 * (A.transpose() * A - MatX::Identity(d, d))), 1e-13);
    EXPECT_LT(relMax(S, expectedS(c, A, L.p[0], L.p[1])), 1e-12);
  }
}

namespace {
/// A patch of elements around one interior node: the unit square cut into 4 triangles
/// around (0.4, 0.55), or the unit cube's 12 face triangles joined to (0.45, 0.5, 0.55);
/// quadratic elements get shared midside nodes. Returns the elements' node lists (positively
/// oriented) and fills X (dim x nodes); the interior corner node is node 0.
std::vector<std::vector<int>> patch(Simplex s, MatX& X) {
  const int d = simplexDim(s);
  std::vector<VecX> pts;
  std::vector<std::vector<int>> cells;
  auto vec = [](std::initializer_list<double> v) { VecX x(v.size()); int i = 0; for (double a : v) x[i++] = a; return x; };
  if (d == 2) {
    pts = {vec({0.4, 0.55}), vec({0, 0}), vec({1, 0}), vec({1, 1}), vec({0, 1})};
    cells = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
  } else {
    pts.push_back(vec({0.45, 0.5, 0.55}));
    for (int k = 0; k < 8; ++k) pts.push_back(vec({double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)}));
    const int faces[6][4] = {{1, 2, 4, 3}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 4, 8, 7}, {1, 3, 7, 5}, {2, 4, 8, 6}};
    for (const auto& f : faces) {
      cells.push_back({0, f[0], f[1], f[2]});
      cells.push_back({0, f[0], f[2], f[3]});
    }
  }
  for (auto& cell : cells) {  // orient positively
    MatX J(d, d);
    for (int k = 0; k < d; ++k) J.col(k) = pts[cell[k + 1]] - pts[cell[0]];
    if (J.determinant() < 0) std::swap(cell[1], cell[2]);
  }
  if (simplexOrder(s) == 2) {
    std::map<std::pair<int, int>, int> mid;
    for (auto& cell : cells) {
      std::vector<int> full = cell;
      for (const auto& [a, b] : simplexEdges(s)) {
        const auto key = std::minmax(cell[a], cell[b]);
        auto it = mid.find(key);
        if (it == mid.end()) {
          it = mid.emplace(key, static_cast<int>(pts.size())).first;
          pts.push_back(0.5 * (pts[cell[a]] + pts[cell[b]]));
        }
        full.push_back(it->second);
      }
      cell = full;
    }
  }
  X.resize(d, pts.size());
  for (size_t i = 0; i < pts.size(); ++i) X.col(i) = pts[i];
  return cells;
}
}  // namespace

TEST(Solid, ConstantStrainPatchInteriorNodesInEquilibrium) {
  // A homogeneous deformation of a patch: every interior node (the centre, and for quadratic
  // elements the midside nodes of interior edges) carries zero net force; the boundary forces'
  // moment sum_i Q_i X_i^T equals -t V P (V = 1, the unit square or cube).
  for (const Case& c : allCases()) {
    SCOPED_TRACE(c.label());
    const int d = simplexDim(c.shape), n = simplexNodes(c.shape);
    MatX X;
    const auto cells = patch(c.shape, X);
    const int N = static_cast<int>(X.cols());
    const MatX A = homogeneousF(d);
    const MatX x = (A * X).colwise() + VecX::Constant(d, 0.1);
    auto pr = boundProps(c);
    VecX p = params();
    VecX Q = VecX::Zero(d * N);
    std::vector<int> onInterior(N, 0);
    for (const auto& cell : cells) {
      MatX Xe(d, n), xe(d, n);
      for (int i = 0; i < n; ++i) {
        Xe.col(i) = X.col(cell[i]);
        xe.col(i) = x.col(cell[i]);
      }
      Solid e("e", cell, pr, c.shape, Xe);
      LocalState s;
      s.dim = d;
      s.x = flat(xe);
      s.v = VecX::Zero(d * n);
      s.p = &p;
      VecX q;
      e.force(s, q);
      for (int i = 0; i < n; ++i) Q.segment(cell[i] * d, d) += q.segment(i * d, d);
    }
    // interior: node 0 and the midpoints of the edges from node 0 (inside the square/cube)
    const double scale = params()[0];
    for (int i = 0; i < N; ++i) {
      const VecX Xi = X.col(i);
      const bool boundary = (Xi.array() < 1e-12).any() || (Xi.array() > 1 - 1e-12).any();
      if (!boundary) EXPECT_LT(Q.segment(i * d, d).norm(), 1e-12 * scale) << "node " << i;
    }
    MatX QX = MatX::Zero(d, d);
    for (int i = 0; i < N; ++i) QX += Q.segment(i * d, d) * X.col(i).transpose();
    const double t = d == 2 ? p[3] : 1.0;
    EXPECT_LT(relMax(QX, -t * A * expectedS(c, A, p[0], p[1])), 1e-12);
  }
}

TEST(Solid, MassIntegratesAreaVolumeAndFirstMoments) {
  // 1^T M 1 (one component) = rho t V and 1^T M X = rho t V Xc for straight elements
  // (V, Xc from the corners); curved quadratic elements keep 1^T M 1 = int det J0 exactly,
  // checked against the sum of det J0 over a fine collapsed rule independent of massRule.
  for (const Case& c : allCases()) {
    SCOPED_TRACE(c.label());
    const int d = simplexDim(c.shape), n = simplexNodes(c.shape);
    const MatX X = restOf(c.shape);
    Solid e("e", std::vector<int>(n), boundProps(c), c.shape, X);
    Local L(d, flat(X), VecX::Zero(d * n), false);
    MatX M;
    ASSERT_TRUE(e.mass(L.s, M));
    MatX J0(d, d);
    for (int k = 0; k < d; ++k) J0.col(k) = X.col(k + 1) - X.col(0);
    const double V = std::abs(J0.determinant()) / (d == 2 ? 2.0 : 6.0), t = d == 2 ? L.p[3] : 1.0;
    const VecX Xc = X.leftCols(d + 1).rowwise().mean();
    const double rho = L.p[2];
    VecX ones = VecX::Zero(d * n), xs = VecX::Zero(d * n);
    for (int i = 0; i < n; ++i) ones[i * d] = 1.0;
    EXPECT_NEAR(ones.dot(M * ones), rho * t * V, 1e-13 * rho * t * V);
    for (int k = 0; k < d; ++k) {
      for (int i = 0; i < n; ++i) xs[i * d] = X(k, i);
      EXPECT_NEAR(ones.dot(M * xs), rho * t * V * Xc[k], 1e-13 * rho * t * V);
    }
    if (simplexOrder(c.shape) == 2) {  // curved: against a 12-point-per-direction rule
      const MatX Xq = restOf(c.shape, 0.08);
      Solid ec("e", std::vector<int>(n), boundProps(c), c.shape, Xq);
      MatX Mc;
      ec.mass(L.s, Mc);
      const SimplexRule fine = collapsedRule(d, 12);
      double Vq = 0.0;
      VecX N;
      MatX dN;
      for (size_t g = 0; g < fine.x.size(); ++g) {
        simplexShape(c.shape, fine.x[g], N, dN);
        Vq += fine.w[g] * (Xq * dN).determinant();
      }
      EXPECT_NEAR(ones.dot(Mc * ones), rho * t * Vq, 1e-13 * rho * t * Vq);
    }
  }
}

TEST(Solid, DegenerateAndInvertedElementsAreRejected) {
  MatX X = restOf(Simplex::Tri3);
  auto pr = boundProps({Simplex::Tri3, Law::SaintVenantKirchhoff, PlanarState::PlaneStress});
  MatX Xs = X;
  std::swap(Xs(0, 1), Xs(0, 2));
  std::swap(Xs(1, 1), Xs(1, 2));
  try {
    Solid("e", std::vector<int>(3), pr, Simplex::Tri3, Xs);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("inverted"), std::string::npos) << e.what();
  }
  MatX Xd = X;
  Xd.col(2) = 0.5 * (X.col(0) + X.col(1));
  try {
    Solid("e", std::vector<int>(3), pr, Simplex::Tri3, Xd);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("degenerate"), std::string::npos) << e.what();
  }
}
