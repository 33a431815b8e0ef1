// Fully parameterized spatial ANCF beam, the 3243 element (Shabana & Yakoub 2001): two nodes,
// each with its position r and the full position gradient (r_x, r_y, r_z) = dr/dX, 12
// coordinates per node, no rotations. Reference coordinates X = (x, y, z): x in [0, L] along
// the axis, y in [-w/2, w/2], z in [-h/2, h/2] across the rectangular section (width w along
// the node's r_y, height h along r_z). With xi = x / L:
//   r = N1 r_a + N2 r_x,a + (1 - xi)(y r_y,a + z r_z,a) + N3 r_b + N4 r_x,b + xi (y r_y,b + z r_z,b)
// (N_i the cubic Hermite functions of the cable): cubic along the axis, linear across it, so
// cross-sections stay plane (they may rotate, shear and stretch uniformly, but not warp).
// Local coordinates e = (r_a, r_x,a, r_y,a, r_z,a, r_b, r_x,b, r_y,b, r_z,b), 24 entries.
//
// Rest shape: straight, of length L, with orthonormal nodal gradients (r_x along the chord),
// or the curved / twisted shape of given rest coordinates e0 (L then the arc length of the
// axis). J = dr/dX maps the element's parameter space to space, J0 the same of the rest shape.
// At each point the beam's axes are R0, J0's columns at the axis (eta = zeta = 0) made
// orthonormal, r_x first; with B = J0_axis^-1 R0 the Green-Lagrange strain in those axes is
//   E = ((J B)^T (J B) - (J0 B)^T (J0 B)) / 2,
// zero in the rest shape at every point, and (J^T J - I) / 2 for the straight rest (B = I).
// Volumes are weighed by det J0_axis. A curved rest shape neglects the fibres' length ratio
// 1 - kappa y across the section (kappa the rest curvature, y the distance from the axis): the
// strains are those of a thin curved beam, relative error O(kappa h) in a fibre, O((kappa h)^2)
// in the bending stiffness.
//
// Energy U = int_V W(E) dV, Gauss quadrature over the volume (2 x 2 across the section: exact
// for the linear-in-(y, z) fields of small strains), St. Venant-Kirchhoff with this locking
// remedy:
//  - Poisson locking: the section can only stretch uniformly, so with the isotropic law
//    (lambda > 0) the lateral contraction that varies across the section in bending is
//    blocked and bending stiffens (by up to (1 - nu) / ((1 + nu)(1 - 2 nu)), 1.35 at
//    nu = 0.3, with the contraction fully blocked). Remedy: the normal stresses are
//    uncoupled, S_xx = E E_xx, S_yy = E E_yy, S_zz = E E_zz (the law at nu = 0 on the
//    diagonal), while the shear keeps G = E / (2 (1 + nu)): bending gives EI exactly, shear and
//    torsion the shear modulus of the material;
//      W = E/2 (E_xx^2 + E_yy^2 + E_zz^2) + 2 G (E_xy^2 + E_xz^2 + E_yz^2).
//  - Shear locking does not arise: r_x is quadratic along the axis, so the axis can follow the
//    linear rotation of the sections (r_y, r_z) with zero transverse shear strain. The axial
//    and the transverse shear strains (E_xx, E_xy, E_xz) are integrated at 3 Gauss points along
//    the axis (the fewest with no zero-energy mode besides the 6 rigid motions; 2 for the shear
//    strains would relieve nothing, measured, and leave two hourglass modes per element: a
//    transverse bubble of the axis with its shear strain zero at both points, global along a
//    chain).
//  - The section's own strains (E_yy, E_zz, E_yz) are taken at the two nodes (trapezoidal
//    rule), where r_y, r_z are the nodal gradients: between the nodes their linear
//    interpolation shortens and shears a section that turns by dphi over the element by
//    O(dphi^2), an energy that stiffened large rotations and curved rest shapes (the
//    Bathe-Bolourchi bend at 8 elements: tip 11% off with them at 3 Gauss points, 0.66% now).
// Bending: the sections' rotation is linear, the curvature constant per element, so the
// cantilever's tip deflection converges at O(h^2) (error 1 / (4 N^2), measured), to the value
// with shear deformation, P L^3 / (3EI) + P L / (G A) (plane sections: shear coefficient 1).
// Torsion: plane sections without warping give the torsion constant I_p = (w h^3 + h w^3) / 12
// (the polar moment), not Saint-Venant's J (square: 0.1406 a^4 against a^4 / 6).
//
// Constant consistent mass rho int S^T S dV = rho (A M_N + (w^3 h / 12) M_Y + (w h^3 / 12) M_Z) (x) I_3
// (A = w h, int y^2 dA = w^3 h / 12, int z^2 dA = w h^3 / 12; the shape integrals computed once).
// Gravity Q_g = M (g on both positions, 0 on gradients): a uniform field is a translation.
//
// Design parameters: E, nu, density, width and height (or side). Units: E [Pa], density
// [kg/m^3], width, height [m]; positions [m], gradients [-], forces [N] (on gradients [N m]).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "elements/KernelElement.hpp"

namespace flexsens {

/// Material and section of an ancf_beam: a rectangle (every entry bindable as a parameter) or a
/// general section (area, Iy, Iz, J; E, nu, density bindable).
struct AncfBeamSection {
  Quantity E;        ///< Young's modulus [Pa]
  Quantity nu;       ///< Poisson's ratio [-] (enters only G = E / (2 (1 + nu)))
  Quantity density;  ///< [kg/m^3]
  Quantity width;    ///< along the nodes' r_y [m]
  Quantity height;   ///< along the nodes' r_z [m]
  Quantity side;     ///< square section: width = height = side [m]
  bool square = false;
  /// A general section (area, Iy, Iz given): width and height are those of a rectangle with the
  /// radii of gyration of Iy = int z^2 dA, Iz = int y^2 dA (w = sqrt(12 Iz / A), h = sqrt(12 Iy / A)),
  /// weighed by areaScale; only E, nu and density are bindable then.
  bool general = false;
  /// A / (w h) of a general section: its rectangle's w, h place the quadrature points, this
  /// factor on every volume and mass makes the area A (1 for a rectangle).
  double areaScale = 1.0;
  /// sqrt(J / (Iy + Iz)): the shear strains are taken at section points this much closer to
  /// the axis, which scales the torsional stiffness G (Iy + Iz) to G J and leaves the
  /// uniform (transverse) shear G A as it is (1 without a given J).
  double torsionScale = 1.0;
  /// Rotary inertia per length rho int z^2 dA, rho int y^2 dA [kg m] when given; negative:
  /// density times the section's.
  double rotaryY = -1.0, rotaryZ = -1.0;
  const Quantity& widthSource() const { return square ? side : width; }
  const Quantity& heightSource() const { return square ? side : height; }
  /// "E", "nu", "density", then "side" or "width", "height".
  std::vector<std::pair<std::string, Quantity*>> properties();
};

class AncfBeam3D : public KernelElement<AncfBeam3D> {
 public:
  /// L: rest length [m] (> 0). Gauss points along the axis for the normal and for the shear
  /// strains (2 x 2 across the section for both).
  /// rest: the 24 rest coordinates e0 of a curved or twisted rest shape (nullptr: straight);
  /// L is then restLength(rest).
  AncfBeam3D(std::string name, std::vector<int> nodes, std::shared_ptr<AncfBeamSection> section, double L,
             int normalPoints = kNormalPoints, int shearPoints = kShearPoints, const VecX* rest = nullptr);
  /// Arc length [m] of the rest axis of coordinates e0 in which the nodes' r_x are unit
  /// tangents: the L at which the cubic Hermite axis has |dr/dx| closest to 1.
  static double restLength(const VecX& rest);
  static constexpr int kNormalPoints = 3, kShearPoints = 3;
  std::string kind() const override { return "ancf_beam"; }
  int gradients() const override { return 3; }
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return false; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return sec_->properties(); }
  double length() const { return L_; }

 private:
  friend class KernelElement<AncfBeam3D>;
  /// A quadrature point: (xi, eta, zeta) in [0, 1] x [-1/2, 1/2]^2 (y = w eta, z = h zeta),
  /// weight summing to 1 over the points of one strain group.
  struct Point {
    Point(double xi_, double eta_, double zeta_, double w_, int strains_)
        : xi(xi_), eta(eta_), zeta(zeta_), w(w_), strains(strains_) {}
    double xi, eta, zeta, w;
    int strains;  ///< bit k set: the Voigt strain k (E_xx, E_yy, E_zz, 2 E_xy, 2 E_xz, 2 E_yz) is evaluated here
    bool has(int k) const { return (strains >> k) & 1; }
    /// dS_i/dX B = S0 + w Sy + h Sz (8 x 3: the slots' weights in the columns of J B); w, h [m].
    Eigen::Matrix<double, 8, 3> S0, Sy, Sz;
    double detJ0 = 1.0;  ///< det J0 at the axis: rest volume per parameter volume
  };
  /// The point's S = S0 + w Sy + h Sz and its derivative dS along (dw, dh).
  static void slopes(const Point& P, double w, double h, double dw, double dh, Eigen::Matrix<double, 8, 3>& S,
                     Eigen::Matrix<double, 8, 3>& dS);
  /// Completes P's rest frame and adds it to the points.
  void addPoint(Point P);
  /// Fills the point's S0, Sy, Sz and detJ0 for the rest coordinates (none: straight, B = I).
  void setRestFrame(Point& P) const;
  /// Rest metric (J0 B)^T (J0 B) of the point for S and its derivative for dS (identity, zero
  /// for the straight rest).
  void restMetric(const Eigen::Matrix<double, 8, 3>& S, const Eigen::Matrix<double, 8, 3>& dS, Eigen::Matrix3d& C0,
                  Eigen::Matrix3d& dC0) const;
  /// Elastic force per unit E of the normal strains (QN) and per unit G of the shear strains
  /// (QS), optionally the stiffness -dQ/de of E QN + G QS (K, with the moduli E, G), and the
  /// derivative of E QN + G QS along the section change (dw, dh) (dQg, optional).
  void elastic(const LocalState& s, double E, double G, double w, double h, VecX* QN, VecX* QS, MatX* K,
               double dw, double dh, VecX* dQg) const;
  double elasticEnergy(const LocalState& s, double E, double G, double w, double h) const;
  MatX massMatrix(double rho, double w, double h) const;
  VecX gravityLoad(const LocalState& s, const MatX& M) const;
  void checkState(const LocalState& s) const;

  std::vector<const Quantity*> kernelProperties() const {
    return {&sec_->E, &sec_->nu, &sec_->density, &sec_->widthSource(), &sec_->heightSource()};
  }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  static constexpr bool hasMassKernel = true;
  template <class T>
  MatT<T> massT(const LocalState& s, const VecT<T>& props) const;

  std::shared_ptr<AncfBeamSection> sec_;
  double L_;
  bool curved_ = false;                ///< rest coordinates given
  Eigen::Matrix<double, 3, 8> rest_;   ///< rest coordinates e0, column i slot i (if curved_)
  std::vector<Point> pts_;
  /// Shape integrals L int f_i f_j dxi of the axial functions (M_N, slots 0, 1, 4, 5) and of
  /// the section factors (M_Y: slots 2, 6 with 1 - xi, xi; M_Z: slots 3, 7) [m].
  Eigen::Matrix<double, 8, 8> mN_, mY_, mZ_;
};

}  // namespace flexsens
