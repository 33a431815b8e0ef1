// Material and thickness of one discrete shell (elements/ShellTriangle.hpp membranes,
// elements/ShellHinge.hpp bending), shared by its elements, and the plate constants they
// derive from them.
//
// Units: E [Pa], nu [-], density [kg/m^3], thickness [m], alpha [1/s], beta [s].
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/Types.hpp"
#include "elements/Material.hpp"

namespace flexsens {

struct ShellProperties {
  Quantity E;                 ///< Young's modulus [Pa]
  Quantity nu;                ///< Poisson's ratio [-], in (-1, 0.5)
  Quantity density;           ///< [kg/m^3]
  Quantity thickness;         ///< [m]
  Quantity alpha{0.0, -1};    ///< mass-proportional damping [1/s]
  Quantity beta{0.0, -1};     ///< stiffness-proportional (Kelvin-Voigt) damping [s]
  /// The membrane's law, always in plane stress (S33 = 0); the hinges' bending stays linear in
  /// the dihedral angle with D from E, nu, thickness (small bending strains of a thin shell).
  MaterialLaw law{Law::SaintVenantKirchhoff, PlanarState::PlaneStress};
  /// The bending stiffness D [N m] and beta [s] at p and their derivatives along parameter k
  /// (the chain rule over E, nu, thickness); false when neither depends on p_k.
  bool bendingDerivative(const VecX& p, int k, double& D, double& dD, double& b, double& dB) const;
  /// False when a damping can never be nonzero (constant 0): the forces then never depend on v.
  bool damped() const { return alpha.param >= 0 || alpha.constant != 0.0 || bendingDamped(); }
  bool bendingDamped() const { return beta.param >= 0 || beta.constant != 0.0; }  ///< beta's alone
  std::vector<std::pair<std::string, Quantity*>> properties() {
    return {{"E", &E}, {"nu", &nu}, {"density", &density}, {"thickness", &thickness}, {"alpha", &alpha}, {"beta", &beta}};
  }
};

namespace shell {
/// Plate bending stiffness D = E t^3 / (12 (1 - nu^2)) [N m].
template <class T> T bendingStiffness(const T& E, const T& nu, const T& t) {
  return E * t * t * t / (12.0 * (1.0 - nu * nu));
}
/// dD/dE, dD/dnu, dD/dt at (E, nu, t).
inline void bendingStiffnessDerivatives(double E, double nu, double t, double& dE, double& dNu, double& dT) {
  const double D = bendingStiffness(E, nu, t);
  dE = D / E;
  dNu = D * 2.0 * nu / (1.0 - nu * nu);
  dT = 3.0 * D / t;
}
}  // namespace shell

inline bool ShellProperties::bendingDerivative(const VecX& p, int k, double& D, double& dD, double& b,
                                               double& dB) const {
  const double dYoung = E.boundTo(k), dNu = nu.boundTo(k), dT = thickness.boundTo(k);
  dB = beta.boundTo(k);
  if (!(dYoung || dNu || dT || dB)) return false;
  double DE, DNu, DT;
  shell::bendingStiffnessDerivatives(E.value(p), nu.value(p), thickness.value(p), DE, DNu, DT);
  D = shell::bendingStiffness(E.value(p), nu.value(p), thickness.value(p));
  dD = DE * dYoung + DNu * dNu + DT * dT;
  b = beta.value(p);
  return true;
}

}  // namespace flexsens
