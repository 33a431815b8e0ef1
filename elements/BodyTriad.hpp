// Small 3D vector helpers shared by the spatial loads (elements/SpatialTorque.hpp,
// elements/SpatialFollowerForce.hpp), written on the scalar type T so that the same lines
// serve the values (double) and the AD kernels. Constants meet active scalars only through
// scalar-double operations (elements/AutoDiff.hpp).
//
// A follower vector turns with a body through three of its nodes A, B, C: with the triad
// E(q) = [d1, d2, n], d1 = x_B - x_A, d2 = x_C - x_A, n = d1 x d2, and the coefficients
// a = E0^-1 V0 of the vector V0 given in global components at t = 0,
//   V(q) = a1 d1 + a2 d2 + a3 n,
// exactly R V0 when the three nodes move rigidly (E = R E0, n too since det R = 1).
#pragma once

#include <Eigen/Dense>

#include "core/Element.hpp"

namespace flexsens::triad {

template <class T>
using V3 = Eigen::Matrix<T, 3, 1>;

template <class T>
V3<T> cross(const V3<T>& a, const V3<T>& b) {
  V3<T> r;
  r << T(a[1] * b[2] - a[2] * b[1]), T(a[2] * b[0] - a[0] * b[2]), T(a[0] * b[1] - a[1] * b[0]);
  return r;
}

/// Position of local node k (3 coordinates per node).
template <class T>
V3<T> at(const VecT<T>& x, int k) {
  return x.template segment<3>(3 * k);
}

/// [v]x, so that [v]x w = v x w.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

/// Inverse of the triad [d1, d2, d1 x d2]; d1, d2 must not be parallel.
inline Eigen::Matrix3d inverseTriad(const Eigen::Vector3d& d1, const Eigen::Vector3d& d2) {
  Eigen::Matrix3d E;
  E << d1, d2, d1.cross(d2);
  return E.inverse();
}

/// The follower vector fac (a1 d1 + a2 d2 + a3 n), a = Einv0 V0, for the components V0 = c
/// (3 entries) at time factor fac.
template <class T>
V3<T> follower(const V3<T>& d1, const V3<T>& d2, const Eigen::Matrix3d& Einv0, const VecT<T>& c, double fac) {
  T a[3];
  for (int i = 0; i < 3; ++i) a[i] = c[0] * (fac * Einv0(i, 0)) + c[1] * (fac * Einv0(i, 1)) + c[2] * (fac * Einv0(i, 2));
  return a[0] * d1 + a[1] * d2 + a[2] * cross(d1, d2);
}

/// dV/dd1 and dV/dd2 of the follower vector (a = fac Einv0 c, double):
///   dV/dd1 = a1 I - a3 [d2]x,  dV/dd2 = a2 I + a3 [d1]x.
inline void followerJacobian(const Eigen::Vector3d& d1, const Eigen::Vector3d& d2, const Eigen::Vector3d& a,
                             Eigen::Matrix3d& D1, Eigen::Matrix3d& D2) {
  D1 = a[0] * Eigen::Matrix3d::Identity() - a[2] * skew(d2);
  D2 = a[1] * Eigen::Matrix3d::Identity() + a[2] * skew(d1);
}

}  // namespace flexsens::triad
