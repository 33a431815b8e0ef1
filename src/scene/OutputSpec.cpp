// Named outputs: a node coordinate, or a signed joint angle (elements/JointAngle.hpp), and
// their derivative along a direction of q (the sensitivity columns of series.csv).
#include "elements/JointAngle.hpp"
#include "scene/Scene.hpp"

namespace flexsens {

namespace {
/// The 18 coordinates of an angle's six nodes (ground nodes at their fixed positions), from
/// positions q; with zeroGround, ground nodes contribute 0 (for a direction dq).
VecX angleCoordinates(const Model& m, const std::vector<int>& nodes, const VecX& q, bool zeroGround) {
  VecX x(3 * nodes.size());
  for (size_t a = 0; a < nodes.size(); ++a)
    for (int c = 0; c < 3; ++c) {
      const int d = m.dof(nodes[a], c);
      x[3 * a + c] = d >= 0 ? q[d] : (zeroGround ? 0.0 : m.nodes[nodes[a]].position[c]);
    }
  return x;
}
}  // namespace

double OutputSpec::value(const Model& m, const VecX& q) const {
  if (!angle.empty()) return jointAngleT<double>(angleCoordinates(m, angle, q, false), nullptr);
  return m.coordinate(q, node, component);  // a position, or a slope component (ANCF)
}

double OutputSpec::derivative(const Model& m, const VecX& q, const VecX& dq) const {
  if (!angle.empty()) {
    VecX g;
    jointAngleT<double>(angleCoordinates(m, angle, q, false), &g);
    return g.dot(angleCoordinates(m, angle, dq, true));
  }
  const int d = m.dof(node, component);
  return d < 0 ? 0.0 : dq[d];
}

}  // namespace flexsens
