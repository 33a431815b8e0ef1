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
  if (s.dim != dim_ || !s.slopes) throw std::invalid_argument("ancf_cable " + name() + ": needs positions and slopes of dim " + std::to_string(dim_));
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
    if (d == 2) {  // EI/2 (kappa - kappa0)^2, kappa = (a x b) / |a|^3
      const T h = 1.0 / (gg * na), kappa = (a[0] * b[1] - a[1] * b[0]) * h;
      const T m = EI * (kappa - P.kappa0);  // bending moment [N m]
      ga[0] = m * (h * b[1] - 3.0 * kappa * a[0] / gg);
      ga[1] = m * (-h * b[0] - 3.0 * kappa * a[1] / gg);
      gb[0] = -m * h * a[1];
      gb[1] = m * h * a[0];
    } else {  // EI/2 |a x b|^2 / |a|^6
      const T beta = b.squaredNorm(), gam = a.dot(b);
      const T u = 1.0 / (gg * gg * gg), phi = (gg * beta - gam * gam) * u;
      ga = EI * (u * (beta * a - gam * b) - (3.0 * phi / gg) * a);
      gb = EI * u * (gg * b - gam * a);
    }
    for (int i = 0; i < 4; ++i) Q.segment(i * d, d) -= P.w * (P.d1[i] * ga + P.d2[i] * gb);
  }
  return Q;
}

// ------------------------------------------------------------------ analytic derivatives
void AncfCable::axialTerms(const Point& P, const VecX& a, VecX& gA, MatX* HA) const {
  const int d = dim_;
  const double gg = a.squaredNorm(), na = std::sqrt(gg);
  if (!(na > 0.0)) throw NumericalError("ancf_cable " + name() + ": zero slope r' at a Gauss point");
  // 1/2 eps^2, eps = |a|/a0 - 1; grad eps = a/(|a| a0), Hess eps = (I - n n^T)/(|a| a0).
  const double eps = na / P.a0 - 1.0;
  const VecX de = a / (na * P.a0);
  gA = VecX::Zero(2 * d);
  gA.head(d) = eps * de;
  if (HA) {
    HA->setZero(2 * d, 2 * d);
    HA->topLeftCorner(d, d) =
        de * de.transpose() + (eps / (na * P.a0)) * (MatX::Identity(d, d) - a * a.transpose() / gg);
  }
}

void AncfCable::bendingTerms(const Point& P, const VecX& a, const VecX& b, VecX& gB, MatX* HB) const {
  const int d = dim_;
  const double gg = a.squaredNorm(), na = std::sqrt(gg);
  if (!(na > 0.0)) throw NumericalError("ancf_cable " + name() + ": zero slope r' at a Gauss point");
  const MatX Id = MatX::Identity(d, d);
  gB.resize(2 * d);
  if (d == 2) {
    // Per EI: 1/2 (kappa - kappa0)^2, kappa = c h, c = a x b, h = |a|^-3.
    const double h = 1.0 / (gg * na), c = a[0] * b[1] - a[1] * b[0], kappa = c * h, dk = kappa - P.kappa0;
    const Eigen::Vector2d ca(b[1], -b[0]), cb(-a[1], a[0]);     // dc/da, dc/db
    const Eigen::Vector2d hA = (-3.0 * h / gg) * Eigen::Vector2d(a);  // dh/da
    VecX gk(4);
    gk << h * ca + c * hA, h * cb;
    gB = dk * gk;
    if (HB) {
      Eigen::Matrix2d Hh = (-3.0 * h / gg) * Eigen::Matrix2d::Identity() +
                           (15.0 * h / (gg * gg)) * Eigen::Vector2d(a) * Eigen::Vector2d(a).transpose();
      Eigen::Matrix2d Cab;
      Cab << 0.0, 1.0, -1.0, 0.0;  // d2c/(da_i db_j)
      MatX Hk = MatX::Zero(4, 4);
      Hk.topLeftCorner(2, 2) = ca * hA.transpose() + hA * ca.transpose() + c * Hh;
      Hk.topRightCorner(2, 2) = h * Cab + hA * cb.transpose();
      Hk.bottomLeftCorner(2, 2) = Hk.topRightCorner(2, 2).transpose();
      *HB = gk * gk.transpose() + dk * Hk;
    }
  } else {
    // Per EI: 1/2 phi, phi = f u, f = |a|^2 |b|^2 - (a.b)^2 = |a x b|^2, u = |a|^-6.
    const double beta = b.squaredNorm(), gam = a.dot(b), u = 1.0 / (gg * gg * gg);
    const double f = gg * beta - gam * gam;
    const VecX fa = 2.0 * beta * a - 2.0 * gam * b, fb = 2.0 * gg * b - 2.0 * gam * a;
    const VecX ua = (-6.0 * u / gg) * a;
    gB.head(d) = 0.5 * (u * fa + f * ua);
    gB.tail(d) = 0.5 * u * fb;
    if (HB) {
      const MatX faa = 2.0 * beta * Id - 2.0 * b * b.transpose();
      const MatX fbb = 2.0 * gg * Id - 2.0 * a * a.transpose();
      const MatX fab = 4.0 * a * b.transpose() - 2.0 * b * a.transpose() - 2.0 * gam * Id;
      const MatX uaa = (-6.0 * u / gg) * Id + (48.0 * u / (gg * gg)) * a * a.transpose();
      HB->resize(6, 6);
      HB->topLeftCorner(3, 3) = 0.5 * (u * faa + fa * ua.transpose() + ua * fa.transpose() + f * uaa);
      HB->topRightCorner(3, 3) = 0.5 * (u * fab + ua * fb.transpose());
      HB->bottomLeftCorner(3, 3) = HB->topRightCorner(3, 3).transpose();
      HB->bottomRightCorner(3, 3) = 0.5 * u * fbb;
    }
  }
}

void AncfCable::elastic(const LocalState& s, VecX& QA, VecX& QB, MatX* KA, MatX* KB) const {
  if (s.dim != dim_ || !s.slopes) throw std::invalid_argument("ancf_cable " + name() + ": needs positions and slopes of dim " + std::to_string(dim_));
  const int d = dim_, n = 4 * d;
  QA.setZero(n);
  QB.setZero(n);
  if (KA) KA->setZero(n, n);
  if (KB) KB->setZero(n, n);
  MatX B = MatX::Zero(2 * d, n);  // (r', r'') = B e
  auto fill = [&](const Point& P) {
    for (int i = 0; i < 4; ++i) {
      B.block(0, i * d, d, d) = P.d1[i] * MatX::Identity(d, d);
      B.block(d, i * d, d, d) = P.d2[i] * MatX::Identity(d, d);
    }
    return VecX(B * s.x);
  };
  VecX g;
  MatX H;
  for (const Point& P : ptsA_) {
    const VecX ab = fill(P);
    axialTerms(P, ab.head(d), g, KA ? &H : nullptr);
    QA -= P.w * B.transpose() * g;
    if (KA) *KA -= P.w * B.transpose() * H * B;
  }
  for (const Point& P : ptsB_) {
    const VecX ab = fill(P);
    bendingTerms(P, ab.head(d), ab.tail(d), g, KB ? &H : nullptr);
    QB -= P.w * B.transpose() * g;
    if (KB) *KB -= P.w * B.transpose() * H * B;
  }
}

VecX AncfCable::gravityLoad(const LocalState& s, double rhoA) const {
  const int d = dim_;
  VecX Q = VecX::Zero(4 * d);
  if (!s.gravity) return Q;
  for (int i = 0; i < 4; ++i) Q.segment(i * d, d) = rhoA * (massShape_(i, 0) + massShape_(i, 2)) * *s.gravity;
  return Q;
}

void AncfCable::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  VecX QA, QB;
  MatX KA, KB;
  elastic(s, QA, QB, &KA, &KB);
  dQdq = sec_->EA(*s.p) * KA + sec_->EI(*s.p) * KB;
  dQdv.setZero(4 * dim_, 4 * dim_);
}

bool AncfCable::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  if (!sec_->axialDependsOn(k) && !sec_->bendingDependsOn(k)) return false;
  VecX QA, QB;
  elastic(s, QA, QB, nullptr, nullptr);
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
  if (s.dim != dim_ || !s.slopes) throw std::invalid_argument("ancf_cable " + name() + ": needs positions and slopes of dim " + std::to_string(dim_));
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
      const double kappa = (a[0] * b[1] - a[1] * b[0]) / (gg * std::sqrt(gg));
      wb = (kappa - P.kappa0) * (kappa - P.kappa0);
    } else {
      wb = Eigen::Vector3d(a).cross(Eigen::Vector3d(b)).squaredNorm() / (gg * gg * gg);
    }
    U += P.w * 0.5 * EI * wb;
  }
  // minus the work of gravity: -G^T M e, G = (g, 0, g, 0)  [J]
  return U - gravityLoad(s, sec_->rhoA(*s.p)).dot(s.x);
}

template class KernelElement<AncfCable>;

}  // namespace flexsens
