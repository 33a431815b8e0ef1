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

// The double paths below write into the caller's storage without temporaries: the residual
// and the Newton matrix evaluate every distance at every iteration (the rigid five-bar's and
// the flexible one's bars), and their heap temporaries were a third of those calls.
void DistanceConstraint::phi(const LocalState& s, VecX& out) const {
  const int d = s.dim;
  const double L = s.value(length_);
  out.resize(1);
  out[0] = (s.x.tail(d) - s.x.head(d)).squaredNorm() - L * L;
}

void DistanceConstraint::jacobian(const LocalState& s, MatX& J) const {
  const int d = s.dim;
  J.resize(1, 2 * d);
  for (int i = 0; i < d; ++i) {
    const double dx = s.x[d + i] - s.x[i];
    J(0, i) = -2.0 * dx;
    J(0, d + i) = 2.0 * dx;
  }
}

void DistanceConstraint::hessian(const LocalState& s, int, MatX& H) const {
  const int d = s.dim;
  H.setZero(2 * d, 2 * d);
  for (int i = 0; i < d; ++i) {
    H(i, i) = H(d + i, d + i) = 2.0;
    H(i, d + i) = H(d + i, i) = -2.0;
  }
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
