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

ShellClampHinge::ShellClampHinge(std::string name, std::vector<int> nodes, std::shared_ptr<ShellProperties> props,
                                 const VecX& restX, const Eigen::Vector3d& normal, const Eigen::Vector3d& point)
    : ShellClampHinge(std::move(name), std::move(nodes), std::move(props), restX) {
  mirror_ = true;
  normal_ = normal.normalized();
  point_ = point;
  try {
    phi0_ = ShellHinge::dihedralAngle(withGhost(restX), nullptr, nullptr, "shell symmetry " + this->name());
  } catch (const NumericalError& err) {
    throw std::invalid_argument(err.what());
  }
  w_ *= 0.25;  // half the energy of the hinge with the mirror image, whose angle is twice the tilt
}

shell::Vec12 ShellClampHinge::withGhost(const VecX& x) const {
  shell::Vec12 y;
  y << x, ghostOf<double>(x.segment<3>(6));
  return y;
}

void ShellClampHinge::checkDim(const LocalState& s) const {
  if (s.dim != 3 || s.x.size() != 9) throw std::invalid_argument("shell clamp " + name() + ": spatial only (dim must be 3)");
}

double ShellClampHinge::rotation(const VecX& x) const {
  double phi;
  shell::Vec12 g;
  if (!shell::angleDerivatives(withGhost(x), phi, g, nullptr))
    throw NumericalError(shell::degenerateMessage("shell clamp " + name()));
  return ad::wrapAngle(phi - phi0_);
}

// Value template: props = (E, nu, thickness, beta). Q = -D w (phi + beta dphi/dt) grad phi,
// dphi/dt = grad phi . v (the hinge's Kelvin-Voigt term, ShellHinge.cpp), the ghost a constant (its
// entries carry x's derivative layout, all zero, so that it meets x's scalars as they do).
template <class T>
VecT<T> ShellClampHinge::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const {
  checkDim(s);
  VecT<T> y(12);
  y.head(9) = x;
  const Eigen::Matrix<T, 3, 1> x2 = x.template segment<3>(6);
  y.template tail<3>() = ghostOf<T>(x2);
  T phi;
  VecT<T> g;
  if (!shell::angleT<T>(y, phi, g)) throw NumericalError(shell::degenerateMessage("shell clamp " + name()));
  const T D = shell::bendingStiffness(props[0], props[1], props[2]);
  const T dev = ad::wrapAngle(T(phi - phi0_));
  VecT<T> g9 = g.head(9);
  if (mirror_) {  // grad_x2 += M grad_x3: the mirror ghost moves with x2 (M = I - 2 n n^T)
    const Eigen::Matrix<T, 3, 1> g3 = g.template tail<3>();
    g9.template segment<3>(6) += g3 - (2.0 * normal_.cast<T>().dot(g3)) * normal_.cast<T>();
  }
  const T rate = v.size() == x.size() ? T(g9.dot(v)) : T(0.0);
  return -(D * w_ * (dev + props[3] * rate)) * g9;
}

// Fixed size, no heap once the outputs have their size; a fixed ghost leaves the x-blocks (the
// first 9 entries) of the 4-node angle's derivatives, a mirror ghost adds its chain rule.
void ShellClampHinge::bendingState(const LocalState& s, double& Dw, double& dev, Eigen::Matrix<double, 9, 1>& g,
                                   Eigen::Matrix<double, 9, 9>* H) const {
  checkDim(s);
  double phi;
  shell::Vec12 g12;
  shell::Mat12 H12;
  if (!shell::angleDerivatives(withGhost(s.x), phi, g12, H ? &H12 : nullptr))
    throw NumericalError(shell::degenerateMessage("shell clamp " + name()));
  g = g12.head<9>();
  if (H) *H = H12.topLeftCorner<9, 9>();
  if (mirror_) {  // x3 = M x2 + c, M = I - 2 n n^T (symmetric): chain rule through the ghost
    const Eigen::Matrix3d M = Eigen::Matrix3d::Identity() - 2.0 * normal_ * normal_.transpose();
    g.segment<3>(6) += M * g12.tail<3>();
    if (H) {
      H->middleCols<3>(6) += H12.block<9, 3>(0, 9) * M;
      H->middleRows<3>(6) += M * H12.block<3, 9>(9, 0);
      H->block<3, 3>(6, 6) += M * H12.block<3, 3>(9, 9) * M;
    }
  }
  const VecX& p = *s.p;
  Dw = shell::bendingStiffness(props_->E.value(p), props_->nu.value(p), props_->thickness.value(p)) * w_;
  dev = ad::wrapAngle(phi - phi0_);
}

void ShellClampHinge::force(const LocalState& s, VecX& Q) const {
  double Dw, dev;
  Eigen::Matrix<double, 9, 1> g;
  bendingState(s, Dw, dev, g, nullptr);
  shell::bendingForce<9>(Dw, props_->beta.value(*s.p), dev, g, s.v, Q);
}

void ShellClampHinge::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  double Dw, dev;
  Eigen::Matrix<double, 9, 1> g;
  Eigen::Matrix<double, 9, 9> H;
  bendingState(s, Dw, dev, g, &H);
  shell::bendingJacobians<9>(Dw, props_->beta.value(*s.p), dev, g, H, s.v, dQdq, dQdv);
}

bool ShellClampHinge::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  double D, dD, beta, dBeta, Dw, dev;
  if (!props_->bendingDerivative(*s.p, k, D, dD, beta, dBeta)) return false;
  Eigen::Matrix<double, 9, 1> g;
  bendingState(s, Dw, dev, g, nullptr);
  shell::bendingParameterDerivative<9>(Dw, dD * w_, beta, dBeta, dev, g, s.v, dQ);
  dM.resize(0, 0);  // massless, as the AD kernel reports it
  return true;
}

double ShellClampHinge::potential(const LocalState& s) const {
  double Dw, dev;
  Eigen::Matrix<double, 9, 1> g;
  bendingState(s, Dw, dev, g, nullptr);
  return 0.5 * Dw * dev * dev;  // [J]
}

template class KernelElement<ShellClampHinge>;

}  // namespace flexsens
