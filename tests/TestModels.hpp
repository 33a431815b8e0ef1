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

}  // namespace flexsens::test
