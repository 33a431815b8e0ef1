#include "app/FiniteDifferences.hpp"

#include <cmath>

#include "integrators/InitialState.hpp"

namespace flexsens {

namespace {

/// Keeps every frame of a run (perturbed runs are combined frame by frame afterwards).
struct FrameStore : Observer {
  std::vector<State> frames;
  Observer* forward = nullptr;  ///< the nominal run also reports progress and its steps
  void frame(const StateWithSens& s) override { frames.push_back(s.x); }
  void progress(double t) override {
    if (forward) forward->progress(t);
  }
  void stepped(const State& x) override {
    if (forward) forward->stepped(x);
  }
  void reached(const IntegratorStats& st) override {
    if (forward) forward->reached(st);
  }
};

void add(IntegratorStats& a, const IntegratorStats& b) {
  a.steps += b.steps;
  a.newtonIterations += b.newtonIterations;
  a.factorizations += b.factorizations;
  a.sensitivityIterations += b.sensitivityIterations;
  a.sensitivityFactorizations += b.sensitivityFactorizations;
  a.sensitivityReusedLu += b.sensitivityReusedLu;
  a.residualEvaluations += b.residualEvaluations;
  a.jacobianEvaluations += b.jacobianEvaluations;
  a.errorTestFailures += b.errorTestFailures;
  a.convergenceFailures += b.convergenceFailures;
  a.acceleratedIterations += b.acceleratedIterations;
  a.luFill = std::max(a.luFill, b.luFill);
  a.choleskyFactorizations += b.choleskyFactorizations;
  a.ldltFactorizations += b.ldltFactorizations;
  a.factorizationSeconds += b.factorizationSeconds;
}

}  // namespace

IntegratorStats integrateFiniteDifferences(const Assembler& as, const VecX& p0,
                                           const StateWithSens& start, const PimCase* pim,
                                           const IntegratorSettings& set, const NdSettings& nd,
                                           Observer& obs) {
  if (nd.scheme != "central" && nd.scheme != "forward")
    throw InputError("option --nd-scheme: expected forward or central, got '" + nd.scheme + "'");
  if (!(nd.step > 0)) throw InputError("option --nd-step: expected a positive relative step");
  IntegratorStats total;
  StateWithSens nominal = start;
  nominal.dp.clear();
  FrameStore base;
  base.forward = &obs;
  total = integrate(as, p0, nominal, set, base);

  const int np = static_cast<int>(p0.size());
  std::vector<std::vector<State>> diff(np);  // per parameter, per frame
  for (int k = 0; k < np; ++k) {
    const double h = nd.step * std::max(std::abs(p0[k]), 1.0);
    std::vector<FrameStore> runs;
    for (int sgn : nd.scheme == "central" ? std::vector<int>{1, -1} : std::vector<int>{1}) {
      VecX p = p0;
      p[k] += sgn * h;
      StateWithSens s;
      s.x.t = start.x.t;
      as.setTime(s.x.t);  // the nominal run left the assembler at t_end
      s.x.q = pim ? perturbedConfiguration(as, *pim, start.x.q, p0, p, k) : projectPositions(as, start.x.q, p);
      s.x.v = projectVelocities(as, s.x.q, start.x.v + sgn * h * start.dp[k].v, p);
      equilibrateMassless(as, s.x, p);
      solveAccelerations(as, s.x, p);
      runs.emplace_back();
      add(total, integrate(as, p, s, set, runs.back()));
    }
    const auto& plus = runs[0].frames;
    const auto& minus = nd.scheme == "central" ? runs[1].frames : base.frames;
    const double den = nd.scheme == "central" ? 2 * h : h;
    if (plus.size() != base.frames.size() || minus.size() != base.frames.size())
      throw NumericalError("nd: a perturbed run produced a different number of frames");
    for (size_t f = 0; f < base.frames.size(); ++f) {
      State d;
      d.t = base.frames[f].t;
      d.q = (plus[f].q - minus[f].q) / den;
      d.v = (plus[f].v - minus[f].v) / den;
      d.a = (plus[f].a - minus[f].a) / den;
      d.lambda = (plus[f].lambda - minus[f].lambda) / den;
      diff[k].push_back(d);
    }
  }
  for (size_t f = 0; f < base.frames.size(); ++f) {
    StateWithSens out;
    out.x = base.frames[f];
    for (int k = 0; k < np; ++k) out.dp.push_back(diff[k][f]);
    obs.frame(out);
  }
  return total;
}

}  // namespace flexsens
