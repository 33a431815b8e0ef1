// flexsens command line: `flexsens run SCENE [...]`, `flexsens static SCENE`, `flexsens check SCENE`,
// `flexsens modes SCENE`, `flexsens study`, `flexsens sweep SCENE` (cli/SweepCli.cpp), `flexsens gradient SCENE`, `flexsens optimize SCENE`. Exit codes: 0 success, 1 bad input (scene or
// options), 2 numerical failure, 3 other error, 4 results could not be written or the output
// folder was refused (it holds files flexsens did not write; nothing touched), 5 run completed
// but suspect (energy audit), 6 the output folder is in use by another run of any kind (run,
// cases, static, study), 128 + signal (130 SIGINT, 143 SIGTERM) interrupted, results up to the
// time reached.
//
// This file only parses options into the requests of app/Commands.hpp, calls the command and
// prints its result: one small function per subcommand.
#include <CLI/CLI.hpp>

#include <iostream>

#include "app/Commands.hpp"
#include "app/Gradient.hpp"
#include "app/Optimize.hpp"
#include "cli/SweepCli.hpp"
#include "core/Interrupt.hpp"
#include "core/MemoryBudget.hpp"
#include "core/Types.hpp"
#include "output/ResultWriter.hpp"
#include "scene/InputFiles.hpp"

using namespace flexsens;

namespace {

// ------------------------------------------------------------------ run
struct RunArgs {
  CLI::App* command = nullptr;
  RunRequest request;
  std::string integrator, outDir, newtonMode, projections, method, ndScheme;
  double tEnd = 0, dt = 0, rhoInf = 0, rtol = 0, ndStep = 0;
};

void addRun(CLI::App& app, RunArgs& a) {
  auto* run = a.command = app.add_subcommand("run", "simulate a scene and write series.csv, VTK frames and summary.json");
  run->add_option("scene", a.request.scenePath, "scene file (YAML)")->required();
  run->add_option("--out", a.outDir, "output directory (default: the scene's output.directory)");
  run->add_option("--integrator", a.integrator, "idas | trapezoidal | midpoint | bdf1 | generalized_alpha | maggi_rk4 (default: the scene's)");
  run->add_option("--t-end", a.tEnd, "final time [s]");
  run->add_option("--dt", a.dt, "fixed step [s] (IDAS: largest step)");
  run->add_option("--rho-inf", a.rhoInf, "generalized_alpha: spectral radius at infinity, 0..1 (default 0.9; 1 = no dissipation)");
  run->add_option("--rtol", a.rtol, "IDAS relative tolerance");
  run->add_option("--projections", a.projections, "trapezoidal / generalized_alpha: on projects each step's velocities and accelerations onto the constraints (default off)")->check(CLI::IsMember({"on", "off"}));
  run->add_option("--newton", a.newtonMode, "fixed-step Newton: full (factorizes every iteration, default) | modified (keeps the factorization while the iteration contracts fast)");
  run->add_option("--method", a.method, "sensitivities: dd (analytic, default) | ad (forward-mode automatic differentiation) | dq (IDAS difference quotients) | nd (finite differences of perturbed runs)");
  run->add_option("--nd-step", a.ndStep, "nd: relative parameter step (default 1e-6)");
  run->add_option("--nd-scheme", a.ndScheme, "nd: central (default) | forward");
  run->add_option("--case", a.request.cases, "PIM case to run (repeatable; default: every case of the scene)");
}

/// The options given on the command line, as overrides of the scene's settings.
RunOptions runOptions(const RunArgs& a) {
  RunOptions opt;
  const CLI::App& run = *a.command;
  if (!a.integrator.empty()) opt.integrator = a.integrator;
  if (run.count("--t-end")) opt.tEnd = a.tEnd;
  if (run.count("--dt")) opt.dt = a.dt;
  if (run.count("--rho-inf")) opt.rhoInf = a.rhoInf;
  if (run.count("--rtol")) opt.rtol = a.rtol;
  if (!a.newtonMode.empty()) opt.newton = a.newtonMode;
  if (!a.projections.empty()) opt.projections = a.projections == "on";
  if (!a.outDir.empty()) opt.outDir = a.outDir;
  if (!a.method.empty()) opt.method = a.method;
  if (run.count("--nd-step")) opt.ndStep = a.ndStep;
  if (!a.ndScheme.empty()) opt.ndScheme = a.ndScheme;
  return opt;
}

int executeRun(RunArgs& a) {
  a.request.options = runOptions(a);
  installInterruptHandlers();
  const RunCommandResult r = runCommand(a.request, [](const RunCase& c, const RunResult& res) {
    std::cout << "results written to " << res.directory << "/ (series.csv, "
              << (c.scene.output.vtk ? "frames.pvd + frame_*.vtu, " : "") << "summary.json)\n"
              << "  " << res.stats.steps << " steps, " << res.stats.newtonIterations << " Newton iterations, "
              << res.stats.factorizations << " factorizations, " << res.wallSeconds << " s wall, max |Phi| = "
              << res.stats.maxConstraintViolation << "\n";
    if (!res.suspect.empty()) std::cerr << "flexsens: SUSPECT result (summary.json status 'suspect'): " << res.suspect << "\n";
  });
  if (r.interruptedBy) {
    std::cerr << "flexsens: interrupted; " << r.cases.back().directory << " is complete, later cases were not run\n";
    return 128 + r.interruptedBy;
  }
  return r.status;
}

// ------------------------------------------------------------------ static
struct StaticArgs {
  CLI::App* command = nullptr;
  StaticRequest request;
  int loadSteps = 0;
};

void addStatic(CLI::App& app, StaticArgs& a) {
  auto* statik = a.command = app.add_subcommand("static", "load-stepped static equilibrium with exact static sensitivities (series.csv per load step, VTK, summary.json)");
  statik->add_option("scene", a.request.scenePath, "scene file (YAML)")->required();
  statik->add_option("--out", a.request.outDir, "output directory (default: <output.directory>-static)");
  statik->add_option("--load-steps", a.loadSteps, "equal load increments (default: the scene's static.load_steps, else 10)");
  statik->add_option("--method", a.request.method, "sensitivities: dd (analytic, default) | ad");
}

int executeStatic(StaticArgs& a) {
  if (a.command->count("--load-steps")) a.request.loadSteps = a.loadSteps;
  installInterruptHandlers();
  const StaticCommandResult s = staticCommand(a.request);
  if (s.interruptedBy) {
    std::cerr << "flexsens: interrupted after load factor " << s.interruptedAt << "; the converged load steps are in "
              << s.directory << "/, summary.json says interrupted\n";
    return 128 + s.interruptedBy;
  }
  const StaticResult& r = s.result;
  std::cout << "static equilibrium written to " << r.directory << "/ (series.csv, "
            << (s.vtk ? "frames.pvd + frame_*.vtu, " : "") << "summary.json)\n"
            << "  " << (r.linear ? std::string("linear (small-displacement) solution")
                                 : std::to_string(r.loadSteps) + " load steps, " + std::to_string(r.newtonIterations) +
                                       " Newton iterations")
            << ", |R|_inf = " << r.residualNorm << " N, |Phi|_inf = " << r.constraintNorm << "\n";
  return 0;
}

// ------------------------------------------------------------------ gradient
struct GradientArgs {
  CLI::App* command = nullptr;
  GradientRequest request;
  std::string integrator, newtonMode;
  double tEnd = 0, dt = 0, rhoInf = 0;
};

void addGradient(CLI::App& app, GradientArgs& a) {
  auto* g = a.command = app.add_subcommand("gradient", "values of the scene's objectives and their gradients dJ/dp (gradient.json), by the discrete adjoint or the forward sensitivities");
  g->add_option("scene", a.request.scenePath, "scene file (YAML)")->required();
  g->add_option("--objective", a.request.objective, "the objective (default: every objective of the scene)");
  g->add_option("--method", a.request.method, "adjoint (default: one backward sweep for all parameters) | forward (the forward sensitivities)");
  g->add_option("--out", a.request.outDir, "output directory (default: <output.directory>-gradient)");
  g->add_option("--case", a.request.caseName, "a PIM case of the scene (default: the plain model with every parameter, least-norm initial sensitivities)");
  g->add_flag("--static", a.request.statics, "the static equilibrium of flexsens static (its last load step; terminal objectives), by its exact static sensitivities");
  g->add_option("--checkpoint-every", a.request.checkpointEvery, "adjoint: keep every k-th state and recompute the rest (idas: a checkpoint every k IDAS steps; default: from the memory budget)")->check(CLI::Range(1L, 1000000000L));
  g->add_option("--integrator", a.integrator, "trapezoidal | bdf1 | generalized_alpha | midpoint | idas (continuous objectives and adjoint) (default: the scene's)");
  g->add_option("--t-end", a.tEnd, "final time [s]");
  g->add_option("--dt", a.dt, "fixed step [s]");
  g->add_option("--rho-inf", a.rhoInf, "generalized_alpha: spectral radius at infinity, 0..1");
  g->add_option("--newton", a.newtonMode, "fixed-step Newton: full | modified");
}

int executeGradient(GradientArgs& a) {
  RunOptions& opt = a.request.options;
  const CLI::App& g = *a.command;
  if (!a.integrator.empty()) opt.integrator = a.integrator;
  if (g.count("--t-end")) opt.tEnd = a.tEnd;
  if (g.count("--dt")) opt.dt = a.dt;
  if (g.count("--rho-inf")) opt.rhoInf = a.rhoInf;
  if (!a.newtonMode.empty()) opt.newton = a.newtonMode;
  installInterruptHandlers();
  const GradientResult r = gradientCommand(a.request);
  std::cout << "gradient written to " << r.directory << "/gradient.json" << (r.field ? " and gradient.vtu" : "") << " ("
            << r.objectives.size() << " objective"
            << (r.objectives.size() == 1 ? "" : "s") << ", " << r.parameters.size() << " parameters, method " << r.method
            << ")\n  " << (r.method == "static" ? r.stats.steps : r.steps) << (r.method == "static" ? " load steps, " : " steps, ")
            << r.wallSeconds << " s wall\n";
  for (const auto& o : r.objectives) std::cout << "  " << o.name << " = " << o.value << "\n";
  if (r.status != "complete") {
    std::cerr << "flexsens: SUSPECT result (gradient.json status 'suspect'): " << r.reason << "\n";
    return 5;
  }
  return 0;
}

// ------------------------------------------------------------------ optimize
struct OptimizeArgs {
  CLI::App* command = nullptr;
  OptimizeRequest request;
  bool noPlots = false;
};

void addOptimize(CLI::App& app, OptimizeArgs& a) {
  auto* o = a.command = app.add_subcommand("optimize", "minimize an objective over design parameters within bounds, "
                                                       "subject to objective bounds (the scene's optimize:), with NLopt");
  o->add_option("scene", a.request.scenePath, "scene file (YAML)")->required();
  o->add_option("--out", a.request.outDir, "output directory (default: <output.directory>-optimize)");
  o->add_flag("--no-plots", a.noPlots, "do not draw history.png");
}

int executeOptimize(OptimizeArgs& a) {
  a.request.plots = !a.noPlots;
  installInterruptHandlers();
  const OptimizeResult r = optimizeCommand(a.request);
  std::cout << "optimization written to " << r.directory << "/ (history.csv, optimize.json, optimum.csv"
            << (r.best >= 0 ? ", optimized.yaml" : "") << ")\n  status " << r.status << " (NLopt " << r.nloptResult
            << "), " << r.history.size() << " evaluations, " << r.wallSeconds << " s wall\n";
  if (!r.history.empty() && r.history.front().ok)
    std::cout << "  " << r.objective << ": " << r.history.front().objective << " at the start";
  if (r.best >= 0) std::cout << ", " << r.history[size_t(r.best)].objective << " at evaluation " << r.history[size_t(r.best)].index;
  std::cout << "\n";
  if (r.best >= 0) std::cout << "  KKT residual at the best point " << r.kktResidual << " (0 at a stationary point)\n";
  if (!r.plotNote.empty()) std::cerr << "flexsens: note: history.png not drawn: " << r.plotNote << "\n";
  if (r.failed >= 0) {
    const OptimizeEvaluation& e = r.history[size_t(r.failed)];
    std::cerr << "flexsens: evaluation " << e.index << " failed at";
    for (size_t i = 0; i < r.variables.size() && i < 20; ++i) std::cerr << " " << r.variables[i] << " = " << e.x[Eigen::Index(i)];
    std::cerr << (r.variables.size() > 20 ? " ... (optimize.json)" : "") << ": " << e.message
              << "\nflexsens: the optimizer stopped; the best point so far is written (optimize.json status 'failed')\n";
  }
  if (r.interruptedBy) std::cerr << "flexsens: interrupted; the best point so far is written (optimize.json status 'interrupted')\n";
  if (r.status == "stalled")
    std::cerr << "flexsens: NLopt stopped (" << r.nloptResult << ") where the gradient is not stationary (KKT residual "
              << r.kktResidual << " > 0.1): try algorithm slsqp, a feasible start or other bounds\n";
  if (r.status == "max_evaluations" || r.status == "roundoff_limited" || r.status == "infeasible")
    std::cerr << "flexsens: not converged: status " << r.status << " (optimize.json)\n";
  if (r.status == "suspect")
    std::cerr << "flexsens: SUSPECT optimum (optimize.json status 'suspect'): " << r.history[size_t(r.best)].message << "\n";
  return r.exitCode();
}

// ------------------------------------------------------------------ modes, check, study
struct ModesArgs {
  CLI::App* command = nullptr;
  ModesRequest request;
  bool asJson = false;
};

void addModes(CLI::App& app, ModesArgs& a) {
  auto* modes = a.command = app.add_subcommand("modes", "natural frequencies of the constrained model linearized at its initial state, time-step limits and the parts that set them");
  modes->add_option("scene", a.request.scenePath, "scene file (YAML)")->required();
  modes->add_option("--count", a.request.count, "modes listed at each end of the spectrum (default 5)")->check(CLI::Range(1, 1000));
  modes->add_flag("--json", a.asJson, "print JSON instead of the text report");
}

int executeModes(const ModesArgs& a) {
  const ModesCommandResult r = modesCommand(a.request);
  std::cout << (a.asJson ? modesJson(r.analysis, a.request.count)
                         : a.request.scenePath + ": " + modesReport(r.analysis, a.request.count));
  return 0;
}

struct CheckArgs {
  CLI::App* command = nullptr;
  std::string scenePath;
};

void addCheck(CLI::App& app, CheckArgs& a) {
  a.command = app.add_subcommand("check", "validate a scene and print its sizes");
  a.command->add_option("scene", a.scenePath, "scene file (YAML)")->required();
}

int executeCheck(const CheckArgs& a) {
  std::cout << checkReport(checkCommand(a.scenePath));
  return 0;
}

struct StudyArgs {
  CLI::App* command = nullptr;
  StudyOptions options;
};

void addStudy(CLI::App& app, StudyArgs& a) {
  a.command = app.add_subcommand("study", "speed-versus-accuracy study of the sensitivity methods and integrators (markdown report + CSV)");
  a.command->add_option("--out", a.options.outDir, "report directory (default bench/study)");
  a.command->add_option("--source", a.options.sourceDir, "repository root holding examples/ (default .)");
  a.command->add_flag("--quick", a.options.quick, "shortened sweeps (smoke test)");
}

int executeStudy(const StudyArgs& a) {
  const std::string report = studyCommand(a.options);  // first: a failed study prints no "written"
  if (!report.empty()) std::cout << "study report written to " << report << "\n";  // "": not rank 0
  return 0;
}

// ------------------------------------------------------------------ shared options
/// Reach and size of what a scene may make flexsens read or allocate (scene/InputFiles.hpp,
/// core/MemoryBudget.hpp), the same on every command that reads a scene.
struct InputLimits {
  std::vector<std::string> allowPaths;
  double maxMemoryGiB = 0;
};

void addInputLimits(const std::vector<CLI::App*>& commands, InputLimits& a) {
  for (CLI::App* sub : commands) {
    sub->add_option("--allow-path", a.allowPaths, "a folder (and below) whose files the scene may name besides its own "
                                                  "folder: meshes, geometry, tables (repeatable)");
    sub->add_option("--max-memory", a.maxMemoryGiB, "memory budget [GiB] for one large structure (dense matrices of "
                                                    "modes and of PIM cases with massless coordinates, geometry "
                                                    "nodes); default 4")
        ->check(CLI::Range(0.001, 1.0e6));
  }
}

void applyInputLimits(const InputLimits& a) {
  for (const auto& dir : a.allowPaths) allowInputDirectory(dir);
  if (a.maxMemoryGiB > 0) setMemoryBudget(a.maxMemoryGiB * (1ull << 30));
}

/// The exit code of an exception escaping a command, with its message on stderr.
int reportFailure() {
  try {
    throw;
  } catch (const InputError& e) {
    std::cerr << "flexsens: error: " << e.what() << "\n";
    return 1;
  } catch (const Interrupted& e) {
    std::cerr << "flexsens: " << e.what() << "; results up to it written, summary.json says interrupted\n";
    return 128 + e.signal;
  } catch (const InterruptedBeforeRun& e) {
    std::cerr << "flexsens: " << e.what() << "\n";
    return 128 + e.signal;
  } catch (const OutputError& e) {
    std::cerr << "flexsens: output error: " << e.what() << "\n";
    return 4;
  } catch (const DirectoryBusy& e) {
    std::cerr << "flexsens: error: " << e.what() << "\n";
    return 6;
  } catch (const NumericalError& e) {
    std::cerr << "flexsens: numerical failure: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "flexsens: error: " << e.what() << "\n";
    return 3;
  }
}

}  // namespace

int main(int argc, char** argv) {
  keepFreedMemory();  // VTK frames: output/ResultWriter.hpp
  CLI::App app{"flexsens: flexible multibody dynamics with design sensitivities"};
  app.require_subcommand(1);
  RunArgs run;
  StaticArgs statik;
  CheckArgs check;
  ModesArgs modes;
  StudyArgs study;
  SweepArgs sweep;
  GradientArgs gradient;
  OptimizeArgs optimize;
  addRun(app, run);
  addStatic(app, statik);
  addCheck(app, check);
  addModes(app, modes);
  InputLimits limits;
  addStudy(app, study);
  addSweep(app, sweep);
  addGradient(app, gradient);
  addOptimize(app, optimize);
  addInputLimits({run.command, statik.command, check.command, modes.command, sweep.command, gradient.command,
                  optimize.command},
                 limits);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;  // --help is success; any bad option is input error 1
  }
  try {
    applyInputLimits(limits);
    if (*study.command) return executeStudy(study);
    if (*sweep.command) return executeSweep(sweep);
    if (*statik.command) return executeStatic(statik);
    if (*modes.command) return executeModes(modes);
    if (*check.command) return executeCheck(check);
    if (*gradient.command) return executeGradient(gradient);
    if (*optimize.command) return executeOptimize(optimize);
    return executeRun(run);
  } catch (...) {
    return reportFailure();
  }
}
