#include "constraints/Distance.hpp"

namespace flexsens {

void DistanceConstraint::phi(const LocalState& s, VecX& out) const {
  const int d = s.dim;
  const double L = s.value(length_);
  out.resize(1);
  out[0] = (s.x.tail(d) - s.x.head(d)).squaredNorm() - L * L;
}

void DistanceConstraint::jacobian(const LocalState& s, MatX& J) const {
  const int d = s.dim;
  const VecX dx = s.x.tail(d) - s.x.head(d);
  J.resize(1, 2 * d);
  J.row(0).head(d) = -2.0 * dx.transpose();
  J.row(0).tail(d) = 2.0 * dx.transpose();
}

void DistanceConstraint::hessian(const LocalState& s, int, MatX& H) const {
  const int d = s.dim;
  const MatX I = MatX::Identity(d, d);
  H.resize(2 * d, 2 * d);
  H << 2 * I, -2 * I, -2 * I, 2 * I;
}

bool DistanceConstraint::parameterDerivative(const LocalState& s, int k, VecX& dphi,
                                             MatX& dJ) const {
  if (!length_.boundTo(k)) return false;
  dphi.resize(1);
  dphi[0] = -2.0 * s.value(length_);
  dJ.resize(0, 0);  // Phi_q does not depend on L
  return true;
}

}  // namespace flexsens
