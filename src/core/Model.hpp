// The assembled mechanism: nodes, elements, constraints and design parameters.
// Built once by the scene builder and not modified afterwards (per-run data lives elsewhere).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/Element.hpp"

namespace flexsens {

/// A node carries its position (dim coordinates) and, on ANCF elements, its position
/// gradients (dimensionless, dim coordinates each), stored one after the other in `slope`:
///  - on ancf_cable, one: the slope r_s = dr/ds along the reference arc length s (unit length
///    in the rest state);
///  - on ancf_beam (3D), three: r_x, r_y, r_z, the columns of the position gradient dr/dX
///    with respect to the element's reference coordinates X = (axial, section y, section z).
/// A ground node's position is fixed; its gradients are free (a pin) unless the node is
/// clamped (all of its gradients fixed too).
struct Node {
  std::string name;
  VecX position;       ///< initial (and, for ground nodes, permanent) position, dim entries [m]
  VecX velocity;       ///< initial velocity, dim entries [m/s]
  bool ground = false; ///< the position carries no coordinates
  int firstDof = -1;   ///< index of the node's first position coordinate in q, or -1 for ground
  VecX slope;          ///< initial (clamped: permanent) gradients, gradients * dim entries [-]; empty: none
  VecX slopeRate;      ///< their initial rates, as many entries [1/s] (empty: zero)
  bool clamped = false; ///< the gradients are fixed (no gradient coordinates); only with gradients
  int slopeDof = -1;   ///< index of the node's first gradient coordinate in q, or -1
  bool hasSlope() const { return slope.size() > 0; }
  /// Number of gradient vectors the node carries: 0, 1 (cable slope) or 3 (r_x, r_y, r_z).
  int gradients(int dim) const { return static_cast<int>(slope.size()) / dim; }
  bool slopeFree() const { return hasSlope() && !clamped; }
};

struct Parameter {
  std::string name;
  double nominal = 0.0;
  std::string boundTo;  ///< "element.property" description, for reports
  /// `per: element`: the family's name (the parameter is family[i]) and the model element whose
  /// property it is; "" and -1 otherwise.
  std::string family;
  int element = -1;
};

struct Model {
  int dim = 2;
  std::string plane = "xy";      ///< names of the two planar axes ("xy", "xz", "yz"); 3D uses xyz
  VecX gravity;                  ///< dim entries [m/s^2] (nominal)
  std::vector<int> gravityParam; ///< per component: design parameter index, or -1 (empty: none)
  /// Gravity at parameters p (components bound to parameters take their values).
  VecX gravityAt(const VecX& p) const {
    VecX g = gravity;
    for (size_t c = 0; c < gravityParam.size(); ++c)
      if (gravityParam[c] >= 0) g[c] = p[gravityParam[c]];
    return g;
  }
  std::vector<Node> nodes;
  std::vector<std::unique_ptr<Element>> elements;
  std::vector<std::unique_ptr<Constraint>> constraints;
  std::vector<Parameter> parameters;
  /// Redundant constraint rows left out of `constraints` (core/RedundantRows.hpp): their
  /// labels, and the constraints left out whole (rows of the rest live in SelectedRows).
  std::vector<std::string> redundantRows;
  std::vector<std::unique_ptr<Constraint>> leftOut;

  int n = 0;  ///< number of coordinates
  int m = 0;  ///< number of scalar constraint equations
  /// The node each coordinate belongs to (finalize): labels in O(1), not a search over the
  /// nodes (12% of a 20-step run of a 20000-segment chain wrote its labels in O(n^2)).
  std::vector<int> coordinateNode;

  /// Call after nodes, elements and constraints are in place: numbers the coordinates.
  void finalize();
  int nodeIndex(const std::string& name) const;  ///< -1 if absent
  VecX nominalParameters() const;
  VecX initialPositions() const;
  VecX initialVelocities() const;
  /// Label of coordinate i, e.g. "x(n2)", or "x'(n2)" for the x component of n2's slope.
  std::string coordinateLabel(int i) const;
  /// Axis letter of component c of a node ('x', 'y' or 'z').
  char axisName(int c) const { return dim == 3 ? "xyz"[c] : plane[c]; }
  /// Global coordinate index of component c of node i, or -1 where it is fixed: c < dim the
  /// position, dim <= c < dim + slope.size() the gradients (ANCF nodes; dim + c' the slope's
  /// or r_x's component c', 2 dim + c' r_y's, 3 dim + c' r_z's).
  int dof(int node, int c) const {
    const Node& nd = nodes[node];
    if (c < dim) return nd.ground ? -1 : nd.firstDof + c;
    return nd.slopeDof < 0 ? -1 : nd.slopeDof + c - dim;
  }
  /// Value of component c (as in dof) of node i at q: q's entry, or the fixed value.
  double coordinate(const VecX& q, int node, int c) const {
    const int d = dof(node, c);
    if (d >= 0) return q[d];
    return c < dim ? nodes[node].position[c] : nodes[node].slope[c - dim];
  }
};

}  // namespace flexsens
