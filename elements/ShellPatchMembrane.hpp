// Membrane of one triangle of a Kirchhoff shell from its 6-node quadratic fit (`membrane:
// patch`; elements/ShellKirchhoffMesh.cpp builds the fit): the assumed-strain membrane of
// Flores & Onate's EBST1 triangle, positions only, massless (the mass stays the triangle's,
// elements/ShellTriangle.hpp, whose own CST membrane is then off).
//
// With the fit's shape gradients G_a = dN_a/dxi at the triangle's centroid (6 x 2, xi the
// coordinates of the rest plane [m]), F = sum_a x_a G_a^T (3 x 2) and its rest value F0,
//   E = (F^T F - F0^T F0) / 2,  S = S(E) in plane stress (elements/Material.hpp),
//   U = A t W(E)  [J],   Q_a = -A t F S G_a.
// The fit follows the curved surface, so the inextensional bending of a curved shell strains
// it far less than the flat facets' CST (membrane locking): measured in bench/statics.
// Units: positions [m], E [Pa], t [m], forces [N].
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "elements/KernelElement.hpp"
#include "elements/ShellProperties.hpp"

namespace flexsens {

class ShellPatchMembrane : public KernelElement<ShellPatchMembrane> {
 public:
  /// nodes: the 6 fit nodes; restX their rest positions (18 [m]); G the fit's gradients at the
  /// centroid (6 x 2 [1/m]); area the triangle's rest area [m^2].
  ShellPatchMembrane(std::string name, std::vector<int> nodes, std::shared_ptr<ShellProperties> props,
                     const VecX& restX, const Eigen::Matrix<double, 6, 2>& G, double area);
  std::string kind() const override { return "shell_patch_membrane"; }
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return false; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override {
    return parameterDerivativeAD(s, k, dQ, dM);
  }
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return props_->properties(); }

 private:
  friend class KernelElement<ShellPatchMembrane>;
  void checkDim(const LocalState& s) const;
  std::vector<const Quantity*> kernelProperties() const { return {&props_->E, &props_->nu, &props_->thickness}; }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;

  std::shared_ptr<ShellProperties> props_;
  Eigen::Matrix<double, 6, 2> G_;
  Eigen::Matrix2d C0_;  ///< F0^T F0
  double A_;
};

}  // namespace flexsens
