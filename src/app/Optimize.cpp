#include "app/Optimize.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <nlopt.hpp>

#include "app/Commands.hpp"
#include "app/Gradient.hpp"
#include "app/OptimizeOutput.hpp"
#include "app/ParameterValues.hpp"
#include "core/Interrupt.hpp"
#include "integrators/Adjoint.hpp"
#include "output/RunDirectory.hpp"

namespace flexsens {

namespace {

using Clock = std::chrono::steady_clock;

/// The model at the optimizer's points: each evaluation starts from the scene as read (its
/// nodes and parameter values), sets the variables and runs the gradient computation.
class Evaluator {
 public:
  Evaluator(Scene& sc, OptimizeResult& res) : sc_(sc), res_(res), nodes_(sc.model->nodes), p0_(sc.model->nominalParameters()) {
    for (const OptimizeVariable& v : sc.optimize.variables)
      for (int k : v.parameters) index_.push_back(k);
  }
  size_t size() const { return index_.size(); }
  VecX start() const {
    VecX x(Eigen::Index(index_.size()));
    for (size_t i = 0; i < index_.size(); ++i) x[Eigen::Index(i)] = p0_[index_[i]];
    return x;
  }
  /// The evaluation at x, run once per point (NLopt asks for the objective and the
  /// constraints separately at the same point). Throws nlopt::forced_stop when it failed.
  const OptimizeEvaluation& at(const double* x);

 private:
  void setParameters(const VecX& x);
  void run(OptimizeEvaluation& e);
  Scene& sc_;
  OptimizeResult& res_;
  const std::vector<Node> nodes_;
  const VecX p0_;
  std::vector<int> index_;
};

void Evaluator::setParameters(const VecX& x) {
  Model& m = *sc_.model;
  m.nodes = nodes_;  // the scene's start: applyParameterValues perturbs it from there
  for (size_t k = 0; k < m.parameters.size(); ++k) m.parameters[k].nominal = p0_[Eigen::Index(k)];
  ParameterChanges changes;
  for (size_t i = 0; i < index_.size(); ++i) changes.emplace_back(m.parameters[size_t(index_[i])].name, x[Eigen::Index(i)]);
  if (sc_.hasIntegrator) applyParameterValues(sc_, changes);
  else setParameterValues(sc_, changes);
}

void Evaluator::run(OptimizeEvaluation& e) {
  GradientRequest req;
  req.method = sc_.optimize.gradient;
  const GradientResult g = computeGradients(sc_, req);  // every objective: one forward pass, one sweep
  auto valueOf = [&](int objective, VecX& gradient) {
    const ObjectiveGradient& o = g.objectives[size_t(objective)];
    gradient = VecX(Eigen::Index(index_.size()));
    for (size_t i = 0; i < index_.size(); ++i) gradient[Eigen::Index(i)] = o.gradient[index_[i]];
    return o.value;
  };
  e.objective = valueOf(sc_.optimize.objective, e.gradient);
  for (const OptimizeConstraint& c : sc_.optimize.constraints) {
    e.constraintGradients.emplace_back();
    e.constraints.push_back(valueOf(c.objective, e.constraintGradients.back()));
  }
  e.ok = true;
  e.status = g.status;
  e.message = g.reason;
}

const OptimizeEvaluation& Evaluator::at(const double* x) {
  const Eigen::Map<const VecX> point(x, Eigen::Index(index_.size()));
  if (!res_.history.empty() && res_.history.back().x == point) return res_.history.back();
  if (const int sig = interruptSignal()) {
    res_.interruptedBy = sig;
    throw nlopt::forced_stop();
  }
  OptimizeEvaluation e;
  e.index = int(res_.history.size()) + 1;
  e.x = point;
  const auto t0 = Clock::now();
  try {
    setParameters(e.x);
    run(e);
  } catch (const Interrupted& i) {
    res_.interruptedBy = i.signal;
  } catch (const std::exception& err) {  // a rejected step, a Newton failure, a failed start
    e.status = "failed";
    e.message = err.what();
  }
  e.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (res_.interruptedBy) throw nlopt::forced_stop();
  res_.history.push_back(std::move(e));
  if (!res_.history.back().ok) {
    res_.failed = int(res_.history.size()) - 1;
    throw nlopt::forced_stop();
  }
  return res_.history.back();
}

double objectiveCallback(const std::vector<double>& x, std::vector<double>& grad, void* data) {
  const OptimizeEvaluation& e = static_cast<Evaluator*>(data)->at(x.data());
  for (size_t i = 0; i < grad.size(); ++i) grad[i] = e.gradient[Eigen::Index(i)];
  return e.objective;
}

/// NLopt's inequality constraints c(x) <= 0: J - max, or min - J.
struct ConstraintData {
  Evaluator* evaluator;
  const OptimizeSpec* spec;
};

void constraintCallback(unsigned m, double* result, unsigned n, const double* x, double* grad, void* data) {
  const auto& d = *static_cast<ConstraintData*>(data);
  const OptimizeEvaluation& e = d.evaluator->at(x);
  for (unsigned i = 0; i < m; ++i) {
    const OptimizeConstraint& c = d.spec->constraints[i];
    const double sign = c.upper ? 1.0 : -1.0;
    result[i] = sign * (e.constraints[i] - c.bound);
    if (grad)
      for (unsigned j = 0; j < n; ++j) grad[i * n + j] = sign * e.constraintGradients[i][Eigen::Index(j)];
  }
}

const char* resultName(nlopt::result r) {
  switch (r) {
    case nlopt::SUCCESS: return "SUCCESS";
    case nlopt::STOPVAL_REACHED: return "STOPVAL_REACHED";
    case nlopt::FTOL_REACHED: return "FTOL_REACHED";
    case nlopt::XTOL_REACHED: return "XTOL_REACHED";
    case nlopt::MAXEVAL_REACHED: return "MAXEVAL_REACHED";
    case nlopt::MAXTIME_REACHED: return "MAXTIME_REACHED";
    case nlopt::FAILURE: return "FAILURE";
    case nlopt::INVALID_ARGS: return "INVALID_ARGS";
    case nlopt::OUT_OF_MEMORY: return "OUT_OF_MEMORY";
    case nlopt::ROUNDOFF_LIMITED: return "ROUNDOFF_LIMITED";
    case nlopt::FORCED_STOP: return "FORCED_STOP";
    default: return "UNKNOWN";
  }
}

/// A constraint's allowance: NLopt's tolerance and the feasibility test of the best point.
double constraintTolerance(double bound) { return 1e-8 * std::max(1.0, std::abs(bound)); }

nlopt::opt makeOptimizer(const OptimizeSpec& spec, const OptimizeResult& res, size_t n) {
  const nlopt::algorithm a = spec.algorithm == "mma" ? nlopt::LD_MMA : spec.algorithm == "slsqp" ? nlopt::LD_SLSQP
                                                                                                : nlopt::LD_LBFGS;
  nlopt::opt opt(a, unsigned(n));
  opt.set_lower_bounds(std::vector<double>(res.lower.data(), res.lower.data() + n));
  opt.set_upper_bounds(std::vector<double>(res.upper.data(), res.upper.data() + n));
  opt.set_ftol_rel(spec.tolerance);
  opt.set_xtol_rel(spec.tolerance);
  opt.set_maxeval(spec.maxEvaluations);
  return opt;
}

/// How far evaluation e violates the constraints beyond their tolerance (0: feasible).
double violation(const OptimizeSpec& spec, const OptimizeEvaluation& e) {
  double worst = 0.0;
  for (size_t c = 0; c < spec.constraints.size(); ++c) {
    const OptimizeConstraint& k = spec.constraints[c];
    const double excess = (k.upper ? 1.0 : -1.0) * (e.constraints[c] - k.bound);
    worst = std::max(worst, excess - constraintTolerance(k.bound));
  }
  return worst;
}

/// OptimizeResult::kktResidual of evaluation e, relative to the larger of its gradient and the
/// start's (at an unconstrained optimum the gradient itself vanishes): the constraints within 1e-6 max(1, |bound|) of
/// their bound are active, a variable at a bound (1e-9 of the range) is held when the residual
/// pushes it outward.
double kktResidual(const OptimizeSpec& spec, const OptimizeResult& res, const OptimizeEvaluation& e) {
  const Eigen::Index n = e.gradient.size();
  std::vector<Eigen::Index> active;
  for (size_t c = 0; c < spec.constraints.size(); ++c)
    if (std::abs(e.constraints[c] - spec.constraints[c].bound) <= 1e-6 * std::max(1.0, std::abs(spec.constraints[c].bound)))
      active.push_back(Eigen::Index(c));
  auto heldMask = [&](const VecX& r) {  // 1 for the components that count
    VecX mask = VecX::Ones(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double range = res.upper[i] - res.lower[i];
      if ((e.x[i] <= res.lower[i] + 1e-9 * range && r[i] >= 0) || (e.x[i] >= res.upper[i] - 1e-9 * range && r[i] <= 0))
        mask[i] = 0.0;
    }
    return mask;
  };
  const VecX g = e.gradient;
  VecX r = g;
  if (!active.empty()) {  // least-squares multipliers on the components that are not held
    MatX A(n, Eigen::Index(active.size()));
    for (size_t j = 0; j < active.size(); ++j) A.col(Eigen::Index(j)) = e.constraintGradients[size_t(active[j])];
    const VecX free = heldMask(g);
    const VecX mu = (free.asDiagonal() * A).colPivHouseholderQr().solve(-(free.asDiagonal() * g));
    r = g + A * mu;
  }
  const double scale = std::max(g.cwiseAbs().maxCoeff(), res.history.front().gradient.cwiseAbs().maxCoeff());
  return scale > 0 ? (heldMask(r).asDiagonal() * r).cwiseAbs().maxCoeff() / scale : 0.0;
}

/// NLopt said converged, but the best point's gradient is this far from stationary: stalled
/// (MMA from an infeasible start can stop after a jump to a bound: residual 1).
constexpr double kStalledResidual = 0.1;

/// The best evaluation: the lowest objective among the feasible ones, else the least violation.
int bestEvaluation(const OptimizeSpec& spec, const std::vector<OptimizeEvaluation>& history) {
  int best = -1;
  double bestJ = 0.0, bestViolation = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < history.size(); ++i) {
    const OptimizeEvaluation& e = history[i];
    if (!e.ok) continue;
    const double v = violation(spec, e);
    if (v < bestViolation || (v == bestViolation && e.objective < bestJ)) {
      best = int(i);
      bestJ = e.objective;
      bestViolation = v;
    }
  }
  return best;
}

void describe(const Scene& sc, OptimizeResult& res) {
  const OptimizeSpec& spec = sc.optimize;
  res.algorithm = spec.algorithm;
  res.gradient = sc.hasIntegrator ? spec.gradient : "static";
  res.objective = sc.objectives[size_t(spec.objective)].name;
  size_t n = 0;
  for (const OptimizeVariable& v : spec.variables) n += v.parameters.size();
  res.lower.resize(Eigen::Index(n));
  res.upper.resize(Eigen::Index(n));
  n = 0;
  for (const OptimizeVariable& v : spec.variables)
    for (int k : v.parameters) {
      res.variables.push_back(sc.model->parameters[size_t(k)].name);
      res.lower[Eigen::Index(n)] = v.lower;
      res.upper[Eigen::Index(n++)] = v.upper;
    }
  for (const OptimizeConstraint& c : spec.constraints) {
    res.constraints.push_back(sc.objectives[size_t(c.objective)].name);
    res.bounds.push_back(c.bound);
    res.upperBounds.push_back(c.upper);
  }
}

/// Runs NLopt from the scene's values; the status from its return code and the history.
void runOptimizer(Scene& sc, OptimizeResult& res) {
  const OptimizeSpec& spec = sc.optimize;
  Evaluator evaluator(sc, res);
  nlopt::opt opt = makeOptimizer(spec, res, evaluator.size());
  opt.set_min_objective(objectiveCallback, &evaluator);
  ConstraintData data{&evaluator, &spec};
  if (!spec.constraints.empty()) {
    std::vector<double> tol;
    for (const OptimizeConstraint& c : spec.constraints) tol.push_back(constraintTolerance(c.bound));
    opt.add_inequality_mconstraint(constraintCallback, &data, tol);
  }
  const VecX x0 = evaluator.start();
  std::vector<double> x(x0.data(), x0.data() + x0.size());
  double f = 0.0;
  nlopt::result r = nlopt::FAILURE;
  try {
    r = opt.optimize(x, f);
  } catch (const nlopt::forced_stop&) {
    r = nlopt::FORCED_STOP;
  } catch (const nlopt::roundoff_limited&) {
    r = nlopt::ROUNDOFF_LIMITED;
  } catch (const std::exception&) {
    r = opt.last_optimize_result();
  }
  res.nloptCode = int(r);
  res.nloptResult = resultName(r);
  res.best = bestEvaluation(spec, res.history);
  if (res.best >= 0) res.kktResidual = kktResidual(spec, res, res.history[size_t(res.best)]);
  if (res.interruptedBy) res.status = "interrupted";
  else if (res.failed >= 0) res.status = "failed";
  else if (r == nlopt::MAXEVAL_REACHED) res.status = "max_evaluations";
  else if (r == nlopt::ROUNDOFF_LIMITED) res.status = "roundoff_limited";
  else if (r < 0) res.status = "nlopt_failure";
  else res.status = "converged";
  if (res.status == "converged" && res.best >= 0 && violation(spec, res.history[size_t(res.best)]) > 0.0)
    res.status = "infeasible";
  if (res.status == "converged" && res.kktResidual > kStalledResidual) res.status = "stalled";
  if (res.status == "converged" && res.best >= 0 && res.history[size_t(res.best)].status == "suspect")
    res.status = "suspect";  // the optimum of a run the energy audit doubts (its message in optimize.json)
}

/// InputError for what the optimizer cannot run: no `optimize:`, no gradient for the integrator.
void requireOptimizable(const Scene& sc) {
  if (!sc.optimize.given)
    throw InputError(sc.file + ": key 'optimize': the scene has no optimize section; add one "
                     "(docs/scene-reference.md#optimize) for flexsens optimize");
  if (sc.hasIntegrator && !hasAdjoint(sc.integrator.type))
    throw InputError(sc.optimize.where + ": integrator " + sc.integrator.type + " has no gradient path for flexsens "
                     "optimize (neither the adjoint nor the forward objective gradient); use one of " +
                     kAdjointIntegrators);
  if (sc.hasIntegrator) sc.requireDynamics();
}

}  // namespace

std::vector<OptimizeEvaluation> evaluatePoints(Scene& sc, const std::vector<VecX>& points) {
  requireOptimizable(sc);
  OptimizeResult res;
  Evaluator evaluator(sc, res);
  for (const VecX& x : points) {
    try {
      evaluator.at(x.data());
    } catch (const nlopt::forced_stop&) {  // a failed evaluation: kept in the history
    }
  }
  return res.history;
}

int OptimizeResult::exitCode() const {
  if (status == "interrupted") return 128 + interruptedBy;
  if (status == "failed") return 2;
  if (status == "nlopt_failure") return 3;
  return status == "converged" ? 0 : 5;
}

OptimizeResult optimizeCommand(const OptimizeRequest& req) {
  const auto t0 = Clock::now();
  Scene sc = readScene(req.scenePath);
  requireOptimizable(sc);
  const std::string outDir = req.outDir.empty() ? sc.output.directory + "-optimize" : req.outDir;
  RunDirectory dir(outDir, "optimize");
  OptimizeResult res;
  describe(sc, res);
  runOptimizer(sc, res);
  res.wallSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
  res.directory = dir.final();
  writeOptimizeOutputs(dir, sc, res);
  dir.keep("history.png");  // drawn by scripts/plot_optimize.py after the commit
  dir.commit();
  if (req.plots && !res.history.empty()) res.plotNote = drawPlotScript("plot_optimize.py", res.directory);
  return res;
}

}  // namespace flexsens
