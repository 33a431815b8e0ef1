#include "elements/ShellClampHinge.hpp"

#include <cmath>

#include "elements/KernelElementAD.hpp"
#include "elements/ShellDihedralAngle.hpp"
#include "elements/ShellHinge.hpp"

namespace flexsens {

ShellClampHinge::ShellClampHinge(std::string name, std::vector<int> nodes, std::shared_ptr<ShellProperties> props,
                                 const VecX& restX)
    : KernelElement(std::move(name), std::move(nodes)), props_(std::move(props)) {
  const std::string who = "shell clamp " + this->name();
  if (!props_) throw std::invalid_argument(who + ": no material");
  if (this->nodes().size() != 3 || restX.size() != 9) throw std::invalid_argument(who + ": needs 3 nodes in 3D");
  const Eigen::Vector3d X0 = restX.segment<3>(0), e = restX.segment<3>(3) - X0, a = restX.segment<3>(6) - X0;
  const double A = 0.5 * e.cross(a).norm();
  if (!(e.squaredNorm() > 0.0) || !(A > 0.0)) throw std::invalid_argument(shell::degenerateMessage(who));
  const Eigen::Vector3d along = e.dot(a) / e.squaredNorm() * e;
  ghost_ = X0 + along - (a - along);  // X2 reflected across the edge line, in the rest plane
  try {
    phi0_ = ShellHinge::dihedralAngle(withGhost(restX), nullptr, nullptr, who);
  } catch (const NumericalError& err) {
    throw std::invalid_argument(err.what());
  }
  w_ = e.squaredNorm() / A;
}

VecX ShellClampHinge::withGhost(const VecX& x) const {
  VecX y(12);
  y << x, ghost_;
  return y;
}

void ShellClampHinge::checkDim(const LocalState& s) const {
  if (s.dim != 3 || s.x.size() != 9) throw std::invalid_argument("shell clamp " + name() + ": spatial only (dim must be 3)");
}

double ShellClampHinge::rotation(const VecX& x) const {
  return ad::wrapAngle(ShellHinge::dihedralAngle(withGhost(x), nullptr, nullptr, "shell clamp " + name()) - phi0_);
}

// Value template: props = (E, nu, thickness, beta). Q = -D w (phi + beta dphi/dt) grad phi,
// dphi/dt = grad phi . v (the hinge's Kelvin-Voigt term, ShellHinge.cpp), the ghost a constant (its
// entries carry x's derivative layout, all zero, so that it meets x's scalars as they do).
template <class T>
VecT<T> ShellClampHinge::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const {
  checkDim(s);
  VecT<T> y(12);
  y.head(9) = x;
  for (int k = 0; k < 3; ++k) y[9 + k] = x[k] * 0.0 + ghost_[k];
  T phi;
  VecT<T> g;
  if (!shell::angleT<T>(y, phi, g)) throw NumericalError(shell::degenerateMessage("shell clamp " + name()));
  const T D = shell::bendingStiffness(props[0], props[1], props[2]);
  const T dev = ad::wrapAngle(T(phi - phi0_));
  const VecT<T> g9 = g.head(9);
  const T rate = v.size() == x.size() ? T(g9.dot(v)) : T(0.0);
  return -(D * w_ * (dev + props[3] * rate)) * g9;
}

void ShellClampHinge::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  checkDim(s);
  VecX g;
  MatX H;
  const double phi = ShellHinge::dihedralAngle(withGhost(s.x), &g, &H, "shell clamp " + name());
  const VecX& p = *s.p;
  const double D = shell::bendingStiffness(props_->E.value(p), props_->nu.value(p), props_->thickness.value(p));
  // the ghost is fixed: the x-blocks of the 4-node angle's derivatives
  shell::bendingJacobians(D * w_, props_->beta.value(p), ad::wrapAngle(phi - phi0_), g.head(9), H.topLeftCorner(9, 9),
                          s.v, dQdq, dQdv);
}

bool ShellClampHinge::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  double D, dD, beta, dBeta;
  if (!props_->bendingDerivative(*s.p, k, D, dD, beta, dBeta)) return false;
  checkDim(s);
  VecX g;
  const double dev = ad::wrapAngle(ShellHinge::dihedralAngle(withGhost(s.x), &g, nullptr, "shell clamp " + name()) - phi0_);
  dQ = shell::bendingParameterDerivative(D * w_, dD * w_, beta, dBeta, dev, g.head(9), s.v);
  dM.resize(0, 0);  // massless, as the AD kernel reports it
  return true;
}

double ShellClampHinge::potential(const LocalState& s) const {
  checkDim(s);
  const VecX& p = *s.p;
  const double D = shell::bendingStiffness(props_->E.value(p), props_->nu.value(p), props_->thickness.value(p));
  const double dev = rotation(s.x);
  return 0.5 * D * w_ * dev * dev;  // [J]
}

template class KernelElement<ShellClampHinge>;

}  // namespace flexsens
