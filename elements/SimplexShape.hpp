// Lagrange shape functions and quadrature on the reference simplices of the continuum
// elements (elements/Solid.hpp): triangles (3 and 6 nodes) and tetrahedra (4 and 10 nodes).
//
// Node order is VTK's (VTK_TRIANGLE, VTK_QUADRATIC_TRIANGLE, VTK_TETRA, VTK_QUADRATIC_TETRA), so
// the .vtu writer passes connectivity through: corners first at the reference points
// 0, e1, e2 (, e3), then the edge midpoints of the edges (0,1), (1,2), (2,0) (, (0,3), (1,3),
// (2,3)). The mesh reader maps Gmsh's order onto this one by the reference coordinates Gmsh
// reports for its element types, not by a hard-coded table.
//
// Shapes in barycentric coordinates L0 = 1 - sum xi, L_k = xi_k: corners L_i (linear) or
// L_i (2 L_i - 1) (quadratic), edge midpoints 4 L_a L_b.
#pragma once

#include <array>
#include <cstdio>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/Types.hpp"

namespace flexsens {

/// A number for messages: %g (6 significant digits).
inline std::string fmtNumber(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", x);
  return b;
}

enum class Simplex { Tri3, Tri6, Tet4, Tet10 };

inline int simplexDim(Simplex s) { return s == Simplex::Tri3 || s == Simplex::Tri6 ? 2 : 3; }
inline int simplexOrder(Simplex s) { return s == Simplex::Tri3 || s == Simplex::Tet4 ? 1 : 2; }
inline int simplexNodes(Simplex s) {
  switch (s) {
    case Simplex::Tri3: return 3;
    case Simplex::Tri6: return 6;
    case Simplex::Tet4: return 4;
    default: return 10;
  }
}
inline std::string simplexName(Simplex s) {
  switch (s) {
    case Simplex::Tri3: return "triangle3";
    case Simplex::Tri6: return "triangle6";
    case Simplex::Tet4: return "tetra4";
    default: return "tetra10";
  }
}

/// The edges (corner pairs) whose midpoints are the quadratic nodes, in VTK order.
inline std::vector<std::pair<int, int>> simplexEdges(Simplex s) {
  if (s == Simplex::Tri6) return {{0, 1}, {1, 2}, {2, 0}};
  if (s == Simplex::Tet10) return {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  return {};
}

/// Reference coordinates of node i (dim entries).
inline VecX simplexNode(Simplex s, int i) {
  const int d = simplexDim(s), corners = d + 1;
  auto corner = [&](int c) {
    VecX x = VecX::Zero(d);
    if (c > 0) x[c - 1] = 1.0;
    return x;
  };
  if (i < corners) return corner(i);
  const auto e = simplexEdges(s).at(i - corners);
  return 0.5 * (corner(e.first) + corner(e.second));
}

/// Shape values N (nodes) and reference gradients dN/dxi (nodes x dim) at xi.
inline void simplexShape(Simplex s, const VecX& xi, VecX& N, MatX& dN) {
  const int d = simplexDim(s), corners = d + 1, n = simplexNodes(s);
  VecX L(corners);
  L[0] = 1.0 - xi.sum();
  L.tail(d) = xi;
  MatX dL = MatX::Zero(corners, d);  // dL_i / dxi
  dL.row(0).setConstant(-1.0);
  dL.bottomRows(d).setIdentity();
  N.resize(n);
  dN.resize(n, d);
  if (simplexOrder(s) == 1) {
    N = L;
    dN = dL;
    return;
  }
  for (int i = 0; i < corners; ++i) {
    N[i] = L[i] * (2.0 * L[i] - 1.0);
    dN.row(i) = (4.0 * L[i] - 1.0) * dL.row(i);
  }
  const auto edges = simplexEdges(s);
  for (size_t k = 0; k < edges.size(); ++k) {
    const auto [a, b] = edges[k];
    N[corners + k] = 4.0 * L[a] * L[b];
    dN.row(corners + k) = 4.0 * (L[b] * dL.row(a) + L[a] * dL.row(b));
  }
}

/// A quadrature rule on the reference simplex: points (dim each) and weights (summing to the
/// reference measure, 1/2 or 1/6).
struct SimplexRule {
  std::vector<VecX> x;
  std::vector<double> w;
};

/// Stiffness rule: exact for B^T B of the undistorted element (degree 2 (p - 1)): the
/// centroid for linear elements, the symmetric 3-point (triangle) and 4-point (tetrahedron)
/// degree-2 rules for quadratic ones. Positive weights, points inside.
inline SimplexRule stiffnessRule(Simplex s) {
  SimplexRule r;
  auto pt = [](std::initializer_list<double> v) {
    VecX x(v.size());
    int i = 0;
    for (double a : v) x[i++] = a;
    return x;
  };
  switch (s) {
    case Simplex::Tri3:
      r.x = {pt({1.0 / 3.0, 1.0 / 3.0})};
      r.w = {0.5};
      break;
    case Simplex::Tri6:
      r.x = {pt({1.0 / 6.0, 1.0 / 6.0}), pt({2.0 / 3.0, 1.0 / 6.0}), pt({1.0 / 6.0, 2.0 / 3.0})};
      r.w = {1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0};
      break;
    case Simplex::Tet4:
      r.x = {pt({0.25, 0.25, 0.25})};
      r.w = {1.0 / 6.0};
      break;
    case Simplex::Tet10: {
      const double a = (5.0 + 3.0 * std::sqrt(5.0)) / 20.0, b = (5.0 - std::sqrt(5.0)) / 20.0;
      r.x = {pt({b, b, b}), pt({a, b, b}), pt({b, a, b}), pt({b, b, a})};
      r.w = {1.0 / 24.0, 1.0 / 24.0, 1.0 / 24.0, 1.0 / 24.0};
      break;
    }
  }
  return r;
}

/// Gauss-Legendre points and weights on [0, 1] (Newton on the Legendre polynomial).
inline void gaussLegendre01(int n, std::vector<double>& x, std::vector<double>& w) {
  x.resize(n);
  w.resize(n);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    x[i] = 0.5 * (1.0 - z);
    w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
  }
}

/// Collapsed (Duffy) tensor Gauss rule with n points per direction: exact for polynomials of
/// degree <= 2 n - dim on the simplex (the collapse adds dim - 1 to the degree in the first
/// direction). Used for the mass and the body's integrals, where the integrand N_i N_j det J0
/// of a curved quadratic element has degree 6 (triangle) or 7 (tetrahedron).
inline SimplexRule collapsedRule(int dim, int n) {
  std::vector<double> g, gw;
  gaussLegendre01(n, g, gw);
  SimplexRule r;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (dim == 2) {
        VecX x(2);
        x << g[i], g[j] * (1.0 - g[i]);
        r.x.push_back(x);
        r.w.push_back(gw[i] * gw[j] * (1.0 - g[i]));
        continue;
      }
      for (int k = 0; k < n; ++k) {
        VecX x(3);
        x << g[i], g[j] * (1.0 - g[i]), g[k] * (1.0 - g[i]) * (1.0 - g[j]);
        r.x.push_back(x);
        r.w.push_back(gw[i] * gw[j] * gw[k] * (1.0 - g[i]) * (1.0 - g[i]) * (1.0 - g[j]));
      }
    }
  return r;
}

/// The mass rule: exact for the consistent mass of curved quadratic elements.
inline SimplexRule massRule(Simplex s) { return simplexDim(s) == 2 ? collapsedRule(2, 4) : collapsedRule(3, 5); }

}  // namespace flexsens
