#include "elements/RigidBody.hpp"

#include <stdexcept>

#include "elements/KernelElementAD.hpp"

namespace flexsens {

namespace {
/// N = T [1; c] maps body coordinates to the basic-point weights (1 - sum c, c1, c2, c3).
Eigen::Matrix4d weightMap() {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T(0, 1) = T(0, 2) = T(0, 3) = -1.0;
  return T;
}
}  // namespace

Eigen::Matrix3d RigidBody::secondMoments(const Eigen::Matrix3d& I) {
  return 0.5 * I.trace() * Eigen::Matrix3d::Identity() - I;
}

RigidBody::RigidBody(std::string name, std::vector<int> basic, const Eigen::Matrix<double, 3, 4>& X0,
                     Quantity mass, const Eigen::Vector3d& com, const std::array<Quantity, 6>& inertia)
    : KernelElement(std::move(name), std::move(basic)), mass_(mass), inertia_(inertia) {
  if (nodes().size() != 4) throw std::invalid_argument("rigid body " + this->name() + ": needs 4 basic points");
  Eigen::Matrix3d E;
  for (int j = 0; j < 3; ++j) E.col(j) = X0.col(j + 1) - X0.col(0);
  const double scale = E.colwise().norm().maxCoeff();
  if (!(std::abs(E.determinant()) > 1e-9 * scale * scale * scale))
    throw std::invalid_argument("rigid body " + this->name() + ": its basic points are coplanar");
  Einv0_ = E.inverse();
  dG_ = com - X0.col(0);
  cG_ = Einv0_ * dG_;
}

std::vector<const Quantity*> RigidBody::kernelProperties() const {
  std::vector<const Quantity*> r{&mass_};
  for (const auto& q : inertia_) r.push_back(&q);
  return r;
}

std::vector<std::pair<std::string, Quantity*>> RigidBody::properties() {
  static const char* names[6] = {"Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz"};
  std::vector<std::pair<std::string, Quantity*>> r{{"mass", &mass_}};
  for (int i = 0; i < 6; ++i) r.push_back({names[i], &inertia_[i]});
  return r;
}

// Value templates: props = (m, Ixx, Iyy, Izz, Ixy, Ixz, Iyz).
template <class T>
MatT<T> RigidBody::massT(const LocalState&, const VecT<T>& props) const {
  using M3 = Eigen::Matrix<T, 3, 3>;
  const T& m = props[0];
  M3 I;
  I << props[1], props[4], props[5], props[4], props[2], props[6], props[5], props[6], props[3];
  // int (r - r_A)(r - r_A)^T dm at t = 0 = m dG dG^T + second moments about G  [kg m^2]
  M3 S = (0.5 * I.trace()) * M3::Identity() - I;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) S(i, j) += m * (dG_[i] * dG_[j]);
  const M3 Jc = Einv0_.cast<T>() * S * Einv0_.transpose().cast<T>();  // int c c^T dm
  Eigen::Matrix<T, 4, 4> J;
  J(0, 0) = m;
  for (int i = 0; i < 3; ++i) {
    J(0, i + 1) = J(i + 1, 0) = m * cG_[i];
    for (int j = 0; j < 3; ++j) J(i + 1, j + 1) = Jc(i, j);
  }
  const Eigen::Matrix4d Tw = weightMap();
  const Eigen::Matrix<T, 4, 4> M4 = Tw.cast<T>() * J * Tw.transpose().cast<T>();  // int N N^T dm
  MatT<T> M = MatT<T>::Zero(12, 12);
  for (int k = 0; k < 4; ++k)
    for (int l = 0; l < 4; ++l)
      for (int i = 0; i < 3; ++i) M(3 * k + i, 3 * l + i) = M4(k, l);
  return M;
}

template <class T>
VecT<T> RigidBody::forceT(const LocalState& s, const VecT<T>&, const VecT<T>&, const VecT<T>& props) const {
  const T& m = props[0];
  // int N dm = T [m; m c_G]: the share of the weight each basic point carries [kg]
  const Eigen::Matrix4d Tw = weightMap();
  Eigen::Matrix<T, 4, 1> w;
  for (int k = 0; k < 4; ++k) w[k] = m * (Tw(k, 0) + Tw(k, 1) * cG_[0] + Tw(k, 2) * cG_[1] + Tw(k, 3) * cG_[2]);
  const VecX g = s.gravity ? VecX(*s.gravity) : VecX(VecX::Zero(3));
  VecT<T> Q(12);
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) Q[3 * k + i] = w[k] * g[i];
  return Q;
}

void RigidBody::force(const LocalState& s, VecX& Q) const {
  if (s.dim != 3) throw std::invalid_argument("rigid body " + name() + ": spatial scenes only (dimension 3)");
  KernelElement::force(s, Q);
}

void RigidBody::forceJacobian(const LocalState&, MatX& dQdq, MatX& dQdv) const {
  dQdq.setZero(12, 12);  // the weight does not depend on the configuration
  dQdv.setZero(12, 12);
}

bool RigidBody::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  // M and Q are linear in (m, I): their derivative along the bound properties is their
  // value with those properties set to 1 and all others to 0 (exact, no differencing).
  const auto props = kernelProperties();
  VecX unit = VecX::Zero(props.size());
  for (size_t i = 0; i < props.size(); ++i)
    if (props[i]->boundTo(k)) unit[i] = 1.0;
  if (unit.isZero()) return false;
  dM = massT<double>(s, unit);
  dQ = forceT<double>(s, s.x, s.v, unit);
  return true;
}

double RigidBody::potential(const LocalState& s) const {
  VecX Q;
  force(s, Q);
  return -Q.dot(s.x);  // -m g . r_G: Q . x = sum_k (int N_k dm) g . r_k = m g . r_G
}

template class KernelElement<RigidBody>;

}  // namespace flexsens
