// Kirchhoff-Love bending of one triangle of a shell (elements/ShellMesh.hpp, `bending:
// kirchhoff`): positions only, massless; the membrane and the mass stay the triangle's CST
// (elements/ShellTriangle.hpp).
//
// Curvature (a Morley-type shape operator with mid-edge slopes): for a quadratic deflection w
// over the triangle, measured from the facet, the divergence theorem gives exactly
//   A kappa = sum_i l_i g_i nu_i nu_i^T,
// l_i the length and nu_i the outward unit normal (in the rest plane) of edge i (opposite
// vertex i), g_i the outward slope of w at the edge's midpoint (A the rest area [m^2]). Here
//   g_i = y_i = n . d_i,
// n the triangle's current unit normal and d_i the surface's tangent across edge i at its
// midpoint (dx/dnu_i) [-], linear in the positions: d_i = sum_a C_ia x_a over a stencil of
// nearby nodes (ShellMesh.cpp builds C: the average of the two neighbouring triangles'
// quadratic fits through 6 nodes, so d_i is exact for quadratic surfaces on any mesh and the
// same vector for both triangles of an edge, which makes the element pass the patch test).
// Energy, with y0 the rest values (0 for rest_shape: flat) and Dy = y - y0:
//   U = A D/2 [(1 - nu) tr(dk^2) + nu tr(dk)^2] = 1/2 Dy^T K Dy,
//   K_ij = D l_i l_j / A [(1 - nu) (nu_i . nu_j)^2 + nu],  D = E t^3 / (12 (1 - nu^2)) [N m].
// Edges on the boundary:
//   fixed (clamp, symmetry plane): d_i is a constant unit vector (the rest outward normal of
//     the edge, or the plane's normal), so Dy_i is the triangle's rotation about the edge;
//   free (free or simply supported edge): y_i is the free mid-edge slope, eliminated by
//     minimizing U - b_i (y_i - y0_i + phi_i) (b_i = m_i l_i, m_i an applied edge moment per
//     unit length [N m/m], 0 by default; phi_i the triangle's rotation about the edge from rest,
//     positive lifting the outward side, phi = atan2(-n . nu0_i, n . n0)): the Schur complement
//     Ke of the free rows, so that the edge's normal moment M_nn equals m_i (0 when free).
//   U = 1/2 Dy^T Ke Dy - be^T Dy - sum_free b_i phi_i,  be = -K_ZF K_FF^-1 b_F.
// Forces are -dU/dx, the Jacobian analytic (the normal's Hessian by nested fixed-size forward
// AD), parameter derivatives (E, nu, thickness) by forward AD of the force template.
// Objective (n and d_i turn with a rigid motion); no transverse shear; no damping of its own.
// Units: positions [m], forces [N], energy [J].
#pragma once

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "elements/KernelElement.hpp"
#include "elements/ShellProperties.hpp"

namespace flexsens {

/// What an edge of a Kirchhoff triangle holds (built by ShellMesh.cpp).
struct KirchhoffEdge {
  enum class Kind { Shared, Fixed, Free };
  Kind kind = Kind::Free;
  VecX coeff;                                    ///< Shared: d = sum_a coeff[a] x_a over the stencil [-]
  Eigen::Vector3d fixed = Eigen::Vector3d::Zero();  ///< Fixed: the constant unit vector d
  double moment = 0.0;                           ///< Free: applied edge moment per length [N m/m]
};

class ShellKirchhoffBending : public KernelElement<ShellKirchhoffBending> {
 public:
  /// nodes: the triangle's 3 vertices, then the rest of the stencil; restX their rest
  /// positions (3 per node [m]); edges[i] the edge opposite vertex i. flatRest: y0 = 0. Throws
  /// std::invalid_argument for a degenerate triangle or coefficients of the wrong size.
  ShellKirchhoffBending(std::string name, std::vector<int> nodes, std::shared_ptr<ShellProperties> props,
                        const VecX& restX, std::array<KirchhoffEdge, 3> edges, bool flatRest);
  std::string kind() const override { return "shell_kirchhoff"; }
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return false; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override {
    return parameterDerivativeAD(s, k, dQ, dM);
  }
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return props_->properties(); }

  /// The curvature change kappa - kappa0 (2 x 2, in the rest basis t1 = edge 2 direction, t2 =
  /// n0 x t1) at positions x [1/m], the free edges' slopes at their energy minimum.
  Eigen::Matrix2d curvatureChange(const LocalState& s) const;
  double restArea() const { return A_; }

 private:
  friend class KernelElement<ShellKirchhoffBending>;
  void checkDim(const LocalState& s) const;
  std::vector<const Quantity*> kernelProperties() const { return {&props_->E, &props_->nu, &props_->thickness}; }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  /// Ke and be (above) at D, nu.
  template <class T>
  void condensed(const T& D, const T& nu, Eigen::Matrix<T, 3, 3>& Ke, Eigen::Matrix<T, 3, 1>& be) const;
  /// y_i (0 on free edges) and the vectors d_i at positions x.
  template <class T>
  void slopes(const VecT<T>& x, Eigen::Matrix<T, 3, 1>& n, std::array<Eigen::Matrix<T, 3, 1>, 3>& d,
              Eigen::Matrix<T, 3, 1>& y) const;
  /// The edge moments' rotation phi_i of a free edge at the unit normal n [rad], and d phi/dn.
  template <class T>
  T rotation(int i, const Eigen::Matrix<T, 3, 1>& n, Eigen::Matrix<T, 3, 1>* dPhi) const;

  std::shared_ptr<ShellProperties> props_;
  std::array<KirchhoffEdge, 3> edges_;
  int N_;                      ///< stencil nodes
  double A_;                   ///< rest area [m^2]
  Eigen::Matrix3d G_, L_;      ///< l_i l_j (nu_i . nu_j)^2 / A and l_i l_j / A [m^0]
  Eigen::Vector3d y0_;         ///< rest slopes [-]
  Eigen::Vector3d n0_;         ///< rest unit normal
  std::array<Eigen::Vector3d, 3> nu0_;  ///< rest outward edge normals (unit, in the rest plane)
  std::array<double, 3> length_;        ///< rest edge lengths [m]
  Eigen::Matrix<double, 3, 2> basis_;   ///< rest basis t1, t2
};

}  // namespace flexsens
