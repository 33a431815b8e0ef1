// The one rigidization generator (paper section 4): turns a cloud of nodes into a rigid body
// in natural coordinates. Basic points A, B (1D), A, B, C (2D) or A, B, C, D (3D) keep their
// mutual distances (quadratic constraints); every other point i keeps its coordinates c_i in
// the basis e_j = r_j - r_A, found once from the metric G c_i = b_i:
//   Lambda_i = r_i - r_A - sum_j c_ij e_j = C_i q   (linear, dim rows).
// A node's free slope (ANCF) is a direction fixed in the body, with coordinates from G c = B^T r_i':
//   Lambda_i' = r_i' - sum_j c_ij e_j               (linear, dim rows).
// An ancf_beam body (nodes with r_x, r_y, r_z): the frame is the gradient triad of its first
// node, kept rigid by its metric (6 quadratic rows); every other point and gradient keeps its
// coordinates in it (linear rows; see rigidizeBeamBody in the .cpp).
// Used by the PIM for initially undeformed flexible bodies, and for rigid models of bodies.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "constraints/KernelConstraint.hpp"
#include "core/Model.hpp"

namespace flexsens {

/// Linear constraint Lambda_i = r_i - r_A - sum_j c_j (r_Bj - r_A); nodes = (A, B.., i).
/// With `slope`, node i's slope instead: Lambda_i' = r_i' - sum_j c_j (r_Bj - r_A); the local
/// coordinates are then positions and slopes of every node (all must carry one).
class AttachedPointConstraint : public KernelConstraint<AttachedPointConstraint> {
 public:
  AttachedPointConstraint(std::string name, std::vector<int> nodes, VecX coefficients, int dim,
                          bool slope = false);
  /// Any linear point relation J x = 0 over the nodes' positions (dim rows, position-only
  /// nodes); e.g. a planar body's point r_P = (1 - xi) r_A + xi r_B + eta R90 (r_B - r_A).
  /// With `gradients` = 3 (ancf_beam nodes) J acts on positions and gradients, 12 per node.
  /// `kind` names it in messages (default attached_point / attached_slope; `weld`, `hinge`).
  AttachedPointConstraint(std::string name, std::vector<int> nodes, MatX J, int gradients = 0, std::string kind = "")
      : KernelConstraint(std::move(name), std::move(nodes)), dim_(static_cast<int>(J.rows())),
        slope_(gradients > 0), gradients_(gradients), J_(std::move(J)), kind_(std::move(kind)) {}
  std::string kind() const override {
    return !kind_.empty() ? kind_ : slope_ ? "attached_slope" : "attached_point";
  }
  int gradients() const override { return gradients_; }
  int rows() const override { return dim_; }
  void jacobian(const LocalState& s, MatX& J) const override;
  void hessian(const LocalState& s, int r, MatX& H) const override;
  bool constantHessian() const override { return true; }
  bool parameterDerivative(const LocalState&, int, VecX&, MatX&) const override { return false; }
  std::vector<std::pair<std::string, Quantity*>> properties() override { return {}; }

 private:
  friend class KernelConstraint<AttachedPointConstraint>;
  /// No properties: never depends on a parameter (the coefficients are constants).
  std::vector<const Quantity*> kernelProperties() const { return {}; }
  /// Value template (props is empty).
  template <class T>
  VecT<T> phiT(const LocalState& s, const VecT<T>& x, const VecT<T>& props) const;
  VecX c_;
  int dim_;
  bool slope_;
  int gradients_;
  MatX J_;  ///< constant Jacobian, dim x (coordinates per node)*(k+2)
  std::string kind_;
};

struct Rigidization {
  int cloudDimension = 0;            ///< 1, 2 or 3
  std::vector<int> basicPoints;      ///< node indices A, B, (C, (D))
  std::vector<std::unique_ptr<Constraint>> constraints;
  int rows() const;
};

/// How the generator picks basic points and which equations it may leave out.
struct RigidizeOptions {
  /// Basic points in list order (the next node that widens the span) instead of the
  /// best-conditioned greedy choice (farthest from the span so far). Rigid bodies of a scene
  /// use it so that the user decides which points carry the mass matrix.
  bool inOrder = false;
  /// linked(i, j): the distance of model nodes i and j is fixed already (both ground, or both
  /// on an earlier rigid body, as the two axis points a revolute joint shares); the
  /// generator then omits that distance, which would be a redundant constraint.
  std::function<bool(int, int)> linked;
  /// Rigidize the nodes' free slopes too (an ANCF body: each slope a direction fixed in the
  /// body). Off for bodies whose elements carry no slopes (a positions-only beam, a diagonal,
  /// a rigid body's attached points): a slope there belongs to another body's ANCF chain
  /// that is only pinned to this one.
  bool slopes = false;
};

/// Rigidizes the cloud `nodes` at positions X (one column per model node). `pairLength`,
/// if given, is the quantity the distance of a two-node cloud keeps (e.g. a spring's
/// natural length, so that a parameter bound to it enters Lambda_p). Throws InputError
/// (prefixed by `where`) for degenerate clouds. Equations among ground nodes only are left out.
Rigidization rigidize(const std::string& name, const std::vector<int>& nodes, const Model& m,
                      const MatX& X, const std::string& where, const Quantity* pairLength = nullptr,
                      const RigidizeOptions& options = {});

}  // namespace flexsens
