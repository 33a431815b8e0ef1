#include "app/Gradient.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>

#include "app/BodyMass.hpp"
#include "app/Commands.hpp"
#include "app/EnergyAudit.hpp"
#include "app/IdasGradient.hpp"
#include "app/Objectives.hpp"
#include "app/Run.hpp"
#include "core/Interrupt.hpp"
#include "core/MemoryBudget.hpp"
#include "integrators/FixedStepper.hpp"
#include "integrators/Static.hpp"
#include "integrators/StepEnd.hpp"
#include "integrators/TimeGrid.hpp"
#include "output/Energy.hpp"
#include "output/GradientVtu.hpp"
#include "output/ResultWriter.hpp"
#include "output/RunDirectory.hpp"

namespace flexsens {

namespace {

/// Every output at the start and after every step (Observer::stepped): the objective's samples.
class OutputSampler : public Observer {
 public:
  OutputSampler(const Scene& sc, long steps) : sc_(sc), samples_(MatX::Zero(steps + 1, Eigen::Index(sc.outputs.size()))) {}
  void frame(const StateWithSens&) override {}
  void stepped(const State& x) override {
    for (size_t k = 0; k < sc_.outputs.size(); ++k) samples_(row_, Eigen::Index(k)) = sc_.outputs[k].value(*sc_.model, x);
    ++row_;
  }
  const MatX& samples() const { return samples_; }

 private:
  const Scene& sc_;
  MatX samples_;
  Eigen::Index row_ = 0;
};

/// The objectives asked for: the named one, or all of them.
std::vector<size_t> selectedObjectives(const Scene& sc, const std::string& name) {
  if (sc.objectives.empty())
    throw InputError(sc.file + ": key 'objectives': the scene defines no objectives; add an objectives list "
                     "(docs/scene-reference.md) for flexsens gradient");
  std::vector<size_t> out;
  std::string names;
  for (size_t i = 0; i < sc.objectives.size(); ++i) {
    if (name.empty() || sc.objectives[i].name == name) out.push_back(i);
    names += (names.empty() ? "" : ", ") + sc.objectives[i].name;
  }
  if (out.empty()) throw InputError("option --objective: the scene has no objective '" + name + "'; its objectives: " + names);
  return out;
}

/// dJ_i/d samples of the selected objectives.
std::vector<MatX> sampleDerivatives(const Scene& sc, const std::vector<size_t>& sel, const StepGrid& g, const MatX& s) {
  std::vector<MatX> dJ;
  for (size_t i : sel) {
    dJ.push_back(MatX::Zero(s.rows(), s.cols()));
    addObjectiveDerivative(sc.objectives, i, g, s, 1.0, dJ.back());
  }
  return dJ;
}

/// Forward method: the outputs' sensitivities at every step (sens[n]: outputs x parameters),
/// then dJ/dp = sum_n sens[n]^T dJ/do_n.
MatX forwardGradients(const Scene& sc, const Assembler& as, const VecX& p, const StateWithSens& start,
                      const std::vector<size_t>& sel, const StepGrid& g, Observer& audit, const OutputSampler& sampler,
                      GradientResult& res) {
  const Model& m = *sc.model;
  const Eigen::Index nout = Eigen::Index(sc.outputs.size()), np = Eigen::Index(start.dp.size());
  requireMemory(doubles(double(g.steps + 1) * double(nout) * double(np + 1)),
                "the forward gradient's output sensitivities at every step", "use --method adjoint or fewer steps");
  std::vector<MatX> sens;
  auto record = [&](const StateWithSens& s) {
    sens.emplace_back(nout, np);
    for (Eigen::Index k = 0; k < nout; ++k)
      for (Eigen::Index j = 0; j < np; ++j) sens.back()(k, j) = sc.outputs[size_t(k)].derivative(m, s.x, s.dp[size_t(j)]);
  };
  FixedStepper stepper(as, p, start, sc.integrator);
  beginRun(audit, stepper.current());
  record(stepper.current());
  while (!stepper.done()) {
    stepper.step();
    endStep(audit, stepper.current(), stepper.statistics(), stepper.frameDue());
    record(stepper.current());
  }
  res.stats = stepper.statistics();
  const std::vector<MatX> dJ = sampleDerivatives(sc, sel, g, sampler.samples());
  MatX G = MatX::Zero(np, Eigen::Index(sel.size()));
  for (size_t i = 0; i < sel.size(); ++i)
    for (long n = 0; n <= g.steps; ++n) G.col(Eigen::Index(i)) += sens[size_t(n)].transpose() * dJ[i].row(n).transpose();
  return G;
}

/// Parameters whose least-norm initial sensitivities are held at once when the adjoint adds
/// their terms after the sweep (4 vectors of n each): 1083 thickness parameters of a plate
/// (n = 2.2k) held at once took 83 MB beside the plain run's 74 MB.
constexpr int kInitialSensitivityBlock = 128;

/// The initial sensitivities' terms of dJ/dp for a start without them (the least-norm rule),
/// a block of parameters at a time.
void addInitialTerms(const Assembler& as, const VecX& p, const State& x0, const StartAdjoints& mu, MatX& G) {
  for (int first = 0; first < int(G.rows()); first += kInitialSensitivityBlock) {
    const std::vector<State> ds =
        leastNormSensitivities(as, x0, p, first, std::min(kInitialSensitivityBlock, int(G.rows()) - first));
    for (size_t j = 0; j < ds.size(); ++j) G.row(first + Eigen::Index(j)) += mu.termsOf(ds[j]);
  }
}

/// Adjoint method: the forward pass samples, then one backward sweep for the selected objectives.
MatX adjointGradients(const Scene& sc, const Assembler& as, const VecX& p, const StateWithSens& start,
                      const std::vector<size_t>& sel, const StepGrid& g, long checkpointEvery, Observer& audit,
                      const OutputSampler& sampler, GradientResult& res) {
  DiscreteAdjoint adjoint(as, p, start, sc.integrator, checkpointEvery);
  res.stats = adjoint.forward(audit);
  const std::vector<MatX> dJ = sampleDerivatives(sc, sel, g, sampler.samples());
  const Model& m = *sc.model;
  MatX G = adjoint.backward(int(sel.size()), [&](long n, const State& x, MatX& gq, MatX& gv) {
    for (size_t i = 0; i < dJ.size(); ++i)
      for (size_t k = 0; k < sc.outputs.size(); ++k)
        if (const double w = dJ[i](n, Eigen::Index(k)); w != 0.0)
          sc.outputs[k].addGradient(m, x, w, gq.col(Eigen::Index(i)), gv.col(Eigen::Index(i)));
  });
  if (start.dp.empty()) addInitialTerms(as, p, start.x, adjoint.startAdjoints(), G);
  res.adjoint = adjoint.statistics();
  return G;
}

/// Static scenes: every objective asked for is terminal (or a sum of terminals).
void requireStaticObjectives(const Scene& sc, const std::vector<size_t>& sel) {
  for (size_t i : sel) {
    for (const auto& [k, w] : objectiveLeaves(sc.objectives, i))
      if (sc.objectives[size_t(k)].kind != "mass" &&
          (sc.objectives[size_t(k)].kind != "terminal" || sc.objectives[size_t(k)].at >= 0))
        throw InputError(sc.objectives[size_t(k)].where + ": objective '" + sc.objectives[size_t(k)].name +
                         "': a static equilibrium has terminal objectives only, without at (the last load step)");
  }
}

/// The equilibrium of `flexsens static` (load-stepped, or linear) and its exact sensitivities,
/// as one sample on a grid of no steps; dJ/dp = sum_k dJ/do_k do_k/dp.
MatX staticGradients(const Scene& sc, const std::vector<size_t>& sel, MatX& samples, GradientResult& res) {
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = m.nominalParameters();
  StaticSettings set;
  set.steps = sc.statics.loadSteps;
  set.stepLoadFactor = true;
  set.maxIterations = sc.integrator.maxNewtonIterations;
  set.tol = sc.integrator.newtonTol;
  StaticReport rep;
  State x;
  x.q = sc.statics.linear ? solveLinearStatic(as, p, m.initialPositions(), set.time, &rep)
                          : solveStatic(as, p, m.initialPositions(), set, &rep);
  x.v = VecX::Zero(m.n);
  const StaticSensitivity d = sc.statics.linear ? linearStaticSensitivities(as, m.initialPositions(), x.q, rep.lambda, p)
                                                : staticSensitivities(as, x.q, rep.lambda, p);
  res.stats.steps = rep.steps;
  res.stats.newtonIterations = rep.iterations;
  res.stats.maxConstraintViolation = rep.constraintNorm;
  const Eigen::Index nout = Eigen::Index(sc.outputs.size());
  samples.resize(1, nout);
  MatX sens(nout, p.size());
  for (Eigen::Index k = 0; k < nout; ++k) {
    samples(0, k) = sc.outputs[size_t(k)].value(m, x);
    for (Eigen::Index j = 0; j < p.size(); ++j) {
      State dj;
      dj.q = d.qp.col(j);
      dj.v = VecX::Zero(m.n);
      sens(k, j) = sc.outputs[size_t(k)].derivative(m, x, dj);
    }
  }
  const std::vector<MatX> dJ = sampleDerivatives(sc, sel, StepGrid{}, samples);
  MatX G(p.size(), Eigen::Index(sel.size()));
  for (size_t i = 0; i < sel.size(); ++i) G.col(Eigen::Index(i)) = sens.transpose() * dJ[i].row(0).transpose();
  return G;
}

/// The objective's value and gradient through the motion plus its direct dependence on the
/// parameters (a body's mass: app/BodyMass.hpp).
ObjectiveGradient withExplicitPart(const Scene& sc, size_t i, ObjectiveGradient g) {
  const ExplicitObjective e = explicitObjective(*sc.model, sc.objectives, i, sc.model->nominalParameters());
  g.value += e.value;
  g.gradient += e.gradient;
  return g;
}

/// Integrator idas: the objectives in continuous time (app/IdasGradient.hpp), the energy audit on the run.
GradientResult idasGradientResult(const Scene& sc, const Assembler& as, const VecX& p, const StateWithSens& start,
                                  const std::vector<size_t>& sel, const GradientRequest& req,
                                  std::chrono::steady_clock::time_point t0) {
  struct NoFrames : Observer {
    void frame(const StateWithSens&) override {}
  } noFrames;
  GradientResult res;
  res.method = req.method;
  for (const auto& par : sc.model->parameters) res.parameters.push_back(par.name);
  const EnergyMeter meter(as, p);
  EnergyAudit audit(meter, noFrames, sc.integrator.energyTolerance, sc.integrator.energyLossTolerance);
  std::vector<double> values;
  const MatX G = idasGradients(sc, as, p, start, sel, req, audit, res, values);
  for (size_t i = 0; i < sel.size(); ++i)
    res.objectives.push_back(withExplicitPart(sc, sel[i], {sc.objectives[sel[i]].name, values[i], G.col(Eigen::Index(i))}));
  res.reason = audit.reason();
  if (!res.reason.empty()) res.status = "suspect";
  res.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

void requireGradientMethod(const Scene& sc, const std::string& method) {
  if (method != "adjoint" && method != "forward")
    throw InputError("option --method: expected adjoint or forward, got '" + method + "'");
  const std::string& type = sc.integrator.type;
  if (type == "idas") return;  // the continuous adjoint and IDAS' forward sensitivities (app/IdasGradient.hpp)
  if (method == "adjoint" && !hasAdjoint(type))
    throw InputError("option --method adjoint: integrator " + type + " has no discrete adjoint; the methods that have one: " +
                     kAdjointIntegrators + " (--integrator), and idas its continuous adjoint; or use --method forward with one of those");
  if (method == "forward" && !hasAdjoint(type))
    throw InputError("option --method forward: flexsens gradient integrates with idas or a fixed-step scheme (" +
                     std::string(kAdjointIntegrators) + "), not " + type + " (--integrator)");
}

}  // namespace

GradientResult computeGradients(const Scene& sc, const GradientRequest& req) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<size_t> sel = selectedObjectives(sc, req.objective);
  if (req.statics || !sc.hasIntegrator) {
    requireStaticObjectives(sc, sel);
    GradientResult res;
    res.method = "static";
    for (const auto& par : sc.model->parameters) res.parameters.push_back(par.name);
    MatX samples;
    const MatX G = staticGradients(sc, sel, samples, res);
    for (size_t i = 0; i < sel.size(); ++i)
      res.objectives.push_back(withExplicitPart(sc, sel[i], {sc.objectives[sel[i]].name,
                                                             objectiveValue(sc.objectives, sel[i], StepGrid{}, samples),
                                                             G.col(Eigen::Index(i))}));
    res.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
  }
  sc.requireDynamics();
  requireGradientMethod(sc, req.method);
  for (size_t i : sel) checkObjectiveTimes(sc.objectives[i], sc.integrator.tEnd);
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = m.nominalParameters();
  if (sc.integrator.type == "idas")  // its adjoint takes the initial sensitivities at the start
    return idasGradientResult(sc, as, p, initialState(as, p, sc.pimCase.get()), sel, req, t0);
  // The adjoint of a start by the least-norm rule takes the initial sensitivities after the
  // sweep, a block at a time (addInitialTerms); a PIM case gives them all here.
  const StateWithSens start = req.method == "adjoint" && !sc.pimCase ? StateWithSens{consistentState(as, p), {}}
                                                                     : initialState(as, p, sc.pimCase.get());
  StepGrid g{start.x.t, sc.integrator.dt, sc.integrator.tEnd, fixedStepCount(sc.integrator.tEnd - start.x.t, sc.integrator.dt)};
  GradientResult res;
  res.method = req.method;
  res.steps = g.steps;
  for (const auto& par : m.parameters) res.parameters.push_back(par.name);
  // The outputs at every step, and dJ/do of each objective asked for: (N + 1) x outputs each.
  requireMemory(doubles(double(g.steps + 1) * double(sc.outputs.size()) * double(sel.size() + 1)),
                "the objectives' output samples at every step", "use fewer steps (a larger dt) or fewer outputs");
  OutputSampler sampler(sc, g.steps);
  const EnergyMeter meter(as, p);
  EnergyAudit audit(meter, sampler, sc.integrator.energyTolerance, sc.integrator.energyLossTolerance);
  const MatX G = req.method == "forward" ? forwardGradients(sc, as, p, start, sel, g, audit, sampler, res)
                                         : adjointGradients(sc, as, p, start, sel, g, req.checkpointEvery, audit, sampler, res);
  for (size_t i = 0; i < sel.size(); ++i)
    res.objectives.push_back(withExplicitPart(sc, sel[i], {sc.objectives[sel[i]].name,
                                                           objectiveValue(sc.objectives, sel[i], g, sampler.samples()),
                                                           G.col(Eigen::Index(i))}));
  res.reason = audit.reason();
  if (!res.reason.empty()) res.status = "suspect";
  res.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

std::string gradientJson(const GradientResult& r, bool single) {
  std::ostringstream stats;
  const IntegratorStats& s = r.stats;
  stats << "{\"status\": " << jsonString(r.status);
  if (!r.reason.empty()) stats << ", \"reason\": " << jsonString(r.reason);
  stats << ", \"method\": " << jsonString(r.method) << ", \"steps\": " << (r.method == "static" ? r.stats.steps : r.steps)
        << ", \"newton_iterations\": " << s.newtonIterations << ", \"factorizations\": " << s.factorizations
        << ", \"max_constraint_violation\": " << jsonNumber(s.maxConstraintViolation);
  if (r.method == "adjoint") {
    const AdjointStatistics& a = r.adjoint;
    stats << ", \"checkpoint_every\": " << a.checkpointEvery << ", \"checkpoints\": " << a.checkpoints;
    if (a.peakStates > 0)  // (the discrete adjoint's own storage; IDAS keeps its own, not counted)
      stats << ", \"recomputed_steps\": " << a.recomputedSteps << ", \"peak_states\": " << a.peakStates
            << ", \"peak_state_bytes\": " << jsonNumber(a.peakStateBytes);
    stats << ", \"backward_steps\": " << a.backwardSteps
          << ", \"backward_factorizations\": " << a.backwardFactorizations
          << ", \"forward_pass_s\": " << jsonNumber(a.forwardSeconds) << ", \"backward_pass_s\": " << jsonNumber(a.backwardSeconds);
  }
  stats << ", \"wall_time_s\": " << jsonNumber(r.wallSeconds) << "}";
  std::ostringstream js;
  if (!single) js << "[\n";
  for (size_t i = 0; i < r.objectives.size(); ++i) {
    const ObjectiveGradient& o = r.objectives[i];
    js << (single ? "" : "  ") << "{\"objective\": " << jsonString(o.name) << ", \"value\": " << jsonNumber(o.value)
       << ", \"gradient\": {";
    for (size_t k = 0; k < r.parameters.size(); ++k)
      js << (k ? ", " : "") << jsonString(r.parameters[k]) << ": " << jsonNumber(o.gradient[Eigen::Index(k)]);
    js << "}, \"statistics\": " << stats.str() << "}" << (i + 1 < r.objectives.size() ? ",\n" : "\n");
  }
  if (!single) js << "]\n";
  return js.str();
}

GradientResult gradientCommand(const GradientRequest& req) {
  Scene sc = readRequestedScene(req.scenePath, req.sceneText, req.caseName);
  const bool statics = req.statics || !sc.hasIntegrator;
  if (!statics) applyOptions(sc, req.options);
  const std::string outDir = req.outDir.empty() ? sc.output.directory + "-gradient" : req.outDir;
  // Input errors first, then the folder (locked, refused when it holds what flexsens did not write).
  const std::vector<size_t> sel = selectedObjectives(sc, req.objective);
  if (statics) requireStaticObjectives(sc, sel);
  else requireGradientMethod(sc, req.method);
  if (!statics && sc.integrator.type == "idas" && req.method == "adjoint") requireIdasAdjointObjectives(sc, sel);
  RunDirectory dir(outDir, "gradient");
  GradientResult res;
  try {
    res = computeGradients(sc, req);
  } catch (const Interrupted& e) {  // nothing to write: a gradient needs the whole sweep
    std::ostringstream during;
    during << "during flexsens gradient (at t = " << e.t << " s)";
    throw InterruptedBeforeRun(e.signal, during.str());
  }
  res.directory = outDir;
  const std::string path = dir.staging() + "/gradient.json";
  errno = 0;
  std::ofstream out(path);
  out << gradientJson(res, !req.objective.empty());
  out.close();
  if (!out) throw OutputError("cannot write " + outDir + "/gradient.json: " + std::strerror(errno ? errno : EIO));
  if (hasPerElementParameters(*sc.model)) {  // where the design matters, for ParaView
    std::vector<std::pair<std::string, VecX>> fields;
    for (const auto& o : res.objectives) fields.emplace_back(o.name, o.gradient);
    writeGradientVtu(dir.staging() + "/gradient.vtu", outDir + "/gradient.vtu", *sc.model, fields);
    res.field = true;
  }
  dir.commit();
  return res;
}

}  // namespace flexsens
