#include "app/StaticRun.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>

#include <cerrno>
#include <cstring>

#include "core/Interrupt.hpp"
#include "integrators/Static.hpp"
#include "output/RunDirectory.hpp"
#include "output/ResultWriter.hpp"

namespace flexsens {

namespace {

void writeStaticSummary(const std::string& path, const std::string& shownPath, const Scene& sc,
                        const StaticResult& r, const std::string& status, const std::string& error,
                        const ResultWriter& w) {
  const Model& m = *sc.model;
  errno = 0;
  std::ofstream js(path);
  js << "{\n  \"status\": " << jsonString(status) << ",\n";
  if (!error.empty()) js << "  \"error\": " << jsonString(error) << ",\n";
  js << "  \"analysis\": \"static\",\n  \"scene\": " << jsonString(sc.file) << ",\n";
  js << "  \"n\": " << m.n << ", \"m\": " << m.m << ",\n  \"parameters\": [";
  for (size_t k = 0; k < m.parameters.size(); ++k)
    js << (k ? ", " : "") << "{\"name\": " << jsonString(m.parameters[k].name) << ", \"bound_to\": "
       << jsonString(m.parameters[k].boundTo) << ", \"nominal\": " << jsonNumber(m.parameters[k].nominal) << "}";
  js << "],\n  \"statistics\": {\"load_steps\": " << r.loadSteps << ", \"newton_iterations\": " << r.newtonIterations
     << ", \"residual_inf_N\": " << jsonNumber(r.residualNorm) << ", \"constraint_inf\": " << jsonNumber(r.constraintNorm)
     << "},\n  \"final\": {";
  for (size_t i = 0; i < w.columns().size() && i < w.lastRow().size(); ++i)
    js << (i ? ", " : "") << jsonString(w.columns()[i]) << ": " << jsonNumber(w.lastRow()[i]);
  js << "},\n  \"wall_time_s\": " << jsonNumber(r.wallSeconds) << ",\n  \"files\": [";
  for (size_t i = 0; i < w.files().size(); ++i)
    js << (i ? ", " : "") << jsonString(std::filesystem::path(w.files()[i]).filename().string());
  js << "]\n}\n";
  js.close();
  if (!js) throw OutputError("cannot write " + shownPath + ": " + std::strerror(errno ? errno : EIO));
}

}  // namespace

StaticResult runStaticScene(const Scene& sc, const std::string& outDir, int loadSteps) {
  const auto t0 = std::chrono::steady_clock::now();
  const Model& m = *sc.model;
  Assembler as(m, sc.sensitivity.method == "ad" ? Derivatives::AutomaticDifferentiation : Derivatives::Analytic);
  const VecX p = m.nominalParameters();
  StaticResult res;
  res.directory = outDir;  // as the user named it
  // Locked, staged and moved into place whole, like `run` (output/RunDirectory.hpp).
  RunDirectory dir(outDir, "static");
  ResultWriter writer(sc, dir.staging(), "", dir.final(), "load_factor");
  auto finish = [&](const std::string& status, const std::string& error) {
    writer.close();
    writeStaticSummary(dir.staging() + "/summary.json", dir.final() + "/summary.json", sc, res, status, error, writer);
    dir.commit();
  };
  StaticSettings set;
  set.steps = loadSteps;
  set.stepLoadFactor = true;
  set.maxIterations = sc.integrator.maxNewtonIterations;
  // Each converged load step is a frame (t = load factor) with its exact sensitivities.
  set.onStep = [&](int, double lf, const VecX& q, const VecX& lambda) {
    StateWithSens s;
    s.x.t = lf;
    s.x.q = q;
    s.x.v = VecX::Zero(m.n);
    s.x.lambda = lambda;
    if (!p.size()) return writer.frame(s);
    const StaticSensitivity d = staticSensitivities(as, q, lambda, p);
    for (int k = 0; k < p.size(); ++k) {
      State dk;
      dk.q = d.qp.col(k);
      dk.v = VecX::Zero(m.n);
      s.dp.push_back(dk);
    }
    writer.frame(s);
    // SIGINT/SIGTERM: stop after this converged load step, as `run` stops after a step.
    if (const int sig = interruptSignal()) throw Interrupted(sig, lf);
  };
  StaticReport rep;
  try {
    solveStatic(as, p, m.initialPositions(), set, &rep);
  } catch (const OutputError&) {
    throw;  // the staging directory goes; earlier results stay as they were
  } catch (const Interrupted& e) {
    res.loadSteps = static_cast<int>(writer.frames());
    finish("interrupted", "interrupted by signal " + std::to_string(e.signal) + " after load factor " +
                              std::to_string(e.t) + " (the last row and frame)");
    throw;
  } catch (const std::exception& e) {
    res.loadSteps = static_cast<int>(writer.frames());
    finish("failed", e.what());
    throw;
  }
  res.loadSteps = rep.steps;
  res.newtonIterations = rep.iterations;
  res.residualNorm = rep.residualNorm;
  res.constraintNorm = rep.constraintNorm;
  res.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  finish("complete", "");
  return res;
}

}  // namespace flexsens
