#include "core/Model.hpp"

namespace flexsens {

void Model::finalize() {
  // Node after node: its position coordinates, then its slope's (if it carries a free one).
  n = 0;
  coordinateNode.clear();
  for (auto& nd : nodes) {
    const int k = static_cast<int>(&nd - nodes.data());
    nd.firstDof = nd.ground ? -1 : n;
    if (!nd.ground) n += dim;
    nd.slopeDof = nd.slopeFree() ? n : -1;
    if (nd.slopeFree()) n += static_cast<int>(nd.slope.size());
    coordinateNode.resize(n, k);
  }
  m = 0;
  for (const auto& c : constraints) m += c->rows();
}

int Model::nodeIndex(const std::string& name) const {
  for (size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].name == name) return static_cast<int>(i);
  return -1;
}

VecX Model::nominalParameters() const {
  VecX p(parameters.size());
  for (size_t k = 0; k < parameters.size(); ++k) p[k] = parameters[k].nominal;
  return p;
}

VecX Model::initialPositions() const {
  VecX q(n);
  for (const auto& nd : nodes) {
    if (!nd.ground) q.segment(nd.firstDof, dim) = nd.position;
    if (nd.slopeDof >= 0) q.segment(nd.slopeDof, nd.slope.size()) = nd.slope;
  }
  return q;
}

VecX Model::initialVelocities() const {
  VecX v(n);
  for (const auto& nd : nodes) {
    if (!nd.ground) v.segment(nd.firstDof, dim) = nd.velocity;
    if (nd.slopeDof >= 0)
      v.segment(nd.slopeDof, nd.slope.size()) = nd.slopeRate.size() ? nd.slopeRate : VecX(VecX::Zero(nd.slope.size()));
  }
  return v;
}

std::string Model::coordinateLabel(int i) const {
  if (i < 0 || i >= static_cast<int>(coordinateNode.size())) return "?";
  const Node& nd = nodes[coordinateNode[i]];
  if (!nd.ground && i >= nd.firstDof && i < nd.firstDof + dim)
    return std::string(1, axisName(i - nd.firstDof)) + "(" + nd.name + ")";
  // the slope's x' = dx/ds; a full gradient's x_x, x_y, x_z = dx/dX_j (j the reference axis)
  const int k = i - nd.slopeDof, c = k % dim;
  if (nd.gradients(dim) == 1) return std::string(1, axisName(c)) + "'(" + nd.name + ")";
  return std::string(1, axisName(c)) + "_" + "xyz"[k / dim] + "(" + nd.name + ")";
}

}  // namespace flexsens
