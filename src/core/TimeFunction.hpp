// Scalar functions of time f(t) for loads and drivers, with f' and f'' and their derivatives
// with respect to the function's constants (each a Quantity, bindable as a design parameter).
// The unit of f is that of what it scales or prescribes (a factor [-] on a force, a
// coordinate [m], an angle [rad]); t in [s].
//   constant     f = value
//   ramp         f = offset + slope max(0, t - start); f' = 0 at t <= start (at rest until
//                the kink, then at once `slope`: a ramp from t = 0 starts at zero speed)
//   linear       f = offset + slope t for every t: f' = slope from t = 0 on (a driver at
//                constant speed from the start)
//   smooth_step  f = from + (to - from) s^3 (10 - 15 s + 6 s^2), s = (t - t0)/(t1 - t0) in [0, 1]
//                (quintic: f, f', f'' continuous; f' = f'' = 0 at both ends)
//   harmonic     f = offset + amplitude sin(omega t + phase)
//   spin_up      Simo and Vu-Quoc's hub angle: for t < T
//                f = (omega/T) (t^2/2 + (T/2pi)^2 (cos(2 pi t/T) - 1)), then omega (t - T/2)
//   table        f = scale * piecewise-linear interpolation of (t_i, f_i) from a CSV file,
//                held at the end values outside [t_0, t_last]; f'' = 0 inside the segments
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/Types.hpp"

namespace flexsens {

/// f [unit], f' [unit/s], f'' [unit/s^2] at one time (or their derivatives with respect to p_k).
struct TimeValue {
  double f = 0.0, df = 0.0, ddf = 0.0;
};

class TimeFunction {
 public:
  virtual ~TimeFunction() = default;
  virtual std::string kind() const = 0;
  TimeValue at(double t, const VecX& p) const { return eval(t, constantValues(p)); }
  /// d(f, f', f'')/dp_k at t; false (d untouched) when no constant is bound to k.
  bool parameterDerivative(double t, const VecX& p, int k, TimeValue& d) const;
  /// The bindable constants by name (e.g. "amplitude").
  std::vector<std::pair<std::string, Quantity*>> properties();

 protected:
  TimeFunction(std::vector<std::string> names, std::vector<Quantity> constants)
      : names_(std::move(names)), c_(std::move(constants)) {}
  /// f, f', f'' at t with constants c (the order of names_).
  virtual TimeValue eval(double t, const VecX& c) const = 0;
  /// d(f, f', f'')/dc_i at t.
  virtual TimeValue constantDerivative(double t, const VecX& c, int i) const = 0;

 private:
  VecX constantValues(const VecX& p) const;
  std::vector<std::string> names_;
  std::vector<Quantity> c_;
};

std::unique_ptr<TimeFunction> makeConstant(double value);
std::unique_ptr<TimeFunction> makeRamp(double slope, double start, double offset);
std::unique_ptr<TimeFunction> makeLinear(double slope, double offset);
/// t0 < t1 [s].
std::unique_ptr<TimeFunction> makeSmoothStep(double t0, double t1, double from, double to);
std::unique_ptr<TimeFunction> makeHarmonic(double amplitude, double omega, double phase, double offset);
/// omega [rad/s] reached at duration T [s].
std::unique_ptr<TimeFunction> makeSpinUp(double omega, double duration);
/// times strictly increasing (at least two).
std::unique_ptr<TimeFunction> makeTable(std::vector<double> times, std::vector<double> values, double scale);

}  // namespace flexsens
