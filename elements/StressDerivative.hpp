// Forward-mode AD in one direction for the stress outputs of meshed bodies (Solid, ShellTriangle):
// a stress template evaluated with AD1 scalars seeded by the run's dq/dp and the parameter's
// own direction gives the chain-rule derivative d(strain, stress)/dp of a .vtu cell.
#pragma once

#include <unsupported/Eigen/AutoDiff>

#include <cmath>

#include "core/Types.hpp"

namespace flexsens::stressad {

using AD1 = Eigen::AutoDiffScalar<Eigen::Matrix<double, 1, 1>>;

/// The value v with directional derivative dv.
inline AD1 seeded(double v, double dv) { return AD1(v, Eigen::Matrix<double, 1, 1>::Constant(dv)); }

/// The directional derivatives of a matrix of AD1.
inline MatX derivativeOf(const MatT<AD1>& A) {
  MatX D(A.rows(), A.cols());
  for (int r = 0; r < A.rows(); ++r)
    for (int c = 0; c < A.cols(); ++c) D(r, c) = A(r, c).derivatives()[0];
  return D;
}

/// d(von Mises) from the deviatoric Cauchy stress dev (3 x 3, AD1): d sqrt(1.5 dev:dev) =
/// 1.5 dev:ddev / vm; at zero stress, where it has none, the one-sided directional one
/// |ddev| sqrt(3/2).
inline double vonMisesDerivative(const MatT<AD1>& dev) {
  MatX value(dev.rows(), dev.cols());
  for (int r = 0; r < dev.rows(); ++r)
    for (int c = 0; c < dev.cols(); ++c) value(r, c) = dev(r, c).value();
  const MatX d = derivativeOf(dev);
  const double vm = std::sqrt(1.5 * (value.array() * value.array()).sum());
  return vm > 0.0 ? 1.5 * (value.array() * d.array()).sum() / vm : std::sqrt(1.5 * (d.array() * d.array()).sum());
}

/// The directional derivative of an element's stress output along positions dx and (E, nu)
/// seeds dYoung, dNu: stressT(x, E, nu, E_out, S, sigma, dev) (MatT<AD1> outputs, dev the
/// deviatoric Cauchy stress) evaluated once in AD1.
template <class StressT>
void directionalDerivative(const VecX& x, const VecX& dx, double young, double dYoung, double nu, double dNu,
                           const StressT& stressT, MatX& dE, MatX& dS, MatX& dsigma, double& dVonMises) {
  VecT<AD1> xs(x.size());
  for (int i = 0; i < x.size(); ++i) xs[i] = seeded(x[i], dx[i]);
  MatT<AD1> E, S, sigma, dev;
  stressT(xs, seeded(young, dYoung), seeded(nu, dNu), E, S, sigma, dev);
  dE = derivativeOf(E);
  dS = derivativeOf(S);
  dsigma = derivativeOf(sigma);
  dVonMises = vonMisesDerivative(dev);
}

}  // namespace flexsens::stressad
