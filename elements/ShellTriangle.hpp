// Membrane and mass of one triangle of a discrete shell (elements/ShellMesh.hpp): 3 nodes
// in 3D, positions only. Bending is carried by the hinges on the interior edges
// (elements/ShellHinge.hpp).
//
// Constant strain triangle, total Lagrangian on the rest triangle X0, X1, X2 [m]: with an
// orthonormal basis (t1, t2) of the rest plane, Dm = [X1 - X0, X2 - X0] in that basis (2x2),
//   F = [x1 - x0, x2 - x0] Dm^-1  (3x2),  E = (F^T F - I) / 2  (2x2, Green-Lagrange),
//   S = S(E) in plane stress (S33 = 0; elements/Material.hpp): St. Venant-Kirchhoff
//   S = lambda* tr(E) I + 2 mu E, lambda* = E nu / (1 - nu^2), or compressible neo-Hookean
//   S = mu (I - c C^-1) with the thickness stretch^2 c from S33 = 0 (the thickness follows
//   the membrane's area change), mu = E / (2 (1 + nu)) [Pa],
//   U = A t W(E)  [J],   Q_i = -A t F S G_i,  G_i = dN_i/dX (2).
// A the rest area [m^2], t the thickness [m]. Frame-indifferent: any rigid motion of the rest
// triangle gives E = 0 and Q = 0. No drilling or transverse stiffness of its own.
// Mass: consistent and constant, M = rho t A / 12 (1 + delta_ij) I3 [kg]; gravity Q_i =
// rho t A / 3 g; optional Rayleigh damping: mass-proportional Q = -alpha M v and the
// Kelvin-Voigt membrane stress beta C0 : dE/dt (C0 the rest plane-stress elasticity: beta K0 v
// at small strain, zero under rigid motion; the hinges carry its bending part).
// Design parameters: E, nu, density, thickness, alpha, beta.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "elements/KernelElement.hpp"
#include "elements/ShellProperties.hpp"

namespace flexsens {

class ShellTriangle : public KernelElement<ShellTriangle> {
 public:
  /// restX: rest positions of the 3 nodes (9 entries [m]). Throws std::invalid_argument for a
  /// degenerate rest triangle (area below 1e-10 (longest edge)^2).
  ShellTriangle(std::string name, std::vector<int> nodes, std::shared_ptr<ShellProperties> props, const VecX& restX);
  std::string kind() const override { return "shell_triangle"; }
  /// Q and its Jacobians by the fixed-size kernel (elements/ContinuumKernel.hpp, no heap);
  /// kernelForce() and the AD Jacobians evaluate the value template forceT instead.
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return props_->damped(); }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return props_->properties(); }

  double restArea() const { return A_; }  ///< [m^2]
  /// Mass, gravity and mass damping only: the membrane is another element's
  /// (elements/ShellPatchMembrane.hpp, `membrane: patch`).
  void disableMembrane() { membrane_ = false; }
  bool hasMembrane() const { return membrane_; }
  /// For output, at s.x and the nominal values s.p: Green-Lagrange strain E and second
  /// Piola-Kirchhoff stress S as 3x3 tensors in the scene's axes (the rest plane's 2x2 ones
  /// rotated by the rest basis), the membrane Cauchy stress sigma = F S F^T / J (J the area
  /// ratio, thickness change ignored) [Pa] and its von Mises stress (plane stress) [Pa].
  void membraneStress(const LocalState& s, MatX& E, MatX& S, MatX& sigma, double& vonMises) const;
  /// Their derivatives with respect to parameter k along dx = d x/dp_k of the 3 nodes'
  /// positions (the run's dq/dp; 0 for ground nodes): the chain rule through F plus the
  /// explicit dependence on E and nu (the thickness enters none of them), by forward AD of the
  /// same template as membraneStress.
  void membraneStressDerivative(const LocalState& s, const VecX& dx, int k, MatX& dE, MatX& dS, MatX& dsigma,
                                double& dVonMises) const;

 private:
  friend class KernelElement<ShellTriangle>;
  void checkDim(const LocalState& s) const;
  /// The material's constants at parameters p.
  struct Coefficients {
    double mu, lam, lamStar;  ///< Lame constants and the plane-stress lambda of C0 [Pa]
    double t, m;              ///< thickness [m], mass rho t A [kg]
    double alpha, beta;       ///< damping [1/s], [s]
  };
  Coefficients coefficients(const VecX& p) const;
  /// membraneStress for any scalar; dev: the deviatoric membrane Cauchy stress (3 x 3).
  template <class T>
  void membraneStressT(const VecT<T>& x, const T& E0, const T& nu, MatT<T>& E, MatT<T>& S, MatT<T>& sigma,
                       MatT<T>& dev) const;
  std::vector<const Quantity*> kernelProperties() const {
    return {&props_->E, &props_->nu, &props_->density, &props_->thickness, &props_->alpha, &props_->beta};
  }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  static constexpr bool hasMassKernel = true;
  template <class T>
  MatT<T> massT(const LocalState& s, const VecT<T>& props) const;

  std::shared_ptr<ShellProperties> props_;
  double A_;      ///< rest area [m^2]
  MatX G_;        ///< dN_i/dX in the rest basis, 3 x 2 [1/m]
  MatX basis_;    ///< the rest basis (t1, t2) in the scene's axes, 3 x 2
  bool membrane_ = true;  ///< false: no membrane stress (disableMembrane)
};

}  // namespace flexsens
