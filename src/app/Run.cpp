#include "app/Run.hpp"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include "app/EnergyAudit.hpp"
#include "app/RunHealth.hpp"
#include "app/FiniteDifferences.hpp"
#include "app/ParameterValues.hpp"
#include "integrators/FixedStep.hpp"
#include "integrators/Idas.hpp"
#include "integrators/InitialState.hpp"
#include "integrators/Maggi.hpp"
#include "integrators/TimeGrid.hpp"
#include "core/Interrupt.hpp"
#include "output/ResultWriter.hpp"
#include "output/RunDirectory.hpp"

namespace flexsens {

void applyOptions(Scene& sc, const RunOptions& opt) {
  auto& s = sc.integrator;
  if (opt.integrator) {
    if (!isIntegratorType(*opt.integrator))
      throw InputError(std::string("option --integrator: expected ") + kIntegratorTypes + ", got '" +
                       *opt.integrator + "'");
    s.type = *opt.integrator;
  }
  if (opt.tEnd) {
    if (!(*opt.tEnd > 0)) throw InputError("option --t-end: expected a positive time in seconds");
    s.tEnd = *opt.tEnd;
  }
  if (opt.dt) {
    if (!(*opt.dt > 0)) throw InputError("option --dt: expected a positive step in seconds");
    s.dt = *opt.dt;
    if (s.frameInterval < s.dt) s.frameInterval = s.dt;
  }
  if (opt.rhoInf) {
    if (!(*opt.rhoInf >= 0.0 && *opt.rhoInf <= 1.0)) throw InputError("option --rho-inf: expected a number in [0, 1]");
    s.rhoInf = *opt.rhoInf;
  }
  if (opt.newton) {
    if (!isNewtonMode(*opt.newton)) throw InputError("option --newton: expected full or modified, got '" + *opt.newton + "'");
    s.newton = *opt.newton;
  }
  if (opt.projections) s.projections = *opt.projections;
  if (s.projections && !takesProjections(s.type))
    throw InputError("projections (--projections on, integrator.projections) apply to the trapezoidal rule and "
                     "generalized_alpha, not to " + s.type);
  if (opt.rtol) {
    if (!(*opt.rtol > 0)) throw InputError("option --rtol: expected a positive relative tolerance");
    s.rtol = *opt.rtol;
  }
  auto& sens = sc.sensitivity;
  if (opt.method) sens.method = *opt.method;
  if (opt.ndStep) sens.ndStep = *opt.ndStep;
  if (opt.ndScheme) sens.ndScheme = *opt.ndScheme;
  if (sens.method != "dd" && sens.method != "ad" && sens.method != "dq" && sens.method != "nd")
    throw InputError("option --method: expected dd, ad, dq or nd, got '" + sens.method + "'");
  if (sens.method == "dq" && s.type != "idas")
    throw InputError("option --method: dq (IDAS' internal difference quotients) needs --integrator idas");
  if (sens.ndScheme != "central" && sens.ndScheme != "forward")
    throw InputError("option --nd-scheme: expected forward or central, got '" + sens.ndScheme + "'");
  if (!(sens.ndStep > 0)) throw InputError("option --nd-step: expected a positive relative step");
  s.sensitivityMethod = sens.method == "dq" ? "dq" : "dd";
  if (s.type != "idas" && !(s.dt > 0))
    throw InputError(sc.file + ": key 'integrator.dt': the " + s.type +
                     " integrator needs a fixed step dt (give it in the scene or with --dt)");
  if (s.frameInterval > s.tEnd) s.frameInterval = s.tEnd;
  // The scene's times were checked when read; overrides can break the rule (TimeGrid.hpp).
  if (const auto pr = checkTimes(s)) {
    std::string given;
    for (const auto& [set, name] : {std::pair{opt.tEnd.has_value(), "--t-end"}, {opt.dt.has_value(), "--dt"},
                                    {opt.integrator.has_value(), "--integrator"}})
      if (set) given += (given.empty() ? "" : ", ") + std::string(name);
    throw InputError((given.empty() ? sc.file : "option " + given) + ": key 'integrator." + pr->key + "': " +
                     pr->message);
  }
  if (opt.outDir) sc.output.directory = *opt.outDir;
  if (!opt.parameters.empty()) applyParameterValues(sc, opt.parameters);
}

State consistentState(const Assembler& as, const VecX& p) {
  const Model& m = as.model();
  State s;
  s.t = 0.0;
  as.setTime(s.t);
  s.q = projectPositions(as, m.initialPositions(), p);
  s.v = projectVelocities(as, s.q, m.initialVelocities(), p);
  equilibrateMassless(as, s, p);  // parts with inertia: none (no-op otherwise)
  solveAccelerations(as, s, p);
  return s;
}

StateWithSens initialState(const Assembler& as, const VecX& p, const PimCase* pim, PimReport* rep) {
  const Model& m = as.model();
  if (pim) {
    PimReport local;
    // Massless coordinates: the PIM's rows of their equilibrium fix them (pim/Pim.hpp).
    return pimInitialState(as, *pim, consistentState(as, p), p, rep ? *rep : local);
  }
  StateWithSens s;
  s.x = consistentState(as, p);
  s.dp = leastNormSensitivities(as, s.x, p, 0, int(m.parameters.size()));
  return s;
}

std::vector<State> leastNormSensitivities(const Assembler& as, const State& x, const VecX& p, int first, int count) {
  std::vector<State> ds;
  if (count <= 0) return ds;
  as.setTime(x.t);  // drivers' constraints at the start
  std::optional<LeastNorm> cod;
  if (as.m()) cod.emplace(as, x.q, p);
  for (int k = first; k < first + count; ++k) {
    State d;
    if (cod) {
      d.q = cod->solve(VecX(-as.phiParamDerivative(x.q, p, k)));
      d.v = cod->solve(velocitySensitivityRhs(as, x.q, x.v, p, k, d.q));
    } else {
      d.q = VecX::Zero(as.n());
      d.v = VecX::Zero(as.n());
    }
    masslessSensitivity(as, x, p, k, d);  // no-op without massless coordinates
    ds.push_back(d);
  }
  solveAccelerationSensitivities(as, x, p, ds, first);
  return ds;
}

IntegratorStats integrate(const Assembler& as, const VecX& p, const StateWithSens& start,
                          const IntegratorSettings& set, Observer& obs) {
  if (set.type == "idas") return integrateIdas(as, p, start, set, obs);
  if (set.type == "maggi_rk4") return integrateMaggi(as, p, start, set, obs);
  return integrateFixedStep(as, p, start, set, obs);
}

namespace {

/// summary.json's text: status, the time reached, where the frames landed, and the statistics
/// up to there, the energy audit.
std::string summaryJson(const Scene& sc, const IntegratorStats& st, double wall, const std::string& status,
                        const std::string& error, const ResultWriter& w, const PimReport* pim,
                        const std::string& energy, const std::string& health, double velocityChange) {
  const Model& m = *sc.model;
  const std::vector<std::string>& files = w.files();
  std::ostringstream js;
  js << "{\n";
  js << "  \"status\": " << jsonString(status) << ",\n";
  if (!error.empty()) js << "  \"error\": " << jsonString(error) << ",\n";
  const auto& ft = w.frameTimes();
  js << "  \"t_reached\": " << jsonNumber(w.timeReached()) << ",\n";
  js << "  \"frames\": {\"count\": " << ft.size() << ", \"first_t\": " << jsonNumber(ft.empty() ? 0.0 : ft.front())
     << ", \"last_t\": " << jsonNumber(ft.empty() ? 0.0 : ft.back()) << ", \"spacing\": "
     << jsonNumber(frameSpacing(sc.integrator)) << ", \"requested_interval\": " << jsonNumber(sc.integrator.frameInterval)
     << "},\n";
  js << "  \"scene\": " << jsonString(sc.file) << ",\n";
  if (pim && sc.pimCase) {
    const PimCase& c = *sc.pimCase;
    auto list = [](const std::vector<std::string>& v) {
      std::string r = "[";
      for (size_t i = 0; i < v.size(); ++i) r += (i ? ", " : "") + jsonString(v[i]);
      return r + "]";
    };
    std::vector<std::string> sdofs;
    for (const auto& z : c.sdofs) sdofs.push_back(z->name);
    js << "  \"case\": {\"name\": " << jsonString(c.name) << ", \"n\": " << pim->n << ", \"m\": " << pim->m
       << ", \"d\": " << pim->d << ", \"m_r\": " << pim->mr << ", \"d_s\": " << pim->ds
       << ", \"lambda_generated\": " << pim->lambdaGenerated << ", \"lambda_dropped\": " << pim->lambdaDropped
       << ", \"massless\": " << pim->massless << ", \"massless_equilibrium_rows\": " << pim->me
       << ", \"rigidized\": " << list(c.rigidized) << ", \"rigid_model\": " << list(c.rigidModel)
       << ", \"sdofs\": " << list(sdofs) << ", \"condition_A\": " << jsonNumber(pim->condition) << ",\n"
       << "           \"q_p0\": {";
    for (int k = 0; k < pim->qp.cols(); ++k) {
      js << (k ? ", " : "") << jsonString(m.parameters[k].name) << ": [";
      for (int i = 0; i < pim->qp.rows(); ++i) js << (i ? ", " : "") << jsonNumber(pim->qp(i, k));
      js << "]";
    }
    js << "}, \"v_p0\": {";
    for (int k = 0; k < pim->vp.cols(); ++k) {
      js << (k ? ", " : "") << jsonString(m.parameters[k].name) << ": [";
      for (int i = 0; i < pim->vp.rows(); ++i) js << (i ? ", " : "") << jsonNumber(pim->vp(i, k));
      js << "]";
    }
    js << "}},\n";
  }
  js << "  \"sensitivity\": {\"method\": " << jsonString(sc.sensitivity.method);
  if (sc.sensitivity.method == "nd")
    js << ", \"scheme\": " << jsonString(sc.sensitivity.ndScheme) << ", \"relative_step\": " << jsonNumber(sc.sensitivity.ndStep);
  js << "},\n";
  js << "  \"integrator\": {\"type\": " << jsonString(sc.integrator.type)
     << ", \"t_end\": " << jsonNumber(sc.integrator.tEnd) << ", \"dt\": " << jsonNumber(sc.integrator.dt)
     << ", \"rtol\": " << jsonNumber(sc.integrator.rtol) << ", \"atol\": " << jsonNumber(sc.integrator.atol)
     << ", \"newton\": " << jsonString(sc.integrator.newton)
     << ", \"projections\": " << (sc.integrator.projections ? "true" : "false") << "},\n";
  js << "  \"n\": " << m.n << ", \"m\": " << m.m << ", \"d\": " << m.n - m.m << ",\n";
  js << "  \"coordinates\": [";
  for (int i = 0; i < m.n; ++i) js << (i ? ", " : "") << jsonString(m.coordinateLabel(i));
  js << "],\n  \"parameters\": [";
  for (size_t k = 0; k < m.parameters.size(); ++k)
    js << (k ? ", " : "") << "{\"name\": " << jsonString(m.parameters[k].name) << ", \"bound_to\": "
       << jsonString(m.parameters[k].boundTo) << ", \"nominal\": " << jsonNumber(m.parameters[k].nominal) << "}";
  js << "],\n";
  js << "  \"statistics\": {\"steps\": " << st.steps << ", \"newton_iterations\": " << st.newtonIterations
     << ", \"factorizations\": " << st.factorizations << ", \"sensitivity_iterations\": " << st.sensitivityIterations
     << ", \"sensitivity_factorizations\": " << st.sensitivityFactorizations
     << ", \"sensitivity_reused_lu\": " << st.sensitivityReusedLu
     << ", \"residual_evaluations\": " << st.residualEvaluations
     << ", \"jacobian_evaluations\": " << st.jacobianEvaluations << ", \"error_test_failures\": "
     << st.errorTestFailures << ", \"convergence_failures\": " << st.convergenceFailures
     << ", \"accelerated_iterations\": " << st.acceleratedIterations << ", \"lu_fill\": " << jsonNumber(st.luFill)
     << ", \"cholesky_factorizations\": " << st.choleskyFactorizations
     << ", \"ldlt_factorizations\": " << st.ldltFactorizations
     << ", \"factorization_seconds\": " << jsonNumber(st.factorizationSeconds) << "},\n";
  js << "  \"max_constraint_violation\": " << jsonNumber(st.maxConstraintViolation) << ",\n";
  js << "  \"energy\": " << energy << ",\n";
  js << "  \"health\": " << health << ",\n";
  js << "  \"initial_velocity_change\": " << jsonNumber(velocityChange) << ",\n";
  js << "  \"wall_time_s\": " << jsonNumber(wall) << ",\n";
  js << "  \"files\": [";
  for (size_t i = 0; i < files.size(); ++i)
    js << (i ? ", " : "") << jsonString(std::filesystem::path(files[i]).filename().string());
  js << "]\n}\n";
  return js.str();
}

/// summary.json, written last. Throws OutputError (shownPath and the OS reason) if it cannot.
void writeSummary(const std::string& path, const std::string& shownPath, const std::string& text) {
  errno = 0;
  std::ofstream js(path);
  if (!js) throw OutputError("cannot write " + shownPath + ": " + std::strerror(errno ? errno : EIO));
  js << text;
  js.close();
  if (!js) throw OutputError("cannot write " + shownPath + ": " + std::strerror(errno ? errno : EIO));
}

/// Between the energy audit and the writer: hands each frame's series row (the writer's, so
/// the numbers are series.csv's) and the progress to the run's listener.
class ListenerLink : public ForwardingObserver {
 public:
  ListenerLink(ResultWriter& writer, RunListener& listener, double tEnd)
      : ForwardingObserver(writer), writer_(writer), listener_(listener), tEnd_(tEnd) {}
  void frame(const StateWithSens& s) override {
    next_.frame(s);
    listener_.frame(s, writer_.lastRow());
  }
  void progress(double t) override {
    next_.progress(t);
    listener_.progress(t, tEnd_);
  }

 private:
  const ResultWriter& writer_;
  RunListener& listener_;
  double tEnd_;  ///< [s]
};

}  // namespace

RunResult runScene(const Scene& sc, const std::string& outDir) {
  sc.requireDynamics();  // before the folder is locked or checked: input errors first
  RunDirectory dir(outDir, "run");
  return runScene(sc, dir, "");
}

namespace {

/// The scene's integrator (or the finite-difference runs of --method nd) from `start`, frames to
/// `health` (-> audit -> writer); maggi_rk4 reports its error estimate to the health.
IntegratorStats integrateScene(const Scene& sc, const Assembler& as, const VecX& p, const StateWithSens& start,
                               RunHealth& health, const EnergyAudit& audit) {
  if (sc.sensitivity.method == "nd" && !start.dp.empty()) {
    NdSettings nd{sc.sensitivity.ndScheme, sc.sensitivity.ndStep};
    return integrateFiniteDifferences(as, p, start, sc.pimCase.get(), sc.integrator, nd, health);
  }
  if (sc.integrator.type != "maggi_rk4") return integrate(as, p, start, sc.integrator, health);
  MaggiReport maggi;  // with its error estimate, for the health
  const IntegratorStats st = integrateMaggi(as, p, start, sc.integrator, health, MaggiOptions{}, &maggi);
  // The audit switched off on both sides (tolerances 0) stays off here too.
  const bool audited = sc.integrator.energyTolerance > 0 || sc.integrator.energyLossTolerance > 0;
  health.errorEstimate("maggi_rk4", maggi.errorEstimate, maggi.maxStepErrorEstimate, maggi.maxStepErrorTime,
                       audited ? audit.worstFraction() : -1.0);
  return st;
}

/// Given velocities that violate the velocity constraints are projected (least change in the
/// mass-free Euclidean norm); says by how much, never silently. Returns the change [m/s].
double noteVelocityProjection(const Assembler& as, const Model& m, const StateWithSens& start) {
  const VecX v0 = m.initialVelocities();
  const double dv = m.n ? (start.x.v - v0).lpNorm<Eigen::Infinity>() : 0.0;
  if (dv > 1e-9 * std::max(1.0, v0.lpNorm<Eigen::Infinity>())) {
    std::ostringstream note;  // one write: runs in other threads do not cut into it
    note << "flexsens: note: the given initial velocities violate the constraints"
         << (as.rheonomic() ? " and drivers (Phi_q v = -Phi_t)" : "") << "; projected onto them, "
         << "changing them by up to " << dv << " m/s (summary.json initial_velocity_change)\n";
    std::cerr << note.str();
  }
  return dv;
}

}  // namespace

RunResult runScene(const Scene& sc, RunDirectory& dir, const std::string& part) {
  return runScene(sc, &dir, part, nullptr);
}

RunResult runScene(const Scene& sc, RunDirectory* dir, const std::string& part, RunListener* listener) {
  sc.requireDynamics();  // a massless direction nothing restrains: an input error, not a failed run
  const auto t0 = std::chrono::steady_clock::now();
  const Model& m = *sc.model;
  // ad: the same tangent linear model with partials from forward-mode AD of the kernels.
  Assembler as(m, sc.sensitivity.method == "ad" ? Derivatives::AutomaticDifferentiation : Derivatives::Analytic);
  const VecX p = m.nominalParameters();
  PimReport pim;
  const StateWithSens start = initialState(as, p, sc.pimCase.get(), &pim);  // before any file is written
  const double dv = noteVelocityProjection(as, m, start);

  // Locked, staged, and moved into place at the end: never a mixture with an earlier
  // run's files, never a half-written directory under the final name.
  const std::string staging = dir ? dir->staging(part) : "", final = dir ? dir->final(part) : "";
  const std::string notMoved = dir ? "; nothing was moved into " + final : "";
  const EnergyMeter meter(as, p);
  ResultWriter writer(sc, staging, "", final, "t", &meter);
  std::optional<ListenerLink> link;
  if (listener) {
    writer.hideProgress();
    link.emplace(writer, *listener, sc.integrator.tEnd);
    listener->started(writer.columns());
  }
  EnergyAudit audit(meter, link ? static_cast<Observer&>(*link) : writer, sc.integrator.energyTolerance,
                    sc.integrator.energyLossTolerance);
  RunHealth health(as, p, audit);
  RunResult res;
  res.directory = final;
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  // Ends the run with `status`: closes the files, writes summary.json last, moves the
  // directory into place. A write failure on the way becomes an OutputError that also says
  // how the run itself ended.
  auto finish = [&](const std::string& status, const std::string& error, const IntegratorStats& st) {
    try {
      writer.close();
      const std::string summary = summaryJson(sc, st, elapsed(), status, error, writer, &pim, audit.json(),
                                              health.json(), dv);
      if (dir) writeSummary(staging + "/summary.json", final + "/summary.json", summary);
      if (dir) dir->commit(part);
      if (listener) listener->finished(summary);
    } catch (const OutputError& e) {
      throw OutputError(std::string(e.what()) + (status == "complete" ? "" : " (the run itself " + status + ": " + error + ")") +
                        notMoved);
    }
  };
  try {
    res.stats = integrateScene(sc, as, p, start, health, audit);
  } catch (const OutputError& e) {
    // A result file could not be written: the staging directory goes (RunDirectory's
    // destructor), earlier results stay as they were.
    throw OutputError(std::string(e.what()) + notMoved);
  } catch (const Interrupted& e) {
    finish("interrupted", e.what(), writer.statistics());
    throw;
  } catch (const NumericalError& e) {
    // A failure next to a singular configuration says so (the N-four-bar's collinear passage).
    const std::string what = e.what() + health.failureHint();
    finish("failed", what, writer.statistics());
    throw NumericalError(what);
  } catch (const std::exception& e) {
    finish("failed", e.what(), writer.statistics());
    throw;
  }
  res.wallSeconds = elapsed();
  res.suspect = audit.reason();
  const std::string broken = health.reason();
  if (!broken.empty()) res.suspect += (res.suspect.empty() ? "" : "; ") + broken;
  finish(res.suspect.empty() ? "complete" : "suspect", res.suspect, res.stats);
  return res;
}

}  // namespace flexsens
