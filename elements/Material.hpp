// Hyperelastic laws of the continuum elements (elements/Solid.hpp), in the total Lagrangian
// form: second Piola-Kirchhoff stress S from the Green-Lagrange strain E = (C - I) / 2,
// C = F^T F, with Lame constants (mu, lambda) from Young's modulus and Poisson's ratio.
//
//  - St. Venant-Kirchhoff: W = lambda/2 tr(E)^2 + mu E:E, S = lambda tr(E) I + 2 mu E.
//  - compressible neo-Hookean (Ogden / Bonet & Wood form):
//      W = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2,  S = mu (I - C^-1) + lambda ln J C^-1.
//
// Planar states (d = 2, stresses per unit thickness times the thickness):
//  - plane strain: E33 = 0; the 2x2 formulas as they stand (C33 = 1, J = sqrt(det C)).
//  - plane stress: S33 = 0. St. Venant-Kirchhoff: lambda becomes 2 lambda mu / (lambda + 2 mu)
//    = E nu / (1 - nu^2). Neo-Hookean: C33 = c solves mu (c - 1) + lambda ln J = 0 with
//    ln J = (ln det C + ln c) / 2 (Newton in double; for AD one more Newton step in T, which
//    carries the exact first derivatives of the implicit c); then S = mu (I - c C^-1).
//
// Each law gives S as a value template (the force templates the AD kernels differentiate);
// elements/MaterialPoint.hpp evaluates the same laws in fixed size with their tangent dS/dE,
// dS/dmu, dS/dlambda and W for the analytic kernels. Units: mu, lambda, S [Pa]; E, C [-]; W [J/m^3].
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

#include <type_traits>

#include "core/Element.hpp"

namespace flexsens {

enum class Law { SaintVenantKirchhoff, NeoHookean };
enum class PlanarState { None, PlaneStress, PlaneStrain };  ///< None: spatial (d = 3)

namespace material {

/// The double value of a scalar of any AD nesting level (AutoDiffScalar has value()).
template <class T> double plain(const T& x) {
  if constexpr (std::is_arithmetic_v<T>) return x;
  else return plain(x.value());
}

/// Lame constants [Pa] from E [Pa], nu [-]: mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)).
template <class T> T mu(const T& E, const T& nu) { return E / (2.0 * (1.0 + nu)); }
template <class T> T lambda(const T& E, const T& nu) { return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); }
/// d(mu, lambda)/d(E, nu).
inline void lameDerivatives(double E, double nu, double& muE, double& muNu, double& lamE, double& lamNu) {
  const double D = (1.0 + nu) * (1.0 - 2.0 * nu);
  muE = 0.5 / (1.0 + nu);
  muNu = -0.5 * E / ((1.0 + nu) * (1.0 + nu));
  lamE = nu / D;
  lamNu = E * (1.0 + 2.0 * nu * nu) / (D * D);
}

/// The plane-stress St. Venant-Kirchhoff lambda (2 lambda mu / (lambda + 2 mu)) and its
/// derivatives; also the lambda of the linear (rest) tangent of every plane-stress law.
template <class T> T planeStressLambda(const T& mu, const T& lam) { return 2.0 * lam * mu / (lam + 2.0 * mu); }

template <class T> T det(const MatT<T>& A) {
  return A.rows() == 2 ? T(A(0, 0) * A(1, 1) - A(0, 1) * A(1, 0))
                       : T(A(0, 0) * (A(1, 1) * A(2, 2) - A(1, 2) * A(2, 1)) -
                           A(0, 1) * (A(1, 0) * A(2, 2) - A(1, 2) * A(2, 0)) +
                           A(0, 2) * (A(1, 0) * A(2, 1) - A(1, 1) * A(2, 0)));
}
/// Inverse by cofactors (Eigen's inverse() does not take AutoDiff scalars of dynamic size).
template <class T> MatT<T> inverse(const MatT<T>& A) {
  const T D = det(A);
  MatT<T> R(A.rows(), A.cols());
  if (A.rows() == 2) {
    R(0, 0) = A(1, 1) / D;
    R(1, 1) = A(0, 0) / D;
    R(0, 1) = -A(0, 1) / D;
    R(1, 0) = -A(1, 0) / D;
    return R;
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
      R(i, j) = (A(i1, j1) * A(i2, j2) - A(i1, j2) * A(i2, j1)) / D;
    }
  return R;
}

/// Plane-stress neo-Hookean C33 from ln det C (double): Newton on f(c) = mu (c - 1) +
/// lambda/2 (lnD + ln c), f' = mu + lambda / (2 c) > 0, f concave: from c = 1 it converges.
inline double planeStressC33(double mu, double lam, double lnD) {
  double c = 1.0;
  for (int it = 0; it < 100; ++it) {
    const double f = mu * (c - 1.0) + 0.5 * lam * (lnD + std::log(c));
    const double dc = f / (mu + 0.5 * lam / c);
    c -= dc;
    if (!(c > 0.0)) c = 1e-12;  // keep the log defined; f is increasing in c
    if (std::abs(dc) < 1e-15 * c) break;
  }
  return c;
}

}  // namespace material

struct MaterialLaw {
  Law law = Law::SaintVenantKirchhoff;
  PlanarState planar = PlanarState::None;

  bool planeStress() const { return planar == PlanarState::PlaneStress; }
  /// The lambda the law uses: the plane-stress SVK value, else lambda itself.
  template <class T> T lambdaUsed(const T& mu, const T& lam) const {
    return law == Law::SaintVenantKirchhoff && planeStress() ? material::planeStressLambda(mu, lam) : lam;
  }

  /// Second Piola-Kirchhoff stress S(E) [Pa]. Neo-Hookean needs det C > 0 (throws NumericalError
  /// naming `who` otherwise: the element is inside out).
  template <class T>
  MatT<T> stress(const MatT<T>& E, const T& mu, const T& lam, const std::string& who) const {
    using std::log;
    const int d = static_cast<int>(E.rows());
    const MatT<T> I = MatT<T>::Identity(d, d);
    if (law == Law::SaintVenantKirchhoff) return lambdaUsed(mu, lam) * E.trace() * I + 2.0 * mu * E;
    const MatT<T> C = 2.0 * E + I;
    const T D = material::det(C);
    if (!(material::plain(D) > 0.0)) throw NumericalError(who + ": inverted (det F <= 0): the neo-Hookean law is undefined");
    const MatT<T> Ci = material::inverse(C);
    if (!planeStress()) return mu * (I - Ci) + (lam * 0.5 * log(D)) * Ci;
    const T c = c33(mu, lam, D);
    return mu * (I - c * Ci);
  }

 private:
  /// Plane-stress neo-Hookean C33 as a T: converged in double, then one Newton step in T.
  template <class T> T c33(const T& mu, const T& lam, const T& D) const {
    using std::log;
    const double c0 = material::planeStressC33(material::plain(mu), material::plain(lam), std::log(material::plain(D)));
    const T f = mu * (c0 - 1.0) + 0.5 * lam * (log(D) + std::log(c0));
    return c0 - f / (mu + 0.5 * lam / c0);
  }
};

}  // namespace flexsens
