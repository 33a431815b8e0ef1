#include "elements/SpatialTorque.hpp"

#include <stdexcept>

#include "elements/BodyTriad.hpp"
#include "elements/KernelElementAD.hpp"

namespace flexsens {

using triad::V3;

SpatialTorque::SpatialTorque(std::string name, std::vector<int> nodes, std::vector<Quantity> torque,
                             std::unique_ptr<TimeFunction> f, bool follower, const MatX& X0)
    : KernelElement(std::move(name), std::move(nodes)), T0_(std::move(torque)), f_(std::move(f)), follower_(follower) {
  const size_t n = this->nodes().size();
  if (T0_.size() != 3 || (n != 2 && n != 3) || X0.rows() != 3 || X0.cols() != static_cast<Eigen::Index>(n))
    throw std::invalid_argument("point torque '" + this->name() + "': 3 components on 2 or 3 nodes in 3D");
  if (n == 3) {
    const Eigen::Vector3d d1 = X0.col(1) - X0.col(0), d2 = X0.col(2) - X0.col(0);
    if (!(d1.cross(d2).norm() > 1e-6 * d1.norm() * d2.norm()))
      throw std::invalid_argument("point torque '" + this->name() + "': the three nodes are collinear");
    Einv0_ = triad::inverseTriad(d1, d2);
  } else if (follower_) {
    throw std::invalid_argument("point torque '" + this->name() + "': a follower torque needs three nodes");
  }
}

void SpatialTorque::checkDim(const LocalState& s) const {
  if (s.dim != 3) throw std::invalid_argument("point torque '" + name() + "' (3 components) needs a spatial model");
}

std::vector<const Quantity*> SpatialTorque::kernelProperties() const { return {&T0_[0], &T0_[1], &T0_[2]}; }

VecX SpatialTorque::componentValues(const LocalState& s) const {
  return Eigen::Vector3d(s.value(T0_[0]), s.value(T0_[1]), s.value(T0_[2]));
}

template <class T>
VecT<T> SpatialTorque::load(const VecT<T>& x, const VecT<T>& c, double fac) const {
  const V3<T> d1 = triad::at(x, 1) - triad::at(x, 0);
  VecT<T> Q(x.size());
  if (nodes().size() == 2) {
    V3<T> tq;
    for (int i = 0; i < 3; ++i) tq[i] = c[i] * fac;
    const V3<T> fB = triad::cross(tq, d1) / d1.dot(d1);
    Q.template segment<3>(0) = -fB;
    Q.template segment<3>(3) = fB;
    return Q;
  }
  const V3<T> d2 = triad::at(x, 2) - triad::at(x, 0);
  V3<T> tq;
  if (follower_) {
    tq = triad::follower(d1, d2, Einv0_, c, fac);
  } else {
    for (int i = 0; i < 3; ++i) tq[i] = c[i] * fac;
  }
  const V3<T> n = triad::cross(d1, d2);
  const V3<T> w = d1 * d2.dot(d2) - d2 * d1.dot(d2);
  const V3<T> T2 = (tq.dot(d1) / n.dot(n)) * w, T1 = tq - T2;
  const V3<T> fB = triad::cross(T1, d1) / d1.dot(d1), fC = triad::cross(T2, d2) / d2.dot(d2);
  Q.template segment<3>(0) = -(fB + fC);
  Q.template segment<3>(3) = fB;
  Q.template segment<3>(6) = fC;
  return Q;
}

// Value template: props = the components of T0.
template <class T>
VecT<T> SpatialTorque::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>&, const VecT<T>& props) const {
  checkDim(s);
  return load<T>(x, props, factor(s));
}

void SpatialTorque::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  checkDim(s);
  using Eigen::Matrix3d;
  using Eigen::Vector3d;
  const int nn = static_cast<int>(nodes().size());
  dQdq.setZero(3 * nn, 3 * nn);
  dQdv.setZero(3 * nn, 3 * nn);
  const double fac = factor(s);
  const Vector3d c = componentValues(s);
  const Vector3d d1 = s.x.segment<3>(3) - s.x.segment<3>(0);
  const Matrix3d I = Matrix3d::Identity();
  if (nn == 2) {
    // f_B = T x d / L, L = |d|^2: df_B/dd = ([T]x - 2 f_B d^T) / L; f_A = -f_B.
    const Vector3d tq = fac * c;
    const double L = d1.squaredNorm();
    const Vector3d fB = tq.cross(d1) / L;
    const Matrix3d K = (triad::skew(tq) - 2.0 * fB * d1.transpose()) / L;
    dQdq << K, -K, -K, K;
    return;
  }
  const Vector3d d2 = s.x.segment<3>(6) - s.x.segment<3>(0);
  // T and its derivatives Td1 = dT/dd1, Td2 = dT/dd2 (zero unless follower).
  Vector3d tq = fac * c;
  Matrix3d Td1 = Matrix3d::Zero(), Td2 = Matrix3d::Zero();
  if (follower_) {
    const Vector3d a = fac * Einv0_ * c;
    tq = a[0] * d1 + a[1] * d2 + a[2] * d1.cross(d2);
    triad::followerJacobian(d1, d2, a, Td1, Td2);
  }
  const double L1 = d1.squaredNorm(), L2 = d2.squaredNorm(), e = d1.dot(d2);
  const double N = d1.cross(d2).squaredNorm();
  const Vector3d w = d1 * L2 - d2 * e, u = d2 * L1 - d1 * e;  // dN/dd1 = 2 w, dN/dd2 = 2 u
  const double sT = tq.dot(d1), cT = sT / N;                   // T2 = cT w
  const Eigen::RowVector3d dc1 = (d1.transpose() * Td1 + tq.transpose()) / N - 2.0 * sT / (N * N) * w.transpose();
  const Eigen::RowVector3d dc2 = (d1.transpose() * Td2) / N - 2.0 * sT / (N * N) * u.transpose();
  const Matrix3d dw1 = L2 * I - d2 * d2.transpose();
  const Matrix3d dw2 = 2.0 * d1 * d2.transpose() - d2 * d1.transpose() - e * I;
  const Vector3d T2 = cT * w, T1 = tq - T2;
  const Matrix3d dT2_1 = w * dc1 + cT * dw1, dT2_2 = w * dc2 + cT * dw2;
  const Matrix3d dT1_1 = Td1 - dT2_1, dT1_2 = Td2 - dT2_2;
  // f_B = T1 x d1 / L1 = -[d1]x T1 / L1, f_C = T2 x d2 / L2.
  const Vector3d fB = T1.cross(d1) / L1, fC = T2.cross(d2) / L2;
  const Matrix3d fB1 = (triad::skew(T1) - triad::skew(d1) * dT1_1 - 2.0 * fB * d1.transpose()) / L1;
  const Matrix3d fB2 = -triad::skew(d1) * dT1_2 / L1;
  const Matrix3d fC1 = -triad::skew(d2) * dT2_1 / L2;
  const Matrix3d fC2 = (triad::skew(T2) - triad::skew(d2) * dT2_2 - 2.0 * fC * d2.transpose()) / L2;
  // d1 = x_B - x_A, d2 = x_C - x_A: columns A = -(d/dd1 + d/dd2), B = d/dd1, C = d/dd2.
  auto put = [&](int row, const Matrix3d& D1, const Matrix3d& D2) {
    dQdq.block<3, 3>(row, 0) = -(D1 + D2);
    dQdq.block<3, 3>(row, 3) = D1;
    dQdq.block<3, 3>(row, 6) = D2;
  };
  put(3, fB1, fB2);
  put(6, fC1, fC2);
  put(0, -(fB1 + fC1), -(fB2 + fC2));
}

bool SpatialTorque::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  checkDim(s);
  TimeValue d;
  const bool fn = f_ && f_->parameterDerivative(s.t, *s.p, k, d);
  Eigen::Vector3d unit;
  for (int i = 0; i < 3; ++i) unit[i] = T0_[i].boundTo(k) ? 1.0 : 0.0;
  const bool comp = !unit.isZero();
  if (!fn && !comp) return false;
  // Q is linear in T0 and in f: a unit component's Q, plus Q of T0 with df/dp_k.
  dQ = VecX::Zero(s.x.size());
  if (comp) dQ += load<double>(s.x, unit, factor(s));
  if (fn) dQ += load<double>(s.x, componentValues(s), d.f);
  dM.setZero(s.x.size(), s.x.size());  // massless
  return true;
}

bool SpatialTorque::parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  checkDim(s);
  // AD through the components; the time function's constants (Q of df/dp_k) analytic.
  const bool comp = KernelElement::parameterDerivativeAD(s, k, dQ, dM);
  TimeValue d;
  if (!f_ || !f_->parameterDerivative(s.t, *s.p, k, d)) return comp;
  if (!comp) dQ.setZero(s.x.size());
  dQ += load<double>(s.x, componentValues(s), d.f);
  dM.resize(0, 0);  // massless
  return true;
}

std::vector<std::pair<std::string, Quantity*>> SpatialTorque::properties() {
  std::vector<std::pair<std::string, Quantity*>> r{{"x", &T0_[0]}, {"y", &T0_[1]}, {"z", &T0_[2]}};
  if (f_)
    for (auto& pr : f_->properties()) r.push_back(pr);
  return r;
}

template class KernelElement<SpatialTorque>;

}  // namespace flexsens
