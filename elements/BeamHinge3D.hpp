// Spatial (3D) bending hinge of the positions-only beam (elements/Beam.hpp), no torsion.
//
// Nodes a, b, c (dim 3), edges e1 = x_b - x_a, e2 = x_c - x_b [m]. Curvature binormal of
// discrete elastic rods (Bergou et al. 2008):
//   kb = 2 (e1 x e2) / (|e1| |e2| + e1 . e2)   [-],   |kb| = 2 tan(phi / 2),
// phi the (unsigned) turning angle; |kb| = phi + phi^3/12 + O(phi^5), so for small angles it is
// the planar BeamHinge's measure. Energy, with psi0 = |kb| of the rest shape:
//   U = 1/2 (EI / D) (|kb| - psi0)^2                       [J]
// D = (L1 + L2)/2 [m] the Voronoi length of the rest shape (or an override, e.g. h/2 at a clamp
// whose node a is a ghost outside the beam), EI [N m^2] from the shared BeamSection (with
// per-element parameters the two segments' sections, weighted by L1 and L2: HingeSections).
//
// Smoothness.
// - psi0 == 0 (straight rest): U = 1/2 (EI/D) |kb|^2 = 2 (EI/D) |e1 x e2|^2 / (|e1||e2| + e1.e2)^2,
//   a smooth function of the positions everywhere except at phi = pi (the denominator vanishes:
//   the beam folds back onto itself), where a NumericalError naming the hinge is thrown, and at
//   zero edge lengths (also a NumericalError).
// - psi0 > 0 (bent rest): |kb| is not differentiable where kb = 0, so U has a kink at the
//   straight state (its gradient has no limit there). A NumericalError with a suggestion is
//   thrown when |kb| < 1e-12 in that case. Rest shapes with psi0 below kStraightRest (1e-9) are
//   treated as straight (psi0 = 0): the energies differ by at most (EI/D) psi0 |kb| there, far
//   below round-off of the bending forces of a realistic state.
// - Only the magnitude of the rest curvature is restored for psi0 > 0, not its direction (no
//   material frame, no torsion): rotating a hinge's bending plane about the edges costs no
//   energy. Near a bent rest state the stiffness per turning angle is (EI/D) sec^4(phi0/2)
//   = (EI/D)(1 + phi0^2/2 + ...), i.e. the planar hinge's to O(phi0^2) = O(h^2).
//
// Massless, no gravity. Units: positions [m], EI [N m^2], D [m], forces [N], energy [J].
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "elements/Beam.hpp"

namespace flexsens {

class BeamHinge3D : public KernelElement<BeamHinge3D> {
 public:
  /// Rest curvatures |kb| below this are treated as exactly straight (psi0 = 0) [-].
  static constexpr double kStraightRest = 1e-9;
  /// With psi0 > 0, |kb| below this is the kink of the energy: NumericalError [-].
  static constexpr double kKinkTol = 1e-12;

  /// restX: rest positions of a, b, c (9 entries [m]) giving psi0, L1, L2. voronoiLength > 0
  /// overrides D [m]. Throws std::invalid_argument for zero rest edges or a folded rest shape.
  /// sectionB: the second segment's own section (per-element parameters); none: `section` for both.
  BeamHinge3D(std::string name, std::vector<int> nodes, std::shared_ptr<BeamSection> section,
              const VecX& restX, double voronoiLength = 0.0, std::shared_ptr<BeamSection> sectionB = nullptr);
  std::string kind() const override { return "beam_hinge3d"; }
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return false; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return sec_.properties(); }

  /// psi0 = |kb| of the rest shape [-] (0 for a straight rest shape).
  double restCurvature() const { return psi0_; }
  double voronoiLength() const { return D_; }
  /// Curvature binormal kb (3 entries [-]) of positions x (9 entries); throws
  /// std::invalid_argument at zero edges or phi = pi.
  static Eigen::Vector3d curvatureBinormal(const VecX& x);

 private:
  friend class KernelElement<BeamHinge3D>;
  void checkDim(const LocalState& s) const;
  /// f = |kb|^2 of s.x, and optionally its gradient (9) and Hessian (9x9) in x.
  double curvatureSquared(const LocalState& s, VecX* g, MatX* H) const;
  /// dU/df (the gradient of U is dU/df grad f) after the kink / fold checks [N m].
  double dUdf(double EI, double f) const;
  /// Properties the kernel reads, in the order of its props vector (HingeSections).
  std::vector<const Quantity*> kernelProperties() const { return sec_.kernelProperties(); }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  HingeSections sec_;
  double psi0_, D_;
};

}  // namespace flexsens
