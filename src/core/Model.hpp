// The assembled mechanism: nodes, elements, constraints and design parameters.
// Built once by the scene builder and not modified afterwards (per-run data lives elsewhere).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/Element.hpp"

namespace flexsens {

struct Node {
  std::string name;
  VecX position;       ///< initial (and, for ground nodes, permanent) position, dim entries [m]
  VecX velocity;       ///< initial velocity, dim entries [m/s]
  bool ground = false; ///< ground nodes carry no coordinates
  int firstDof = -1;   ///< index of the node's first coordinate in q, or -1 for ground
};

struct Parameter {
  std::string name;
  double nominal = 0.0;
  std::string boundTo;  ///< "element.property" description, for reports
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

  int n = 0;  ///< number of coordinates
  int m = 0;  ///< number of scalar constraint equations

  /// Call after nodes, elements and constraints are in place: numbers the coordinates.
  void finalize();
  int nodeIndex(const std::string& name) const;  ///< -1 if absent
  VecX nominalParameters() const;
  VecX initialPositions() const;
  VecX initialVelocities() const;
  /// Label of coordinate i, e.g. "x(n2)".
  std::string coordinateLabel(int i) const;
  /// Axis letter of component c of a node ('x', 'y' or 'z').
  char axisName(int c) const { return dim == 3 ? "xyz"[c] : plane[c]; }
  /// Global coordinate index of component c of node i, or -1 for a ground node.
  int dof(int node, int c) const { return nodes[node].ground ? -1 : nodes[node].firstDof + c; }
};

}  // namespace flexsens
