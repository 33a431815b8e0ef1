#include "pim/MassProperties.hpp"

#include <map>
#include <set>

namespace flexsens {

MassProperties rigidMassProperties(const Model& m, const std::vector<int>& nodes, const VecX& p) {
  const int d = m.dim;
  const std::set<int> in(nodes.begin(), nodes.end());
  std::map<int, int> local;  // node -> position in the body's list
  for (size_t i = 0; i < nodes.size(); ++i) local[nodes[i]] = static_cast<int>(i);
  const int N = static_cast<int>(nodes.size());
  // u^T M w summed element by element (no global matrix: meshes have thousands of nodes).
  std::vector<std::pair<std::vector<int>, MatX>> blocks;
  const VecX g = VecX::Zero(d);
  for (const auto& e : m.elements) {
    bool mine = !e->nodes().empty() && !e->usesSlopes();
    for (int n : e->nodes()) mine = mine && in.count(n);
    if (!mine) continue;
    LocalState s;
    s.dim = d;
    s.p = &p;
    s.gravity = &g;
    s.x.resize(d * e->nodes().size());
    for (size_t j = 0; j < e->nodes().size(); ++j) s.x.segment(j * d, d) = m.nodes[e->nodes()[j]].position;
    s.v = VecX::Zero(s.x.size());
    MatX Me;
    if (!e->mass(s, Me)) continue;
    std::vector<int> ids;
    for (int n : e->nodes()) ids.push_back(local[n]);
    blocks.emplace_back(ids, Me);
  }
  auto quad = [&](const VecX& u, const VecX& w) {
    double sum = 0.0;
    for (const auto& [ids, Me] : blocks) {
      VecX ue(Me.rows()), we(Me.rows());
      for (size_t j = 0; j < ids.size(); ++j) {
        ue.segment(j * d, d) = u.segment(ids[j] * d, d);
        we.segment(j * d, d) = w.segment(ids[j] * d, d);
      }
      sum += ue.dot(Me * we);
    }
    return sum;
  };
  MatX X(d, N);
  for (int i = 0; i < N; ++i) X.col(i) = m.nodes[nodes[i]].position;
  auto translation = [&](int a) {
    VecX u = VecX::Zero(d * N);
    for (int i = 0; i < N; ++i) u[i * d + a] = 1.0;
    return u;
  };
  auto field = [&](const MatX& W) { return VecX(Eigen::Map<const VecX>(W.data(), W.size())); };
  MassProperties r;
  r.mass = quad(translation(0), translation(0));
  r.centre = VecX::Zero(d);
  for (int a = 0; a < d; ++a) {
    MatX Xa = MatX::Zero(d, N);
    Xa.row(a) = X.row(a);  // the field whose component a is X_a: u_a^T M it = int rho X_a
    r.centre[a] = quad(translation(a), field(Xa)) / r.mass;
  }
  const MatX R = X.colwise() - r.centre;
  if (d == 2) {
    MatX W(2, N);
    W.row(0) = -R.row(1);
    W.row(1) = R.row(0);
    r.inertia = MatX::Constant(1, 1, quad(field(W), field(W)));
    return r;
  }
  std::vector<VecX> w;
  for (int a = 0; a < 3; ++a) {
    MatX W(3, N);
    for (int i = 0; i < N; ++i) W.col(i) = Eigen::Vector3d::Unit(a).cross(Eigen::Vector3d(R.col(i)));
    w.push_back(field(W));
  }
  r.inertia.resize(3, 3);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) r.inertia(a, b) = quad(w[a], w[b]);
  return r;
}

}  // namespace flexsens
