// Positions-only (rotation-free) nonlinear beam: axial segments + bending hinges.
//
// Why this variant: nodes carry Cartesian positions only (no slopes, no rotations), as in the
// paper's beam. A beam of one segment is then a pure axial bar (two nodes, energy depends on
// the length only), and a beam of two segments adds just the midpoint's coordinates, whose
// hinge carries the bending energy. Axial energy per segment (engineering strain), bending
// energy per interior node from the turning angle (discrete-elastic-rod / Flores-Onate type),
// consistent bar mass. See /work/shared/reference/beams-and-checks.md.
//
// Units: E [Pa], density [kg/m^3], area [m^2], inertia [m^4], side [m]; EA [N], EI [N m^2],
// rhoA [kg/m]; positions [m], forces [N], energies [J].
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "elements/KernelElement.hpp"

namespace flexsens {

/// Cross-section and material of one beam, shared by its segments and hinges.
struct BeamSection {
  Quantity E;        ///< Young's modulus [Pa]
  Quantity density;  ///< [kg/m^3]
  Quantity area;     ///< A [m^2] (explicit form)
  Quantity inertia;  ///< I [m^4] (explicit form)
  Quantity side;     ///< square side a [m]: A = a^2, I = a^4/12 (square form)
  bool square = false;  ///< true: section from side; false: from area and inertia
  bool massless = false;  ///< scene `inertia: none`: density 0 and not a property (no mass, no weight)

  double A(const VecX& p) const;
  double I(const VecX& p) const;
  /// The quantity A (square form: side) and the one I (square form: side) are computed from.
  const Quantity& areaSource() const { return square ? side : area; }
  const Quantity& inertiaSource() const { return square ? side : inertia; }
  /// A and I from their source quantity's value, for any scalar type (value templates).
  template <class T> T areaOf(const T& v) const {
    if (square) return T(v * v);
    return v;
  }
  template <class T> T inertiaOf(const T& v) const {
    if (square) return T(v * v * v * v / 12.0);
    return v;
  }
  double EA(const VecX& p) const { return E.value(p) * A(p); }
  double EI(const VecX& p) const { return E.value(p) * I(p); }
  double rhoA(const VecX& p) const { return density.value(p) * A(p); }
  /// Partial derivatives with respect to design parameter k (chain rule through side).
  double dA(const VecX& p, int k) const;
  double dI(const VecX& p, int k) const;
  double dEA(const VecX& p, int k) const;
  double dEI(const VecX& p, int k) const;
  double drhoA(const VecX& p, int k) const;
  /// Structural dependence (binding), independent of the current values.
  bool areaDependsOn(int k) const { return square ? side.boundTo(k) : area.boundTo(k); }
  bool inertiaDependsOn(int k) const { return square ? side.boundTo(k) : inertia.boundTo(k); }
  bool axialDependsOn(int k) const { return E.boundTo(k) || density.boundTo(k) || areaDependsOn(k); }
  bool bendingDependsOn(int k) const { return E.boundTo(k) || inertiaDependsOn(k); }
  /// Named quantities ("E", "density" unless massless, then "side" or "area", "inertia").
  std::vector<std::pair<std::string, Quantity*>> properties();
};

/// The sections a bending hinge reads: the beam's one section, or (per-element parameters) the
/// two segments' own, a and b; its EI is their mean weighted by the half-segments it spans,
/// wa = L1 / (L1 + L2), wb = L2 / (L1 + L2) (each half bends with its own section).
struct HingeSections {
  std::shared_ptr<BeamSection> a, b;
  double wa = 1.0, wb = 0.0;
  /// One section (second null or the same: b = a, weights (1, 0)) or two.
  HingeSections(std::shared_ptr<BeamSection> first, std::shared_ptr<BeamSection> second)
      : a(first), b(second ? std::move(second) : std::move(first)) {}
  /// Two sections bend over the rest lengths L1, L2 [m] they span: the weights from them.
  void span(double L1, double L2) {
    if (b != a) wa = L1 / (L1 + L2), wb = L2 / (L1 + L2);
  }
  double EI(const VecX& p) const { return wa * a->EI(p) + wb * b->EI(p); }
  double dEI(const VecX& p, int k) const { return wa * a->dEI(p, k) + wb * b->dEI(p, k); }
  bool bendingDependsOn(int k) const { return a->bendingDependsOn(k) || b->bendingDependsOn(k); }
  /// The kernels' props (E, I source of a, then of b) and their EI, for any scalar type.
  std::vector<const Quantity*> kernelProperties() const {
    return {&a->E, &a->inertiaSource(), &b->E, &b->inertiaSource()};
  }
  template <class T> T EIof(const VecT<T>& props) const {
    return wa * props[0] * a->inertiaOf(props[1]) + wb * props[2] * b->inertiaOf(props[3]);
  }
  /// a's named quantities, then b's when b is another section.
  std::vector<std::pair<std::string, Quantity*>> properties() const;
};

/// Two-node axial segment (dim 2 or 3): U = 1/2 EA L eps^2, eps = (l - L)/L; consistent mass
/// (rho A L / 6) [[2I, I], [I, 2I]]; gravity rho A L g / 2 on each node.
class BeamSegment : public KernelElement<BeamSegment> {
 public:
  /// restLength L [m] > 0, the node distance in the rest shape.
  BeamSegment(std::string name, std::vector<int> nodes, std::shared_ptr<BeamSection> section,
              double restLength);
  std::string kind() const override { return "beam_segment"; }
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return false; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return sec_->properties(); }
  double restLength() const { return L_; }

 private:
  friend class KernelElement<BeamSegment>;
  /// Properties the kernels read, in the order of their props vector: (E, density, A source).
  std::vector<const Quantity*> kernelProperties() const {
    return {&sec_->E, &sec_->density, &sec_->areaSource()};
  }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  static constexpr bool hasMassKernel = true;
  template <class T>
  MatT<T> massT(const LocalState& s, const VecT<T>& props) const;
  std::shared_ptr<BeamSection> sec_;
  double L_;
};

/// Three-node planar bending hinge at node b between e1 = x_b - x_a and e2 = x_c - x_b:
/// phi = atan2(e1 x e2, e1 . e2), U = 1/2 (EI / D) (phi - phi0)^2, D = (L1 + L2)/2 [m].
/// Massless, no gravity. Planar only (dim 2).
class BeamHinge : public KernelElement<BeamHinge> {
 public:
  /// restX: rest positions of a, b, c (6 entries) giving phi0, L1, L2. voronoiLength > 0
  /// overrides D (e.g. D = L2/2 at a clamp whose node a is a ghost outside the beam).
  /// sectionB: the second segment's own section (per-element parameters); none: `section` for both.
  BeamHinge(std::string name, std::vector<int> nodes, std::shared_ptr<BeamSection> section,
            const VecX& restX, double voronoiLength = 0.0, std::shared_ptr<BeamSection> sectionB = nullptr);
  std::string kind() const override { return "beam_hinge"; }
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return false; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return sec_.properties(); }
  double restAngle() const { return phi0_; }
  double voronoiLength() const { return D_; }
  /// Turning angle phi [rad] of positions x (6 entries), in (-pi, pi].
  static double angle(const VecX& x);

 private:
  friend class KernelElement<BeamHinge>;
  /// (phi - phi0) wrapped to (-pi, pi], and optionally dphi/dx (6) and d2phi/dx2 (6x6).
  double deviation(const LocalState& s, VecX* g, MatX* H) const;
  /// Properties the kernel reads, in the order of its props vector (HingeSections).
  std::vector<const Quantity*> kernelProperties() const { return sec_.kernelProperties(); }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  HingeSections sec_;
  double phi0_, D_;
};

}  // namespace flexsens
