#include "elements/ShellKirchhoff.hpp"

#include <cmath>

#include "elements/KernelElementAD.hpp"
#include "elements/SimplexShape.hpp"  // fmtNumber

namespace flexsens {

namespace {
using Ad9 = Eigen::AutoDiffScalar<Eigen::Matrix<double, 9, 1>>;
using Ad9x2 = Eigen::AutoDiffScalar<Eigen::Matrix<Ad9, 9, 1>>;
template <class T> using V3 = Eigen::Matrix<T, 3, 1>;

/// The unit normal of the triangle x0, x1, x2 (the first 9 entries of x) and |(x1-x0) x (x2-x0)|.
template <class T, class Vec>
V3<T> unitNormal(const Vec& x, T& twiceArea) {
  using std::sqrt;
  const V3<T> x0(x[0], x[1], x[2]), e1 = V3<T>(x[3], x[4], x[5]) - x0, e2 = V3<T>(x[6], x[7], x[8]) - x0;
  const V3<T> u = e1.cross(e2);
  twiceArea = sqrt(u.dot(u));
  return u / twiceArea;
}
}  // namespace

ShellKirchhoffBending::ShellKirchhoffBending(std::string name, std::vector<int> nodes,
                                             std::shared_ptr<ShellProperties> props, const VecX& restX,
                                             std::array<KirchhoffEdge, 3> edges, bool flatRest)
    : KernelElement(std::move(name), std::move(nodes)), props_(std::move(props)), edges_(std::move(edges)) {
  const std::string who = "shell kirchhoff triangle " + this->name();
  if (!props_) throw std::invalid_argument(who + ": no material");
  N_ = static_cast<int>(this->nodes().size());
  if (N_ < 3 || restX.size() != 3 * N_) throw std::invalid_argument(who + ": needs 3 positions per stencil node");
  for (const auto& e : edges_)
    if (e.kind == KirchhoffEdge::Kind::Shared && e.coeff.size() != N_)
      throw std::invalid_argument(who + ": an edge's coefficients do not match the stencil");
  std::array<Eigen::Vector3d, 3> X;
  for (int k = 0; k < 3; ++k) X[k] = restX.segment<3>(3 * k);
  const Eigen::Vector3d u = (X[1] - X[0]).cross(X[2] - X[0]);
  const double h = std::max({(X[1] - X[0]).norm(), (X[2] - X[1]).norm(), (X[0] - X[2]).norm()});
  A_ = 0.5 * u.norm();
  if (!(A_ > 1e-10 * h * h))
    throw std::invalid_argument(who + ": degenerate (rest area " + fmtNumber(A_) + " m^2 for a longest edge of " +
                                fmtNumber(h) + " m; expected a positive area)");
  n0_ = u.normalized();
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d e = X[(i + 2) % 3] - X[(i + 1) % 3];
    length_[i] = e.norm();
    nu0_[i] = e.cross(n0_).normalized();  // counterclockwise about n0: outward
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      L_(i, j) = length_[i] * length_[j] / A_;
      G_(i, j) = L_(i, j) * std::pow(nu0_[i].dot(nu0_[j]), 2);
    }
  basis_.col(0) = (X[1] - X[0]).normalized();
  basis_.col(1) = n0_.cross(basis_.col(0));
  Eigen::Vector3d n;
  std::array<Eigen::Vector3d, 3> d;
  slopes<double>(restX, n, d, y0_);
  if (flatRest) y0_.setZero();
}

void ShellKirchhoffBending::checkDim(const LocalState& s) const {
  if (s.dim != 3 || s.x.size() != 3 * N_)
    throw std::invalid_argument("shell kirchhoff triangle " + name() + ": spatial only (dim must be 3)");
}

template <class T>
void ShellKirchhoffBending::slopes(const VecT<T>& x, V3<T>& n, std::array<V3<T>, 3>& d, V3<T>& y) const {
  T twiceArea;
  n = unitNormal<T>(x, twiceArea);
  if (!(ad::valueOf(twiceArea) > 1e-12 * A_))
    throw NumericalError("shell kirchhoff triangle " + name() +
                         ": the triangle has zero area (its normal, and so its curvature, is undefined)");
  for (int i = 0; i < 3; ++i) {
    d[i].setZero();
    if (edges_[i].kind == KirchhoffEdge::Kind::Shared) {
      for (int a = 0; a < N_; ++a)
        if (edges_[i].coeff[a] != 0.0) d[i] += edges_[i].coeff[a] * V3<T>(x.template segment<3>(3 * a));
    } else if (edges_[i].kind == KirchhoffEdge::Kind::Fixed) {
      d[i] = edges_[i].fixed.cast<T>();
    }
    y[i] = edges_[i].kind == KirchhoffEdge::Kind::Free ? T(0.0) : T(n.dot(d[i]));
  }
}

template <class T>
T ShellKirchhoffBending::rotation(int i, const V3<T>& n, V3<T>* dPhi) const {
  using std::atan2;
  const T a = -n.dot(nu0_[i].cast<T>()), c = n.dot(n0_.cast<T>());
  if (dPhi) *dPhi = (c * (-nu0_[i].cast<T>()) - a * n0_.cast<T>()) / (a * a + c * c);
  return atan2(a, c);
}

template <class T>
void ShellKirchhoffBending::condensed(const T& D, const T& nu, Eigen::Matrix<T, 3, 3>& Ke,
                                      Eigen::Matrix<T, 3, 1>& be) const {
  Eigen::Matrix<T, 3, 3> K;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) K(i, j) = D * ((1.0 - nu) * G_(i, j) + nu * L_(i, j));
  std::vector<int> F, Z;
  for (int i = 0; i < 3; ++i) (edges_[i].kind == KirchhoffEdge::Kind::Free ? F : Z).push_back(i);
  Ke.setZero();
  be.setZero();
  if (F.empty()) {
    Ke = K;
    return;
  }
  if (F.size() == 3) return;
  // K_FF^-1 by hand (1 x 1 or 2 x 2) so that any scalar type works
  Eigen::Matrix<T, 2, 2> inv = Eigen::Matrix<T, 2, 2>::Zero();
  if (F.size() == 1) {
    inv(0, 0) = 1.0 / K(F[0], F[0]);
  } else {
    const T det = K(F[0], F[0]) * K(F[1], F[1]) - K(F[0], F[1]) * K(F[1], F[0]);
    inv << K(F[1], F[1]) / det, -K(F[0], F[1]) / det, -K(F[1], F[0]) / det, K(F[0], F[0]) / det;
  }
  const int nf = static_cast<int>(F.size());
  for (int i : Z) {
    for (int j : Z) {
      T sum = K(i, j);
      for (int p = 0; p < nf; ++p)
        for (int q = 0; q < nf; ++q) sum -= K(i, F[p]) * inv(p, q) * K(F[q], j);
      Ke(i, j) = sum;
    }
    for (int p = 0; p < nf; ++p)
      for (int q = 0; q < nf; ++q) be[i] -= K(i, F[p]) * inv(p, q) * (edges_[F[q]].moment * length_[F[q]]);
  }
}

// props = (E, nu, thickness). Q = -dU/dx: through n, (dn/dx)^T r with r = sum_i s_i d_i -
// sum_free b_i dphi_i/dn, s = Ke Dy - be; through d_i, (sum_i s_i C_ia) n on node a.
template <class T>
VecT<T> ShellKirchhoffBending::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>&, const VecT<T>& props) const {
  checkDim(s);
  const T D = shell::bendingStiffness(props[0], props[1], props[2]);
  Eigen::Matrix<T, 3, 3> Ke;
  V3<T> be, n, y;
  condensed<T>(D, props[1], Ke, be);
  std::array<V3<T>, 3> d;
  slopes<T>(x, n, d, y);
  const V3<T> sv = Ke * (y - y0_.cast<T>()) - be;
  V3<T> r = V3<T>::Zero();
  for (int i = 0; i < 3; ++i) {
    if (edges_[i].kind != KirchhoffEdge::Kind::Free) r += sv[i] * d[i];
    else if (edges_[i].moment != 0.0) {
      V3<T> dPhi;
      rotation<T>(i, n, &dPhi);
      r -= (edges_[i].moment * length_[i]) * dPhi;
    }
  }
  T twiceArea;
  unitNormal<T>(x, twiceArea);
  const V3<T> x0 = x.template segment<3>(0), e1 = V3<T>(x.template segment<3>(3)) - x0, e2 = V3<T>(x.template segment<3>(6)) - x0;
  const V3<T> Pr = (r - n * n.dot(r)) / twiceArea;
  const V3<T> g1 = e2.cross(Pr), g2 = Pr.cross(e1);
  VecT<T> Q = VecT<T>::Zero(3 * N_);
  Q.template segment<3>(0) += g1 + g2;
  Q.template segment<3>(3) -= g1;
  Q.template segment<3>(6) -= g2;
  for (int i = 0; i < 3; ++i) {
    if (edges_[i].kind != KirchhoffEdge::Kind::Shared) continue;
    for (int a = 0; a < N_; ++a)
      if (edges_[i].coeff[a] != 0.0) Q.template segment<3>(3 * a) -= (sv[i] * edges_[i].coeff[a]) * n;
  }
  return Q;
}

double ShellKirchhoffBending::potential(const LocalState& s) const {
  checkDim(s);
  const VecX& p = *s.p;
  const double D = shell::bendingStiffness(props_->E.value(p), props_->nu.value(p), props_->thickness.value(p));
  Eigen::Matrix3d Ke;
  Eigen::Vector3d be, n, y;
  condensed<double>(D, props_->nu.value(p), Ke, be);
  std::array<Eigen::Vector3d, 3> d;
  slopes<double>(s.x, n, d, y);
  const Eigen::Vector3d dy = y - y0_;
  double U = 0.5 * dy.dot(Ke * dy) - be.dot(dy);
  for (int i = 0; i < 3; ++i)
    if (edges_[i].kind == KirchhoffEdge::Kind::Free && edges_[i].moment != 0.0)
      U -= edges_[i].moment * length_[i] * rotation<double>(i, n, nullptr);
  return U;  // [J]
}

Eigen::Matrix2d ShellKirchhoffBending::curvatureChange(const LocalState& s) const {
  checkDim(s);
  const VecX& p = *s.p;
  const double nu = props_->nu.value(p);
  const double D = shell::bendingStiffness(props_->E.value(p), nu, props_->thickness.value(p));
  Eigen::Matrix3d Ke, K;
  Eigen::Vector3d be, n, y;
  condensed<double>(D, nu, Ke, be);
  std::array<Eigen::Vector3d, 3> d;
  slopes<double>(s.x, n, d, y);
  Eigen::Vector3d dy = y - y0_;
  // the free slopes at the minimum: K_FF dy_F = b_F - K_FZ dy_Z
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) K(i, j) = D * ((1.0 - nu) * G_(i, j) + nu * L_(i, j));
  std::vector<int> F;
  for (int i = 0; i < 3; ++i)
    if (edges_[i].kind == KirchhoffEdge::Kind::Free) F.push_back(i);
  if (!F.empty() && F.size() < 3) {
    const int nf = static_cast<int>(F.size());
    Eigen::MatrixXd KFF(nf, nf);
    Eigen::VectorXd rhs(nf);
    for (int p2 = 0; p2 < nf; ++p2) {
      rhs[p2] = edges_[F[p2]].moment * length_[F[p2]];
      for (int j = 0; j < 3; ++j)
        if (edges_[j].kind != KirchhoffEdge::Kind::Free) rhs[p2] -= K(F[p2], j) * dy[j];
      for (int q = 0; q < nf; ++q) KFF(p2, q) = K(F[p2], F[q]);
    }
    const Eigen::VectorXd sol = KFF.ldlt().solve(rhs);
    for (int p2 = 0; p2 < nf; ++p2) dy[F[p2]] = sol[p2];
  }
  Eigen::Matrix2d kappa = Eigen::Matrix2d::Zero();
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d v = basis_.transpose() * nu0_[i];
    kappa += (length_[i] / A_) * dy[i] * v * v.transpose();
  }
  return kappa;
}

// dQ/dx = -J^T Ke J - H_psi - [(dn/dx_k)^T c_a and its transpose], J the rows grad y_i,
// psi(x0, x1, x2) = n . w - sum_free b_i phi_i at fixed w = sum_i s_i d_i, c_a = sum_i s_i C_ia.
void ShellKirchhoffBending::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  checkDim(s);
  const VecX& p = *s.p;
  const double nu = props_->nu.value(p);
  const double D = shell::bendingStiffness(props_->E.value(p), nu, props_->thickness.value(p));
  Eigen::Matrix3d Ke;
  Eigen::Vector3d be, n, y;
  condensed<double>(D, nu, Ke, be);
  std::array<Eigen::Vector3d, 3> d;
  slopes<double>(s.x, n, d, y);
  const Eigen::Vector3d sv = Ke * (y - y0_) - be;
  const int m = 3 * N_;
  // dn/dx_k (3 x 3 each)
  const Eigen::Vector3d x0 = s.x.segment<3>(0), e1 = s.x.segment<3>(3) - x0, e2 = s.x.segment<3>(6) - x0;
  const double twiceArea = e1.cross(e2).norm();
  const Eigen::Matrix3d P = (Eigen::Matrix3d::Identity() - n * n.transpose()) / twiceArea;
  auto skew = [](const Eigen::Vector3d& v) {
    Eigen::Matrix3d S;
    S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    return S;
  };
  std::array<Eigen::Matrix3d, 3> dn;
  dn[1] = -P * skew(e2);
  dn[2] = P * skew(e1);
  dn[0] = -(dn[1] + dn[2]);
  MatX J = MatX::Zero(3, m);
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  VecX c = VecX::Zero(N_);
  for (int i = 0; i < 3; ++i) {
    if (edges_[i].kind == KirchhoffEdge::Kind::Free) continue;
    w += sv[i] * d[i];
    for (int k = 0; k < 3; ++k) J.block<1, 3>(i, 3 * k) += (dn[k].transpose() * d[i]).transpose();
    if (edges_[i].kind != KirchhoffEdge::Kind::Shared) continue;
    for (int a = 0; a < N_; ++a) {
      J.block<1, 3>(i, 3 * a) += edges_[i].coeff[a] * n.transpose();
      c[a] += sv[i] * edges_[i].coeff[a];
    }
  }
  dQdq.noalias() = -J.transpose() * Ke * J;
  dQdv.setZero(m, m);
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < N_; ++a) {
      if (c[a] == 0.0) continue;
      dQdq.block<3, 3>(3 * k, 3 * a) -= c[a] * dn[k].transpose();
      dQdq.block<3, 3>(3 * a, 3 * k) -= c[a] * dn[k];
    }
  // H_psi by nested fixed-size forward AD on the 9 vertex coordinates
  Eigen::Matrix<Ad9x2, 9, 1> xa;
  for (int i = 0; i < 9; ++i) {
    Eigen::Matrix<Ad9, 9, 1> inner = Eigen::Matrix<Ad9, 9, 1>::Constant(Ad9(0.0, Eigen::Matrix<double, 9, 1>::Zero()));
    inner[i] = Ad9(1.0, Eigen::Matrix<double, 9, 1>::Zero());
    xa[i] = Ad9x2(Ad9(s.x[i], Eigen::Matrix<double, 9, 1>::Unit(i)), inner);
  }
  Ad9x2 area2;
  const V3<Ad9x2> na = unitNormal<Ad9x2>(xa, area2);
  Ad9x2 psi = na.dot(w.cast<Ad9x2>());
  for (int i = 0; i < 3; ++i)
    if (edges_[i].kind == KirchhoffEdge::Kind::Free && edges_[i].moment != 0.0)
      psi -= edges_[i].moment * length_[i] * rotation<Ad9x2>(i, na, nullptr);
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) dQdq(i, j) -= psi.derivatives()[i].derivatives()[j];
}

template class KernelElement<ShellKirchhoffBending>;

}  // namespace flexsens
