#include "app/IdasGradient.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "app/Objectives.hpp"
#include "integrators/Idas.hpp"
#include "integrators/IdasAdjoint.hpp"
#include "integrators/IdasStepper.hpp"

namespace flexsens {

namespace {

/// 3-point Gauss-Legendre on [-1, 1]: nodes and weights (exact for degree 5).
constexpr double kGaussNode = 0.7745966692414834;  // sqrt(3/5)
constexpr double kGaussNodes[3] = {-kGaussNode, 0.0, kGaussNode};
constexpr double kGaussWeights[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};

/// The running sums of one leaf objective (not a sum): integral and tracking the integral and
/// its gradient; max the shifted sum S = integral exp(rho (o - shift)) and its gradient.
struct LeafSums {
  double value = 0.0, shift = -std::numeric_limits<double>::infinity();
  VecX gradient;
  bool reached = false;  ///< terminal: the time was passed
};

class ContinuousObjectives {
 public:
  ContinuousObjectives(const Scene& sc, const std::vector<size_t>& sel, double t0, double tEnd, Eigen::Index np)
      : sc_(sc), t0_(t0), tEnd_(tEnd), np_(np) {
    for (size_t i : sel) {
      std::vector<std::pair<int, double>> terms;
      for (const auto& [k, w] : objectiveLeaves(sc.objectives, i))  // a mass has no part in the motion (Gradient.cpp adds it)
        if (sc.objectives[size_t(k)].kind != "mass") terms.push_back({k, w});
      for (const auto& [k, w] : terms) sums_[k].gradient = VecX::Zero(np);
      terms_.push_back(terms);
    }
  }
  /// The terminal objectives at t0 (at <= t0).
  void begin(const StateWithSens& start) {
    for (auto& [k, s] : sums_)
      if (spec(k).kind == "terminal" && timeOf(spec(k)) <= t0_) addTerminal(k, start);
  }
  /// IDAS' step [tPrev, stepper.time()] (clipped to [t0, t_end]).
  void addStep(IdasStepper& stepper, double tPrev) {
    const double t = std::min(stepper.time(), tEnd_);
    for (auto& [k, s] : sums_) {
      const ObjectiveSpec& o = spec(k);
      if (o.kind == "terminal") {
        const double at = timeOf(o);
        if (!s.reached && at > tPrev && at <= t) addTerminal(k, stepper.stateAt(at));
        continue;
      }
      const double a = std::max(o.from, tPrev), b = std::min(windowEnd(o), t);
      if (!(b > a)) continue;
      for (int g = 0; g < 3; ++g) {
        const double tau = 0.5 * (a + b) + 0.5 * (b - a) * kGaussNodes[g];
        addSample(k, 0.5 * (b - a) * kGaussWeights[g], tau, stepper.stateAt(tau));
      }
    }
  }
  double value(size_t i) const {
    double J = 0.0;
    for (const auto& [k, w] : terms_[i]) J += w * leafValue(k);
    return J;
  }
  VecX gradient(size_t i) const {
    VecX G = VecX::Zero(np_);
    for (const auto& [k, w] : terms_[i]) {
      const LeafSums& s = sums_.at(k);
      G += w * (spec(k).kind == "max" ? VecX(s.gradient / s.value) : s.gradient);
    }
    return G;
  }
  /// The adjoint's terminal part of objective i at t_end: dphi/dq, dphi/dv added into gq, gv.
  void addTerminalGradient(const State& x, int i, Eigen::Ref<VecX> gq, Eigen::Ref<VecX> gv) const {
    for (const auto& [k, w] : terms_[size_t(i)])
      if (spec(k).kind == "terminal") sc_.outputs[size_t(spec(k).output)].addGradient(*sc_.model, x, w, gq, gv);
  }
  /// The adjoint's source of objective i at (t, x): dg/dq, dg/dv added into gq, gv.
  void addSource(double t, const State& x, int i, Eigen::Ref<VecX> gq, Eigen::Ref<VecX> gv) const {
    for (const auto& [k, w] : terms_[size_t(i)]) {
      const ObjectiveSpec& o = spec(k);
      if (o.kind == "terminal" || t < o.from || t > windowEnd(o)) continue;
      const OutputSpec& out = sc_.outputs[size_t(o.output)];
      const double value = out.value(*sc_.model, x);
      double dgdo = integrand(o, value, t).second;
      if (o.kind == "max") dgdo = std::exp(o.rho * (value - sums_.at(k).shift)) / sums_.at(k).value;
      out.addGradient(*sc_.model, x, w * dgdo, gq, gv);
    }
  }

 private:
  const ObjectiveSpec& spec(int k) const { return sc_.objectives[size_t(k)]; }
  double windowEnd(const ObjectiveSpec& o) const { return o.to < 0 ? tEnd_ : o.to; }
  double timeOf(const ObjectiveSpec& o) const { return o.at < 0 ? tEnd_ : o.at; }

  /// g(o, t) and dg/do of integral and tracking.
  static std::pair<double, double> integrand(const ObjectiveSpec& o, double value, double t) {
    if (o.kind == "tracking") {
      const double e = value - o.targetAt(t);
      return {e * e, 2.0 * e};
    }
    return {std::pow(value, o.power), o.power * std::pow(value, o.power - 1)};
  }
  /// do/dp at x (empty without sensitivities).
  VecX outputSensitivities(const OutputSpec& out, const StateWithSens& x) const {
    VecX d = VecX::Zero(np_);
    for (size_t j = 0; j < x.dp.size(); ++j) d[Eigen::Index(j)] = out.derivative(*sc_.model, x.x, x.dp[j]);
    return d;
  }
  void addTerminal(int k, const StateWithSens& x) {
    const OutputSpec& out = sc_.outputs[size_t(spec(k).output)];
    LeafSums& s = sums_[k];
    s.value = out.value(*sc_.model, x.x);
    s.gradient = outputSensitivities(out, x);
    s.reached = true;
  }
  /// One quadrature node: weight w [s] at time tau.
  void addSample(int k, double w, double tau, const StateWithSens& x) {
    const ObjectiveSpec& o = spec(k);
    const OutputSpec& out = sc_.outputs[size_t(o.output)];
    const double value = out.value(*sc_.model, x.x);
    LeafSums& s = sums_[k];
    if (o.kind == "max") {  // S = integral exp(rho (o - shift)), the shift the largest value so far
      if (value > s.shift) {
        const double scale = std::isinf(s.shift) ? 0.0 : std::exp(o.rho * (s.shift - value));
        s.value *= scale;
        s.gradient *= scale;
        s.shift = value;
      }
      const double e = w * std::exp(o.rho * (value - s.shift));
      s.value += e;
      if (!x.dp.empty()) s.gradient += e * outputSensitivities(out, x);
      return;
    }
    const auto [g, dg] = integrand(o, value, tau);
    s.value += w * g;
    if (!x.dp.empty()) s.gradient += w * dg * outputSensitivities(out, x);
  }
  double leafValue(int k) const {
    const ObjectiveSpec& o = spec(k);
    const LeafSums& s = sums_.at(k);
    if (o.kind != "max") return s.value;
    return s.shift + std::log(s.value / (windowEnd(o) - o.from)) / o.rho;
  }

  const Scene& sc_;
  const double t0_, tEnd_;
  const Eigen::Index np_;
  std::map<int, LeafSums> sums_;  ///< per leaf objective (index into sc.objectives)
  std::vector<std::vector<std::pair<int, double>>> terms_;  ///< per selected objective: (leaf, weight)
};

}  // namespace

void requireIdasAdjointObjectives(const Scene& sc, const std::vector<size_t>& sel) {
  for (size_t i : sel) {
    for (const auto& [k, w] : objectiveLeaves(sc.objectives, i))
      if (const ObjectiveSpec& o = sc.objectives[size_t(k)];
          o.kind == "terminal" && o.at >= 0 && o.at < sc.integrator.tEnd * (1.0 - 1e-12))
        throw InputError(o.where + ": objective '" + o.name +
                         "': a terminal objective before t_end (at) has no continuous adjoint on integrator idas (only "
                         "at t_end); use --method forward, or a fixed-step integrator (" +
                         kAdjointIntegrators + ") whose discrete adjoint has it");
  }
}

MatX idasGradients(const Scene& sc, const Assembler& as, const VecX& p, const StateWithSens& start,
                   const std::vector<size_t>& sel, const GradientRequest& req, Observer& audit, GradientResult& res,
                   std::vector<double>& values) {
  const IntegratorSettings& set = sc.integrator;
  ContinuousObjectives objectives(sc, sel, start.x.t, set.tEnd, p.size());
  objectives.begin(start);
  const IdasStepHook hook = [&](IdasStepper& stepper, double tPrev) { objectives.addStep(stepper, tPrev); };
  MatX G(p.size(), Eigen::Index(sel.size()));
  if (req.method == "forward") {
    IdasStepper stepper(as, p, start, set);
    res.stats = integrateIdas(stepper, start, set, audit, hook);
    for (size_t i = 0; i < sel.size(); ++i) G.col(Eigen::Index(i)) = objectives.gradient(i);
  } else {
    requireIdasAdjointObjectives(sc, sel);
    IdasAdjoint adjoint(as, p, start, set, req.checkpointEvery);
    res.stats = adjoint.forward(audit, hook);
    G = adjoint.backward(
        int(sel.size()),
        [&](double t, const State& x, int i, Eigen::Ref<VecX> gq, Eigen::Ref<VecX> gv) { objectives.addSource(t, x, i, gq, gv); },
        [&](const State& x, int i, Eigen::Ref<VecX> gq, Eigen::Ref<VecX> gv) { objectives.addTerminalGradient(x, i, gq, gv); });
    res.adjoint = adjoint.statistics();
  }
  res.steps = res.stats.steps;
  values.clear();
  for (size_t i = 0; i < sel.size(); ++i) values.push_back(objectives.value(i));
  return G;
}

}  // namespace flexsens
