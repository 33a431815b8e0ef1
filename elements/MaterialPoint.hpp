// The laws of elements/Material.hpp at one quadrature point in fixed size (double): the second
// Piola-Kirchhoff stress S and the material tangent dS/dE in Voigt form, from C, C^-1 and
// det C computed once per point. For the analytic force and Jacobian kernels of the continuum
// elements (elements/ContinuumKernel.hpp); the value templates of Material.hpp stay the
// reference the AD kernels and the tests differentiate.
//
// Every law's tangent has the form  dS = a C^-1 dE C^-1 + b tr(C^-1 dE) C^-1, i.e.
//   C_ABCD = b Ci_AB Ci_CD + a/2 (Ci_AC Ci_BD + Ci_AD Ci_BC):
//  - St. Venant-Kirchhoff: Ci = I, a = 2 mu, b = lambda used (plane stress: E nu / (1 - nu^2));
//  - neo-Hookean (spatial, plane strain): a = 2 (mu - lambda ln J), b = lambda;
//  - neo-Hookean plane stress: a = 2 mu c, b = mu lambda / (mu + lambda / (2 c)), c = C33.
// Voigt order: (11, 22, 12) in 2D, (11, 22, 33, 12, 23, 13) in 3D; stresses as they are,
// strains with engineering shears (2 E_12), so that dS_voigt = D dE_voigt and E : S = E_v . S_v.
// Units: mu, lambda, S, D [Pa]; C, E [-].
#pragma once

#include <cmath>

#include <Eigen/Dense>

#include "elements/Material.hpp"

namespace flexsens::material {

/// Voigt components of a symmetric DM x DM tensor.
constexpr int voigtSize(int dm) { return dm == 2 ? 3 : 6; }
/// The (row, column) of Voigt component I.
constexpr int voigtRow(int dm, int I) { return dm == 2 ? (I < 2 ? I : 0) : (I < 3 ? I : I - 3); }
constexpr int voigtCol(int dm, int I) { return dm == 2 ? (I < 2 ? I : 1) : (I < 3 ? I : (I - 2) % 3); }

template <int DM>
using Sym = Eigen::Matrix<double, DM, DM>;
template <int DM>
using VoigtMatrix = Eigen::Matrix<double, voigtSize(DM), voigtSize(DM)>;

/// C = b Ci (x) Ci + a Ci (.) Ci in Voigt form (Ci symmetric).
template <int DM>
VoigtMatrix<DM> isotropicTangent(const Sym<DM>& Ci, double a, double b) {
  constexpr int NV = voigtSize(DM);
  VoigtMatrix<DM> D;
  for (int I = 0; I < NV; ++I) {
    const int A = voigtRow(DM, I), B = voigtCol(DM, I);
    for (int J = I; J < NV; ++J) {
      const int C = voigtRow(DM, J), E = voigtCol(DM, J);
      D(I, J) = D(J, I) = b * Ci(A, B) * Ci(C, E) + 0.5 * a * (Ci(A, C) * Ci(B, E) + Ci(A, E) * Ci(B, C));
    }
  }
  return D;
}

/// S and dS/dE at one point.
template <int DM>
struct PointStress {
  Sym<DM> S;          ///< second Piola-Kirchhoff stress [Pa]
  VoigtMatrix<DM> D;  ///< dS/dE (Voigt, engineering shears) [Pa]; filled when asked for
};

/// S (and D when withTangent) of `law` at C = F^T F. False when the neo-Hookean law is
/// undefined (det C <= 0): the caller throws, naming the element.
template <int DM>
bool pointStress(const MaterialLaw& law, const Sym<DM>& C, double mu, double lam, bool withTangent,
                 PointStress<DM>& out) {
  const Sym<DM> I = Sym<DM>::Identity();
  if (law.law == Law::SaintVenantKirchhoff) {
    const double lu = law.lambdaUsed(mu, lam);
    const Sym<DM> E = 0.5 * (C - I);
    out.S = (lu * E.trace()) * I + (2.0 * mu) * E;
    if (withTangent) out.D = isotropicTangent<DM>(I, 2.0 * mu, lu);
    return true;
  }
  const double detC = C.determinant();
  if (!(detC > 0.0)) return false;
  const Sym<DM> Ci = C.inverse();
  double a, b;
  if (!law.planeStress()) {  // S = mu (I - C^-1) + lambda ln J C^-1
    const double lnJ = 0.5 * std::log(detC);
    out.S = mu * (I - Ci) + (lam * lnJ) * Ci;
    a = 2.0 * (mu - lam * lnJ);
    b = lam;
  } else {  // S = mu (I - c C^-1), c = C33 from S33 = 0
    const double c = planeStressC33(mu, lam, std::log(detC));
    out.S = mu * (I - c * Ci);
    a = 2.0 * mu * c;
    b = mu * lam / (mu + 0.5 * lam / c);
  }
  if (withTangent) out.D = isotropicTangent<DM>(Ci, a, b);
  return true;
}

/// The strain energy density W [J/m^3] of `law` at C = F^T F, as MaterialLaw::energy (planar:
/// C33 = 1, or c from S33 = 0 in plane stress). Neo-Hookean needs det C > 0.
template <int DM>
double pointEnergy(const MaterialLaw& law, const Sym<DM>& C, double mu, double lam) {
  if (law.law == Law::SaintVenantKirchhoff) {
    const Sym<DM> E = 0.5 * (C - Sym<DM>::Identity());
    const double tr = E.trace();
    return 0.5 * law.lambdaUsed(mu, lam) * tr * tr + mu * E.squaredNorm();
  }
  const double lnD = std::log(C.determinant());
  double I1 = C.trace() + (DM == 2 ? 1.0 : 0.0), lnJ = 0.5 * lnD;
  if (law.planeStress()) {
    const double c = planeStressC33(mu, lam, lnD);
    I1 += c - 1.0;
    lnJ += 0.5 * std::log(c);
  }
  return 0.5 * mu * (I1 - 3.0) - mu * lnJ + 0.5 * lam * lnJ * lnJ;
}

/// dS = dS/dmu dmu + dS/dlambda dlam of `law` at C = F^T F (det C > 0 for neo-Hookean: the
/// caller has evaluated pointStress there). As MaterialLaw::stressDerivatives.
template <int DM>
Sym<DM> stressParameterDerivative(const MaterialLaw& law, const Sym<DM>& C, double mu, double lam, double dmu,
                                  double dlam) {
  const Sym<DM> I = Sym<DM>::Identity();
  if (law.law == Law::SaintVenantKirchhoff) {
    double lMu = 0.0, lLam = 1.0;  // d lambdaUsed / d(mu, lambda)
    if (law.planeStress()) {
      const double s = lam + 2.0 * mu;
      lMu = 2.0 * lam * lam / (s * s);
      lLam = 4.0 * mu * mu / (s * s);
    }
    const Sym<DM> E = 0.5 * (C - I);
    return ((lMu * dmu + lLam * dlam) * E.trace()) * I + (2.0 * dmu) * E;
  }
  const double lnD = std::log(C.determinant());
  const Sym<DM> Ci = C.inverse();
  if (!law.planeStress()) return dmu * (I - Ci) + (0.5 * lnD * dlam) * Ci;
  // S = mu (I - c C^-1); f(c; mu, lambda) = mu (c - 1) + lambda ln J = 0 gives
  // dc/dmu = -(c - 1) / f_c, dc/dlambda = -ln J / f_c.
  const double c = planeStressC33(mu, lam, lnD);
  const double fc = mu + 0.5 * lam / c, lnJ = 0.5 * (lnD + std::log(c));
  return dmu * (I - c * Ci) + (mu * (dmu * (c - 1.0) + dlam * lnJ) / fc) * Ci;
}

/// d(mu, lambda) [Pa] along (dE, dnu) at (E, nu), and of lambda0, the lambda of the rest
/// elasticity C0 (planeStress: 2 lambda mu / (lambda + 2 mu), else lambda).
struct LameDerivative {
  double mu, lam, lam0;
};
inline LameDerivative lameDerivative(double E, double nu, double dE, double dNu, bool planeStress) {
  double muE, muNu, lamE, lamNu;
  lameDerivatives(E, nu, muE, muNu, lamE, lamNu);
  LameDerivative d{muE * dE + muNu * dNu, lamE * dE + lamNu * dNu, 0.0};
  d.lam0 = d.lam;
  if (planeStress) {  // d(2 lambda mu / (lambda + 2 mu)) = (2 lambda^2 dmu + 4 mu^2 dlambda) / (lambda + 2 mu)^2
    const double m = mu(E, nu), l = lambda(E, nu), sum = l + 2.0 * m;
    d.lam0 = (2.0 * l * l * d.mu + 4.0 * m * m * d.lam) / (sum * sum);
  }
  return d;
}

/// The rest (linear) elasticity C0 : A = lambda0 tr(A) I + 2 mu A of a symmetric A [Pa].
template <int DM>
Sym<DM> restElasticity(double mu, double lambda0, const Sym<DM>& A) {
  return (lambda0 * A.trace()) * Sym<DM>::Identity() + (2.0 * mu) * A;
}

}  // namespace flexsens::material
