#include "app/Objectives.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace flexsens {

namespace {

using Weights = std::vector<std::pair<long, double>>;  // (step, weight)

/// The step whose interval [t_n, t_{n+1}] holds t (the last one for t = t_end).
long intervalOf(const StepGrid& g, double t) {
  if (g.steps == 0) return 0;
  const long n = long(std::floor((t - g.t0) / g.h));
  return std::clamp(n, 0L, g.steps - 1);
}

/// terminal: linear interpolation between the steps around t.
Weights pointWeights(const StepGrid& g, double t) {
  if (g.steps == 0) return {{0, 1.0}};
  const long n = intervalOf(g, t);
  const double s = std::clamp((t - g.time(n)) / (g.time(n + 1) - g.time(n)), 0.0, 1.0);
  return {{n, 1.0 - s}, {n + 1, s}};
}

/// The exact integral over [a, b] of the piecewise-linear interpolant of samples f_n, as
/// sum_n w_n f_n: each step's part [alpha, beta] contributes (beta - alpha) times the
/// interpolant at its middle (the trapezoidal rule on whole steps).
Weights windowWeights(const StepGrid& g, double a, double b) {
  Weights w;
  for (long n = intervalOf(g, a); n < g.steps; ++n) {
    const double tn = g.time(n), tn1 = g.time(n + 1);
    if (tn >= b) break;
    const double alpha = std::max(a, tn), beta = std::min(b, tn1);
    if (!(beta > alpha)) continue;
    const double s = (0.5 * (alpha + beta) - tn) / (tn1 - tn);
    w.emplace_back(n, (beta - alpha) * (1.0 - s));
    w.emplace_back(n + 1, (beta - alpha) * s);
  }
  return w;
}

/// max: the steps in [a, b] (to a millionth of a step).
std::vector<long> windowSteps(const StepGrid& g, double a, double b) {
  std::vector<long> steps;
  const double eps = 1e-6 * (g.steps ? g.h : 1.0);
  for (long n = 0; n <= g.steps; ++n)
    if (g.time(n) >= a - eps && g.time(n) <= b + eps) steps.push_back(n);
  return steps;
}

double windowEnd(const ObjectiveSpec& o, const StepGrid& g) { return o.to < 0 ? g.tEnd : o.to; }

/// The integrand f(o_n, t_n) of integral and tracking, and df/do.
std::pair<double, double> integrand(const ObjectiveSpec& o, double value, double t) {
  if (o.kind == "tracking") {
    const double e = value - o.targetAt(t);
    return {e * e, 2.0 * e};
  }
  return {std::pow(value, o.power), o.power * std::pow(value, o.power - 1)};
}

/// KS aggregate over the window: the shift m, the sum S and the steps.
struct KsParts {
  std::vector<long> steps;
  double m = 0.0, sum = 0.0;
};

KsParts ksParts(const ObjectiveSpec& o, const StepGrid& g, const VecX& series) {
  KsParts ks;
  ks.steps = windowSteps(g, o.from, windowEnd(o, g));
  ks.m = -INFINITY;
  for (long n : ks.steps) ks.m = std::max(ks.m, series[n]);
  for (long n : ks.steps) ks.sum += std::exp(o.rho * (series[n] - ks.m));
  return ks;
}

/// dJ/do_n of a leaf objective into column `column` of dJ, times factor (value returned).
double leaf(const ObjectiveSpec& o, const StepGrid& g, const MatX& samples, double factor, MatX* dJ) {
  if (o.kind == "mass") return 0.0;  // no output: app/BodyMass.hpp
  const VecX series = samples.col(o.output);
  double J = 0.0;
  if (o.kind == "terminal") {
    for (const auto& [n, w] : pointWeights(g, o.at < 0 ? g.tEnd : o.at)) {
      J += w * series[n];
      if (dJ) (*dJ)(n, o.output) += factor * w;
    }
  } else if (o.kind == "integral" || o.kind == "tracking") {
    for (const auto& [n, w] : windowWeights(g, o.from, windowEnd(o, g))) {
      const auto [f, df] = integrand(o, series[n], g.time(n));
      J += w * f;
      if (dJ) (*dJ)(n, o.output) += factor * w * df;
    }
  } else {  // max
    const KsParts ks = ksParts(o, g, series);
    J = ks.m + std::log(ks.sum) / o.rho;
    if (dJ)
      for (long n : ks.steps) (*dJ)(n, o.output) += factor * std::exp(o.rho * (series[n] - ks.m)) / ks.sum;
  }
  return J;
}

}  // namespace

double objectiveValue(const std::vector<ObjectiveSpec>& objectives, size_t i, const StepGrid& grid,
                      const MatX& samples) {
  const ObjectiveSpec& o = objectives[i];
  if (o.kind != "sum") return leaf(o, grid, samples, 0.0, nullptr);
  double J = 0.0;
  for (const auto& [k, w] : o.terms) J += w * leaf(objectives[size_t(k)], grid, samples, 0.0, nullptr);
  return J;
}

void addObjectiveDerivative(const std::vector<ObjectiveSpec>& objectives, size_t i, const StepGrid& grid,
                            const MatX& samples, double factor, MatX& dJ) {
  const ObjectiveSpec& o = objectives[i];
  if (o.kind != "sum") {
    leaf(o, grid, samples, factor, &dJ);
    return;
  }
  for (const auto& [k, w] : o.terms) leaf(objectives[size_t(k)], grid, samples, factor * w, &dJ);
}

void checkObjectiveTimes(const ObjectiveSpec& o, double tEnd) {
  auto beyond = [&](double t, const char* what) {
    if (!(t > tEnd * (1.0 + 1e-12))) return;
    std::ostringstream os;
    os << o.where << ": objective '" << o.name << "': its " << what << " time " << t
       << " s lies beyond the run's end t_end = " << tEnd << " s (--t-end); give a longer --t-end";
    throw InputError(os.str());
  };
  if (o.kind == "terminal" && o.at >= 0) beyond(o.at, "terminal");
  if (o.kind != "terminal" && o.kind != "sum") {
    beyond(o.from, "window's start");
    if (o.to >= 0) beyond(o.to, "window's end");
    if (o.kind == "tracking" && !o.target && o.targetTimes.back() < (o.to < 0 ? tEnd : o.to))
      throw InputError(o.where + ": objective '" + o.name + "': the target's rows end before the run's end t_end (--t-end)");
  }
}

}  // namespace flexsens
