#include "elements/AncfBeam3D.hpp"

#include <array>
#include <cmath>

#include "elements/KernelElementAD.hpp"
#include "elements/SimplexShape.hpp"

namespace flexsens {

std::vector<std::pair<std::string, Quantity*>> AncfBeamSection::properties() {
  std::vector<std::pair<std::string, Quantity*>> r = {{"E", &E}, {"nu", &nu}, {"density", &density}};
  if (square) r.push_back({"side", &side});
  else {
    r.push_back({"width", &width});
    r.push_back({"height", &height});
  }
  return r;
}

namespace {

using V3 = Eigen::Vector3d;
using Vec8 = Eigen::Matrix<double, 8, 1>;
constexpr int kN = 24;  // local coordinates

/// Axial functions of the eight slots at xi (cubic Hermite on positions and r_x, 0 on r_y, r_z).
Vec8 axialShape(double xi, double L) {
  const double x2 = xi * xi, x3 = x2 * xi;
  Vec8 f = Vec8::Zero();
  f[0] = 1.0 - 3.0 * x2 + 2.0 * x3;
  f[1] = L * (xi - 2.0 * x2 + x3);
  f[4] = 3.0 * x2 - 2.0 * x3;
  f[5] = L * (x3 - x2);
  return f;
}

/// The x-independent part of d S_i / dx at xi (the y, z terms are added per point).
Vec8 axialSlope(double xi, double L) {
  const double x2 = xi * xi;
  Vec8 a = Vec8::Zero();
  a[0] = (-6.0 * xi + 6.0 * x2) / L;
  a[1] = 1.0 - 4.0 * xi + 3.0 * x2;
  a[4] = (6.0 * xi - 6.0 * x2) / L;
  a[5] = 3.0 * x2 - 2.0 * xi;
  return a;
}

/// d S_i / dx, dy, dz (a, b, c) at the point (xi, eta, zeta) of an element of length L and
/// section w x h [m]: the section terms of a and the linear-in-xi b, c on the gradient slots.
void pointSlopes(double xi, double eta, double zeta, double L, double w, double h, Vec8& a, Vec8& b, Vec8& c) {
  a = axialSlope(xi, L);
  a[2] = -w * eta / L;
  a[3] = -h * zeta / L;
  a[6] = -a[2];
  a[7] = -a[3];
  b.setZero();
  c.setZero();
  b[2] = c[3] = 1.0 - xi;
  b[6] = c[7] = xi;
}

/// Voigt strains (E_xx, E_yy, E_zz, 2 E_xy, 2 E_xz, 2 E_yz) of the columns Fx, Fy, Fz of J.
template <class V, class S>
void strains(const V& Fx, const V& Fy, const V& Fz, S eps[6]) {
  eps[0] = 0.5 * (Fx.squaredNorm() - 1.0);
  eps[1] = 0.5 * (Fy.squaredNorm() - 1.0);
  eps[2] = 0.5 * (Fz.squaredNorm() - 1.0);
  eps[3] = Fx.dot(Fy);
  eps[4] = Fx.dot(Fz);
  eps[5] = Fy.dot(Fz);
}

}  // namespace

AncfBeam3D::AncfBeam3D(std::string name, std::vector<int> nodes, std::shared_ptr<AncfBeamSection> section,
                       double L, int normalPoints, int shearPoints)
    : KernelElement(std::move(name), std::move(nodes)), sec_(std::move(section)), L_(L) {
  const std::string who = "ancf_beam " + this->name();
  if (this->nodes().size() != 2) throw std::invalid_argument(who + ": needs 2 nodes");
  if (!sec_) throw std::invalid_argument(who + ": no section");
  if (!(L_ > 0.0)) throw std::invalid_argument(who + ": zero length (its nodes coincide)");
  if (normalPoints < 1 || shearPoints < 1) throw std::invalid_argument(who + ": needs at least one Gauss point");
  // 2 x 2 Gauss across the section: eta, zeta = +-1/(2 sqrt 3) on [-1/2, 1/2], weight 1/4 each.
  const double c = 0.5 / std::sqrt(3.0);
  // One set of points for both strain groups when they share the rule (the default).
  using Group = std::array<int, 3>;  // points, k0, k1
  const std::vector<Group> groups = normalPoints == shearPoints ? std::vector<Group>{{normalPoints, 0, 6}}
                                                                : std::vector<Group>{{normalPoints, 0, 3}, {shearPoints, 3, 6}};
  for (const Group& gr : groups) {
    std::vector<double> xs, ws;
    gaussLegendre01(gr[0], xs, ws);
    for (int g = 0; g < gr[0]; ++g)
      for (double eta : {-c, c})
        for (double zeta : {-c, c}) pts_.push_back({xs[g], eta, zeta, 0.25 * ws[g], gr[1], gr[2]});
  }
  // Shape integrals (degree 6 in xi: 4 Gauss points are exact).
  std::vector<double> xs, ws;
  gaussLegendre01(4, xs, ws);
  mN_.setZero();
  mY_.setZero();
  mZ_.setZero();
  for (int g = 0; g < 4; ++g) {
    const Vec8 f = axialShape(xs[g], L_);
    Vec8 sec = Vec8::Zero();  // the section factor of r_y (slots 2, 6) or r_z (slots 3, 7)
    sec[2] = sec[3] = 1.0 - xs[g];
    sec[6] = sec[7] = xs[g];
    Vec8 y = Vec8::Zero(), z = Vec8::Zero();
    y[2] = sec[2];
    y[6] = sec[6];
    z[3] = sec[3];
    z[7] = sec[7];
    mN_ += (ws[g] * L_) * f * f.transpose();
    mY_ += (ws[g] * L_) * y * y.transpose();
    mZ_ += (ws[g] * L_) * z * z.transpose();
  }
}

void AncfBeam3D::checkState(const LocalState& s) const {
  if (s.dim != 3 || s.gradients != 3 || s.x.size() != kN)
    throw std::invalid_argument("ancf_beam " + name() + ": needs positions and three gradients of dim 3");
}

// ------------------------------------------------------------------ value templates
// props = (E, nu, density, width source, height source).
template <class T>
MatT<T> AncfBeam3D::massT(const LocalState&, const VecT<T>& props) const {
  const T rho = props[2], w = props[3], h = props[4];
  const T mA = rho * w * h, mY = rho * w * w * w * h / 12.0, mZ = rho * w * h * h * h / 12.0;  // [kg/m], [kg m]
  MatT<T> M = MatT<T>::Zero(kN, kN);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      const T mij = mA * mN_(i, j) + mY * mY_(i, j) + mZ * mZ_(i, j);
      for (int c = 0; c < 3; ++c) M(3 * i + c, 3 * j + c) = mij;
    }
  return M;
}

template <class T>
VecT<T> AncfBeam3D::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>&, const VecT<T>& props) const {
  checkState(s);
  using V3T = Eigen::Matrix<T, 3, 1>;
  const T E = props[0], G = E / (2.0 * (1.0 + props[1])), w = props[3], h = props[4];
  VecT<T> Q = VecT<T>::Zero(kN);
  if (s.gravity) {  // M u, u = (g, 0, 0, 0, g, 0, 0, 0): only M_N reaches the positions
    const T mA = props[2] * w * h;  // [kg/m]
    for (int i = 0; i < 8; ++i)
      for (int c = 0; c < 3; ++c) Q[3 * i + c] = mA * ((mN_(i, 0) + mN_(i, 4)) * (*s.gravity)[c]);
  }
  const T V = L_ * w * h;  // [m^3]
  for (const Point& P : pts_) {
    // d S_i / dx: a double on the axial slots, a T (it moves with w, h) on the section slots
    // 2, 3, 6, 7; AD constants meet active scalars only through double operations.
    const Vec8 a0 = axialSlope(P.xi, L_);
    const T yL = w * (P.eta / L_), zL = h * (P.zeta / L_);
    auto aSec = [&](int i) -> T { return i == 2 ? T(-yL) : i == 3 ? T(-zL) : i == 6 ? yL : zL; };
    Vec8 b = Vec8::Zero(), c = Vec8::Zero();
    b[2] = c[3] = 1.0 - P.xi;
    b[6] = c[7] = P.xi;
    auto e = [&](int i) -> V3T { return x.template segment<3>(3 * i); };
    V3T Fx = yL * (e(6) - e(2)) + zL * (e(7) - e(3)), Fy = b[2] * e(2) + b[6] * e(6), Fz = c[3] * e(3) + c[7] * e(7);
    for (int i : {0, 1, 4, 5}) Fx += a0[i] * e(i);
    T eps[6];
    strains(Fx, Fy, Fz, eps);
    const T W = V * P.w;
    // dU/de_i / W = sum_k sigma_k d eps_k / d e_i, sigma = E eps (normal) or G eps (shear)
    auto grad = [&](const auto& ai, int i) -> V3T {
      V3T g = V3T::Zero();
      if (P.k0 == 0) g += E * ((eps[0] * ai) * Fx + (eps[1] * b[i]) * Fy + (eps[2] * c[i]) * Fz);
      if (P.k1 == 6) g += G * (eps[3] * (ai * Fy + b[i] * Fx) + eps[4] * (ai * Fz + c[i] * Fx) + eps[5] * (b[i] * Fz + c[i] * Fy));
      return g;
    };
    for (int i = 0; i < 8; ++i) {
      const bool sec = i == 2 || i == 3 || i == 6 || i == 7;
      const V3T dU = sec ? grad(aSec(i), i) : grad(a0[i], i);
      Q.template segment<3>(3 * i) -= W * dU;
    }
  }
  return Q;
}

// ------------------------------------------------------------------ analytic derivatives
// Per point: Voigt strains eps_k with gradients d eps_k / d e_i = alpha_ki Fu + beta_ki Fv
// (rows B_k, 1 x 24) and second derivatives H_k(i, j) I_3 (constant in e). The stiffness of
// the point is -W mod_k (B_k^T B_k + eps_k H_k (x) I_3) summed over its active strains.
void AncfBeam3D::elastic(const LocalState& s, double E, double G, double w, double h, VecX* QN, VecX* QS,
                         MatX* K, double dw, double dh, VecX* dQg) const {
  checkState(s);
  const Eigen::Map<const Eigen::Matrix<double, 3, 8>> X(s.x.data());  // column i: e_i
  if (QN) QN->setZero(kN);
  if (QS) QS->setZero(kN);
  Eigen::Matrix<double, kN, kN> Kl;
  if (K) Kl.setZero();
  if (dQg) dQg->setZero(kN);
  const double V = L_ * w * h;
  for (const Point& P : pts_) {
    Vec8 a, b, c, da = Vec8::Zero();
    pointSlopes(P.xi, P.eta, P.zeta, L_, w, h, a, b, c);
    da[2] = -dw * P.eta / L_;
    da[3] = -dh * P.zeta / L_;
    da[6] = -da[2];
    da[7] = -da[3];
    const V3 Fx = X * a, Fy = X * b, Fz = X * c;
    double eps[6];
    strains(Fx, Fy, Fz, eps);
    const double W = V * P.w;
    for (int k = P.k0; k < P.k1; ++k) {
      const double mod = k < 3 ? E : G;
      VecX* Qk = k < 3 ? QN : QS;
      Eigen::Matrix<double, 1, kN> B;
      Vec8 p1, p2;  // d eps_k / d e_i = p1_i U + p2_i V
      const V3 *U, *Vv;
      switch (k) {
        case 0: p1 = a; p2.setZero(); U = &Fx; Vv = &Fx; break;
        case 1: p1 = b; p2.setZero(); U = &Fy; Vv = &Fy; break;
        case 2: p1 = c; p2.setZero(); U = &Fz; Vv = &Fz; break;
        case 3: p1 = a; p2 = b; U = &Fy; Vv = &Fx; break;
        case 4: p1 = a; p2 = c; U = &Fz; Vv = &Fx; break;
        default: p1 = b; p2 = c; U = &Fz; Vv = &Fy; break;
      }
      for (int i = 0; i < 8; ++i) B.template segment<3>(3 * i) = (p1[i] * *U + p2[i] * *Vv).transpose();
      if (Qk) *Qk -= (W * eps[k]) * B.transpose();
      if (K) {
        Kl.noalias() -= (mod * W) * B.transpose() * B;
        // H_k(i, j) = p1_i q1_j + ...: E_uu: p1 p1^T; shear: p1 p2^T + p2 p1^T
        const Eigen::Matrix<double, 8, 8> H =
            k < 3 ? Eigen::Matrix<double, 8, 8>(p1 * p1.transpose()) : Eigen::Matrix<double, 8, 8>(p1 * p2.transpose() + p2 * p1.transpose());
        const double f = mod * W * eps[k];
        for (int i = 0; i < 8; ++i)
          for (int j = 0; j < 8; ++j)
            if (H(i, j) != 0.0) Kl.template block<3, 3>(3 * i, 3 * j).diagonal().array() -= f * H(i, j);
      }
      if (dQg && (dw != 0.0 || dh != 0.0)) {
        // Along (dw, dh): the weight W and the y, z terms of a change; only the strains with
        // Fx (k = 0, 3, 4) move: d Fx = X da.
        const double dW = W * (dw / w + dh / h);
        const V3 dFx = X * da;
        double deps = 0.0;
        Eigen::Matrix<double, 1, kN> dB = Eigen::Matrix<double, 1, kN>::Zero();
        if (k == 0) {
          deps = Fx.dot(dFx);
          for (int i = 0; i < 8; ++i) dB.template segment<3>(3 * i) = (da[i] * Fx + a[i] * dFx).transpose();
        } else if (k == 3 || k == 4) {
          const V3& Fo = k == 3 ? Fy : Fz;
          const Vec8& po = k == 3 ? b : c;
          deps = dFx.dot(Fo);
          for (int i = 0; i < 8; ++i) dB.template segment<3>(3 * i) = (da[i] * Fo + po[i] * dFx).transpose();
        }
        *dQg -= mod * ((dW * eps[k] + W * deps) * B.transpose() + (W * eps[k]) * dB.transpose());
      }
    }
  }
  if (K) *K = Kl;
}

double AncfBeam3D::elasticEnergy(const LocalState& s, double E, double G, double w, double h) const {
  checkState(s);
  const Eigen::Map<const Eigen::Matrix<double, 3, 8>> X(s.x.data());
  double U = 0.0;
  for (const Point& P : pts_) {
    Vec8 a, b, c;
    pointSlopes(P.xi, P.eta, P.zeta, L_, w, h, a, b, c);
    double eps[6];
    strains(V3(X * a), V3(X * b), V3(X * c), eps);
    for (int k = P.k0; k < P.k1; ++k) U += 0.5 * (k < 3 ? E : G) * L_ * w * h * P.w * eps[k] * eps[k];
  }
  return U;
}

MatX AncfBeam3D::massMatrix(double rho, double w, double h) const {
  VecX props(5);
  props << 0.0, 0.0, rho, w, h;
  return massT<double>(LocalState(), props);
}

VecX AncfBeam3D::gravityLoad(const LocalState& s, const MatX& M) const {
  if (!s.gravity) return VecX::Zero(kN);
  VecX u = VecX::Zero(kN);
  u.segment<3>(0) = *s.gravity;
  u.segment<3>(12) = *s.gravity;
  return M * u;
}

void AncfBeam3D::force(const LocalState& s, VecX& Q) const {
  const VecX& p = *s.p;
  const double E = sec_->E.value(p), nu = sec_->nu.value(p);
  const double w = sec_->widthSource().value(p), h = sec_->heightSource().value(p);
  VecX QN, QS;
  elastic(s, E, 0.0, w, h, &QN, &QS, nullptr, 0.0, 0.0, nullptr);
  Q = E * QN + E / (2.0 * (1.0 + nu)) * QS + gravityLoad(s, massMatrix(sec_->density.value(p), w, h));
}

void AncfBeam3D::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  const VecX& p = *s.p;
  const double E = sec_->E.value(p), nu = sec_->nu.value(p);
  elastic(s, E, E / (2.0 * (1.0 + nu)), sec_->widthSource().value(p), sec_->heightSource().value(p), nullptr,
          nullptr, &dQdq, 0.0, 0.0, nullptr);
  dQdv.setZero(kN, kN);
}

bool AncfBeam3D::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  const bool bE = sec_->E.boundTo(k), bNu = sec_->nu.boundTo(k), bRho = sec_->density.boundTo(k);
  const double dw = sec_->widthSource().boundTo(k) ? 1.0 : 0.0, dh = sec_->heightSource().boundTo(k) ? 1.0 : 0.0;
  if (!bE && !bNu && !bRho && dw == 0.0 && dh == 0.0) return false;
  const VecX& p = *s.p;
  const double E = sec_->E.value(p), nu = sec_->nu.value(p), rho = sec_->density.value(p);
  const double w = sec_->widthSource().value(p), h = sec_->heightSource().value(p);
  const double G = E / (2.0 * (1.0 + nu));
  VecX QN, QS, dQg;
  elastic(s, E, G, w, h, &QN, &QS, nullptr, dw, dh, &dQg);
  dQ = VecX::Zero(kN);
  dM = MatX::Zero(kN, kN);
  if (bE) dQ += QN + QS / (2.0 * (1.0 + nu));
  if (bNu) dQ -= (E / (2.0 * (1.0 + nu) * (1.0 + nu))) * QS;
  if (bRho) dM += massMatrix(1.0, w, h);
  if (dw != 0.0 || dh != 0.0) {
    dQ += dQg;
    // d(rho (A M_N + w^3 h / 12 M_Y + w h^3 / 12 M_Z)) along (dw, dh)
    const double dA = dw * h + w * dh;
    const double dIy = (3.0 * w * w * h * dw + w * w * w * dh) / 12.0;
    const double dIz = (h * h * h * dw + 3.0 * w * h * h * dh) / 12.0;
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j) {
        const double mij = rho * (dA * mN_(i, j) + dIy * mY_(i, j) + dIz * mZ_(i, j));
        for (int c = 0; c < 3; ++c) dM(3 * i + c, 3 * j + c) += mij;
      }
  }
  dQ += gravityLoad(s, dM);
  return true;
}

double AncfBeam3D::potential(const LocalState& s) const {
  const VecX& p = *s.p;
  const double E = sec_->E.value(p), nu = sec_->nu.value(p);
  const double w = sec_->widthSource().value(p), h = sec_->heightSource().value(p);
  // minus the work of gravity: -G^T M e [J]
  return elasticEnergy(s, E, E / (2.0 * (1.0 + nu)), w, h) -
         gravityLoad(s, massMatrix(sec_->density.value(p), w, h)).dot(s.x);
}

template class KernelElement<AncfBeam3D>;

}  // namespace flexsens
