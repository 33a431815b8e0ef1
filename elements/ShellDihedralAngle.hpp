// The dihedral angle of a discrete-shell hinge (elements/ShellHinge.hpp: the angle, its
// notation and its derivatives) as a value template on the scalar, shared by the interior hinge
// and the clamped-edge hinge (elements/ShellClampHinge.hpp). Include from .cpp files only (it
// needs elements/AutoDiff.hpp's ad::valueOf).
#pragma once

#include <cmath>
#include <string>

#include "elements/AutoDiff.hpp"
#include "elements/BodyTriad.hpp"

namespace flexsens::shell {

using triad::V3;
using triad::cross;

/// |n1| |n2| below this times |e|^4 is a triangle of zero area.
constexpr double kDegenerateTol = 1e-12;

/// theta and its gradient (12) at x (12) for any scalar; false for a zero edge or triangle.
template <class T>
bool angleT(const VecT<T>& x, T& theta, VecT<T>& g) {
  using std::sqrt;
  using std::atan2;
  const V3<T> x0 = x.template segment<3>(0);
  const V3<T> e = x.template segment<3>(3) - x0, a = x.template segment<3>(6) - x0, b = x.template segment<3>(9) - x0;
  const T ee = e.dot(e), ea = e.dot(a), eb = e.dot(b), ab = a.dot(b);
  if (!(ad::valueOf(ee) > 0.0)) return false;
  const T L = sqrt(ee);
  const V3<T> axb = cross(a, b);
  const T det = e.dot(axb);
  const T X = ea * eb - ee * ab, Y = L * det, R = X * X + Y * Y;
  if (!(std::sqrt(ad::valueOf(R)) > kDegenerateTol * ad::valueOf(ee) * ad::valueOf(ee))) return false;
  const V3<T> gXe = eb * a + ea * b - (2.0 * ab) * e, gXa = eb * e - ee * b, gXb = ea * e - ee * a;
  const V3<T> gYe = (det / L) * e + L * axb, gYa = L * cross(b, e), gYb = L * cross(e, a);
  const V3<T> te = (X * gYe - Y * gXe) / R, ta = (X * gYa - Y * gXa) / R, tb = (X * gYb - Y * gXb) / R;
  theta = atan2(Y, X);
  g.resize(12);
  g.template segment<3>(0) = -(te + ta + tb);
  g.template segment<3>(3) = te;
  g.template segment<3>(6) = ta;
  g.template segment<3>(9) = tb;
  return true;
}

inline std::string degenerateMessage(const std::string& who) {
  return who + ": a triangle of the hinge has zero area (or its edge zero length): the dihedral angle is undefined";
}

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

/// theta, its gradient (12) and, when hess is given, its Hessian (12 x 12) at x (12), in fixed
/// size (ShellHinge.cpp); false for a zero edge or triangle.
bool angleDerivatives(const Vec12& x, double& theta, Vec12& grad, Mat12* hess);

/// The bending law of a hinge or clamp on an angle with deviation dev from rest, gradient g and
/// Hessian H (M positions x): Q = -D w (dev + beta g.v) g, the Kelvin-Voigt moment included.
/// Its analytic Jacobians: dQ/dq = -D w (g (g + beta H v)^T + (dev + beta g.v) H) [N/m],
/// dQ/dv = -D w beta g g^T [N s/m]; v empty means zero velocities. No heap once dQdq and dQdv
/// have their size.
template <int M>
void bendingJacobians(double Dw, double beta, double dev, const Eigen::Matrix<double, M, 1>& g,
                      const Eigen::Matrix<double, M, M>& H, const VecX& v, MatX& dQdq, MatX& dQdv) {
  dQdq.resize(M, M);
  dQdv.resize(M, M);
  Eigen::Map<Eigen::Matrix<double, M, M>> Kq(dQdq.data()), Kv(dQdv.data());
  Eigen::Matrix<double, M, 1> dir = g;  // g + beta H v
  double moment = dev;                  // dev + beta g.v
  if (beta != 0.0 && v.size() == M) {
    const Eigen::Map<const Eigen::Matrix<double, M, 1>> w(v.data());
    dir.noalias() += beta * (H * w);
    moment += beta * g.dot(w);
  }
  Kq.noalias() = (-Dw * moment) * H;
  Kq.noalias() -= (Dw * g) * dir.transpose();
  if (beta != 0.0) Kv.noalias() = (-Dw * beta * g) * g.transpose();
  else Kv.setZero();
}

/// Q of the same law: -D w (dev + beta g.v) g.
template <int M>
void bendingForce(double Dw, double beta, double dev, const Eigen::Matrix<double, M, 1>& g, const VecX& v, VecX& Q) {
  double moment = dev;
  if (beta != 0.0 && v.size() == M) moment += beta * g.dot(Eigen::Map<const Eigen::Matrix<double, M, 1>>(v.data()));
  Q.resize(M);
  Eigen::Map<Eigen::Matrix<double, M, 1>>(Q.data()) = (-Dw * moment) * g;
}

/// dQ/dp of the same law, for d(D w)/dp = dDw and dbeta/dp = dBeta.
template <int M>
void bendingParameterDerivative(double Dw, double dDw, double beta, double dBeta, double dev,
                                const Eigen::Matrix<double, M, 1>& g, const VecX& v, VecX& dQ) {
  const double rate = v.size() == M ? g.dot(Eigen::Map<const Eigen::Matrix<double, M, 1>>(v.data())) : 0.0;
  dQ.resize(M);
  Eigen::Map<Eigen::Matrix<double, M, 1>>(dQ.data()) = -(dDw * (dev + beta * rate) + Dw * dBeta * rate) * g;
}

}  // namespace flexsens::shell
