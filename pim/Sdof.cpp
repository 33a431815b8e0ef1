#include "pim/Sdof.hpp"

#include <cmath>

namespace flexsens {

namespace {
double coord(const Model& m, const VecX& q, int node, int c) { return m.coordinate(q, node, c); }
}  // namespace

double LinearSdof::value(const Model& m, const VecX& q) const {
  double z = 0.0;
  for (const auto& t : terms) z += t.coef * coord(m, q, t.node, t.component);
  return z;
}

VecX LinearSdof::gradient(const Model& m, const VecX&) const {
  VecX g = VecX::Zero(m.n);
  for (const auto& t : terms)
    if (m.dof(t.node, t.component) >= 0) g[m.dof(t.node, t.component)] += t.coef;
  return g;
}

MatX LinearSdof::hessian(const Model& m, const VecX&) const { return MatX::Zero(m.n, m.n); }

double AngleSdof::value(const Model& m, const VecX& q) const {
  return std::atan2(coord(m, q, b, 1) - coord(m, q, a, 1), coord(m, q, b, 0) - coord(m, q, a, 0));
}

VecX AngleSdof::gradient(const Model& m, const VecX& q) const {
  const double dx = coord(m, q, b, 0) - coord(m, q, a, 0), dz = coord(m, q, b, 1) - coord(m, q, a, 1);
  const double r2 = dx * dx + dz * dz;
  const double g[2] = {-dz / r2, dx / r2};  // d theta / d(dx, dz)
  VecX out = VecX::Zero(m.n);
  for (int c = 0; c < 2; ++c) {
    if (m.dof(b, c) >= 0) out[m.dof(b, c)] += g[c];
    if (m.dof(a, c) >= 0) out[m.dof(a, c)] -= g[c];
  }
  return out;
}

MatX AngleSdof::hessian(const Model& m, const VecX& q) const {
  const double dx = coord(m, q, b, 0) - coord(m, q, a, 0), dz = coord(m, q, b, 1) - coord(m, q, a, 1);
  const double r4 = std::pow(dx * dx + dz * dz, 2);
  const double h[2][2] = {{2 * dx * dz / r4, (dz * dz - dx * dx) / r4},
                          {(dz * dz - dx * dx) / r4, -2 * dx * dz / r4}};
  MatX H = MatX::Zero(m.n, m.n);
  const int nodes[2] = {a, b};
  const double sign[2] = {-1.0, 1.0};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int c = 0; c < 2; ++c)
        for (int e = 0; e < 2; ++e) {
          const int r = m.dof(nodes[i], c), s = m.dof(nodes[j], e);
          if (r >= 0 && s >= 0) H(r, s) += sign[i] * sign[j] * h[c][e];
        }
  return H;
}

}  // namespace flexsens
