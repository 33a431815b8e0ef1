// ANCF cable / Euler-Bernoulli beam element (Shabana; Gerstmayr & Shabana 2006): two nodes,
// each with its position r and its slope r_s = dr/ds (s the reference arc length), no
// rotations. Cubic Hermite interpolation r(s) = N1 r_a + N2 r_a' + N3 r_b + N4 r_b' over the
// element's reference length L; local coordinates e = (r_a, r_a', r_b, r_b'), 4 dim entries.
//
// Energy  U = int_0^L [ EA/2 eps^2 + EI/2 w_b ] ds0  by Gauss quadrature, with
//  - engineering axial strain eps = |r'| / |r0'| - 1: the law of BeamSegment, so the two beams
//    agree at any stretch, and a uniform stretch gives the axial force EA eps exactly;
//  - bending, planar: w_b = (kappa - kappa0)^2 with the material curvature
//    kappa = (r' x r'') / (|r'|^2 |r0'|) = d(theta)/ds0, the tangent's rotation per reference
//    length (Reissner's bending strain, as the positions-only beam's hinge angle / l0 and
//    Gerstmayr & Irschik's cable); invariant under rigid motion for any rest shape, exact in
//    large deflection. The Frenet curvature (r' x r'')/|r'|^3 (per deformed length, used here
//    until 2026-11-24) differs by the factor 1 + eps: in the pendulum bench (eps ~ 1e-3) it
//    moved the converged tip by ~1e-4 m away from the positions-only beam's limit;
//    spatial (the gradient-deficient cable, no torsion): w_b = |r' x r''|^2 / (|r'|^4 |r0'|^2),
//    smooth at straight states, so the rest shape must be straight.
// The simpler measure |r''|^2 (constant stiffness) was not chosen: it is not invariant for
// curved rest shapes and mixes the stretch gradient into bending.
// Consistent mass rho A int S^T S ds0, constant: its shape integral is computed once.
// Gravity Q_g = M (g on every position, 0 on slopes): a uniform field is a translation.
//
// Units: E [Pa], density [kg/m^3], A [m^2], I [m^4]; positions [m], slopes [-], forces [N]
// (on slope coordinates [N m]), energies [J].
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "elements/Beam.hpp"

namespace flexsens {

class AncfCable : public KernelElement<AncfCable> {
 public:
  /// restX: rest coordinates (r_a, r_a', r_b, r_b'), 4 dim entries, dim = 2 or 3; the rest
  /// slopes' directions set the shape, the reference length L is the chord |r_b - r_a| > 0.
  /// Gauss points of the axial and of the bending energy (the mass is integrated exactly).
  AncfCable(std::string name, std::vector<int> nodes, std::shared_ptr<BeamSection> section,
            const VecX& restX, int axialPoints = kAxialPoints, int bendingPoints = kBendingPoints);
  /// Default quadrature: 3 points for each energy, the fewest that leave no zero-energy mode
  /// besides the rigid motions. 2 axial points relieve the locking of thin bent elements (the
  /// N = 8 elastica, side 1 mm: errors 4e-3 with 3 points, <= 9e-5 with 2) at the price of one
  /// zero-energy mode at straight states (u' = c P2: both slopes lengthened along the axis,
  /// positions fixed), global along a chain and removed only by a clamped slope; in the pinned
  /// pendulum it spoils convergence (bench/ancf_pendulum), so 2 is an option, not the default.
  static constexpr int kAxialPoints = 3, kBendingPoints = 3;
  std::string kind() const override { return "ancf_cable"; }
  int gradients() const override { return 1; }
  /// The hand-coded force (fixed-size kernels); forceT is its value template, for AD.
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return false; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return sec_->properties(); }
  double length() const { return L_; }  ///< reference length L [m]

  /// Cubic Hermite shape functions on xi = s / L in [0, 1] and their s-derivatives (1/m, 1/m^2).
  static Eigen::Vector4d shape(double xi, double L);
  static Eigen::Vector4d shapeS(double xi, double L);
  static Eigen::Vector4d shapeSS(double xi, double L);

 private:
  friend class KernelElement<AncfCable>;
  /// A stiffness quadrature point: r' = sum d1_i e_i, r'' = sum d2_i e_i.
  struct Point {
    Eigen::Vector4d d1, d2;  ///< dN_i/ds [1/m], d2N_i/ds2 [1/m^2]
    double w;                ///< weight times rest length element ds0 = |r0'| L dxi [m]
    double a0;               ///< |r0'| at the point [-]
    double kappa0;           ///< planar rest curvature [1/m] (0 in 3D)
  };
  std::vector<Point> makePoints(const VecX& restX, int n, bool checkStraight) const;
  /// Axial elastic force times cA (QA), bending force times cB (QB) and optional stiffnesses
  /// dQ/dq; (cA, cB) = (1, 1): per unit EA and EI, (EA, EI): the force. QB may be QA and KB
  /// may be KA: the two parts then add up in one vector / matrix.
  void elastic(const LocalState& s, double cA, double cB, VecX& QA, VecX& QB, MatX* KA, MatX* KB) const;
  template <int D>
  void elasticD(const LocalState& s, double cA, double cB, VecX& QA, VecX& QB, MatX* KA, MatX* KB) const;
  VecX gravityLoad(const LocalState& s, double rhoA) const;

  std::vector<const Quantity*> kernelProperties() const {
    return {&sec_->E, &sec_->density, &sec_->areaSource(), &sec_->inertiaSource()};
  }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  static constexpr bool hasMassKernel = true;
  template <class T>
  MatT<T> massT(const LocalState& s, const VecT<T>& props) const;

  std::shared_ptr<BeamSection> sec_;
  int dim_;
  double L_;
  std::vector<Point> ptsA_, ptsB_;  ///< axial and bending quadrature points
  Eigen::Matrix4d massShape_;  ///< int N_i N_j ds0 [m] (mass = rho A massShape_ (x) I)
};

}  // namespace flexsens
