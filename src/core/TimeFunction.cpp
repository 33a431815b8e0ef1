#include "core/TimeFunction.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace flexsens {

VecX TimeFunction::constantValues(const VecX& p) const {
  VecX c(c_.size());
  for (size_t i = 0; i < c_.size(); ++i) c[i] = c_[i].value(p);
  return c;
}

bool TimeFunction::parameterDerivative(double t, const VecX& p, int k, TimeValue& d) const {
  bool dep = false;
  TimeValue sum;
  const VecX c = constantValues(p);
  for (size_t i = 0; i < c_.size(); ++i) {
    if (!c_[i].boundTo(k)) continue;
    const TimeValue di = constantDerivative(t, c, static_cast<int>(i));
    sum.f += di.f;
    sum.df += di.df;
    sum.ddf += di.ddf;
    dep = true;
  }
  if (dep) d = sum;
  return dep;
}

std::vector<std::pair<std::string, Quantity*>> TimeFunction::properties() {
  std::vector<std::pair<std::string, Quantity*>> r;
  for (size_t i = 0; i < c_.size(); ++i) r.emplace_back(names_[i], &c_[i]);
  return r;
}

namespace {

Quantity constant(double v) { return {v, -1}; }

class Constant : public TimeFunction {
 public:
  explicit Constant(double v) : TimeFunction({"value"}, {constant(v)}) {}
  std::string kind() const override { return "constant"; }

 protected:
  TimeValue eval(double, const VecX& c) const override { return {c[0], 0.0, 0.0}; }
  TimeValue constantDerivative(double, const VecX&, int) const override { return {1.0, 0.0, 0.0}; }
};

class Ramp : public TimeFunction {
 public:
  Ramp(double slope, double start, double offset)
      : TimeFunction({"slope", "start", "offset"}, {constant(slope), constant(start), constant(offset)}) {}
  std::string kind() const override { return "ramp"; }

 protected:
  // c = (slope [unit/s], start [s], offset [unit]); the kink at t = start has f'' = 0 on both sides.
  TimeValue eval(double t, const VecX& c) const override {
    const bool on = t > c[1];
    return {c[2] + (on ? c[0] * (t - c[1]) : 0.0), on ? c[0] : 0.0, 0.0};
  }
  TimeValue constantDerivative(double t, const VecX& c, int i) const override {
    const bool on = t > c[1];
    if (i == 0) return {on ? t - c[1] : 0.0, on ? 1.0 : 0.0, 0.0};
    if (i == 1) return {on ? -c[0] : 0.0, 0.0, 0.0};
    return {1.0, 0.0, 0.0};
  }
};

class Linear : public TimeFunction {
 public:
  Linear(double slope, double offset) : TimeFunction({"slope", "offset"}, {constant(slope), constant(offset)}) {}
  std::string kind() const override { return "linear"; }

 protected:
  // c = (slope [unit/s], offset [unit]).
  TimeValue eval(double t, const VecX& c) const override { return {c[1] + c[0] * t, c[0], 0.0}; }
  TimeValue constantDerivative(double t, const VecX&, int i) const override {
    return i == 0 ? TimeValue{t, 1.0, 0.0} : TimeValue{1.0, 0.0, 0.0};
  }
};

class SmoothStep : public TimeFunction {
 public:
  SmoothStep(double t0, double t1, double from, double to)
      : TimeFunction({"from", "to"}, {constant(from), constant(to)}), t0_(t0), t1_(t1) {}
  std::string kind() const override { return "smooth_step"; }

 protected:
  /// The unit step's value, first and second time derivatives.
  TimeValue unit(double t) const {
    const double T = t1_ - t0_;
    if (t <= t0_) return {0.0, 0.0, 0.0};
    if (t >= t1_) return {1.0, 0.0, 0.0};
    const double s = (t - t0_) / T;
    return {s * s * s * (10.0 - 15.0 * s + 6.0 * s * s), 30.0 * s * s * (1.0 - s) * (1.0 - s) / T,
            60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / (T * T)};
  }
  TimeValue eval(double t, const VecX& c) const override {
    const TimeValue u = unit(t);
    const double d = c[1] - c[0];
    return {c[0] + d * u.f, d * u.df, d * u.ddf};
  }
  TimeValue constantDerivative(double t, const VecX&, int i) const override {
    const TimeValue u = unit(t);
    return i == 0 ? TimeValue{1.0 - u.f, -u.df, -u.ddf} : u;
  }

 private:
  double t0_, t1_;  ///< [s]
};

class Harmonic : public TimeFunction {
 public:
  Harmonic(double amplitude, double omega, double phase, double offset)
      : TimeFunction({"amplitude", "omega", "phase", "offset"},
                     {constant(amplitude), constant(omega), constant(phase), constant(offset)}) {}
  std::string kind() const override { return "harmonic"; }

 protected:
  // c = (A [unit], omega [rad/s], phase [rad], offset [unit]).
  TimeValue eval(double t, const VecX& c) const override {
    const double th = c[1] * t + c[2], s = std::sin(th), co = std::cos(th);
    return {c[3] + c[0] * s, c[0] * c[1] * co, -c[0] * c[1] * c[1] * s};
  }
  TimeValue constantDerivative(double t, const VecX& c, int i) const override {
    const double A = c[0], w = c[1], th = w * t + c[2], s = std::sin(th), co = std::cos(th);
    switch (i) {
      case 0: return {s, w * co, -w * w * s};
      case 1: return {A * t * co, A * co - A * w * t * s, -2.0 * A * w * s - A * w * w * t * co};
      case 2: return {A * co, -A * w * s, -A * w * w * co};
      default: return {1.0, 0.0, 0.0};
    }
  }
};

class SpinUp : public TimeFunction {
 public:
  SpinUp(double omega, double duration) : TimeFunction({"omega"}, {constant(omega)}), T_(duration) {}
  std::string kind() const override { return "spin_up"; }

 protected:
  /// The profile for omega = 1 (f is linear in omega).
  TimeValue unit(double t) const {
    if (t <= 0.0) return {0.0, 0.0, 0.0};
    if (t >= T_) return {t - 0.5 * T_, 1.0, 0.0};
    const double a = 2.0 * M_PI / T_, b = T_ / (2.0 * M_PI);
    return {(0.5 * t * t + b * b * (std::cos(a * t) - 1.0)) / T_, (t - b * std::sin(a * t)) / T_,
            (1.0 - std::cos(a * t)) / T_};
  }
  TimeValue eval(double t, const VecX& c) const override {
    const TimeValue u = unit(t);
    return {c[0] * u.f, c[0] * u.df, c[0] * u.ddf};
  }
  TimeValue constantDerivative(double t, const VecX&, int) const override { return unit(t); }

 private:
  double T_;  ///< [s]
};

class Table : public TimeFunction {
 public:
  Table(std::vector<double> t, std::vector<double> f, double scale)
      : TimeFunction({"scale"}, {constant(scale)}), t_(std::move(t)), f_(std::move(f)) {
    if (t_.size() < 2 || t_.size() != f_.size())
      throw std::invalid_argument("table time function: need at least two (t, f) rows");
    for (size_t i = 1; i < t_.size(); ++i)
      if (!(t_[i] > t_[i - 1])) throw std::invalid_argument("table time function: times must increase");
  }
  std::string kind() const override { return "table"; }

 protected:
  /// The unscaled interpolation.
  TimeValue unit(double t) const {
    if (t <= t_.front()) return {f_.front(), 0.0, 0.0};
    if (t >= t_.back()) return {f_.back(), 0.0, 0.0};
    const size_t j = std::upper_bound(t_.begin(), t_.end(), t) - t_.begin();  // t_[j-1] <= t < t_[j]
    const double slope = (f_[j] - f_[j - 1]) / (t_[j] - t_[j - 1]);
    return {f_[j - 1] + slope * (t - t_[j - 1]), slope, 0.0};
  }
  TimeValue eval(double t, const VecX& c) const override {
    const TimeValue u = unit(t);
    return {c[0] * u.f, c[0] * u.df, 0.0};
  }
  TimeValue constantDerivative(double t, const VecX&, int) const override { return unit(t); }

 private:
  std::vector<double> t_, f_;
};

}  // namespace

std::unique_ptr<TimeFunction> makeConstant(double value) { return std::make_unique<Constant>(value); }
std::unique_ptr<TimeFunction> makeRamp(double slope, double start, double offset) {
  return std::make_unique<Ramp>(slope, start, offset);
}
std::unique_ptr<TimeFunction> makeLinear(double slope, double offset) {
  return std::make_unique<Linear>(slope, offset);
}
std::unique_ptr<TimeFunction> makeSmoothStep(double t0, double t1, double from, double to) {
  if (!(t1 > t0)) throw std::invalid_argument("smooth_step: need t1 > t0");
  return std::make_unique<SmoothStep>(t0, t1, from, to);
}
std::unique_ptr<TimeFunction> makeHarmonic(double amplitude, double omega, double phase, double offset) {
  return std::make_unique<Harmonic>(amplitude, omega, phase, offset);
}
std::unique_ptr<TimeFunction> makeSpinUp(double omega, double duration) {
  if (!(duration > 0)) throw std::invalid_argument("spin_up: need a positive duration");
  return std::make_unique<SpinUp>(omega, duration);
}
std::unique_ptr<TimeFunction> makeTable(std::vector<double> times, std::vector<double> values, double scale) {
  return std::make_unique<Table>(std::move(times), std::move(values), scale);
}

}  // namespace flexsens
