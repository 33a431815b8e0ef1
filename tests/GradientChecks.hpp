// Shared by the gradient tests: flexsens gradient in-process and the comparison of two results.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "app/Gradient.hpp"

namespace flexsens::test {

/// computeGradients of every objective (or the named one) by `method`.
inline GradientResult gradients(const Scene& sc, const std::string& method, long checkpointEvery = 0,
                                const std::string& objective = "") {
  GradientRequest req;
  req.method = method;
  req.checkpointEvery = checkpointEvery;
  req.objective = objective;
  return computeGradients(sc, req);
}

/// Largest |a - b| / max(|b|, floor) over objectives and parameters.
inline double worstRelative(const GradientResult& a, const GradientResult& b, double floor) {
  double worst = 0.0;
  for (size_t i = 0; i < b.objectives.size(); ++i)
    for (Eigen::Index k = 0; k < b.objectives[i].gradient.size(); ++k) {
      const double ref = b.objectives[i].gradient[k];
      worst = std::max(worst, std::abs(a.objectives[i].gradient[k] - ref) / std::max(std::abs(ref), floor));
    }
  return worst;
}

}  // namespace flexsens::test
