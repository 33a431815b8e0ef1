// Signed angle between two vectors about an axis, in natural coordinates (points only):
//   n = x1 - x0 (axis), w1 = x3 - x2 (from), w2 = x5 - x4 (to), u = n / |n|
//   theta = atan2(u . (w1 x w2), w1 . w2 - (u . w1)(u . w2))       in (-pi, pi] [rad]
// i.e. the angle from w1 to w2 measured in the plane normal to the axis (both vectors
// projected on it), positive counter-clockwise about u. Smooth wherever |n| > 0 and the
// projections do not vanish. Used by the rotational spring-damper of a revolute joint and by
// the angle outputs (panel opening angles, joint angles).
// x is the 18-vector of the six points (any of them may be the same node).
#pragma once

#include <cmath>

#include "core/Element.hpp"

namespace flexsens {

/// theta(x) and, if grad != nullptr, d theta / d x (18), for any scalar type (AD kernels).
template <class T>
T jointAngleT(const VecT<T>& x, VecT<T>* grad) {
  using std::atan2;
  using std::sqrt;
  using V3 = Eigen::Matrix<T, 3, 1>;
  const V3 n = x.template segment<3>(3) - x.template segment<3>(0);
  const V3 w1 = x.template segment<3>(9) - x.template segment<3>(6);
  const V3 w2 = x.template segment<3>(15) - x.template segment<3>(12);
  const T nn = n.dot(n), L = sqrt(nn);
  const V3 w12 = w1.cross(w2);
  const T Tr = n.dot(w12);              // triple product det[n, w1, w2]
  const T a = n.dot(w1), b = n.dot(w2);
  const T s = Tr / L;                   // sine part  [m^2]
  const T c = w1.dot(w2) - a * b / nn;  // cosine part [m^2]
  const T theta = atan2(s, c);
  if (grad) {
    // d s = dT / L - T n . dn / L^3;  d c = w2.dw1 + w1.dw2 - (b da + a db)/nn + 2 a b n.dn / nn^2
    const V3 sn = w12 / L - (Tr / (L * nn)) * n, s1 = w2.cross(n) / L, s2 = n.cross(w1) / L;
    const V3 cn = -(b * w1 + a * w2) / nn + (2.0 * a * b / (nn * nn)) * n;
    const V3 c1 = w2 - (b / nn) * n, c2 = w1 - (a / nn) * n;
    const T r2 = s * s + c * c;
    const V3 gn = (c * sn - s * cn) / r2, g1 = (c * s1 - s * c1) / r2, g2 = (c * s2 - s * c2) / r2;
    grad->resize(18);
    grad->template segment<3>(0) = -gn;
    grad->template segment<3>(3) = gn;
    grad->template segment<3>(6) = -g1;
    grad->template segment<3>(9) = g1;
    grad->template segment<3>(12) = -g2;
    grad->template segment<3>(15) = g2;
  }
  return theta;
}

/// Analytic Hessian d2 theta / d x2 (18 x 18) at x (hand-derived; checked against finite
/// differences and against AD of jointAngleT's gradient in the tests).
MatX jointAngleHessian(const VecX& x);

/// Node list of an angle (axis from, axis to, from-vector from/to, to-vector from/to).
struct AngleNodes {
  int axis0, axis1, from0, from1, to0, to1;
  std::vector<int> list() const { return {axis0, axis1, from0, from1, to0, to1}; }
};

}  // namespace flexsens
