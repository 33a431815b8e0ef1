#include "app/StaticRun.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <cerrno>
#include <cstring>

#include "core/Interrupt.hpp"
#include "integrators/Static.hpp"
#include "output/RunDirectory.hpp"
#include "output/ResultWriter.hpp"

namespace flexsens {

namespace {

std::string staticSummaryJson(const Scene& sc, const StaticResult& r, const std::string& status,
                              const std::string& error, const ResultWriter& w) {
  const Model& m = *sc.model;
  std::ostringstream js;
  js << "{\n  \"status\": " << jsonString(status) << ",\n";
  if (!error.empty()) js << "  \"error\": " << jsonString(error) << ",\n";
  js << "  \"analysis\": \"static\",\n  \"linear\": " << (sc.statics.linear ? "true" : "false")
     << ",\n  \"scene\": " << jsonString(sc.file) << ",\n";
  js << "  \"n\": " << m.n << ", \"m\": " << m.m << ",\n  \"parameters\": [";
  for (size_t k = 0; k < m.parameters.size(); ++k)
    js << (k ? ", " : "") << "{\"name\": " << jsonString(m.parameters[k].name) << ", \"bound_to\": "
       << jsonString(m.parameters[k].boundTo) << ", \"nominal\": " << jsonNumber(m.parameters[k].nominal) << "}";
  FactorizationCounters all = r.newtonFactor;
  all.add(r.sensitivityFactor);
  js << "],\n  \"statistics\": {\"load_steps\": " << r.loadSteps << ", \"newton_iterations\": " << r.newtonIterations
     << ", \"residual_inf_N\": " << jsonNumber(r.residualNorm) << ", \"constraint_inf\": " << jsonNumber(r.constraintNorm)
     << ", \"factorizations\": " << all.factorizations << ", \"sensitivity_factorizations\": "
     << r.sensitivityFactor.factorizations << ", \"lu_fill\": " << jsonNumber(all.maxFill)
     << ", \"factorization_seconds\": " << jsonNumber(all.seconds) << "},\n  \"final\": {";
  for (size_t i = 0; i < w.columns().size() && i < w.lastRow().size(); ++i)
    js << (i ? ", " : "") << jsonString(w.columns()[i]) << ": " << jsonNumber(w.lastRow()[i]);
  js << "},\n  \"wall_time_s\": " << jsonNumber(r.wallSeconds) << ",\n  \"files\": [";
  for (size_t i = 0; i < w.files().size(); ++i)
    js << (i ? ", " : "") << jsonString(std::filesystem::path(w.files()[i]).filename().string());
  js << "]\n}\n";
  return js.str();
}

void writeStaticSummary(const std::string& path, const std::string& shownPath, const std::string& text) {
  errno = 0;
  std::ofstream js(path);
  js << text;
  js.close();
  if (!js) throw OutputError("cannot write " + shownPath + ": " + std::strerror(errno ? errno : EIO));
}

/// Hands each load step's series row to the listener after the writer computed it.
struct StaticFrames {
  ResultWriter& writer;
  RunListener* listener;
  void frame(const StateWithSens& s) {
    writer.frame(s);
    if (listener) listener->frame(s, writer.lastRow());
  }
};

}  // namespace

StaticResult runStaticScene(const Scene& sc, const std::string& outDir, int loadSteps, RunListener* listener) {
  const auto t0 = std::chrono::steady_clock::now();
  const Model& m = *sc.model;
  Assembler as(m, sc.sensitivity.method == "ad" ? Derivatives::AutomaticDifferentiation : Derivatives::Analytic);
  const VecX p = m.nominalParameters();
  StaticResult res;
  res.directory = outDir;  // as the user named it
  // Locked, staged and moved into place whole, like `run` (output/RunDirectory.hpp).
  std::optional<RunDirectory> dir;
  if (!outDir.empty()) dir.emplace(outDir, "static");
  ResultWriter writer(sc, dir ? dir->staging() : "", "", dir ? dir->final() : "", "load_factor");
  StaticFrames frames{writer, listener};
  if (listener) listener->started(writer.columns());
  auto finish = [&](const std::string& status, const std::string& error) {
    writer.close();
    const std::string summary = staticSummaryJson(sc, res, status, error, writer);
    if (dir) writeStaticSummary(dir->staging() + "/summary.json", dir->final() + "/summary.json", summary);
    if (dir) dir->commit();
    if (listener) listener->finished(summary);
  };
  StaticSettings set;
  set.steps = loadSteps;
  set.stepLoadFactor = true;
  set.maxIterations = sc.integrator.maxNewtonIterations;
  set.tol = sc.integrator.newtonTol;
  // Each converged load step is a frame (t = load factor) with its exact sensitivities.
  auto frame = [&](double lf, const VecX& q, const VecX& lambda, const StaticSensitivity* d) {
    StateWithSens s;
    s.x.t = lf;
    s.x.q = q;
    s.x.v = VecX::Zero(m.n);
    s.x.lambda = lambda;
    for (int k = 0; d && k < p.size(); ++k) {
      State dk;
      dk.q = d->qp.col(k);
      dk.v = VecX::Zero(m.n);
      s.dp.push_back(dk);
    }
    frames.frame(s);
    if (listener) listener->progress(lf, 1.0);
  };
  set.onStep = [&](int, double lf, const VecX& q, const VecX& lambda) {
    if (p.size()) {
      const StaticSensitivity d = staticSensitivities(as, q, lambda, p);
      res.sensitivityFactor.add(d.factor);
      frame(lf, q, lambda, &d);
    } else {
      frame(lf, q, lambda, nullptr);
    }
    // SIGINT/SIGTERM: stop after this converged load step, as `run` stops after a step.
    if (const int sig = interruptSignal()) throw Interrupted(sig, lf);
  };
  StaticReport rep;
  try {
    if (sc.statics.linear) {
      const VecX q0 = m.initialPositions();
      const VecX q = solveLinearStatic(as, p, q0, set.time, &rep);
      if (p.size()) {  // without parameters no second factorization
        const StaticSensitivity d = linearStaticSensitivities(as, q0, q, rep.lambda, p);
        res.sensitivityFactor.add(d.factor);
        frame(1.0, q, rep.lambda, &d);
      } else {
        frame(1.0, q, rep.lambda, nullptr);
      }
    } else {
      solveStatic(as, p, m.initialPositions(), set, &rep);
    }
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
  res.linear = sc.statics.linear;
  res.newtonFactor = rep.factor;
  res.loadSteps = rep.steps;
  res.newtonIterations = rep.iterations;
  res.residualNorm = rep.residualNorm;
  res.constraintNorm = rep.constraintNorm;
  res.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  finish("complete", "");
  return res;
}

}  // namespace flexsens
