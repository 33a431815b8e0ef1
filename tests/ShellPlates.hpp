// Plate problems of the discrete-shell tests (tests/test_shell.cpp, test_shell_clamp.cpp):
// structured near-equilateral meshes of a rectangle and the transverse (z) stiffness, mass and
// natural frequencies of shell elements at their flat rest state.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include <sstream>
#include <string>

#include "TestModels.hpp"
#include "core/Element.hpp"
#include "scene/Scene.hpp"

namespace flexsens::test {

struct PlateMesh {
  std::vector<Eigen::Vector3d> X;
  std::vector<std::array<int, 3>> tris;
  double h = 0.0;  ///< longest edge [m]
};

/// Rows of nodes y_j = j ay / ny on the rectangle ax x ay [m]; even rows at x = i ax / nx, odd
/// rows shifted by half a spacing (plus the two side nodes): near-equilateral triangles when
/// (ay / ny) / (ax / nx) ~ sqrt(3) / 2, half triangles along the sides x = 0, ax.
inline PlateMesh shiftedRows(int nx, int ny, double ax = 1.0, double ay = 1.0) {
  PlateMesh m;
  std::vector<std::vector<int>> rows(ny + 1);
  for (int j = 0; j <= ny; ++j) {
    const double y = ay * j / ny;
    std::vector<double> xs;
    if (j % 2 == 0)
      for (int i = 0; i <= nx; ++i) xs.push_back(ax * i / nx);
    else {
      xs.push_back(0.0);
      for (int i = 0; i < nx; ++i) xs.push_back(ax * (i + 0.5) / nx);
      xs.push_back(ax);
    }
    for (double x : xs) {
      rows[j].push_back(static_cast<int>(m.X.size()));
      m.X.emplace_back(x, y, 0.0);
    }
  }
  for (int j = 0; j < ny; ++j) {  // zip rows j and j+1, always advancing the one whose next node comes first
    const auto &A = rows[j], &B = rows[j + 1];
    size_t i = 0, k = 0;
    while (i + 1 < A.size() || k + 1 < B.size()) {
      const bool advanceA = k + 1 == B.size() || (i + 1 < A.size() && m.X[A[i + 1]].x() <= m.X[B[k + 1]].x() - 1e-12);
      if (advanceA) {
        m.tris.push_back({A[i], A[i + 1], B[k]});
        ++i;
      } else {
        m.tris.push_back({A[i], B[k + 1], B[k]});
        ++k;
      }
    }
  }
  for (const auto& t : m.tris)
    for (int j = 0; j < 3; ++j) m.h = std::max(m.h, (m.X[t[j]] - m.X[t[(j + 1) % 3]]).norm());
  return m;
}

/// Transverse stiffness K [N/m] and mass M [kg] of shell elements `els` at their rest
/// positions X (flat, z = 0) on the z coordinates of the nodes not fixed (zdof: index or -1).
/// At the flat rest state the transverse (z) motion decouples from the in-plane motion
/// (checked), so the plate problems below are solved on these alone. unitLoad: the free rows'
/// sums of the whole consistent mass [kg] (the load of a unit gravity on every node, fixed ones
/// included).
inline void transverseMatrices(const std::vector<std::unique_ptr<Element>>& els, const std::vector<Eigen::Vector3d>& X,
                        const std::vector<bool>& fixed, MatX& K, MatX& M, std::vector<int>& zdof, VecX* unitLoad = nullptr) {
  zdof.assign(X.size(), -1);
  int n = 0;
  for (size_t i = 0; i < X.size(); ++i)
    if (!fixed[i]) zdof[i] = n++;
  K = MatX::Zero(n, n);
  M = MatX::Zero(n, n);
  if (unitLoad) *unitLoad = VecX::Zero(n);
  double coupling = 0.0, scale = 0.0;
  const VecX p(0);
  for (const auto& el : els) {
    const auto& idx = el->nodes();
    LocalState s;
    s.dim = 3;
    s.p = &p;
    s.x.resize(3 * idx.size());
    s.v = VecX::Zero(3 * idx.size());
    for (size_t j = 0; j < idx.size(); ++j) s.x.segment<3>(3 * j) = X[idx[j]];
    MatX Kq, Kv, Me;
    el->forceJacobian(s, Kq, Kv);
    const bool massive = el->mass(s, Me);
    for (size_t a = 0; a < idx.size(); ++a)
      for (size_t b = 0; b < idx.size(); ++b) {
        scale = std::max(scale, std::abs(Kq(3 * a + 2, 3 * b + 2)));
        for (int c = 0; c < 2; ++c) coupling = std::max(coupling, std::abs(Kq(3 * a + 2, 3 * b + c)));
        const int r = zdof[idx[a]], q = zdof[idx[b]];
        if (unitLoad && massive && r >= 0) (*unitLoad)[r] += Me(3 * a + 2, 3 * b + 2);
        if (r < 0 || q < 0) continue;
        K(r, q) -= Kq(3 * a + 2, 3 * b + 2);
        if (massive) M(r, q) += Me(3 * a + 2, 3 * b + 2);
      }
  }
  EXPECT_LE(coupling, 1e-12 * scale) << "transverse and in-plane motion couple at the flat state";
}

/// Lowest `count` natural frequencies [rad/s]: the dense generalized eigenproblem K y = w^2 M y.
inline std::vector<double> transverseFrequencies(const std::vector<std::unique_ptr<Element>>& els,
                                          const std::vector<Eigen::Vector3d>& X, const std::vector<bool>& fixed,
                                          int count) {
  MatX K, M;
  std::vector<int> zdof;
  transverseMatrices(els, X, fixed, K, M, zdof);
  Eigen::GeneralizedSelfAdjointEigenSolver<MatX> es(0.5 * (K + K.transpose()), M, Eigen::EigenvaluesOnly);
  std::vector<double> w;
  for (int k = 0; k < count; ++k) w.push_back(std::sqrt(es.eigenvalues()[k]));
  return w;
}

/// The unit square plate of tests/scenes/shell/square.geo as a scene (type: shell) at Gmsh
/// element size `size`, supported on its edges by `support` ("ground": simply supported, or
/// "clamp"), with its nodes' rest positions X and which are fixed.
struct ScenePlate {
  Scene sc;
  std::vector<Eigen::Vector3d> X;
  std::vector<bool> fixed;
};
inline ScenePlate squarePlateScene(double size, const std::string& support, double E, double nu, double rho, double t) {
  std::ostringstream text;
  text.precision(17);
  text << "dimension: 3\nelements:\n  - {name: plate, type: shell, mesh: square.geo, group: plate, size: " << size
       << ", E: " << E << ", nu: " << nu << ", density: " << rho << ", thickness: " << t << ", " << support
       << ": [edges]}\nintegrator: {type: trapezoidal, t_end: 0.01, dt: 0.001}\n";
  ScenePlate r{readSceneText(text.str(), sourceDir() + "/tests/scenes/shell/scene.yaml"), {}, {}};
  for (const Node& nd : r.sc.model->nodes) {
    r.X.push_back(nd.position);
    r.fixed.push_back(nd.ground);
  }
  return r;
}

}  // namespace flexsens::test
