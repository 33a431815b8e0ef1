// Small models and finite-difference helpers shared by the tests.
#pragma once

#include <functional>
#include <string>

#include "integrators/State.hpp"
#include "scene/Scene.hpp"

namespace flexsens::test {

inline std::string sourceDir() { return FLEXSENS_SOURCE_DIR; }

/// Central finite-difference Jacobian of f at x (columns = d f / d x_j).
inline MatX fdJacobian(const std::function<VecX(const VecX&)>& f, const VecX& x, double h = 1e-6) {
  const VecX f0 = f(x);
  MatX J(f0.size(), x.size());
  for (int j = 0; j < x.size(); ++j) {
    VecX xp = x, xm = x;
    const double s = h * std::max(1.0, std::abs(x[j]));
    xp[j] += s;
    xm[j] -= s;
    J.col(j) = (f(xp) - f(xm)) / (2 * s);
  }
  return J;
}

/// Records the full state (and sensitivities) at every output frame.
struct Recorder : Observer {
  std::vector<StateWithSens> frames;
  void frame(const StateWithSens& s) override { frames.push_back(s); }
  const StateWithSens& at(double t) const {
    for (const auto& f : frames)
      if (std::abs(f.x.t - t) < 1e-9) return f;
    throw std::runtime_error("no frame at t = " + std::to_string(t));
  }
};

/// Relative error |a - b| / max(|b|, floor) in the max norm.
inline double relErr(const MatX& a, const MatX& b, double floor = 1.0) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(b.lpNorm<Eigen::Infinity>(), floor);
}

/// A planar model with every element and constraint type of the foundation, all
/// properties bound to parameters so that every parameter derivative is exercised.
inline Scene mixedScene() {
  return readSceneText(R"(
dimension: 2
plane: xz
gravity: [0.3, -9.81]
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: n1, position: [-1, -1]}
  - {name: n2, position: [0.5, -2]}
  - {name: n3, position: [2, -1]}
  - {name: n4, position: [2.5, 0.3]}
  - {name: n5, position: [-1.5, -1.4]}
  - {name: n6, position: [-2.1, -1.5]}
elements:
  - {name: bA1, type: rigid_bar, nodes: [A, n1], mass: 1.0}
  - {name: b12, type: rigid_bar, nodes: [n1, n2], mass: 1.5}
  - {name: s23, type: spring_damper, nodes: [n2, n3], stiffness: 50, damping: 3, natural_length: 1.3}
  - {name: s3A, type: spring_damper, nodes: [n3, A], stiffness: 20, damping: 0.5}
  - {name: b34, type: rigid_bar, nodes: [n3, n4], mass: 0.7}
  - {name: beam, type: beam, nodes: [n1, n5, n6], E: 2.0e6, density: 500, section: {side: 0.05}}
constraints:
  - {name: d24, type: distance, nodes: [n2, n4], length: 2.9}
  - {name: fx, type: fixed, node: n4, position: [2.5, 0.3]}
parameters:
  - {name: L, of: bA1, property: length}
  - {name: mass, of: b12, property: mass}
  - {name: k, of: s23, property: stiffness}
  - {name: c, of: s23, property: damping}
  - {name: L0, of: s23, property: natural_length}
  - {name: Ld, of: d24, property: length}
  - {name: gz, of: gravity, property: z}
  - {name: E, of: beam, property: E}
  - {name: rho, of: beam, property: density}
integrator: {type: idas, t_end: 1}
)", "mixed.yaml");
}

}  // namespace flexsens::test
