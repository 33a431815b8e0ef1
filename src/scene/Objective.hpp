// Objectives of a scene (`objectives:`): scalar functions J of the outputs' time series that
// `flexsens gradient` differentiates with respect to the design parameters. Each is defined on
// the integrator's step grid t_0 ... t_N (t_n = n dt, t_N = t_end), so that its discrete form is
// what the adjoint and the forward sensitivities differentiate exactly (app/Objectives.hpp).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/TimeFunction.hpp"

namespace flexsens {

struct ObjectiveSpec {
  std::string name;
  /// terminal | integral | tracking | max | mass | sum
  std::string kind;
  int output = -1;  ///< index into Scene::outputs (not for sum)
  /// terminal: the time [s] (negative: t_end, or the last load step of `flexsens static`).
  double at = -1.0;
  /// integral, tracking, max: the window [s]; `to` negative: t_end.
  double from = 0.0, to = -1.0;
  int power = 1;     ///< integral: the integrand is output^power
  double rho = 0.0;  ///< max: the KS aggregate's sharpness [1/unit of the output]
  /// tracking: the target r(t), a time function or (when null) the CSV's piecewise-linear rows.
  std::shared_ptr<const TimeFunction> target;
  std::vector<double> targetTimes, targetValues;  ///< [s], [unit of the output]
  /// mass: the body's elements (indices into Model::elements), app/BodyMass.hpp.
  std::vector<int> elements;
  /// sum: (objective index, weight); the terms are objectives of the other kinds.
  std::vector<std::pair<int, double>> terms;
  /// "file:line:column: key 'objectives[i]'", for errors found later (times after --t-end).
  std::string where;

  /// The tracking target at t [s].
  double targetAt(double t) const;
};

}  // namespace flexsens
