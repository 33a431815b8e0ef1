// prepareSweep (app/Sweep.hpp): the options checked against the scene before anything runs.
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "app/Commands.hpp"
#include "app/Sweep.hpp"
#include "integrators/TimeGrid.hpp"

namespace flexsens {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string r;
  for (const auto& n : names) r += (r.empty() ? "" : ", ") + n;
  return r.empty() ? "none" : r;
}

std::string timeText(double t) {
  std::ostringstream os;
  os.precision(12);
  os << t;
  return os.str();
}

/// The parameter names are the scene's; the outputs (default: all) are the scene's.
std::vector<std::string> checkNames(const SweepRequest& req, const Scene& scene, const SweepDesign& design) {
  std::vector<std::string> params, outputs;
  for (const Parameter& p : scene.model->parameters) params.push_back(p.name);
  for (const ParameterRange& r : design.ranges)
    if (std::find(params.begin(), params.end(), r.name) == params.end())
      throw InputError("option --parameter: " + req.scenePath + " has no parameter '" + r.name +
                       "' under parameters; its parameters: " + joined(params));
  for (const OutputSpec& o : scene.outputs) outputs.push_back(o.name);
  if (outputs.empty())
    throw InputError("option --output: " + req.scenePath + " has no outputs (add an outputs list to the scene)");
  for (const std::string& o : req.outputs)
    if (std::find(outputs.begin(), outputs.end(), o) == outputs.end())
      throw InputError("option --output: " + req.scenePath + " has no output '" + o + "'; its outputs: " +
                       joined(outputs));
  return req.outputs.empty() ? outputs : req.outputs;
}

/// Properties that take either sign: gravity, load components and torques, products of
/// inertia, the constants of time functions. Any other property (a mass, a length, a
/// stiffness, a modulus) positive in the scene must not be made negative by a sweep: the
/// scene reader would refuse that value, which the sweep applies after it.
bool signedProperty(const std::string& boundTo) {
  static const std::set<std::string> signedNames = {"x", "y", "z", "torque", "Ixy", "Ixz", "Iyz", "amplitude",
                                                    "omega", "phase", "offset", "value", "slope", "start", "from",
                                                    "to", "scale"};
  const size_t dot = boundTo.rfind('.');
  return boundTo.rfind("gravity.", 0) == 0 || signedNames.count(boundTo.substr(dot + 1));
}

void checkSigns(const Scene& scene, const SweepDesign& design) {
  for (const ParameterRange& r : design.ranges)
    for (const Parameter& p : scene.model->parameters)
      if (p.name == r.name && p.nominal > 0 && r.low < 0 && !signedProperty(p.boundTo)) {
        std::ostringstream os;
        os << "option --parameter: " << r.name << " is " << p.boundTo << ", " << p.nominal
           << " in the scene; its values must not be negative (the range starts at " << r.low << ")";
        throw InputError(os.str());
      }
}

/// Each --at time must be a frame of the run: series.csv has a row there.
void checkTimes(const std::vector<double>& times, const IntegratorSettings& s) {
  const double spacing = frameSpacing(s);
  for (double t : times) {
    const bool atEnd = std::abs(t - s.tEnd) <= 1e-9 * std::max(1.0, s.tEnd);
    const double k = t / spacing;
    if (!(t >= 0 && t <= s.tEnd * (1 + 1e-12)) || (!atEnd && std::abs(k - std::round(k)) > 1e-6))
      throw InputError("option --at: t = " + timeText(t) + " s is not a frame time of the run: frames come every " +
                       timeText(spacing) + " s (integrator.frame_interval, dt) from 0 and at t_end = " +
                       timeText(s.tEnd) + " s");
  }
}

/// The static sweep's options: no integrator options, no times, no cases.
void checkStaticOptions(const SweepRequest& req) {
  const RunOptions& o = req.options;
  if (o.integrator || o.tEnd || o.dt || o.rhoInf || o.rtol || o.newton || o.projections || o.ndStep || o.ndScheme)
    throw InputError("option --static: a static sweep has no integrator; leave out --integrator, --t-end, --dt, "
                     "--rho-inf, --rtol, --newton, --projections and the nd options");
  if (!req.times.empty()) throw InputError("option --at: a static sweep keeps the equilibrium at load factor 1");
  if (!req.cases.empty()) throw InputError("option --case: a static sweep has no PIM cases");
  if (req.perturbedStart)
    throw InputError("option --start: a static sweep finds each equilibrium from the scene's positions; leave out "
                     "--start perturbed");
  if (req.loadSteps && (*req.loadSteps < 1 || *req.loadSteps > 100000))
    throw InputError("option --load-steps: expected 1 to 100000");
  if (o.method && *o.method != "dd" && *o.method != "ad")
    throw InputError("option --method: static sensitivities are dd or ad, got '" + *o.method + "'");
}

/// Columns: per time, per output its value, then d(output)/d(p) for every parameter of any case.
std::vector<OutputColumn> columnsFor(const SweepTable& t, const std::vector<std::string>& params) {
  std::vector<OutputColumn> cols;
  const std::vector<double> times = t.statics ? std::vector<double>{1.0} : t.times;
  for (double time : times)
    for (const std::string& o : t.outputs)
      for (size_t k = 0; k <= params.size(); ++k) {
        OutputColumn c{o, k ? params[k - 1] : "", time, ""};
        c.header = c.source() + (t.statics ? "" : "@" + timeText(time));
        cols.push_back(c);
      }
  return cols;
}

void addUnique(std::vector<std::string>& list, const std::string& s) {
  if (std::find(list.begin(), list.end(), s) == list.end()) list.push_back(s);
}

/// The dynamic sweep: every case read and its options applied (prepareRun); the times.
std::vector<std::string> prepareDynamic(const SweepRequest& req, const ParameterValues& first, SweepPlan& plan) {
  RunRequest run;
  run.scenePath = req.scenePath;
  run.options = req.options;
  run.cases = req.cases;
  run.parameterValues = first;
  const std::vector<RunCase> cases = prepareRun(run);
  std::vector<std::string> params;
  for (const RunCase& c : cases) {
    plan.table.design.cases.push_back(c.name);
    for (const Parameter& p : c.scene.model->parameters) addUnique(params, p.name);
  }
  const IntegratorSettings& s = cases.front().scene.integrator;
  plan.table.times = req.times.empty() ? std::vector<double>{s.tEnd} : req.times;
  checkTimes(plan.table.times, s);
  plan.setup.timeTolerance = 1e-3 * frameSpacing(s);
  return params;
}

}  // namespace

SweepPlan prepareSweep(const SweepRequest& req) {
  SweepPlan plan;
  SweepDesign& design = plan.table.design;
  for (const std::string& spec : req.parameters) design.ranges.push_back(parseParameterRange(spec));
  design.samples = req.samples;
  design.seed = req.seed.value_or(1);
  design.seedGiven = req.seed.has_value();
  if (req.samples < 0) throw InputError("option --samples: expected a positive number of samples");
  if (!(req.sampleTimeLimit >= 0)) throw InputError("option --sample-time-limit: expected seconds >= 0 (0: none)");
  if (!(req.rankTimeout > 0)) throw InputError("option --rank-timeout: expected a positive number of seconds");
  const Scene nominal = readScene(req.scenePath);  // every declared parameter, no case
  plan.table.scenePath = req.scenePath;
  plan.table.statics = req.statics;
  plan.table.outputs = checkNames(req, nominal, design);
  checkSigns(nominal, design);
  ParameterValues first;
  for (const ParameterRange& r : design.ranges) first[r.name] = r.low;
  std::vector<std::string> params;
  if (req.statics) {
    checkStaticOptions(req);
    const Scene withValues = readScene(req.scenePath, "", first);
    for (const Parameter& p : withValues.model->parameters) params.push_back(p.name);
    design.cases = {""};
  } else {
    params = prepareDynamic(req, first, plan);
  }
  plan.table.columns = columnsFor(plan.table, params);
  plan.table.samples = planSamples(design);
  plan.outDir = req.outDir.empty() ? nominal.output.directory + "-sweep" : req.outDir;
  SweepSetup& s = plan.setup;
  s.scenePath = req.scenePath;
  s.options = req.options;
  s.options.outDir.reset();
  s.statics = req.statics;
  s.perturbedStart = req.perturbedStart;
  s.loadSteps = req.loadSteps;
  s.columns = plan.table.columns;
  s.keepFiles = req.keepSamples;
  return plan;
}

}  // namespace flexsens
