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

namespace {

using triad::V3;
using triad::cross;
using triad::skew;

using shell::angleT;

/// d(e, a, b)/d(x0, x1, x2, x3), 9 x 12.
MatX edgeMap() {
  MatX B = MatX::Zero(9, 12);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  for (int k = 0; k < 3; ++k) {
    B.block<3, 3>(3 * k, 0) = -I;
    B.block<3, 3>(3 * k, 3 * (k + 1)) = I;
  }
  return B;
}

}  // namespace

double ShellHinge::dihedralAngle(const VecX& x, VecX* grad, MatX* hess, const std::string& who) {
  if (x.size() != 12) throw std::invalid_argument(who + ": positions of 4 nodes in 3D (12 entries) expected");
  double theta;
  VecX g;
  if (!angleT<double>(x, theta, g)) throw NumericalError(shell::degenerateMessage(who));
  if (grad) *grad = g;
  if (hess) {
    const Eigen::Vector3d x0 = x.segment<3>(0);
    const Eigen::Vector3d e = x.segment<3>(3) - x0, a = x.segment<3>(6) - x0, b = x.segment<3>(9) - x0;
    const double ee = e.dot(e), ea = e.dot(a), eb = e.dot(b), ab = a.dot(b), L = std::sqrt(ee);
    const double det = e.dot(a.cross(b)), X = ea * eb - ee * ab, Y = L * det, R = X * X + Y * Y;
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    VecX gX(9), gD(9), gL = VecX::Zero(9);
    gX << eb * a + ea * b - 2.0 * ab * e, eb * e - ee * b, ea * e - ee * a;
    gD << a.cross(b), b.cross(e), e.cross(a);
    gL.head<3>() = e / L;
    const VecX gY = det * gL + L * gD;
    MatX HX = MatX::Zero(9, 9), HD = MatX::Zero(9, 9), HL = MatX::Zero(9, 9);
    HX.block<3, 3>(0, 0) = a * b.transpose() + b * a.transpose() - 2.0 * ab * I;
    HX.block<3, 3>(0, 3) = eb * I + b * e.transpose() - 2.0 * e * b.transpose();
    HX.block<3, 3>(0, 6) = a * e.transpose() + ea * I - 2.0 * e * a.transpose();
    HX.block<3, 3>(3, 6) = e * e.transpose() - ee * I;
    HD.block<3, 3>(0, 3) = -skew(b);
    HD.block<3, 3>(0, 6) = skew(a);
    HD.block<3, 3>(3, 6) = -skew(e);
    for (MatX* H : {&HX, &HD})  // the lower blocks by symmetry
      for (int r = 0; r < 3; ++r)
        for (int c = r + 1; c < 3; ++c) H->block<3, 3>(3 * c, 3 * r) = H->block<3, 3>(3 * r, 3 * c).transpose();
    HL.block<3, 3>(0, 0) = (I - e * e.transpose() / ee) / L;
    const MatX HY = gL * gD.transpose() + gD * gL.transpose() + det * HL + L * HD;
    const VecX gT = (X * gY - Y * gX) / R;
    const MatX Hu = (X * HY - Y * HX + gY * gX.transpose() - gX * gY.transpose()) / R -
                    gT * (2.0 * X * gX + 2.0 * Y * gY).transpose() / R;
    const MatX B = edgeMap();
    *hess = B.transpose() * Hu * B;
  }
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
  if (!angleT<T>(x, theta, g)) throw NumericalError(shell::degenerateMessage("shell hinge " + name()));
  const T D = shell::bendingStiffness(props[0], props[1], props[2]);
  const T dev = ad::wrapAngle(T(theta - theta0_));
  const T rate = v.size() == x.size() ? T(g.dot(v)) : T(0.0);
  return -(D * w_ * (dev + props[3] * rate)) * g;
}

void ShellHinge::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  checkDim(s);
  VecX g;
  MatX H;
  const double theta = dihedralAngle(s.x, &g, &H, "shell hinge " + name());
  const VecX& p = *s.p;
  const double D = shell::bendingStiffness(props_->E.value(p), props_->nu.value(p), props_->thickness.value(p));
  shell::bendingJacobians(D * w_, props_->beta.value(p), ad::wrapAngle(theta - theta0_), g, H, s.v, dQdq, dQdv);
}

bool ShellHinge::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  double D, dD, beta, dBeta;
  if (!props_->bendingDerivative(*s.p, k, D, dD, beta, dBeta)) return false;
  checkDim(s);
  VecX g;
  const double dev = ad::wrapAngle(dihedralAngle(s.x, &g, nullptr, "shell hinge " + name()) - theta0_);
  dQ = shell::bendingParameterDerivative(D * w_, dD * w_, beta, dBeta, dev, g, s.v);
  dM.resize(0, 0);  // massless, as the AD kernel reports it
  return true;
}

double ShellHinge::potential(const LocalState& s) const {
  checkDim(s);
  const VecX& p = *s.p;
  const double D = shell::bendingStiffness(props_->E.value(p), props_->nu.value(p), props_->thickness.value(p));
  const double dev = ad::wrapAngle(dihedralAngle(s.x, nullptr, nullptr, "shell hinge " + name()) - theta0_);
  return 0.5 * D * w_ * dev * dev;  // [J]
}

template class KernelElement<ShellHinge>;

}  // namespace flexsens
