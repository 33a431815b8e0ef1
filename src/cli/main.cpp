// flexsens command line: `flexsens run SCENE [...]`, `flexsens static SCENE`, `flexsens check SCENE`,
// `flexsens modes SCENE`. Exit codes: 0 success, 1 bad input (scene or options), 2 numerical
// failure, 3 other error, 4 results could not be written or the output folder was refused
// (it holds files flexsens did not write; nothing touched), 5 run completed but suspect
// (energy audit), 6 the output folder is in use by another run of any kind (run, cases,
// static, study), 128 + signal (130 SIGINT, 143 SIGTERM) interrupted, results up to the time
// reached.
#include <CLI/CLI.hpp>
#include <malloc.h>

#include <iostream>

#include "app/Modes.hpp"
#include "app/Run.hpp"
#include "app/StaticRun.hpp"
#include "app/Study.hpp"
#include "core/Interrupt.hpp"
#include "core/MemoryBudget.hpp"
#include "core/RedundantRows.hpp"
#include "core/Types.hpp"
#include "integrators/InitialState.hpp"
#include "output/RunDirectory.hpp"
#include "scene/InputFiles.hpp"

using namespace flexsens;

namespace {

/// Runs the scene (or each of its PIM cases, into <folder>/<case>/) with the output folder
/// locked once for all of them. Returns the exit status: 0, or 5 when a result is suspect,
/// or 128 + signal when a signal arrived after a case's last step.
int runScenes(const std::string& scenePath, const std::vector<Scene>& scenes, const std::vector<std::string>& cases) {
  RunDirectory out(scenes.front().output.directory, cases.front().empty() ? "run" : "cases");
  int status = 0;
  for (size_t i = 0; i < scenes.size(); ++i) {
    const Scene& sc = scenes[i];
    std::cerr << "flexsens: running " << scenePath << (cases[i].empty() ? "" : " case " + cases[i]) << " with "
              << sc.integrator.type << " to t = " << sc.integrator.tEnd << " s\n";
    const RunResult r = runScene(sc, out, cases[i]);
    std::cout << "results written to " << r.directory << "/ (series.csv, "
              << (sc.output.vtk ? "frames.pvd + frame_*.vtu, " : "") << "summary.json)\n"
              << "  " << r.stats.steps << " steps, " << r.stats.newtonIterations << " Newton iterations, "
              << r.stats.factorizations << " factorizations, " << r.wallSeconds << " s wall, max |Phi| = "
              << r.stats.maxConstraintViolation << "\n";
    if (!r.suspect.empty()) {
      std::cerr << "flexsens: SUSPECT result (summary.json status 'suspect'): " << r.suspect << "\n";
      status = 5;
    }
    if (const int sig = interruptSignal()) {  // arrived after the last step: later cases do not start
      std::cerr << "flexsens: interrupted; " << r.directory << " is complete, later cases were not run\n";
      return 128 + sig;
    }
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  // VTK's XML writer allocates and frees large buffers for every frame; glibc would return
  // them to the kernel each time (brk shrink + TLB flush), which cost 80% of a 500-frame run
  // of a small model. Keep freed memory in the process instead.
  mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);
  mallopt(M_MMAP_THRESHOLD, 64 * 1024 * 1024);
  CLI::App app{"flexsens: flexible multibody dynamics with design sensitivities"};
  app.require_subcommand(1);

  std::string scenePath;
  RunOptions opt;
  std::string integrator, outDir;
  double tEnd = 0, dt = 0;
  auto* run = app.add_subcommand("run", "simulate a scene and write series.csv, VTK frames and summary.json");
  run->add_option("scene", scenePath, "scene file (YAML)")->required();
  run->add_option("--out", outDir, "output directory (default: the scene's output.directory)");
  run->add_option("--integrator", integrator, "idas | trapezoidal | midpoint | bdf1 | generalized_alpha | maggi_rk4 (default: the scene's)");
  run->add_option("--t-end", tEnd, "final time [s]");
  run->add_option("--dt", dt, "fixed step [s] (IDAS: largest step)");
  double rhoInf = 0, rtol = 0;
  run->add_option("--rho-inf", rhoInf, "generalized_alpha: spectral radius at infinity, 0..1 (default 0.9; 1 = no dissipation)");
  run->add_option("--rtol", rtol, "IDAS relative tolerance");
  std::string newtonMode, projections;
  run->add_option("--projections", projections, "trapezoidal / generalized_alpha: on projects each step's velocities and accelerations onto the constraints (default off)")->check(CLI::IsMember({"on", "off"}));
  run->add_option("--newton", newtonMode, "fixed-step Newton: full (factorizes every iteration, default) | modified (keeps the factorization while the iteration contracts fast)");
  std::string method, ndScheme;
  double ndStep = 0;
  run->add_option("--method", method, "sensitivities: dd (analytic, default) | ad (forward-mode automatic differentiation) | dq (IDAS difference quotients) | nd (finite differences of perturbed runs)");
  run->add_option("--nd-step", ndStep, "nd: relative parameter step (default 1e-6)");
  run->add_option("--nd-scheme", ndScheme, "nd: central (default) | forward");
  std::vector<std::string> cases;
  run->add_option("--case", cases, "PIM case to run (repeatable; default: every case of the scene)");

  std::string staticPath, staticOut, staticMethod;
  int loadSteps = 0;
  auto* statik = app.add_subcommand("static", "load-stepped static equilibrium with exact static sensitivities (series.csv per load step, VTK, summary.json)");
  statik->add_option("scene", staticPath, "scene file (YAML)")->required();
  statik->add_option("--out", staticOut, "output directory (default: <output.directory>-static)");
  statik->add_option("--load-steps", loadSteps, "equal load increments (default: the scene's static.load_steps, else 10)");
  statik->add_option("--method", staticMethod, "sensitivities: dd (analytic, default) | ad");

  std::string checkPath;
  auto* check = app.add_subcommand("check", "validate a scene and print its sizes");
  check->add_option("scene", checkPath, "scene file (YAML)")->required();

  std::string modesPath;
  int modesCount = 5;
  bool modesAsJson = false;
  auto* modes = app.add_subcommand("modes", "natural frequencies of the constrained model linearized at its initial state, time-step limits and the parts that set them");
  modes->add_option("scene", modesPath, "scene file (YAML)")->required();
  modes->add_option("--count", modesCount, "modes listed at each end of the spectrum (default 5)")->check(CLI::Range(1, 1000));
  modes->add_flag("--json", modesAsJson, "print JSON instead of the text report");

  // Reach and size of what a scene may make flexsens read or allocate (scene/InputFiles.hpp,
  // core/MemoryBudget.hpp), the same on every command that reads a scene.
  std::vector<std::string> allowPaths;
  double maxMemoryGiB = 0;
  for (CLI::App* sub : {run, statik, check, modes}) {
    sub->add_option("--allow-path", allowPaths, "a folder (and below) whose files the scene may name besides its own "
                                                "folder: meshes, geometry, tables (repeatable)");
    sub->add_option("--max-memory", maxMemoryGiB, "memory budget [GiB] for one large structure (dense matrices of "
                                                  "modes and PIM cases, geometry nodes); default 4")
        ->check(CLI::Range(0.001, 1.0e6));
  }

  StudyOptions study;
  auto* studyCmd = app.add_subcommand("study", "speed-versus-accuracy study of the sensitivity methods and integrators (markdown report + CSV)");
  studyCmd->add_option("--out", study.outDir, "report directory (default bench/study)");
  studyCmd->add_option("--source", study.sourceDir, "repository root holding examples/ (default .)");
  studyCmd->add_flag("--quick", study.quick, "shortened sweeps (smoke test)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;  // --help is success; any bad option is input error 1
  }
  try {
    for (const auto& dir : allowPaths) allowInputDirectory(dir);
    if (maxMemoryGiB > 0) setMemoryBudget(maxMemoryGiB * (1ull << 30));
    if (*studyCmd) {
      const std::string report = runStudy(study);  // first: a failed study prints no "written"
      std::cout << "study report written to " << report << "\n";
      return 0;
    }
    if (*statik) {
      Scene sc = readScene(staticPath);
      if (statik->count("--load-steps")) {
        if (loadSteps < 1 || loadSteps > 100000) throw InputError("option --load-steps: expected 1 to 100000");
        sc.statics.loadSteps = loadSteps;
      }
      if (!staticMethod.empty()) {
        if (staticMethod != "dd" && staticMethod != "ad")
          throw InputError("option --method: static sensitivities are dd or ad, got '" + staticMethod + "'");
        sc.sensitivity.method = staticMethod;
      }
      // Beside the run's directory, not inside it: a rerun replaces its directory whole.
      const std::string dir = staticOut.empty() ? sc.output.directory + "-static" : staticOut;
      installInterruptHandlers();
      StaticResult r;
      try {
        r = runStaticScene(sc, dir, sc.statics.loadSteps);
      } catch (const Interrupted& e) {
        std::cerr << "flexsens: interrupted after load factor " << e.t << "; the converged load steps are in " << dir
                  << "/, summary.json says interrupted\n";
        return 128 + e.signal;
      }
      std::cout << "static equilibrium written to " << r.directory << "/ (series.csv, "
                << (sc.output.vtk ? "frames.pvd + frame_*.vtu, " : "") << "summary.json)\n"
                << "  " << r.loadSteps << " load steps, " << r.newtonIterations << " Newton iterations, |R|_inf = "
                << r.residualNorm << " N, |Phi|_inf = " << r.constraintNorm << "\n";
      return 0;
    }
    if (*modes) {
      // Exit 2 (numerical) when Phi_q is rank deficient at the initial positions: like `run`,
      // the scene reads fine and the defect is one of the configuration, not of a file line.
      Scene sc = readScene(modesPath);
      sc.requireDynamics();
      requireModesMemory(sc.model->n);
      Assembler as(*sc.model);
      const VecX p = sc.model->nominalParameters();
      if (!sc.model->redundantRows.empty()) {  // left out by the reader; the modes are those of the rest
        std::cerr << "flexsens: note: constraint rows dependent on the others at the initial positions, left out:";
        for (const auto& l : sc.model->redundantRows) std::cerr << " " << l;
        std::cerr << "\n";
      }
      requireIndependentConstraints(as, projectPositions(as, sc.model->initialPositions(), p), p);
      const ModalAnalysis a = analyzeModes(as, consistentState(as, p), p, modesCount);
      std::cout << (modesAsJson ? modesJson(a, modesCount) : modesPath + ": " + modesReport(a, modesCount));
      return 0;
    }
    if (*check) {
      Scene sc = readScene(checkPath);
      sc.requireDynamics();
      const Model& m = *sc.model;
      std::cout << checkPath << ": valid\n"
                << "  dimension " << m.dim << ", n = " << m.n << " coordinates, m = " << m.m
                << " constraint equations, d = " << m.n - m.m << " degrees of freedom\n"
                << "  " << m.elements.size() << " elements, " << m.constraints.size()
                << " constraints, " << m.parameters.size() << " parameters, "
                << sc.outputs.size() << " outputs\n";
      {
        // The reader left dependent rows out already (core/RedundantRows.hpp); confirm the rest.
        const DependentRows red = dependentRows(m, m.initialPositions(), m.nominalParameters());
        if (!red.rows.empty())  // cannot happen after leaveOutRedundantRows; say so if it does
          std::cout << "  constraints still dependent after the elimination: rank " << red.rank << " of " << m.m << "\n";
        else if (m.redundantRows.empty())
          std::cout << "  constraints independent at the initial positions (rank Phi_q = " << m.m << ")\n";
        else {
          std::cout << "  REDUNDANT constraints: rank Phi_q = " << m.m << " of " << m.m + m.redundantRows.size()
                    << " rows, so the mechanism has " << m.n - m.m << " degrees of freedom. Dependent rows, left out "
                       "of the dynamics (run checks that they stay satisfied; remove them from the scene, or "
                       "replace joints by ones that constrain less, e.g. a spherical for a revolute in a planar loop):";
          for (const auto& l : m.redundantRows) std::cout << " " << l;
          std::cout << "\n";
        }
      }
      for (const auto& name : sc.caseNames) {
        // The PIM's own count: m_r = independent rigidization equations (rank-revealing).
        Scene cs = readScene(checkPath, name);
        const Model& cm = *cs.model;
        Assembler as(cm);
        const VecX p = cm.nominalParameters();
        PimReport rep;
        initialState(as, p, cs.pimCase.get(), &rep);
        std::cout << "  case " << name << ": n = " << cm.n << ", m = " << cm.m << ", d = " << cm.n - cm.m
                  << ", m_r = " << rep.mr << " (" << rep.lambdaGenerated << " generated, " << rep.lambdaDropped
                  << " implied by the constraints), ";
        if (rep.massless)
          std::cout << "e = " << rep.me << " equilibrium rows of " << rep.massless << " massless coordinates, ";
        std::cout << "d_s = " << rep.ds << " SDOFs, cond(A) = " << rep.condition << "\n";
      }
      return 0;
    }
    if (!integrator.empty()) opt.integrator = integrator;
    if (run->count("--t-end")) opt.tEnd = tEnd;
    if (run->count("--dt")) opt.dt = dt;
    if (run->count("--rho-inf")) opt.rhoInf = rhoInf;
    if (run->count("--rtol")) opt.rtol = rtol;
    if (!newtonMode.empty()) opt.newton = newtonMode;
    if (!projections.empty()) opt.projections = projections == "on";
    if (!outDir.empty()) opt.outDir = outDir;
    if (!method.empty()) opt.method = method;
    if (run->count("--nd-step")) opt.ndStep = ndStep;
    if (!ndScheme.empty()) opt.ndScheme = ndScheme;
    installInterruptHandlers();
    Scene base = readScene(scenePath);
    base.requireDynamics();
    if (cases.empty()) cases = base.caseNames;
    if (cases.empty()) cases.push_back("");
    // Validate every requested case (and the options) before anything is written.
    std::vector<Scene> scenes;
    if (!base.hasIntegrator)
      throw InputError(scenePath + ":1:1: key 'integrator': the scene has no integrator (a static scene: "
                       "use `flexsens static`, or add an integrator to run it)");
    for (const auto& c : cases) {
      scenes.push_back(c.empty() ? std::move(base) : readScene(scenePath, c));
      applyOptions(scenes.back(), opt);
    }
    return runScenes(scenePath, scenes, cases);
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
