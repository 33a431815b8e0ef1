// The stencils of the Kirchhoff bending triangles (elements/ShellKirchhoff.hpp).
//
// Each triangle T gets a quadratic fit x(xi) = sum_a N_a(xi) x_a through 6 nodes: its 3
// vertices and, by preference, the 3 apexes of its edge neighbours; xi are the rest positions
// projected on T's rest plane (so the fit reproduces every quadratic surface over that plane
// and its in-plane coordinates exactly). When an apex is missing (a boundary triangle) or the
// 6 nodes lie close to a conic (the fit ill-posed), the 3 extra nodes are the best-posed triple
// among the nearest nodes of the triangles around T's vertices. The tangent across an interior
// edge at its midpoint is the mean of the two neighbours' fits' derivatives along the edge's
// outward normal (each in its own rest plane), the same vector, with opposite signs, for both
// triangles of the edge.
#include <algorithm>
#include <set>
#include <stdexcept>

#include "elements/ShellKirchhoff.hpp"
#include "elements/ShellMesh.hpp"
#include "elements/ShellPatchMembrane.hpp"

namespace flexsens {

namespace {

using Basis = Eigen::Matrix<double, 6, 1>;

/// A triangle's quadratic fit: nodes, the rest-plane frame, the inverse of the 6 x 6
/// interpolation matrix (N_a(xi) = basis(xi)^T Vinv.col(a)).
struct QuadraticFit {
  std::array<int, 6> nodes{};
  Eigen::Vector3d center, t1, t2;
  Eigen::Matrix<double, 6, 6> Vinv;
};

Basis basis(const Eigen::Vector2d& p) {
  Basis b;
  b << 1.0, p.x(), p.y(), p.x() * p.x(), p.x() * p.y(), p.y() * p.y();
  return b;
}

/// The smallest singular value of the interpolation matrix of the nodes (rows normalized, the
/// coordinates in units of h): 0 when the 6 nodes lie on a conic.
double posedness(const std::array<Eigen::Vector2d, 6>& p, double h) {
  Eigen::Matrix<double, 6, 6> V;
  for (int a = 0; a < 6; ++a) V.row(a) = basis(p[a] / h).normalized().transpose();
  return Eigen::JacobiSVD<Eigen::Matrix<double, 6, 6>>(V).singularValues()[5];
}

/// A posedness above this keeps the apexes (a regular patch has about 0.1).
constexpr double kGoodFit = 0.02;
/// Below this no fit is usable.
constexpr double kNoFit = 1e-6;

struct Topology {
  std::map<std::pair<int, int>, std::vector<int>> edgeTris;  ///< sorted edge -> triangles
  std::vector<std::vector<int>> nodeTris;                    ///< node -> triangles
};

Topology topology(const std::vector<std::array<int, 3>>& tris, size_t nodes) {
  Topology t;
  t.nodeTris.resize(nodes);
  for (size_t k = 0; k < tris.size(); ++k)
    for (int j = 0; j < 3; ++j) {
      const int a = tris[k][j], b = tris[k][(j + 1) % 3];
      t.edgeTris[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(k));
      t.nodeTris[a].push_back(static_cast<int>(k));
    }
  return t;
}

/// The third node of triangle k that is not a or b.
int thirdNode(const std::array<int, 3>& t, int a, int b) {
  for (int v : t)
    if (v != a && v != b) return v;
  return -1;
}

QuadraticFit fitOf(int k, const std::vector<Eigen::Vector3d>& X, const std::vector<std::array<int, 3>>& tris,
                   const Topology& topo, const std::string& who) {
  const auto& t = tris[k];
  QuadraticFit f;
  f.center = (X[t[0]] + X[t[1]] + X[t[2]]) / 3.0;
  const Eigen::Vector3d n = (X[t[1]] - X[t[0]]).cross(X[t[2]] - X[t[0]]).normalized();
  f.t1 = (X[t[1]] - X[t[0]]).normalized();
  f.t2 = n.cross(f.t1);
  const double h = std::max({(X[t[1]] - X[t[0]]).norm(), (X[t[2]] - X[t[1]]).norm(), (X[t[0]] - X[t[2]]).norm()});
  auto local = [&](int node) { return Eigen::Vector2d(f.t1.dot(X[node] - f.center), f.t2.dot(X[node] - f.center)); };
  std::array<int, 3> extra{-1, -1, -1};
  for (int j = 0; j < 3; ++j) {
    const int a = t[(j + 1) % 3], b = t[(j + 2) % 3];
    for (int other : topo.edgeTris.at({std::min(a, b), std::max(a, b)}))
      if (other != k) extra[j] = thirdNode(tris[other], a, b);
  }
  auto score = [&](const std::array<int, 3>& e) {
    std::array<Eigen::Vector2d, 6> p;
    for (int a = 0; a < 3; ++a) p[a] = local(t[a]), p[3 + a] = local(e[a]);
    return posedness(p, h);
  };
  double best = -1.0;
  if (extra[0] >= 0 && extra[1] >= 0 && extra[2] >= 0 && extra[0] != extra[1] && extra[1] != extra[2] &&
      extra[0] != extra[2])
    best = score(extra);
  if (best < kGoodFit) {  // the nearest nodes around the vertices, best-posed triple
    std::set<int> ring;
    for (int v : t)
      for (int tri : topo.nodeTris[v])
        for (int w : tris[tri])
          if (w != t[0] && w != t[1] && w != t[2]) ring.insert(w);
    std::vector<int> cand(ring.begin(), ring.end());
    std::sort(cand.begin(), cand.end(),
              [&](int a, int b) { return (X[a] - f.center).squaredNorm() < (X[b] - f.center).squaredNorm(); });
    if (cand.size() > 12) cand.resize(12);
    for (size_t a = 0; a < cand.size(); ++a)
      for (size_t b = a + 1; b < cand.size(); ++b)
        for (size_t c = b + 1; c < cand.size(); ++c) {
          const std::array<int, 3> e{cand[a], cand[b], cand[c]};
          const double sc = score(e);
          if (sc > best) best = sc, extra = e;
        }
  }
  if (!(best > kNoFit))
    throw std::invalid_argument(who + ": no quadratic fit through the triangle and 3 nodes around it is well posed "
                                      "(too few nodes near it, or they lie on a conic); expected a finer or less distorted mesh");
  Eigen::Matrix<double, 6, 6> V;
  for (int a = 0; a < 3; ++a) f.nodes[a] = t[a], f.nodes[3 + a] = extra[a];
  for (int a = 0; a < 6; ++a) V.row(a) = basis(local(f.nodes[a])).transpose();
  f.Vinv = V.inverse();
  return f;
}

/// Coefficients of the fit's derivative along the unit direction dir (3D, in the fit's rest
/// plane) at point m, added times w to coef (mesh node -> coefficient).
void addDerivative(const QuadraticFit& f, const Eigen::Vector3d& m, const Eigen::Vector3d& dir, double w,
                   std::map<int, double>& coef) {
  const Eigen::Vector2d p(f.t1.dot(m - f.center), f.t2.dot(m - f.center)), u(f.t1.dot(dir), f.t2.dot(dir));
  Basis g;
  g << 0.0, u.x(), u.y(), 2.0 * p.x() * u.x(), p.y() * u.x() + p.x() * u.y(), 2.0 * p.y() * u.y();
  const Eigen::Matrix<double, 1, 6> c = g.transpose() * f.Vinv;
  for (int a = 0; a < 6; ++a) coef[f.nodes[a]] += w * c[a];
}

/// The outward unit normal of edge (a, b) in triangle t's rest plane.
Eigen::Vector3d outward(const std::vector<Eigen::Vector3d>& X, const std::array<int, 3>& t, int a, int b) {
  const Eigen::Vector3d e = (X[b] - X[a]).normalized(), away = X[a] - X[thirdNode(t, a, b)];
  return (away - e * e.dot(away)).normalized();
}

/// The EBST1 membrane of a fit: its shape gradients at the centroid (xi = 0).
void addPatchMembrane(const std::string& name, const QuadraticFit& f, const std::vector<Eigen::Vector3d>& rest,
                      const std::vector<int>& ids, const std::shared_ptr<ShellProperties>& props,
                      std::vector<std::unique_ptr<Element>>& out) {
  Eigen::Matrix<double, 6, 2> G;
  VecX X(18);
  std::vector<int> model(6);
  for (int a = 0; a < 6; ++a) {
    G(a, 0) = f.Vinv(1, a);
    G(a, 1) = f.Vinv(2, a);
    X.segment<3>(3 * a) = rest[f.nodes[a]];
    model[a] = ids[f.nodes[a]];
  }
  const Eigen::Vector3d& X0 = rest[f.nodes[0]];
  const double area = 0.5 * (rest[f.nodes[1]] - X0).cross(rest[f.nodes[2]] - X0).norm();
  out.push_back(std::make_unique<ShellPatchMembrane>(name, model, props, X, G, area));
}

}  // namespace

int buildKirchhoffBending(const std::string& name, const std::vector<Eigen::Vector3d>& rest,
                          const std::vector<std::array<int, 3>>& tris, const std::vector<int>& ids,
                          const std::shared_ptr<ShellProperties>& props, bool flatRest,
                          std::vector<std::unique_ptr<Element>>& out, const std::function<std::string(int)>& label,
                          const KirchhoffBoundaries& boundary, bool patchMembrane,
                          const std::vector<std::shared_ptr<ShellProperties>>& perTriangle) {
  const Topology topo = topology(tris, rest.size());
  std::vector<QuadraticFit> fits;
  for (size_t k = 0; k < tris.size(); ++k) {
    const auto& t = tris[k];
    fits.push_back(fitOf(static_cast<int>(k), rest, tris, topo,
                         "shell " + name + ": triangle of nodes " + label(t[0]) + " " + label(t[1]) + " " + label(t[2])));
  }
  for (size_t k = 0; k < tris.size(); ++k) {
    const auto& t = tris[k];
    std::array<KirchhoffEdge, 3> edges;
    std::array<std::map<int, double>, 3> coef;
    for (int i = 0; i < 3; ++i) {  // edge i opposite vertex i
      const int a = t[(i + 1) % 3], b = t[(i + 2) % 3];
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      const std::vector<int>& wings = topo.edgeTris.at(key);
      const Eigen::Vector3d mid = 0.5 * (rest[a] + rest[b]), nu = outward(rest, t, a, b);
      if (wings.size() == 2) {
        const int other = wings[0] == static_cast<int>(k) ? wings[1] : wings[0];
        edges[i].kind = KirchhoffEdge::Kind::Shared;
        addDerivative(fits[k], mid, nu, 0.5, coef[i]);
        addDerivative(fits[other], mid, outward(rest, tris[other], a, b), -0.5, coef[i]);
        continue;
      }
      const auto it = boundary.find(key);
      if (it != boundary.end() && it->second.fixed) {
        edges[i].kind = KirchhoffEdge::Kind::Fixed;
        const Eigen::Vector3d& pn = it->second.normal;
        edges[i].fixed = pn.squaredNorm() > 0.0 ? Eigen::Vector3d((pn.dot(nu) >= 0.0 ? 1.0 : -1.0) * pn.normalized()) : nu;
      } else {
        edges[i].kind = KirchhoffEdge::Kind::Free;
        if (it != boundary.end()) edges[i].moment = it->second.moment;
      }
    }
    std::vector<int> stencil{t[0], t[1], t[2]};
    for (const auto& c : coef)
      for (const auto& [node, w] : c)
        if (std::find(stencil.begin(), stencil.end(), node) == stencil.end()) stencil.push_back(node);
    const int N = static_cast<int>(stencil.size());
    VecX X(3 * N);
    std::vector<int> model(N);
    for (int a = 0; a < N; ++a) X.segment<3>(3 * a) = rest[stencil[a]], model[a] = ids[stencil[a]];
    for (int i = 0; i < 3; ++i) {
      if (edges[i].kind != KirchhoffEdge::Kind::Shared) continue;
      edges[i].coeff = VecX::Zero(N);
      for (int a = 0; a < N; ++a) {
        const auto f = coef[i].find(stencil[a]);
        if (f != coef[i].end()) edges[i].coeff[a] = f->second;
      }
    }
    const auto& own = perTriangle.empty() ? props : perTriangle[k];
    out.push_back(std::make_unique<ShellKirchhoffBending>(name + ".bend" + std::to_string(k), model, own, X, edges,
                                                          flatRest));
    if (patchMembrane) addPatchMembrane(name + ".membrane" + std::to_string(k), fits[k], rest, ids, own, out);
  }
  return static_cast<int>(tris.size());
}

}  // namespace flexsens
