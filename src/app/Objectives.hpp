// The discrete objectives of a scene (scene/Objective.hpp) on the integrator's step grid
// t_0 ... t_N, from the outputs' samples o_n = o(t_n):
//   terminal  J = o at `at`: o_N, or linear interpolation between the two steps around `at`
//   integral  J = integral over [from, to] of the piecewise-linear interpolant of f_n = o_n^power
//             (the trapezoidal rule on the step times; a window end inside a step cuts it)
//   tracking  the same with f_n = (o_n - r(t_n))^2
//   max       J = KS(o) = m + ln(sum_n exp(rho (o_n - m))) / rho over the steps in [from, to],
//             m = max o_n: max o_n <= J <= max o_n + ln(count) / rho
//   mass      J = a body's mass: no output; 0 here, its value and gradient app/BodyMass.hpp
//   sum       J = sum_j weight_j J_j
// Each J is a function of the samples alone, so dJ/dp = sum_n dJ/do_n do_n/dp exactly (the
// forward method) and dJ/do_n is the adjoint's source at step n.
#pragma once

#include <utility>
#include <vector>

#include "core/Types.hpp"
#include "scene/Objective.hpp"

namespace flexsens {

/// A fixed-step run's times: t_n = t0 + n h for n < steps, t_steps = tEnd [s]. `flexsens
/// static`: steps = 0, the one sample the last load step.
struct StepGrid {
  double t0 = 0.0, h = 0.0, tEnd = 0.0;
  long steps = 0;
  double time(long n) const { return n == steps ? tEnd : t0 + double(n) * h; }
};

/// J_i from the samples (rows: steps 0 ... N; columns: the scene's outputs).
double objectiveValue(const std::vector<ObjectiveSpec>& objectives, size_t i, const StepGrid& grid,
                      const MatX& samples);
/// factor * dJ_i / d samples, added into dJ (the samples' shape).
void addObjectiveDerivative(const std::vector<ObjectiveSpec>& objectives, size_t i, const StepGrid& grid,
                            const MatX& samples, double factor, MatX& dJ);
/// InputError (the objective's file:line and key) when a time of objective i lies beyond the
/// run's end (t_end changed by --t-end after the scene was read).
void checkObjectiveTimes(const ObjectiveSpec& objective, double tEnd);

/// Objective i as (leaf objective index, weight) pairs: a sum's terms, any other kind itself.
inline std::vector<std::pair<int, double>> objectiveLeaves(const std::vector<ObjectiveSpec>& objectives, size_t i) {
  if (objectives[i].kind == "sum") return objectives[i].terms;
  return {{int(i), 1.0}};
}

}  // namespace flexsens
