#include "pim/Sdof.hpp"

#include <cmath>
#include <stdexcept>

#include "elements/AutoDiff.hpp"

namespace flexsens {

namespace {
Eigen::Matrix3d initialBasis(const Eigen::Matrix<double, 3, 4>& X0) {
  Eigen::Matrix3d E;
  for (int j = 0; j < 3; ++j) E.col(j) = X0.col(j + 1) - X0.col(0);
  return E;
}
}  // namespace

std::unique_ptr<LinearSdof> centerOfMassSdof(const std::array<int, 4>& basic,
                                             const Eigen::Matrix<double, 3, 4>& X0,
                                             const Eigen::Vector3d& com, int component) {
  const Eigen::Vector3d c = initialBasis(X0).inverse() * (com - X0.col(0));
  auto s = std::make_unique<LinearSdof>();
  s->terms.push_back({basic[0], component, 1.0 - c.sum()});
  for (int j = 0; j < 3; ++j) s->terms.push_back({basic[j + 1], component, c[j]});
  return s;
}

BodyRotationSdof::BodyRotationSdof(const std::array<int, 4>& basic, const Eigen::Matrix<double, 3, 4>& X0,
                                   int axis)
    : basic_(basic), Einv0_(initialBasis(X0).inverse()), axis_(axis) {
  if (axis < 0 || axis > 2) throw std::invalid_argument("BodyRotationSdof: axis must be 0, 1 or 2");
  if (!Einv0_.allFinite()) throw std::invalid_argument("BodyRotationSdof: coplanar basic points");
}

template <class T>
T BodyRotationSdof::angleT(const VecT<T>& x) const {
  using std::asin;
  using std::atan2;
  // R(i, j) = sum_k E(i, k) Einv0(k, j), E(i, k) = x[3 (k + 1) + i] - x[i]
  auto R = [&](int i, int j) {
    T sum = (x[3 + i] - x[i]) * Einv0_(0, j);
    for (int k = 1; k < 3; ++k) sum += (x[3 * (k + 1) + i] - x[i]) * Einv0_(k, j);
    return sum;
  };
  if (axis_ == 0) return atan2(R(2, 1), R(2, 2));  // roll
  if (axis_ == 1) return -asin(R(2, 0));           // pitch
  return atan2(R(1, 0), R(0, 0));                  // yaw
}

VecX BodyRotationSdof::local(const Model& m, const VecX& q) const {
  VecX x(12);
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) {
      const int d = m.dof(basic_[k], i);
      x[3 * k + i] = d < 0 ? m.nodes[basic_[k]].position[i] : q[d];
    }
  return x;
}

double BodyRotationSdof::angle(const VecX& x) const { return angleT<double>(x); }

double BodyRotationSdof::value(const Model& m, const VecX& q) const { return angle(local(m, q)); }

VecX BodyRotationSdof::gradient(const Model& m, const VecX& q) const {
  const VecT<ad::AD1> x = ad::seed1(local(m, q), ad::unitSeed(12, 12, 0));
  const ad::AD1 y = angleT(x);
  VecX g = VecX::Zero(m.n);
  if (y.derivatives().size() == 0) return g;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 3; ++i) {
      const int d = m.dof(basic_[k], i);
      if (d >= 0) g[d] += y.derivatives()[3 * k + i];
    }
  return g;
}

MatX BodyRotationSdof::hessian(const Model& m, const VecX& q) const {
  const VecT<ad::AD2> x = ad::seed2(local(m, q), ad::unitSeed(12, 12, 0));
  const MatX h = ad::hessian(angleT(x), 12);
  MatX H = MatX::Zero(m.n, m.n);
  for (int a = 0; a < 12; ++a) {
    const int r = m.dof(basic_[a / 3], a % 3);
    if (r < 0) continue;
    for (int b = 0; b < 12; ++b) {
      const int s = m.dof(basic_[b / 3], b % 3);
      if (s >= 0) H(r, s) += h(a, b);
    }
  }
  return H;
}

}  // namespace flexsens
