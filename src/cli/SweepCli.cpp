#include "cli/SweepCli.hpp"

#include <csignal>
#include <iomanip>
#include <iostream>

#include "core/Interrupt.hpp"

namespace flexsens {

namespace {

void addDesignOptions(CLI::App* s, SweepArgs& a) {
  s->add_option("--parameter", a.request.parameters,
                "NAME=LOW:HIGH:COUNT (a grid axis), NAME=LOW:HIGH (a Latin-hypercube range, with --samples) or "
                "NAME=VALUE (fixed); a scene parameter, repeatable");
  s->add_option("--samples", a.request.samples, "Latin hypercube: number of samples");
  s->add_option("--seed", a.seed, "Latin hypercube: random seed (default 1)");
  s->add_option("--case,--cases", a.request.cases, "PIM case (repeatable or comma-separated; default: every case)")
      ->delimiter(',');
  s->add_flag("--static", a.request.statics, "each sample is a static equilibrium (flexsens static)");
  s->add_option("--start", a.start,
                "a run's start: scene (the scene with the sample's values written in, default) | perturbed (the "
                "nominal start moved to the values as a PIM case says, as Scene.run(parameters=) in Python)")
      ->check(CLI::IsMember({"scene", "perturbed"}));
  s->add_option("--load-steps", a.loadSteps, "static: equal load increments");
  s->add_option("--at", a.request.times, "time [s] at which outputs are kept (repeatable; a frame time; default t_end)");
  s->add_option("--output", a.request.outputs, "output kept (repeatable; default: every output of the scene)");
}

void addRunOverrides(CLI::App* s, SweepArgs& a) {
  s->add_option("--integrator", a.integrator, "as for run");
  s->add_option("--t-end", a.tEnd, "final time [s]");
  s->add_option("--dt", a.dt, "fixed step [s] (IDAS: largest step)");
  s->add_option("--rho-inf", a.rhoInf, "generalized_alpha: spectral radius at infinity");
  s->add_option("--rtol", a.rtol, "IDAS relative tolerance");
  s->add_option("--newton", a.newtonMode, "fixed-step Newton: full | modified");
  s->add_option("--projections", a.projections, "on | off, as for run")->check(CLI::IsMember({"on", "off"}));
  s->add_option("--method", a.method, "sensitivities: dd | ad | dq | nd (static: dd | ad)");
}

/// The run options given, as overrides of the scene's settings (app/Run.hpp).
RunOptions runOverrides(const SweepArgs& a) {
  const CLI::App& s = *a.command;
  RunOptions o;
  if (!a.integrator.empty()) o.integrator = a.integrator;
  if (s.count("--t-end")) o.tEnd = a.tEnd;
  if (s.count("--dt")) o.dt = a.dt;
  if (s.count("--rho-inf")) o.rhoInf = a.rhoInf;
  if (s.count("--rtol")) o.rtol = a.rtol;
  if (!a.newtonMode.empty()) o.newton = a.newtonMode;
  if (!a.projections.empty()) o.projections = a.projections == "on";
  if (!a.method.empty()) o.method = a.method;
  return o;
}

/// The samples that did not complete, up to `shown` per status.
void reportProblems(const SweepResult& r) {
  constexpr int kShown = 10;
  for (const std::string& status : {"suspect", "failed", "lost", "interrupted"}) {
    int n = 0;
    for (const SampleRow& row : r.table.rows) {
      if (row.status != status) continue;
      if (n++ < kShown) std::cout << "  " << status << ": sample " << row.index << ": " << row.reason.substr(0, 300) << "\n";
    }
    if (n > kShown) std::cout << "  and " << n - kShown << " more " << status << " (sweep.csv)\n";
  }
  for (const std::string& l : r.info.lostRanks) std::cout << "  lost rank: " << l << "\n";
}

}  // namespace

void addSweep(CLI::App& app, SweepArgs& a) {
  auto* s = a.command = app.add_subcommand(
      "sweep", "run a scene over a grid or Latin hypercube of parameter values (and its PIM cases): outputs and "
               "sensitivities per sample in sweep.csv, sweep.json, sweep.png; spreads over the ranks of mpirun");
  s->add_option("scene", a.request.scenePath, "scene file (YAML)")->required();
  s->add_option("--out", a.request.outDir, "output directory (default: <output.directory>-sweep)");
  addDesignOptions(s, a);
  addRunOverrides(s, a);
  s->add_option("--sample-time-limit", a.request.sampleTimeLimit,
                "wall time [s] after which a sample is killed and marked lost (default: none)");
  s->add_option("--rank-timeout", a.request.rankTimeout,
                "silence [s] after which rank 0 counts a rank running a sample as lost (default 10)");
  s->add_flag("--keep-samples", a.request.keepSamples, "keep each sample's series.csv and summary.json in samples/<index>/");
  s->add_flag("--no-plots", a.noPlots, "do not draw sweep.png");
}

int executeSweep(SweepArgs& a) {
  SweepRequest& req = a.request;
  req.options = runOverrides(a);
  if (a.command->count("--seed")) req.seed = a.seed;
  if (a.command->count("--load-steps")) req.loadSteps = a.loadSteps;
  req.plots = !a.noPlots;
  req.perturbedStart = a.start == "perturbed";
  installInterruptHandlers();
  const SweepResult r = sweepCommand(req);
  if (!r.reporter) return 0;  // ranks 1..P-1: rank 0 reports
  const std::map<std::string, int> n = countStatuses(r.table.rows);
  std::cout << "sweep written to " << r.directory << "/ (sweep.csv, sweep.json"
            << (req.plots && r.plotNote.empty() && !r.interruptedBy ? ", sweep.png" : "") << ")\n  "
            << r.table.rows.size() << " samples:";
  const char* sep = " ";
  for (const std::string& s : sampleStatuses()) {
    if (!n.at(s)) continue;
    std::cout << sep << n.at(s) << " " << s;
    sep = ", ";
  }
  std::cout << "; " << r.info.ranks << (r.info.ranks == 1 ? " rank, " : " ranks, ") << std::setprecision(3)
            << r.info.wallSeconds << " s wall, " << r.info.overheadPerSample * 1e3 << " ms scheduling per sample\n";
  reportProblems(r);
  if (req.plots && !r.plotNote.empty() && !r.interruptedBy) std::cerr << "flexsens: note: no sweep.png: " << r.plotNote << "\n";
  if (r.interruptedBy) {
    std::cerr << "flexsens: sweep interrupted by " << (r.interruptedBy == SIGINT ? "SIGINT" : "SIGTERM")
              << "; sweep.csv holds the samples that finished, sweep.json says interrupted\n";
    return 128 + r.interruptedBy;
  }
  return r.status();
}

}  // namespace flexsens
