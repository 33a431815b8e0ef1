// flexsens command line: `flexsens run SCENE [...]` and `flexsens check SCENE`.
// Exit codes: 0 success, 1 bad input (scene or options), 2 numerical failure, 3 other error,
// 4 results could not be written, 6 the output directory is in use by another run (5 is
// taken on main by the energy audit's "suspect"),
// 128 + signal (130 SIGINT, 143 SIGTERM) interrupted, results up to the time reached.
#include <CLI/CLI.hpp>
#include <malloc.h>

#include <iostream>

#include "app/Run.hpp"
#include "app/Study.hpp"
#include "core/Interrupt.hpp"
#include "core/Types.hpp"

using namespace flexsens;

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
  run->add_option("--integrator", integrator, "idas | trapezoidal | bdf1 | generalized_alpha | maggi_rk4 (default: the scene's)");
  run->add_option("--t-end", tEnd, "final time [s]");
  run->add_option("--dt", dt, "fixed step [s] (IDAS: largest step)");
  double rhoInf = 0, rtol = 0;
  run->add_option("--rho-inf", rhoInf, "generalized_alpha: spectral radius at infinity, 0..1 (default 0.9; 1 = no dissipation)");
  run->add_option("--rtol", rtol, "IDAS relative tolerance");
  std::string method, ndScheme;
  double ndStep = 0;
  run->add_option("--method", method, "sensitivities: dd (analytic, default) | ad (forward-mode automatic differentiation) | dq (IDAS difference quotients) | nd (finite differences of perturbed runs)");
  run->add_option("--nd-step", ndStep, "nd: relative parameter step (default 1e-6)");
  run->add_option("--nd-scheme", ndScheme, "nd: central (default) | forward");
  std::vector<std::string> cases;
  run->add_option("--case", cases, "PIM case to run (repeatable; default: every case of the scene)");

  std::string checkPath;
  auto* check = app.add_subcommand("check", "validate a scene and print its sizes");
  check->add_option("scene", checkPath, "scene file (YAML)")->required();

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
    if (*studyCmd) {
      std::cout << "study report written to " << runStudy(study) << "\n";
      return 0;
    }
    if (*check) {
      Scene sc = readScene(checkPath);
      const Model& m = *sc.model;
      std::cout << checkPath << ": valid\n"
                << "  dimension " << m.dim << ", n = " << m.n << " coordinates, m = " << m.m
                << " constraint equations, d = " << m.n - m.m << " degrees of freedom\n"
                << "  " << m.elements.size() << " elements, " << m.constraints.size()
                << " constraints, " << m.parameters.size() << " parameters, "
                << sc.outputs.size() << " outputs\n";
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
                  << " implied by the constraints), d_s = " << rep.ds << " SDOFs, cond(A) = " << rep.condition << "\n";
      }
      return 0;
    }
    if (!integrator.empty()) opt.integrator = integrator;
    if (run->count("--t-end")) opt.tEnd = tEnd;
    if (run->count("--dt")) opt.dt = dt;
    if (run->count("--rho-inf")) opt.rhoInf = rhoInf;
    if (run->count("--rtol")) opt.rtol = rtol;
    if (!outDir.empty()) opt.outDir = outDir;
    if (!method.empty()) opt.method = method;
    if (run->count("--nd-step")) opt.ndStep = ndStep;
    if (!ndScheme.empty()) opt.ndScheme = ndScheme;
    installInterruptHandlers();
    Scene base = readScene(scenePath);
    if (cases.empty()) cases = base.caseNames;
    if (cases.empty()) cases.push_back("");
    // Validate every requested case (and the options) before anything is written.
    std::vector<Scene> scenes;
    for (const auto& c : cases) {
      scenes.push_back(c.empty() ? std::move(base) : readScene(scenePath, c));
      applyOptions(scenes.back(), opt);
    }
    for (size_t i = 0; i < scenes.size(); ++i) {
      const Scene& sc = scenes[i];
      const std::string dir = sc.output.directory + (cases[i].empty() ? "" : "/" + cases[i]);
      std::cerr << "flexsens: running " << scenePath << (cases[i].empty() ? "" : " case " + cases[i])
                << " with " << sc.integrator.type << " to t = " << sc.integrator.tEnd << " s\n";
      const RunResult r = runScene(sc, dir);
      std::cout << "results written to " << r.directory << "/ (series.csv, "
                << (sc.output.vtk ? "frames.pvd + frame_*.vtu, " : "") << "summary.json)\n"
                << "  " << r.stats.steps << " steps, " << r.stats.newtonIterations << " Newton iterations, "
                << r.stats.factorizations << " factorizations, " << r.wallSeconds << " s wall, max |Phi| = "
                << r.stats.maxConstraintViolation << "\n";
      if (const int sig = interruptSignal()) {  // arrived after the last step: later cases do not start
        std::cerr << "flexsens: interrupted; " << r.directory << " is complete, later cases were not run\n";
        return 128 + sig;
      }
    }
    return 0;
  } catch (const InputError& e) {
    std::cerr << "flexsens: error: " << e.what() << "\n";
    return 1;
  } catch (const Interrupted& e) {
    std::cerr << "flexsens: " << e.what() << "; results up to it written, summary.json says interrupted\n";
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
