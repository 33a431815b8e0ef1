// Forward-mode automatic differentiation ("ad" sensitivity method) of the element and
// constraint value templates, with Eigen's AutoDiffScalar.
//
// Every kernel is a template on the scalar T (double for the values, AD1/AD2 here):
//   element force   Q(x, v, props)      -> VecT<T>
//   element mass    M(props)            -> MatT<T>
//   constraint      Phi(x, props)       -> VecT<T>
// where props are the values of the Quantities the kernel reads, in a fixed order (the CRTP
// bases KernelElement / KernelConstraint bind the LocalState and pass these callables). A seed
// matrix S (inputs x variables) makes input i the active scalar x_i + S(i, :) z at z = 0, so
// independent variables (S = I), a parameter direction (one column: 1 on every property
// bound to the parameter) and constants (S = 0) are all the same call.
//
// Every input is seeded with a full-length derivative vector, so that constants inside the
// kernels only meet active scalars through scalar-double operations; outputs without any
// derivative (empty vectors, e.g. structural zeros) are read as zero.
//
// Include from .cpp files only (it pulls in unsupported/Eigen/AutoDiff).
#pragma once

#include <cmath>
#include <stdexcept>
#include <unsupported/Eigen/AutoDiff>
#include <vector>

#include "core/Element.hpp"

namespace flexsens::ad {

/// First derivatives.
using AD1 = Eigen::AutoDiffScalar<VecX>;
/// First and second derivatives (nested forward mode): value().derivatives() is the
/// gradient, derivatives()[i].derivatives() row i of the Hessian.
using AD2 = Eigen::AutoDiffScalar<VecT<AD1>>;

/// The double value of a scalar of any nesting level.
inline double valueOf(double x) { return x; }
template <class D>
double valueOf(const Eigen::AutoDiffScalar<D>& x) { return valueOf(x.value()); }

/// Angle wrapped to (-pi, pi] (std::remainder). The wrap shifts by a constant multiple of
/// 2 pi, so every derivative passes through unchanged.
inline double wrapAngle(double a) { return std::remainder(a, 2.0 * M_PI); }
template <class D>
Eigen::AutoDiffScalar<D> wrapAngle(const Eigen::AutoDiffScalar<D>& a) {
  Eigen::AutoDiffScalar<D> r = a;
  r.value() = wrapAngle(a.value());
  return r;
}

// ------------------------------------------------------------------------------ seeding
/// Seed S = [0 .. I .. 0]: m inputs as variables offset .. offset+m-1 of n.
inline MatX unitSeed(int m, int n, int offset) {
  MatX S = MatX::Zero(m, n);
  S.block(0, offset, m, m).setIdentity();
  return S;
}
/// Seed with one nonzero column `col` (of n) equal to dir.
inline MatX directionSeed(const VecX& dir, int n, int col) {
  MatX S = MatX::Zero(dir.size(), n);
  S.col(col) = dir;
  return S;
}

inline VecT<AD1> seed1(const VecX& x0, const MatX& S) {
  VecT<AD1> y(x0.size());
  for (int i = 0; i < x0.size(); ++i) y[i] = AD1(x0[i], VecX(S.row(i).transpose()));
  return y;
}

inline VecT<AD2> seed2(const VecX& x0, const MatX& S) {
  const int n = static_cast<int>(S.cols());
  VecT<AD2> y(x0.size());
  for (int i = 0; i < x0.size(); ++i) {
    VecT<AD1> d(n);
    for (int j = 0; j < n; ++j) d[j] = AD1(S(i, j), VecX::Zero(n));
    y[i] = AD2(AD1(x0[i], VecX(S.row(i).transpose())), d);
  }
  return y;
}

// ----------------------------------------------------------------------------- reading
namespace detail {
inline void checkSize(Eigen::Index got, int n) {
  if (got != 0 && got != n) throw std::logic_error("AD: derivative vector of unexpected size");
}
}  // namespace detail

/// Value of an AD1 vector.
inline VecX values(const VecT<AD1>& y) {
  VecX r(y.size());
  for (int i = 0; i < y.size(); ++i) r[i] = y[i].value();
  return r;
}

/// d y / d z: y.size() x n.
inline MatX jacobian(const VecT<AD1>& y, int n) {
  MatX J = MatX::Zero(y.size(), n);
  for (int i = 0; i < y.size(); ++i) {
    const VecX& d = y[i].derivatives();
    detail::checkSize(d.size(), n);
    if (d.size()) J.row(i) = d.transpose();
  }
  return J;
}

/// Entrywise d M / d z for a single variable z (n = 1).
inline MatX derivative(const MatT<AD1>& M) {
  MatX D = MatX::Zero(M.rows(), M.cols());
  for (int j = 0; j < M.cols(); ++j)
    for (int i = 0; i < M.rows(); ++i) {
      const VecX& d = M(i, j).derivatives();
      detail::checkSize(d.size(), 1);
      if (d.size()) D(i, j) = d[0];
    }
  return D;
}

/// Gradient (n) of a nested scalar.
inline VecX gradient(const AD2& y, int n) {
  VecX g = VecX::Zero(n);
  const VecT<AD1>& d = y.derivatives();
  detail::checkSize(d.size(), n);
  for (int i = 0; i < d.size(); ++i) g[i] = d[i].value();
  return g;
}

/// Hessian (n x n) of a nested scalar.
inline MatX hessian(const AD2& y, int n) {
  MatX H = MatX::Zero(n, n);
  const VecT<AD1>& d = y.derivatives();
  detail::checkSize(d.size(), n);
  for (int i = 0; i < d.size(); ++i) {
    const VecX& h = d[i].derivatives();
    detail::checkSize(h.size(), n);
    if (h.size()) H.row(i) = h.transpose();
  }
  return H;
}

// -------------------------------------------------------------------- parameter binding
/// Values at p of the properties a kernel reads, in its order.
inline VecX propertyValues(const std::vector<const Quantity*>& props, const VecX& p) {
  VecX r(props.size());
  for (size_t i = 0; i < props.size(); ++i) r[i] = props[i]->value(p);
  return r;
}
/// Seed direction of parameter k: 1 on every property bound to k (several properties bound
/// to the same parameter add up by the chain rule), all zero when none is.
inline VecX propertyDirection(const std::vector<const Quantity*>& props, int k) {
  VecX r = VecX::Zero(props.size());
  for (size_t i = 0; i < props.size(); ++i)
    if (props[i]->boundTo(k)) r[i] = 1.0;
  return r;
}

// -------------------------------------------------------------------- element drivers
/// f(x, v, props) -> VecT<T>, a generic callable (e.g. a generic lambda around the force
/// template). dQdq, dQdv by one first-order pass with x and v as the 2n variables.
template <class F>
void forceJacobian(const F& f, const LocalState& s, const VecX& props, MatX& dQdq, MatX& dQdv) {
  const int n = static_cast<int>(s.x.size()), N = 2 * n;
  const VecX v = s.v.size() == n ? s.v : VecX(VecX::Zero(n));
  const VecT<AD1> x = seed1(s.x, unitSeed(n, N, 0));
  const VecT<AD1> w = seed1(v, unitSeed(n, N, n));
  const VecT<AD1> pr = seed1(props, MatX::Zero(props.size(), N));
  const MatX J = jacobian(f(x, w, pr), N);
  dQdq = J.leftCols(n);
  dQdv = J.rightCols(n);
}

/// d f / d t at props + t dir, t = 0 (x and v fixed).
template <class F>
VecX forceParameterDerivative(const F& f, const LocalState& s, const VecX& props, const VecX& dir) {
  const int n = static_cast<int>(s.x.size());
  const VecX v = s.v.size() == n ? s.v : VecX(VecX::Zero(n));
  const VecT<AD1> x = seed1(s.x, MatX::Zero(n, 1));
  const VecT<AD1> w = seed1(v, MatX::Zero(n, 1));
  return jacobian(f(x, w, seed1(props, directionSeed(dir, 1, 0))), 1).col(0);
}

/// m(props) -> MatT<T>: d M / d t at props + t dir.
template <class F>
MatX massParameterDerivative(const F& m, const VecX& props, const VecX& dir) {
  return derivative(m(seed1(props, directionSeed(dir, 1, 0))));
}

// ----------------------------------------------------------------- constraint drivers
/// f(x, props) -> VecT<T>. Phi_q by a first-order pass.
template <class F>
MatX constraintJacobian(const F& f, const LocalState& s, const VecX& props) {
  const int n = static_cast<int>(s.x.size());
  return jacobian(f(seed1(s.x, unitSeed(n, n, 0)), seed1(props, MatX::Zero(props.size(), n))), n);
}

/// Hessian of row r by a nested second-order pass.
template <class F>
MatX constraintHessian(const F& f, const LocalState& s, const VecX& props, int r) {
  const int n = static_cast<int>(s.x.size());
  const VecT<AD2> phi = f(seed2(s.x, unitSeed(n, n, 0)), seed2(props, MatX::Zero(props.size(), n)));
  return hessian(phi[r], n);
}

/// Phi_p (rows) and Phi_qp (rows x n) along dir: nested pass in the n + 1 variables (x, t).
template <class F>
void constraintParameterDerivative(const F& f, const LocalState& s, const VecX& props,
                                   const VecX& dir, VecX& dphi, MatX& dJ) {
  const int n = static_cast<int>(s.x.size()), N = n + 1;
  const VecT<AD2> phi = f(seed2(s.x, unitSeed(n, N, 0)), seed2(props, directionSeed(dir, N, n)));
  dphi.resize(phi.size());
  dJ.resize(phi.size(), n);
  for (int r = 0; r < phi.size(); ++r) {
    dphi[r] = gradient(phi[r], N)[n];
    dJ.row(r) = hessian(phi[r], N).row(n).head(n);
  }
}

}  // namespace flexsens::ad
