#include "constraints/Distance.hpp"

#include "constraints/KernelConstraintAD.hpp"

namespace flexsens {

// ------------------------------------------------------------------------------ distance
// Value template: props = (L).
template <class T>
VecT<T> DistanceConstraint::phiT(const LocalState& s, const VecT<T>& x, const VecT<T>& props) const {
  const int d = s.dim;
  const T& L = props[0];
  const VecT<T> dx = x.tail(d) - x.head(d);
  VecT<T> out(1);
  out[0] = dx.squaredNorm() - L * L;
  return out;
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

// ---------------------------------------------------------------------------- fixed node
template <class T>
VecT<T> FixedNodeConstraint::phiT(const LocalState&, const VecT<T>& x, const VecT<T>&) const {
  VecT<T> out(x.size());
  for (int i = 0; i < x.size(); ++i) out[i] = x[i] - position_[i];
  return out;
}

template class KernelConstraint<DistanceConstraint>;
template class KernelConstraint<FixedNodeConstraint>;

}  // namespace flexsens
