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

double OutputSpec::value(const Model& m, const State& x) const {
  if (!angle.empty()) {
    if (!rate) return jointAngleT<double>(angleCoordinates(m, angle, x.q, false), nullptr);
    VecX g;  // theta' = grad theta . x'
    jointAngleT<double>(angleCoordinates(m, angle, x.q, false), &g);
    return g.dot(angleCoordinates(m, angle, x.v, true));
  }
  if (rate) {
    const int d = m.dof(node, component);
    return d < 0 ? 0.0 : x.v[d];  // ground nodes and clamped slopes do not move
  }
  // A displacement's rest position is the scene's (or mesh's) node position: no parameter
  // binds it, so the displacement's derivative is the position's (below).
  if (displacement) return m.coordinate(x.q, node, component) - m.nodes[node].position[component];
  return m.coordinate(x.q, node, component);  // a position, or a slope component (ANCF)
}

double OutputSpec::derivative(const Model& m, const State& x, const State& dx) const {
  if (!angle.empty()) {
    const VecX xq = angleCoordinates(m, angle, x.q, false), dq = angleCoordinates(m, angle, dx.q, true);
    VecX g;
    jointAngleT<double>(xq, &g);
    if (!rate) return g.dot(dq);
    // d/dp (grad theta . v) = v^T Hess(theta) q_p + grad theta . v_p
    const VecX v = angleCoordinates(m, angle, x.v, true);
    return v.dot(jointAngleHessian(xq) * dq) + g.dot(angleCoordinates(m, angle, dx.v, true));
  }
  const int d = m.dof(node, component);
  if (d < 0) return 0.0;
  return rate ? dx.v[d] : dx.q[d];
}

void OutputSpec::addGradient(const Model& m, const State& x, double weight, Eigen::Ref<VecX> gq,
                             Eigen::Ref<VecX> gv) const {
  if (!angle.empty()) {
    // Scatter a gradient over the angle's 18 coordinates onto the model's (ground: none).
    auto scatter = [&](const VecX& g18, Eigen::Ref<VecX> into) {
      for (size_t a = 0; a < angle.size(); ++a)
        for (int c = 0; c < 3; ++c)
          if (const int d = m.dof(angle[a], c); d >= 0) into[d] += weight * g18[Eigen::Index(3 * a + c)];
    };
    const VecX xq = angleCoordinates(m, angle, x.q, false);
    VecX g;
    jointAngleT<double>(xq, &g);
    if (!rate) return scatter(g, gq);
    // theta' = grad theta . v: d/dq = Hess(theta) v (symmetric), d/dv = grad theta.
    const VecX v = angleCoordinates(m, angle, x.v, true);
    scatter(jointAngleHessian(xq) * v, gq);
    scatter(g, gv);
    return;
  }
  const int d = m.dof(node, component);
  if (d < 0) return;
  (rate ? gv : gq)[d] += weight;
}

}  // namespace flexsens
