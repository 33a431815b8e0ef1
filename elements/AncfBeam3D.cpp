#include "elements/AncfBeam3D.hpp"

#include <array>
#include <cmath>
#include <sstream>

#include "elements/KernelElementAD.hpp"
#include "elements/SimplexShape.hpp"

namespace flexsens {

std::vector<std::pair<std::string, Quantity*>> AncfBeamSection::properties() {
  std::vector<std::pair<std::string, Quantity*>> r = {{"E", &E}, {"nu", &nu}, {"density", &density}};
  if (general) return r;
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

using Mat83 = Eigen::Matrix<double, 8, 3>;

/// The Voigt strains (E_xx, E_yy, E_zz, 2 E_xy, 2 E_xz, 2 E_yz) pair the columns u, v of J B.
constexpr int kU[6] = {0, 1, 2, 0, 0, 1}, kV[6] = {0, 1, 2, 1, 2, 2};
/// Strain per dot product of the columns: 1/2 on the normal strains, 1 on the shear strains.
constexpr double kHalf[6] = {0.5, 0.5, 0.5, 1.0, 1.0, 1.0};

/// dS_i/dX of the eight slots at the point (xi, eta, zeta) split as S0 + w Sy + h Sz: the
/// axial slopes and the section factors (1 - xi, xi) of r_y, r_z in S0, the x-slopes of the
/// section terms y r_y, z r_z (y = w eta, z = h zeta) in Sy, Sz.
void parameterSlopes(double xi, double eta, double zeta, double L, Mat83& S0, Mat83& Sy, Mat83& Sz) {
  S0.setZero();
  Sy.setZero();
  Sz.setZero();
  S0.col(0) = axialSlope(xi, L);
  S0(2, 1) = S0(3, 2) = 1.0 - xi;
  S0(6, 1) = S0(7, 2) = xi;
  Sy(2, 0) = -eta / L;
  Sy(6, 0) = eta / L;
  Sz(3, 0) = -zeta / L;
  Sz(7, 0) = zeta / L;
}

/// Adds a point's stiffness for one strain: -(kBB Bk^T Bk + kH H (x) I_3), with the strain's
/// Hessian H = p1 p1^T (normal) or p1 p2^T + p2 p1^T (shear), constant in e.
void addPointStiffness(Eigen::Matrix<double, kN, kN>& K, const Eigen::Matrix<double, 1, kN>& Bk, const Vec8& p1,
                       const Vec8& p2, bool normal, double kBB, double kH) {
  K.noalias() -= kBB * Bk.transpose() * Bk;
  const Eigen::Matrix<double, 8, 8> H = normal ? Eigen::Matrix<double, 8, 8>(p1 * p1.transpose())
                                               : Eigen::Matrix<double, 8, 8>(p1 * p2.transpose() + p2 * p1.transpose());
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      if (H(i, j) != 0.0) K.template block<3, 3>(3 * i, 3 * j).diagonal().array() -= kH * H(i, j);
}

}  // namespace

AncfBeam3D::AncfBeam3D(std::string name, std::vector<int> nodes, std::shared_ptr<AncfBeamSection> section,
                       double L, int normalPoints, int shearPoints, const VecX* rest)
    : KernelElement(std::move(name), std::move(nodes)), sec_(std::move(section)), L_(L), curved_(rest != nullptr) {
  const std::string who = "ancf_beam " + this->name();
  if (this->nodes().size() != 2) throw std::invalid_argument(who + ": needs 2 nodes");
  if (!sec_) throw std::invalid_argument(who + ": no section");
  if (!(L_ > 0.0)) throw std::invalid_argument(who + ": zero length (its nodes coincide)");
  if (normalPoints < 1 || shearPoints < 1) throw std::invalid_argument(who + ": needs at least one Gauss point");
  if (rest) {
    if (rest->size() != kN) throw std::invalid_argument(who + ": rest coordinates need 24 entries");
    rest_ = Eigen::Map<const Eigen::Matrix<double, 3, 8>>(rest->data());
  }
  // Axial and transverse shear strains (E_xx; E_xy, E_xz): Gauss along the axis, 2 x 2 Gauss
  // across the section (eta, zeta = +-1/(2 sqrt 3) on [-1/2, 1/2], weight 1/4 each); one set of
  // points when both rules agree (the default).
  const double c = 0.5 / std::sqrt(3.0);
  struct Group {
    int points, strains;  // Gauss points along the axis, the strains' bits (1 << k)
    double reach;         // section points at reach x (eta, zeta): the torsion scale for the shear
  };
  const int axial = 1 << 0, shear = (1 << 3) | (1 << 4);
  const double s = sec_->torsionScale;
  const std::vector<Group> groups = normalPoints == shearPoints && s == 1.0
                                        ? std::vector<Group>{{normalPoints, axial | shear, 1.0}}
                                        : std::vector<Group>{{normalPoints, axial, 1.0}, {shearPoints, shear, s}};
  for (const Group& gr : groups) {
    std::vector<double> xs, ws;
    gaussLegendre01(gr.points, xs, ws);
    for (int g = 0; g < gr.points; ++g)
      for (double eta : {-c, c})
        for (double zeta : {-c, c}) addPoint({xs[g], gr.reach * eta, gr.reach * zeta, 0.25 * ws[g], gr.strains});
  }
  // The section's own strains (E_yy, E_zz, E_yz) at the two nodes on the axis (trapezoidal rule),
  // where r_y, r_z are the nodal gradients themselves: between the nodes their linear
  // interpolation shortens and shears a section that turns by dphi by O(dphi^2), which at
  // Gauss points inside would stiffen bending by large rotations and curved elements (the
  // Bathe-Bolourchi bend: tip 11% off in 8 elements, 0.66% so; bench/beams). With B = I they are constant
  // across the section, so one point on the axis integrates them.
  const int sectionStrains = (1 << 1) | (1 << 2) | (1 << 5);
  for (double xi : {0.0, 1.0}) addPoint({xi, 0.0, 0.0, 0.5, sectionStrains});
  // Shape integrals (degree 6 in xi: 4 Gauss points are exact).
  std::vector<double> xs, ws;
  gaussLegendre01(4, xs, ws);
  mN_.setZero();
  mY_.setZero();
  mZ_.setZero();
  for (int g = 0; g < 4; ++g) {
    Point axis{xs[g], 0.0, 0.0, 1.0, 0};
    setRestFrame(axis);
    const double wL = ws[g] * L_ * axis.detJ0;  // rest length of the Gauss interval [m]
    const Vec8 f = axialShape(xs[g], L_);
    Vec8 sec = Vec8::Zero();  // the section factor of r_y (slots 2, 6) or r_z (slots 3, 7)
    sec[2] = sec[3] = 1.0 - xs[g];
    sec[6] = sec[7] = xs[g];
    Vec8 y = Vec8::Zero(), z = Vec8::Zero();
    y[2] = sec[2];
    y[6] = sec[6];
    z[3] = sec[3];
    z[7] = sec[7];
    mN_ += wL * f * f.transpose();
    mY_ += wL * y * y.transpose();
    mZ_ += wL * z * z.transpose();
  }
}

void AncfBeam3D::addPoint(Point P) {
  setRestFrame(P);
  pts_.push_back(P);
}

void AncfBeam3D::setRestFrame(Point& P) const {
  Mat83 S0, Sy, Sz;
  parameterSlopes(P.xi, P.eta, P.zeta, L_, S0, Sy, Sz);
  Eigen::Matrix3d B = Eigen::Matrix3d::Identity();
  if (curved_) {
    const Eigen::Matrix3d J0 = rest_ * S0;  // at the axis: the y, z terms vanish
    P.detJ0 = J0.determinant();
    if (!(P.detJ0 > 1e-12 * std::pow(J0.norm(), 3))) {
      std::ostringstream os;
      os << "ancf_beam " << name() << ": its rest shape folds over at xi = " << P.xi << " (det dr0/dX = " << P.detJ0
         << "): the rest axis turns back or the gradients (r_x, r_y, r_z) are not a right-handed frame there";
      throw std::invalid_argument(os.str());
    }
    Eigen::Matrix3d R0;  // the beam's axes: J0's columns made orthonormal, r_x first
    R0.col(0) = J0.col(0).normalized();
    R0.col(1) = (J0.col(1) - J0.col(1).dot(R0.col(0)) * R0.col(0)).normalized();
    R0.col(2) = R0.col(0).cross(R0.col(1));
    B = J0.inverse() * R0;
  }
  P.S0 = S0 * B;
  P.Sy = Sy * B;
  P.Sz = Sz * B;
}

void AncfBeam3D::slopes(const Point& P, double w, double h, double dw, double dh, Mat83& S, Mat83& dS) {
  S = P.S0 + w * P.Sy + h * P.Sz;
  dS = dw * P.Sy + dh * P.Sz;
}

void AncfBeam3D::restMetric(const Mat83& S, const Mat83& dS, Eigen::Matrix3d& C0, Eigen::Matrix3d& dC0) const {
  if (!curved_) {
    C0.setIdentity();
    dC0.setZero();
    return;
  }
  const Eigen::Matrix3d F0 = rest_ * S, dF0 = rest_ * dS;
  C0 = F0.transpose() * F0;
  dC0 = dF0.transpose() * F0 + F0.transpose() * dF0;
}

double AncfBeam3D::restLength(const VecX& rest) {
  const Eigen::Map<const Eigen::Matrix<double, 3, 8>> X(rest.data());
  std::vector<double> xs, ws;
  gaussLegendre01(8, xs, ws);
  double L = (X.col(4) - X.col(0)).norm();
  // Fixed point L = arc length of the axis drawn with end tangents L r_x (contracts fast: the
  // arc length moves with the tangents' length only at second order for a smooth arc).
  for (int it = 0; it < 100; ++it) {
    double arc = 0.0;
    for (size_t g = 0; g < xs.size(); ++g) arc += ws[g] * L * (X * axialSlope(xs[g], L)).norm();
    const bool done = std::abs(arc - L) <= 1e-15 * L;
    L = arc;
    if (done) break;
  }
  return L;
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
  // [kg/m], [kg m]; a given rotary inertia enters as an active zero plus the constant
  const double a = sec_->areaScale;
  const T mA = rho * w * h * a;
  const T mY = sec_->rotaryZ >= 0.0 ? T(rho * 0.0 + sec_->rotaryZ) : T(rho * w * w * w * h * (a / 12.0));
  const T mZ = sec_->rotaryY >= 0.0 ? T(rho * 0.0 + sec_->rotaryY) : T(rho * w * h * h * h * (a / 12.0));
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
    const T mA = props[2] * w * h * sec_->areaScale;  // [kg/m]
    for (int i = 0; i < 8; ++i)
      for (int c = 0; c < 3; ++c) Q[3 * i + c] = mA * ((mN_(i, 0) + mN_(i, 4)) * (*s.gravity)[c]);
  }
  const T V = L_ * w * h * sec_->areaScale;  // [m^3]
  auto e = [&](int i) -> V3T { return x.template segment<3>(3 * i); };
  for (const Point& P : pts_) {
    // S(i, u) = S0 + w Sy + h Sz: AD constants meet active scalars only through double operations.
    T S[8][3];
    for (int i = 0; i < 8; ++i)
      for (int u = 0; u < 3; ++u) S[i][u] = w * P.Sy(i, u) + h * P.Sz(i, u) + P.S0(i, u);
    V3T F[3];  // the columns of J B
    for (int u = 0; u < 3; ++u) {
      F[u] = S[0][u] * e(0);
      for (int i = 1; i < 8; ++i) F[u] += S[i][u] * e(i);
    }
    T eps[6];
    for (int k = 0; k < 6; ++k) eps[k] = kHalf[k] * F[kU[k]].dot(F[kV[k]]);
    if (curved_) {  // minus the rest metric (J0 B)^T (J0 B)
      V3T F0[3];
      for (int u = 0; u < 3; ++u)
        for (int c = 0; c < 3; ++c) {
          F0[u][c] = rest_(c, 0) * S[0][u];
          for (int i = 1; i < 8; ++i) F0[u][c] += rest_(c, i) * S[i][u];
        }
      for (int k = 0; k < 6; ++k) eps[k] -= kHalf[k] * F0[kU[k]].dot(F0[kV[k]]);
    } else {
      for (int k = 0; k < 3; ++k) eps[k] -= 0.5;
    }
    const T W = V * (P.w * P.detJ0);
    // dU/de_i / W = sum_k sigma_k d eps_k / d e_i, sigma = E eps (normal) or G eps (shear),
    // d eps_k / d e_i = S(i, u) F_v + S(i, v) F_u (half of it for u = v)
    for (int i = 0; i < 8; ++i) {
      V3T g = V3T::Zero();
      for (int k = 0; k < 6; ++k) {
        if (!P.has(k)) continue;
        const int u = kU[k], v = kV[k];
        const V3T d = k < 3 ? V3T(S[i][u] * F[u]) : V3T(S[i][u] * F[v] + S[i][v] * F[u]);
        g += ((k < 3 ? E : G) * eps[k]) * d;
      }
      Q.template segment<3>(3 * i) -= W * g;
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
  const double V = L_ * w * h * sec_->areaScale;
  for (const Point& P : pts_) {
    Mat83 S, dS;
    slopes(P, w, h, dw, dh, S, dS);
    Eigen::Matrix3d C0, dC0;
    restMetric(S, dS, C0, dC0);
    const Eigen::Matrix3d F = X * S, dF = X * dS;  // the columns of J B and their change along (dw, dh)
    const double W = V * P.w * P.detJ0;
    for (int k = 0; k < 6; ++k) {
      if (!P.has(k)) continue;
      const int u = kU[k], v = kV[k];
      const double mod = k < 3 ? E : G;
      const double eps = kHalf[k] * (F.col(u).dot(F.col(v)) - C0(u, v));
      VecX* Qk = k < 3 ? QN : QS;
      // d eps_k / d e_i = p1_i U + p2_i Vv: S(i, u) F_u (normal), S(i, u) F_v + S(i, v) F_u (shear)
      const Vec8 p1 = S.col(u), p2 = k < 3 ? Vec8(Vec8::Zero()) : Vec8(S.col(v));
      const V3 U = k < 3 ? V3(F.col(u)) : V3(F.col(v)), Vv = F.col(u);
      Eigen::Matrix<double, 1, kN> Bk;
      for (int i = 0; i < 8; ++i) Bk.template segment<3>(3 * i) = (p1[i] * U + p2[i] * Vv).transpose();
      if (Qk) *Qk -= (W * eps) * Bk.transpose();
      if (K) addPointStiffness(Kl, Bk, p1, p2, k < 3, mod * W, mod * W * eps);
      if (dQg && (dw != 0.0 || dh != 0.0)) {
        // Along (dw, dh): the weight W, the x-slopes of the section terms and the rest metric move.
        const double dW = W * (dw / w + dh / h);
        const double deps = kHalf[k] * (dF.col(u).dot(F.col(v)) + F.col(u).dot(dF.col(v)) - dC0(u, v));
        const Vec8 dp1 = dS.col(u), dp2 = k < 3 ? Vec8(Vec8::Zero()) : Vec8(dS.col(v));
        const V3 dU = k < 3 ? V3(dF.col(u)) : V3(dF.col(v)), dVv = dF.col(u);
        Eigen::Matrix<double, 1, kN> dB;
        for (int i = 0; i < 8; ++i)
          dB.template segment<3>(3 * i) = (dp1[i] * U + p1[i] * dU + dp2[i] * Vv + p2[i] * dVv).transpose();
        *dQg -= mod * ((dW * eps + W * deps) * Bk.transpose() + (W * eps) * dB.transpose());
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
    Mat83 S, dS;
    slopes(P, w, h, 0.0, 0.0, S, dS);
    Eigen::Matrix3d C0, dC0;
    restMetric(S, dS, C0, dC0);
    const Eigen::Matrix3d F = X * S;
    for (int k = 0; k < 6; ++k) {
      if (!P.has(k)) continue;
      const double eps = kHalf[k] * (F.col(kU[k]).dot(F.col(kV[k])) - C0(kU[k], kV[k]));
      U += 0.5 * (k < 3 ? E : G) * L_ * w * h * sec_->areaScale * P.w * P.detJ0 * eps * eps;
    }
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
  // M is affine in the density (a given rotary inertia is its constant part): dM/drho = M(1) - M(0)
  if (bRho) dM += massMatrix(1.0, w, h) - massMatrix(0.0, w, h);
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
