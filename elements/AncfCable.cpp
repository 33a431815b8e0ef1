#include "elements/AncfCable.hpp"

#include <cmath>

#include "elements/KernelElementAD.hpp"

namespace flexsens {

namespace {

/// Gauss-Legendre points and weights on [0, 1] (Newton on the Legendre polynomial).
void gaussLegendre01(int n, std::vector<double>& x, std::vector<double>& w) {
  x.resize(n);
  w.resize(n);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;  // P_0, P_1; recurrence up to P_n
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    x[i] = 0.5 * (1.0 - z);
    w[i] = 1.0 / ((1.0 - z * z) * dp * dp);  // (2 / ((1 - z^2) P_n'^2)) / 2
  }
}

constexpr int kMassPoints = 8;  // exact for the straight element (degree 6); curved: ~1e-12

}  // namespace

Eigen::Vector4d AncfCable::shape(double xi, double L) {
  const double x2 = xi * xi, x3 = x2 * xi;
  return {1.0 - 3.0 * x2 + 2.0 * x3, L * (xi - 2.0 * x2 + x3), 3.0 * x2 - 2.0 * x3, L * (x3 - x2)};
}
Eigen::Vector4d AncfCable::shapeS(double xi, double L) {
  const double x2 = xi * xi;
  return {(-6.0 * xi + 6.0 * x2) / L, 1.0 - 4.0 * xi + 3.0 * x2, (6.0 * xi - 6.0 * x2) / L, 3.0 * x2 - 2.0 * xi};
}
Eigen::Vector4d AncfCable::shapeSS(double xi, double L) {
  return {(-6.0 + 12.0 * xi) / (L * L), (-4.0 + 6.0 * xi) / L, (6.0 - 12.0 * xi) / (L * L), (6.0 * xi - 2.0) / L};
}

AncfCable::AncfCable(std::string name, std::vector<int> nodes, std::shared_ptr<BeamSection> section,
                     const VecX& restX, int axialPoints, int bendingPoints)
    : KernelElement(std::move(name), std::move(nodes)), sec_(std::move(section)) {
  const std::string who = "ancf_cable " + this->name();
  if (this->nodes().size() != 2) throw std::invalid_argument(who + ": needs 2 nodes");
  if (!sec_) throw std::invalid_argument(who + ": no section");
  if (restX.size() != 8 && restX.size() != 12) throw std::invalid_argument(who + ": dim must be 2 or 3");
  if (axialPoints < 1 || bendingPoints < 1) throw std::invalid_argument(who + ": needs at least one Gauss point");
  const int d = dim_ = static_cast<int>(restX.size()) / 4;
  L_ = (restX.segment(2 * d, d) - restX.segment(0, d)).norm();
  if (!(L_ > 0.0)) throw std::invalid_argument(who + ": zero length (its nodes coincide)");
  ptsA_ = makePoints(restX, axialPoints, false);
  ptsB_ = makePoints(restX, bendingPoints, d == 3);
  auto at = [&](const Eigen::Vector4d& N) {
    VecX r = VecX::Zero(d);
    for (int i = 0; i < 4; ++i) r += N[i] * restX.segment(i * d, d);
    return r;
  };
  std::vector<double> xs, ws;
  gaussLegendre01(kMassPoints, xs, ws);
  massShape_.setZero();
  for (int g = 0; g < kMassPoints; ++g) {
    const Eigen::Vector4d N = shape(xs[g], L_);
    massShape_ += (ws[g] * L_ * at(shapeS(xs[g], L_)).norm()) * N * N.transpose();
  }
}

std::vector<AncfCable::Point> AncfCable::makePoints(const VecX& restX, int n, bool checkStraight) const {
  const std::string who = "ancf_cable " + name();
  const int d = dim_;
  std::vector<double> xs, ws;
  gaussLegendre01(n, xs, ws);
  std::vector<Point> pts;
  for (int g = 0; g < n; ++g) {
    Point P;
    P.d1 = shapeS(xs[g], L_);
    P.d2 = shapeSS(xs[g], L_);
    VecX a = VecX::Zero(d), b = VecX::Zero(d);
    for (int i = 0; i < 4; ++i) {
      a += P.d1[i] * restX.segment(i * d, d);
      b += P.d2[i] * restX.segment(i * d, d);
    }
    P.a0 = a.norm();
    if (!(P.a0 > 0.0)) throw std::invalid_argument(who + ": zero rest slope inside the element");
    P.w = ws[g] * L_ * P.a0;
    P.kappa0 = d == 2 ? (a[0] * b[1] - a[1] * b[0]) / (P.a0 * P.a0 * P.a0) : 0.0;
    if (checkStraight) {
      const double k = Eigen::Vector3d(a).cross(Eigen::Vector3d(b)).norm() / std::pow(P.a0, 3);
      if (k * L_ > 1e-9)
        throw std::invalid_argument(who + ": the spatial ANCF cable needs a straight rest shape "
                                          "(rest slopes along the chord)");
    }
    pts.push_back(P);
  }
  return pts;
}

// ------------------------------------------------------------------ value templates
// props = (E, density, A source, I source).
template <class T>
MatT<T> AncfCable::massT(const LocalState&, const VecT<T>& props) const {
  const int d = dim_;
  const T rhoA = props[1] * sec_->areaOf(props[2]);  // [kg/m]
  MatT<T> M = MatT<T>::Zero(4 * d, 4 * d);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int c = 0; c < d; ++c) M(i * d + c, j * d + c) = rhoA * massShape_(i, j);
  return M;
}

template <class T>
VecT<T> AncfCable::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>&,
                          const VecT<T>& props) const {
  using std::sqrt;
  if (s.dim != dim_ || s.gradients != 1) throw std::invalid_argument("ancf_cable " + name() + ": needs positions and slopes of dim " + std::to_string(dim_));
  const int d = dim_;
  const T E = props[0];
  const T EA = E * sec_->areaOf(props[2]), EI = E * sec_->inertiaOf(props[3]);
  const T rhoA = props[1] * sec_->areaOf(props[2]);
  VecT<T> Q(4 * d);
  // Gravity M G, G = (g, 0, g, 0): node blocks 0 and 2 are the positions.
  const VecX g = s.gravity ? VecX(*s.gravity) : VecX(VecX::Zero(d));
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < d; ++c) Q[i * d + c] = rhoA * ((massShape_(i, 0) + massShape_(i, 2)) * g[c]);
  for (const Point& P : ptsA_) {
    VecT<T> a = P.d1[0] * x.segment(0, d);
    for (int i = 1; i < 4; ++i) a += P.d1[i] * x.segment(i * d, d);
    const T na = sqrt(a.squaredNorm());
    if (!(ad::valueOf(na) > 0.0)) throw NumericalError("ancf_cable " + name() + ": zero slope r' at a Gauss point");
    const T eps = na / P.a0 - 1.0;
    const VecT<T> ga = (EA * eps / (na * P.a0)) * a;  // d(EA eps^2 / 2)/dr'  [N]
    for (int i = 0; i < 4; ++i) Q.segment(i * d, d) -= (P.w * P.d1[i]) * ga;
  }
  for (const Point& P : ptsB_) {
    VecT<T> a = P.d1[0] * x.segment(0, d), b = P.d2[0] * x.segment(0, d);
    for (int i = 1; i < 4; ++i) {
      a += P.d1[i] * x.segment(i * d, d);
      b += P.d2[i] * x.segment(i * d, d);
    }
    const T gg = a.squaredNorm(), na = sqrt(gg);
    if (!(ad::valueOf(na) > 0.0)) throw NumericalError("ancf_cable " + name() + ": zero slope r' at a Gauss point");
    VecT<T> ga(d), gb(d);
    if (d == 2) {  // EI/2 (kappa - kappa0)^2, kappa = (a x b) / (|a|^2 a0)
      const T h = 1.0 / (gg * P.a0), kappa = (a[0] * b[1] - a[1] * b[0]) * h;
      const T m = EI * (kappa - P.kappa0);  // bending moment [N m]
      ga[0] = m * (h * b[1] - 2.0 * kappa * a[0] / gg);
      ga[1] = m * (-h * b[0] - 2.0 * kappa * a[1] / gg);
      gb[0] = -m * h * a[1];
      gb[1] = m * h * a[0];
    } else {  // EI/2 |a x b|^2 / (|a|^4 a0^2)
      const T beta = b.squaredNorm(), gam = a.dot(b);
      const T u = 1.0 / (gg * gg * P.a0 * P.a0), phi = (gg * beta - gam * gam) * u;
      ga = EI * (u * (beta * a - gam * b) - (2.0 * phi / gg) * a);
      gb = EI * u * (gg * b - gam * a);
    }
    for (int i = 0; i < 4; ++i) Q.segment(i * d, d) -= P.w * (P.d1[i] * ga + P.d2[i] * gb);
  }
  return Q;
}

// ------------------------------------------------------------------ analytic derivatives
// Hand-coded force and stiffness with fixed-size (D = 2, 3) blocks: (r', r'') = sum_i
// (d1_i, d2_i) e_i, so the stiffness of a quadrature point is a 4 x 4 pattern of D x D blocks
// d1_i d1_j H_aa + d1_i d2_j H_ab + d2_i d1_j H_ba + d2_i d2_j H_bb; no B matrix, no heap
// temporaries (the dynamic-size version spent most of its time in malloc and small GEMMs).
namespace {

template <int D>
using VecD = Eigen::Matrix<double, D, 1>;
template <int D>
using MatD = Eigen::Matrix<double, D, D>;

/// Per unit EI: gradient (ga, gb) and Hessian blocks of the bending density 1/2 w_b at
/// (a, b) = (r', r''); a0 = |r0'|, kappa0 the planar rest curvature. H null: gradient only.
template <int D>
void bendingTerms(const VecD<D>& a, const VecD<D>& b, double a0, double kappa0, VecD<D>& ga, VecD<D>& gb,
                  MatD<D>* Haa, MatD<D>* Hab, MatD<D>* Hbb) {
  const double gg = a.squaredNorm();
  if constexpr (D == 2) {
    // 1/2 (kappa - kappa0)^2, kappa = c h, c = a x b, h = |a|^-2 / a0.
    const double h = 1.0 / (gg * a0), c = a[0] * b[1] - a[1] * b[0], kappa = c * h, dk = kappa - kappa0;
    const VecD<2> ca(b[1], -b[0]), cb(-a[1], a[0]);  // dc/da, dc/db
    const VecD<2> hA = (-2.0 * h / gg) * a;           // dh/da
    const VecD<2> ka = h * ca + c * hA, kb = h * cb;   // dkappa/da, dkappa/db
    ga = dk * ka;
    gb = dk * kb;
    if (Haa) {
      const MatD<2> Hh = (-2.0 * h / gg) * MatD<2>::Identity() + (8.0 * h / (gg * gg)) * a * a.transpose();
      MatD<2> Cab;
      Cab << 0.0, 1.0, -1.0, 0.0;  // d2c/(da_i db_j)
      *Haa = ka * ka.transpose() + dk * (ca * hA.transpose() + hA * ca.transpose() + c * Hh);
      *Hab = ka * kb.transpose() + dk * (h * Cab + hA * cb.transpose());
      *Hbb = kb * kb.transpose();
    }
  } else {
    // 1/2 phi, phi = f u, f = |a|^2 |b|^2 - (a.b)^2 = |a x b|^2, u = |a|^-4 a0^-2.
    (void)kappa0;
    const double beta = b.squaredNorm(), gam = a.dot(b), u = 1.0 / (gg * gg * a0 * a0);
    const double f = gg * beta - gam * gam;
    const VecD<3> fa = 2.0 * beta * a - 2.0 * gam * b, fb = 2.0 * gg * b - 2.0 * gam * a;
    const VecD<3> ua = (-4.0 * u / gg) * a;
    ga = 0.5 * (u * fa + f * ua);
    gb = 0.5 * u * fb;
    if (Haa) {
      const MatD<3> I = MatD<3>::Identity();
      const MatD<3> faa = 2.0 * beta * I - 2.0 * b * b.transpose();
      const MatD<3> fbb = 2.0 * gg * I - 2.0 * a * a.transpose();
      const MatD<3> fab = 4.0 * a * b.transpose() - 2.0 * b * a.transpose() - 2.0 * gam * I;
      const MatD<3> uaa = (-4.0 * u / gg) * I + (24.0 * u / (gg * gg)) * a * a.transpose();
      *Haa = 0.5 * (u * faa + fa * ua.transpose() + ua * fa.transpose() + f * uaa);
      *Hab = 0.5 * (u * fab + ua * fb.transpose());
      *Hbb = 0.5 * u * fbb;
    }
  }
}

}  // namespace

template <int D>
void AncfCable::elasticD(const LocalState& s, double cA, double cB, VecX& QA, VecX& QB, MatX* KA, MatX* KB) const {
  constexpr int n = 4 * D;
  QA.setZero(n);
  QB.setZero(n);  // QB may be QA, KB may be KA: both are zeroed before anything is added
  if (KA) KA->setZero(n, n);
  if (KB) KB->setZero(n, n);
  const Eigen::Map<const Eigen::Matrix<double, D, 4>> X(s.x.data());  // column i: e_i
  // Adds the symmetric stiffness of one point, blocks (i, j) = sum of c_ij H, to K.
  auto addSym = [](MatX& K, auto&& block) {
    for (int i = 0; i < 4; ++i)
      for (int j = i; j < 4; ++j) {
        const MatD<D> B = block(i, j);
        K.template block<D, D>(i * D, j * D) -= B;
        if (j != i) K.template block<D, D>(j * D, i * D) -= B.transpose();
      }
  };
  for (const Point& P : ptsA_) {
    // Per unit EA: 1/2 eps^2, eps = |a|/a0 - 1; grad eps = a/(|a| a0), Hess eps = (I - n n^T)/(|a| a0).
    const VecD<D> a = X * P.d1;
    const double gg = a.squaredNorm(), na = std::sqrt(gg);
    if (!(na > 0.0)) throw NumericalError("ancf_cable " + name() + ": zero slope r' at a Gauss point");
    const double eps = na / P.a0 - 1.0;
    const VecD<D> de = a / (na * P.a0), g = (cA * eps) * de;
    for (int i = 0; i < 4; ++i) QA.template segment<D>(i * D) -= (P.w * P.d1[i]) * g;
    if (!KA) continue;
    const MatD<D> H = (cA * P.w) * (de * de.transpose() +
                                    (eps / (na * P.a0)) * (MatD<D>::Identity() - a * a.transpose() / gg));
    addSym(*KA, [&](int i, int j) { return MatD<D>((P.d1[i] * P.d1[j]) * H); });
  }
  for (const Point& P : ptsB_) {
    const VecD<D> a = X * P.d1, b = X * P.d2;
    if (!(a.squaredNorm() > 0.0)) throw NumericalError("ancf_cable " + name() + ": zero slope r' at a Gauss point");
    VecD<D> ga, gb;
    MatD<D> Haa = MatD<D>::Zero(), Hab = MatD<D>::Zero(), Hbb = MatD<D>::Zero();  // (set when KB)
    bendingTerms<D>(a, b, P.a0, P.kappa0, ga, gb, KB ? &Haa : nullptr, &Hab, &Hbb);
    const double wc = cB * P.w;
    for (int i = 0; i < 4; ++i) QB.template segment<D>(i * D) -= wc * (P.d1[i] * ga + P.d2[i] * gb);
    if (!KB) continue;
    Haa *= wc;
    Hab *= wc;
    Hbb *= wc;
    addSym(*KB, [&](int i, int j) {
      return MatD<D>(P.d1[i] * P.d1[j] * Haa + P.d1[i] * P.d2[j] * Hab + P.d2[i] * P.d1[j] * Hab.transpose() +
                     P.d2[i] * P.d2[j] * Hbb);
    });
  }
}

void AncfCable::elastic(const LocalState& s, double cA, double cB, VecX& QA, VecX& QB, MatX* KA, MatX* KB) const {
  if (s.dim != dim_ || s.gradients != 1) throw std::invalid_argument("ancf_cable " + name() + ": needs positions and slopes of dim " + std::to_string(dim_));
  if (dim_ == 2)
    elasticD<2>(s, cA, cB, QA, QB, KA, KB);
  else
    elasticD<3>(s, cA, cB, QA, QB, KA, KB);
}

void AncfCable::force(const LocalState& s, VecX& Q) const {
  elastic(s, sec_->EA(*s.p), sec_->EI(*s.p), Q, Q, nullptr, nullptr);
  Q += gravityLoad(s, sec_->rhoA(*s.p));
}

VecX AncfCable::gravityLoad(const LocalState& s, double rhoA) const {
  const int d = dim_;
  VecX Q = VecX::Zero(4 * d);
  if (!s.gravity) return Q;
  for (int i = 0; i < 4; ++i) Q.segment(i * d, d) = rhoA * (massShape_(i, 0) + massShape_(i, 2)) * *s.gravity;
  return Q;
}

void AncfCable::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  VecX Q;
  elastic(s, sec_->EA(*s.p), sec_->EI(*s.p), Q, Q, &dQdq, &dQdq);
  dQdv.setZero(4 * dim_, 4 * dim_);
}

bool AncfCable::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  if (!sec_->axialDependsOn(k) && !sec_->bendingDependsOn(k)) return false;
  VecX QA, QB;
  elastic(s, 1.0, 1.0, QA, QB, nullptr, nullptr);
  const double drhoA = sec_->drhoA(*s.p, k);
  dQ = sec_->dEA(*s.p, k) * QA + sec_->dEI(*s.p, k) * QB + gravityLoad(s, drhoA);
  const int d = dim_;
  dM.setZero(4 * d, 4 * d);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int c = 0; c < d; ++c) dM(i * d + c, j * d + c) = drhoA * massShape_(i, j);
  return true;
}

double AncfCable::potential(const LocalState& s) const {
  if (s.dim != dim_ || s.gradients != 1) throw std::invalid_argument("ancf_cable " + name() + ": needs positions and slopes of dim " + std::to_string(dim_));
  const int d = dim_;
  const double EA = sec_->EA(*s.p), EI = sec_->EI(*s.p);
  double U = 0.0;
  auto slopes = [&](const Point& P, VecX& a, VecX& b) {
    a = VecX::Zero(d);
    b = VecX::Zero(d);
    for (int i = 0; i < 4; ++i) {
      a += P.d1[i] * s.x.segment(i * d, d);
      b += P.d2[i] * s.x.segment(i * d, d);
    }
  };
  VecX a, b;
  for (const Point& P : ptsA_) {
    slopes(P, a, b);
    const double eps = a.norm() / P.a0 - 1.0;
    U += P.w * 0.5 * EA * eps * eps;
  }
  for (const Point& P : ptsB_) {
    slopes(P, a, b);
    const double gg = a.squaredNorm();
    double wb;
    if (d == 2) {
      const double kappa = (a[0] * b[1] - a[1] * b[0]) / (gg * P.a0);
      wb = (kappa - P.kappa0) * (kappa - P.kappa0);
    } else {
      wb = Eigen::Vector3d(a).cross(Eigen::Vector3d(b)).squaredNorm() / (gg * gg * P.a0 * P.a0);
    }
    U += P.w * 0.5 * EI * wb;
  }
  // minus the work of gravity: -G^T M e, G = (g, 0, g, 0)  [J]
  return U - gravityLoad(s, sec_->rhoA(*s.p)).dot(s.x);
}

template class KernelElement<AncfCable>;

}  // namespace flexsens
