// Total-Lagrangian continuum elements in absolute nodal coordinates (positions only): planar
// triangles (3 or 6 nodes; plane stress with a thickness, or plane strain per unit of the
// thickness) and spatial tetrahedra (4 or 10 nodes), isoparametric, with the laws of
// elements/Material.hpp (St. Venant-Kirchhoff, compressible neo-Hookean).
//
// Q = M G  -  sum_gp w t F S G_i  -  alpha M v
//   F = sum_i x_i (dN_i/dX)^T, S = S(E) + beta C0 : dE/dt (Kelvin-Voigt), E = (F^T F - I)/2
// where w is the quadrature weight times |det dX/dxi| (rest area or volume), t the thickness
// (1 in 3D), G the gravity on every node. Damping (both optional, default 0):
//   alpha [1/s]: mass-proportional, Q = -alpha M v (damps rigid motion too);
//   beta  [s]:  stiffness-proportional in the Kelvin-Voigt form: viscous stress beta C0 : Edot,
//               C0 the linear (rest) elasticity tensor, Edot = sym(F^T Fdot). It equals
//               beta K0 v at small strain, but is zero for any rigid motion (frame-indifferent),
//               where beta K0 v would damp a rotating body.
// Mass: consistent and constant, M = rho t int N_i N_j dX (x) I, integrated exactly for curved
// quadratic elements (elements/SimplexShape.hpp massRule).
// Design parameters: E, nu, density, thickness (planar only), alpha, beta.
//
// Units: E [Pa], nu [-], density [kg/m^3], thickness [m], positions [m], forces [N],
// energies [J]; alpha [1/s], beta [s].
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "elements/KernelElement.hpp"
#include "elements/Material.hpp"
#include "elements/SimplexShape.hpp"

namespace flexsens {

/// Material, thickness and damping of one meshed body, shared by its elements.
struct SolidProperties {
  Quantity E;                 ///< Young's modulus [Pa]
  Quantity nu;                ///< Poisson's ratio [-], in (-1, 0.5)
  Quantity density;           ///< [kg/m^3]
  Quantity thickness{1.0, -1};  ///< [m], planar bodies only (1 and no property in 3D)
  Quantity alpha{0.0, -1};    ///< mass-proportional damping [1/s]
  Quantity beta{0.0, -1};     ///< stiffness-proportional (Kelvin-Voigt) damping [s]
  MaterialLaw law;
  int dim = 2;
  std::vector<std::pair<std::string, Quantity*>> properties();
  /// False when neither damping can be nonzero (both constant 0): Q then never depends on v.
  bool damped() const { return alpha.param >= 0 || alpha.constant != 0.0 || beta.param >= 0 || beta.constant != 0.0; }
};

class Solid : public KernelElement<Solid> {
 public:
  /// restX: rest positions of the nodes, dim x nodes (VTK node order). Throws
  /// std::invalid_argument when det(dX/dxi) is not positive at a quadrature point (a
  /// degenerate element, or inverted: clockwise triangle, negatively oriented tetrahedron,
  /// misplaced midside node).
  Solid(std::string name, std::vector<int> nodes, std::shared_ptr<SolidProperties> props, Simplex shape,
        const MatX& restX);
  std::string kind() const override { return "solid"; }
  /// Q and its Jacobians by the fixed-size kernels (elements/ContinuumKernel.hpp, no heap);
  /// kernelForce() and the AD Jacobians evaluate the value template forceT instead.
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return props_->damped(); }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return props_->properties(); }

  Simplex shape() const { return shape_; }
  /// int N_i N_j dX [m^2 or m^3] (mass = rho t massShape (x) I).
  const MatX& massShape() const { return massShape_; }
  /// At the element's centroid: Green-Lagrange strain E [-], second Piola-Kirchhoff S [Pa],
  /// Cauchy stress sigma [Pa] (dim x dim, elastic part) and von Mises stress [Pa] (with the
  /// out-of-plane normal stress of plane strain).
  void centroidStress(const LocalState& s, MatX& E, MatX& S, MatX& sigma, double& vonMises) const;
  /// Their derivatives with respect to parameter k along dx = d x/dp_k of the element's node
  /// positions (the run's dq/dp; 0 for ground nodes): the chain rule through F plus the
  /// explicit dependence on E and nu, by forward AD of the same template. von Mises at zero
  /// stress has no derivative; there its one-sided directional one, |d dev| sqrt(3/2).
  void centroidStressDerivative(const LocalState& s, const VecX& dx, int k, MatX& dE, MatX& dS, MatX& dsigma,
                                double& dVonMises) const;

 private:
  friend class KernelElement<Solid>;
  struct Point {
    MatX G;    ///< dN_i/dX, nodes x dim [1/m]
    double w;  ///< weight times rest measure [m^2 or m^3]
  };
  double lambdaRest(double mu, double lam) const;                 ///< lambda of C0
  /// Neo-Hookean: NumericalError naming the element when det F <= 0 (det C cannot tell).
  void checkOrientation(double detF) const;
  /// The material's constants at parameters p.
  struct Coefficients {
    double mu, lam;   ///< Lame constants [Pa]
    double lamV;      ///< lambda of the rest elasticity C0 of the Kelvin-Voigt stress [Pa]
    double t, rt;     ///< thickness [m] (1 in 3D), density times thickness [kg/m^3 or kg/m^2]
    double alpha, beta;  ///< damping [1/s], [s]
  };
  Coefficients coefficients(const VecX& p) const;
  /// std::invalid_argument unless s holds D coordinates per node of this element's N nodes.
  void checkState(const LocalState& s) const;
  /// The fixed-size kernels for D coordinates and N nodes (SolidKernel.cpp).
  template <int D, int N>
  void forceFixed(const LocalState& s, VecX& Q) const;
  template <int D, int N>
  void forceJacobianFixed(const LocalState& s, MatX& dQdq, MatX& dQdv) const;
  template <int D, int N>
  void parameterDerivativeFixed(const LocalState& s, int k, VecX& dQ) const;
  template <int D, int N>
  double potentialFixed(const LocalState& s) const;
  /// centroidStress for any scalar: dev returns the deviatoric Cauchy stress (3 x 3).
  template <class T>
  void centroidStressT(const VecT<T>& x, const T& E0, const T& nu, MatT<T>& E, MatT<T>& S, MatT<T>& sigma,
                       MatT<T>& dev) const;

  std::vector<const Quantity*> kernelProperties() const {
    return {&props_->E, &props_->nu, &props_->density, &props_->thickness, &props_->alpha, &props_->beta};
  }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  static constexpr bool hasMassKernel = true;
  template <class T>
  MatT<T> massT(const LocalState& s, const VecT<T>& props) const;

  std::shared_ptr<SolidProperties> props_;
  Simplex shape_;
  int dim_, n_;
  std::vector<Point> pts_;
  MatX massShape_;
  MatX centroidG_;  ///< dN_i/dX at the centroid (output)
};

}  // namespace flexsens
