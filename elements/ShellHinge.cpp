#include "elements/ShellHinge.hpp"

#include <cmath>

#include "elements/BodyTriad.hpp"
#include "elements/KernelElementAD.hpp"
#include "elements/ShellDihedralAngle.hpp"

namespace flexsens {

// Notation (edge variables u = (e, a, b), e = x1 - x0, a = x2 - x0, b = x3 - x0 [m]):
//   X = n1 . n2 = (e.a)(e.b) - (e.e)(a.b)   [m^4]
//   Y = L det(e, a, b), L = |e|, det = e . (a x b)   [m^4]
//   theta = atan2(Y, X),  R = X^2 + Y^2 = |n1|^2 |n2|^2,  grad theta = (X grad Y - Y grad X) / R
//   grad_e X = a (e.b) + b (e.a) - 2 (a.b) e,  grad_a X = (e.b) e - (e.e) b,  grad_b X = (e.a) e - (e.e) a
//   grad_e det = a x b,  grad_a det = b x e,  grad_b det = e x a
// x-derivatives through x0 = -(e + a + b) terms: d/dx0 = -(d/de + d/da + d/db), d/dx1 = d/de,
// d/dx2 = d/da, d/dx3 = d/db.

namespace shell {

namespace {
using V9 = Eigen::Matrix<double, 9, 1>;
using M9 = Eigen::Matrix<double, 9, 9>;

/// M.block(3c, 3r) = M.block(3r, 3c)^T for the blocks above the diagonal.
void mirrorUpperBlocks(M9& M) {
  for (int r = 0; r < 3; ++r)
    for (int c = r + 1; c < 3; ++c) M.block<3, 3>(3 * c, 3 * r) = M.block<3, 3>(3 * r, 3 * c).transpose();
}

/// The Hessian of theta in the edge variables u = (e, a, b) (9 x 9) from X, Y, det and the
/// gradients gX, gD (of det), gY and gT (of theta) in u.
M9 edgeHessian(const Eigen::Vector3d& e, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double X, double Y,
               double det, const V9& gX, const V9& gD, const V9& gY, const V9& gT) {
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double ee = e.dot(e), ea = e.dot(a), eb = e.dot(b), ab = a.dot(b), L = std::sqrt(ee), R = X * X + Y * Y;
  M9 HX = M9::Zero(), HD = M9::Zero();
  HX.block<3, 3>(0, 0) = a * b.transpose() + b * a.transpose() - 2.0 * ab * I;
  HX.block<3, 3>(0, 3) = eb * I + b * e.transpose() - 2.0 * e * b.transpose();
  HX.block<3, 3>(0, 6) = a * e.transpose() + ea * I - 2.0 * e * a.transpose();
  HX.block<3, 3>(3, 6) = e * e.transpose() - ee * I;
  HD.block<3, 3>(0, 3) = -triad::skew(b);
  HD.block<3, 3>(0, 6) = triad::skew(a);
  HD.block<3, 3>(3, 6) = -triad::skew(e);
  mirrorUpperBlocks(HX);
  mirrorUpperBlocks(HD);
  // HY = gL gD^T + gD gL^T + det HL + L HD, gL = (e / L, 0, 0), HL = (I - e e^T / ee) / L on (e, e)
  M9 HY = L * HD;
  const Eigen::Vector3d gLe = e / L;
  HY.topRows<3>().noalias() += gLe * gD.transpose();
  HY.leftCols<3>().noalias() += gD * gLe.transpose();
  HY.topLeftCorner<3, 3>() += (det / L) * (I - gLe * gLe.transpose());
  M9 Hu = (X / R) * HY - (Y / R) * HX;
  Hu.noalias() += (gY / R) * gX.transpose();
  Hu.noalias() -= (gX / R) * gY.transpose();
  Hu.noalias() -= gT * ((2.0 / R) * (X * gX + Y * gY)).transpose();
  return Hu;
}

/// H = B^T Hu B, the Hessian in x from the one in u (x0 enters every edge variable with -I).
void toPositions(const M9& Hu, Mat12& H) {
  H.bottomRightCorner<9, 9>() = Hu;
  Eigen::Matrix3d corner = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) {
    const Eigen::Matrix3d col = Hu.block<3, 3>(0, 3 * k) + Hu.block<3, 3>(3, 3 * k) + Hu.block<3, 3>(6, 3 * k);
    const Eigen::Matrix3d row = Hu.block<3, 3>(3 * k, 0) + Hu.block<3, 3>(3 * k, 3) + Hu.block<3, 3>(3 * k, 6);
    H.block<3, 3>(0, 3 + 3 * k) = -col;
    H.block<3, 3>(3 + 3 * k, 0) = -row;
    corner += col;
  }
  H.topLeftCorner<3, 3>() = corner;
}
}  // namespace

bool angleDerivatives(const Vec12& x, double& theta, Vec12& grad, Mat12* hess) {
  const Eigen::Vector3d x0 = x.segment<3>(0);
  const Eigen::Vector3d e = x.segment<3>(3) - x0, a = x.segment<3>(6) - x0, b = x.segment<3>(9) - x0;
  const double ee = e.dot(e), ea = e.dot(a), eb = e.dot(b), ab = a.dot(b);
  if (!(ee > 0.0)) return false;
  const double L = std::sqrt(ee);
  const Eigen::Vector3d axb = a.cross(b);
  const double det = e.dot(axb), X = ea * eb - ee * ab, Y = L * det, R = X * X + Y * Y;
  if (!(std::sqrt(R) > kDegenerateTol * ee * ee)) return false;
  V9 gX, gD;
  gX << eb * a + ea * b - 2.0 * ab * e, eb * e - ee * b, ea * e - ee * a;
  gD << axb, b.cross(e), e.cross(a);
  V9 gY = L * gD;
  gY.head<3>() += (det / L) * e;
  const V9 gT = (X * gY - Y * gX) / R;
  theta = std::atan2(Y, X);
  grad.head<3>() = -(gT.segment<3>(0) + gT.segment<3>(3) + gT.segment<3>(6));
  grad.tail<9>() = gT;
  if (hess) toPositions(edgeHessian(e, a, b, X, Y, det, gX, gD, gY, gT), *hess);
  return true;
}

}  // namespace shell

double ShellHinge::dihedralAngle(const VecX& x, VecX* grad, MatX* hess, const std::string& who) {
  if (x.size() != 12) throw std::invalid_argument(who + ": positions of 4 nodes in 3D (12 entries) expected");
  double theta;
  shell::Vec12 g;
  shell::Mat12 H;
  if (!shell::angleDerivatives(x, theta, g, hess ? &H : nullptr)) throw NumericalError(shell::degenerateMessage(who));
  if (grad) *grad = g;
  if (hess) *hess = H;
  return theta;
}

ShellHinge::ShellHinge(std::string name, std::vector<int> nodes, std::shared_ptr<ShellProperties> props,
                       const VecX& restX, bool flatRest)
    : KernelElement(std::move(name), std::move(nodes)), props_(std::move(props)) {
  const std::string who = "shell hinge " + this->name();
  if (!props_) throw std::invalid_argument(who + ": no material");
  if (this->nodes().size() != 4 || restX.size() != 12) throw std::invalid_argument(who + ": needs 4 nodes in 3D");
  try {
    theta0_ = dihedralAngle(restX, nullptr, nullptr, who);
  } catch (const NumericalError& e) {
    throw std::invalid_argument(e.what());
  }
  if (flatRest) theta0_ = 0.0;
  const Eigen::Vector3d X0 = restX.segment<3>(0), e = restX.segment<3>(3) - X0;
  const double A1 = 0.5 * e.cross(restX.segment<3>(6) - X0).norm(), A2 = 0.5 * e.cross(restX.segment<3>(9) - X0).norm();
  w_ = e.squaredNorm() / (A1 + A2);
}

void ShellHinge::checkDim(const LocalState& s) const {
  if (s.dim != 3 || s.x.size() != 12) throw std::invalid_argument("shell hinge " + name() + ": spatial only (dim must be 3)");
}

// Value template: props = (E, nu, thickness, beta).
// Q = -D w (theta - theta0 + beta dtheta/dt) grad theta, dtheta/dt = grad theta . v.
template <class T>
VecT<T> ShellHinge::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const {
  checkDim(s);
  T theta;
  VecT<T> g;
  if (!shell::angleT<T>(x, theta, g)) throw NumericalError(shell::degenerateMessage("shell hinge " + name()));
  const T D = shell::bendingStiffness(props[0], props[1], props[2]);
  const T dev = ad::wrapAngle(T(theta - theta0_));
  const T rate = v.size() == x.size() ? T(g.dot(v)) : T(0.0);
  return -(D * w_ * (dev + props[3] * rate)) * g;
}

// Fixed size, no heap once the outputs have their size: the angle, its gradient and Hessian on
// the stack (shell::angleDerivatives); the element's name only in an error message.
void ShellHinge::bendingState(const LocalState& s, double& Dw, double& dev, shell::Vec12& g, shell::Mat12* H) const {
  checkDim(s);
  double theta;
  if (!shell::angleDerivatives(s.x, theta, g, H)) throw NumericalError(shell::degenerateMessage("shell hinge " + name()));
  const VecX& p = *s.p;
  Dw = shell::bendingStiffness(props_->E.value(p), props_->nu.value(p), props_->thickness.value(p)) * w_;
  dev = ad::wrapAngle(theta - theta0_);
}

void ShellHinge::force(const LocalState& s, VecX& Q) const {
  double Dw, dev;
  shell::Vec12 g;
  bendingState(s, Dw, dev, g, nullptr);
  shell::bendingForce<12>(Dw, props_->beta.value(*s.p), dev, g, s.v, Q);
}

void ShellHinge::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  double Dw, dev;
  shell::Vec12 g;
  shell::Mat12 H;
  bendingState(s, Dw, dev, g, &H);
  shell::bendingJacobians<12>(Dw, props_->beta.value(*s.p), dev, g, H, s.v, dQdq, dQdv);
}

bool ShellHinge::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  double D, dD, beta, dBeta, Dw, dev;
  if (!props_->bendingDerivative(*s.p, k, D, dD, beta, dBeta)) return false;
  shell::Vec12 g;
  bendingState(s, Dw, dev, g, nullptr);
  shell::bendingParameterDerivative<12>(Dw, dD * w_, beta, dBeta, dev, g, s.v, dQ);
  dM.resize(0, 0);  // massless, as the AD kernel reports it
  return true;
}

double ShellHinge::potential(const LocalState& s) const {
  double Dw, dev;
  shell::Vec12 g;
  bendingState(s, Dw, dev, g, nullptr);
  return 0.5 * Dw * dev * dev;  // [J]
}

template class KernelElement<ShellHinge>;

}  // namespace flexsens
