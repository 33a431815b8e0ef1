// Bending hinge of a discrete shell (elements/ShellMesh.hpp) on one interior edge: 4 nodes in
// 3D, positions only, massless; the surface counterpart of the beam's hinges
// (elements/BeamHinge3D.hpp).
//
// Nodes: x0, x1 the shared edge, x2 the third node of one triangle, x3 of the other. With
// e = x1 - x0, a = x2 - x0, b = x3 - x0 and the normals n1 = e x a, n2 = b x e (both point to
// the same side when the hinge is flat), the dihedral angle is
//   theta = atan2(|e| det(e, a, b), n1 . n2),   n1 . n2 = (e.a)(e.b) - |e|^2 (a.b),
// the signed angle between n1 and n2 [rad]: 0 flat, positive when x3 lies on the side n1
// points to. It does not depend on how the triangles are oriented in the mesh.
//
// Energy, with theta0 the rest angle and the rest edge |e|, areas A1, A2 [m^2]:
//   U = D/2 |e|^2 / (A1 + A2) (theta - theta0)^2,   D = E t^3 / (12 (1 - nu^2))  [J],
// i.e. the discrete-shells weight 3 |e|^2 / (A1 + A2) times D/6. Calibration: on a mesh of
// equilateral triangles (side h) bent into a cylinder of curvature kappa, an edge at angle phi
// to the bending direction folds by theta = h kappa (4 cos^2 phi - 1) / (2 sqrt 3) (slope jump
// of the piecewise linear interpolant); summed over the three edge directions this gives
// exactly D/2 kappa^2 per unit area, Kirchhoff's D/2 (Delta w)^2. For a general curvature H
// (2x2) the same mesh gives D/2 [(tr H)^2 - 8/3 det H]: the Gaussian-curvature term has the
// weight of nu = -1/3 instead of Kirchhoff's 2 (1 - nu) det H. That term integrates to zero over
// clamped or simply supported plates with straight edges, so their frequencies converge;
// free edges and curved boundaries see it. On other mesh patterns the hinge energy is
// anisotropic (on right triangles of a square grid a cylinder bent about the cut diagonal
// stores 3 times Kirchhoff's energy): see tests/test_shell.cpp and the README for which
// meshes converge to Kirchhoff's plate (near-equilateral ones, at first order).
// theta - theta0 is wrapped to (-pi, pi]; a triangle of zero area (n1 or n2 = 0) is a
// NumericalError. No membrane-bending coupling beyond the geometry (flat rest: none at the
// linear level). Damping (the bending part of the shell's Kelvin-Voigt beta, ShellTriangle.hpp
// has the membrane's): the moment beta D w dtheta/dt, Q = -D w (theta - theta0 + beta
// dtheta/dt) grad theta, so beta K0 v at small motion and none under rigid motion.
// Units: positions [m], D [N m], forces [N], energy [J], beta [s].
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "elements/KernelElement.hpp"
#include "elements/ShellProperties.hpp"

namespace flexsens {

class ShellHinge : public KernelElement<ShellHinge> {
 public:
  /// restX: rest positions of x0..x3 (12 entries [m]); flatRest: theta0 = 0 instead of the
  /// rest positions' angle. Throws std::invalid_argument for a zero rest edge or triangle.
  ShellHinge(std::string name, std::vector<int> nodes, std::shared_ptr<ShellProperties> props, const VecX& restX,
             bool flatRest = false);
  std::string kind() const override { return "shell_hinge"; }
  /// Q and its Jacobians in fixed size (no heap); kernelForce() and the AD Jacobians evaluate
  /// the value template forceT instead.
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return props_->bendingDamped(); }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return props_->properties(); }

  double restAngle() const { return theta0_; }  ///< [rad]
  double weight() const { return w_; }          ///< |e|^2 / (A1 + A2) of the rest shape [-]
  /// theta of positions x (12 entries) [rad], and optionally its gradient (12) and Hessian
  /// (12x12). Throws NumericalError (naming `who`) when a triangle has zero area.
  static double dihedralAngle(const VecX& x, VecX* grad = nullptr, MatX* hess = nullptr,
                              const std::string& who = "shell hinge");

 private:
  friend class KernelElement<ShellHinge>;
  void checkDim(const LocalState& s) const;
  /// D w [N m], theta - theta0 wrapped [rad], grad theta (12) and, when H is given, its
  /// Hessian at s.x.
  void bendingState(const LocalState& s, double& Dw, double& dev, Eigen::Matrix<double, 12, 1>& g,
                    Eigen::Matrix<double, 12, 12>* H) const;
  std::vector<const Quantity*> kernelProperties() const {
    return {&props_->E, &props_->nu, &props_->thickness, &props_->beta};
  }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;

  std::shared_ptr<ShellProperties> props_;
  double theta0_, w_;
};

}  // namespace flexsens
