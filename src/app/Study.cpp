#include "app/Study.hpp"

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "app/FiniteDifferences.hpp"
#include "app/Run.hpp"
#include "output/Manifest.hpp"
#include "output/RunDirectory.hpp"

namespace flexsens {

namespace {

struct FrameRecorder : Observer {
  std::vector<StateWithSens> frames;
  void frame(const StateWithSens& s) override { frames.push_back(s); }
  const StateWithSens& at(double t) const {
    for (const auto& f : frames)
      if (std::abs(f.x.t - t) < 1e-9) return f;
    throw std::runtime_error("study: no frame at t = " + std::to_string(t));
  }
};

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("study: cannot read " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void replaceOnce(std::string& s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  if (at == std::string::npos) throw std::logic_error("study: scene text changed: '" + from + "' not found");
  s.replace(at, from.size(), to);
}

std::string join(const std::vector<std::string>& names, int k, const std::string& sep = ", ") {
  std::string r;
  for (int i = 0; i < k; ++i) r += (i ? sep : "") + names[i];
  return r;
}

/// Rigid five-bar, case R1 with the first k of: L_A1, m_12, m_23, g_z.
std::string rigidScene(const std::string& src, int k) {
  std::string s = slurp(src + "/examples/fivebar/rigid.yaml");
  replaceOnce(s, "  - {name: L_A1, of: bar_A1, property: length}\n",
              "  - {name: L_A1, of: bar_A1, property: length}\n  - {name: m_12, of: bar_12, property: mass}\n"
              "  - {name: m_23, of: bar_23, property: mass}\n  - {name: g_z, of: gravity, property: z}\n");
  replaceOnce(s, "parameters: [L_A1]", "parameters: [" + join({"L_A1", "m_12", "m_23", "g_z"}, k) + "]");
  return s;
}

/// Flexible five-bar, case F1 with the first k of: L_A1, L_B1, E, g_z; beam in N segments.
std::string flexScene(const std::string& src, int k, int segments) {
  std::string s = slurp(src + "/examples/fivebar/flexible.yaml");
  replaceOnce(s, "  - {name: L_B1, of: spring_B1, property: natural_length}  # cases F4-F6\n",
              "  - {name: L_B1, of: spring_B1, property: natural_length}\n  - {name: E, of: beam_12, property: E}\n"
              "  - {name: g_z, of: gravity, property: z}\n");
  replaceOnce(s, "{name: F1, parameters: [L_A1]", "{name: F1, parameters: [" + join({"L_A1", "L_B1", "E", "g_z"}, k) + "]");
  if (segments != 2) {
    std::string nodes, chain = "[n1";
    for (int j = 1; j < segments; ++j) {
      const double a = double(j) / segments;
      std::ostringstream os;
      os << "  - {name: b" << j << ", position: [" << -1 + 1.5 * a << ", " << -1 - a << "]}\n";
      nodes += os.str();
      chain += ", b" + std::to_string(j);
    }
    replaceOnce(s, "  - {name: n4, position: [-0.25, -1.5]}     # midpoint of beam 1-2\n", nodes);
    replaceOnce(s, "nodes: [n1, n4, n2]", "nodes: " + chain + ", n2]");
  }
  return s;
}

/// A seed-000 scene (no PIM case: every declared parameter is active) keeping the first k
/// entries of its `parameters:` list.
std::string seedScene(const std::string& src, const std::string& file, int k) {
  std::string s = slurp(src + "/examples/seed000/" + file);
  size_t at = s.find("\nparameters:\n");
  if (at == std::string::npos) throw std::logic_error("study: no parameters list in " + file);
  at += std::string("\nparameters:\n").size();
  for (int i = 0; i < k; ++i) {
    if (s.compare(at, 4, "  - ") != 0) throw std::logic_error("study: " + file + " declares fewer than " + std::to_string(k) + " parameters");
    at = s.find('\n', at) + 1;
  }
  size_t end = at;
  while (s.compare(end, 4, "  - ") == 0) end = s.find('\n', end) + 1;
  s.erase(at, end - at);
  return s;
}

struct Config {
  std::string integrator = "trapezoidal";
  double dtOrTol = 1e-3;
  std::string method = "dd";  ///< dd | ad | dq | nd | nd-forward | none
  double ndStep = 1e-6;
  double tEnd = 2.0;
  double frame = 0.05;
};

Config config(const std::string& integrator, double dtOrTol, const std::string& method, double tEnd, double frame,
              double ndStep = 1e-6) {
  Config c;
  c.integrator = integrator;
  c.dtOrTol = dtOrTol;
  c.method = method;
  c.ndStep = ndStep;
  c.tEnd = tEnd;
  c.frame = frame;
  return c;
}

/// The converged reference of every comparison: IDAS with analytic sensitivities, rtol = atol.
Config reference(double tEnd, double frame, double rtol = 1e-10) { return config("idas", rtol, "dd", tEnd, frame); }

std::string setting(const Config& c) {
  std::ostringstream os;
  os << (c.integrator == "idas" ? "rtol " : "dt ") << c.dtOrTol;
  return os.str();
}

struct Result {
  FrameRecorder rec;
  double seconds = 0.0;
  IntegratorStats stats;
  std::string failure;
};

constexpr double kRepeatBudget = 2.0;  ///< [s] CPU: no further repetition once the runs took this long

/// Runs case `name` of scene text `text`: the best CPU time of `reps` repetitions (fewer when
/// the repetitions so far took over kRepeatBudget CPU seconds).
Result runCase(const std::string& text, const std::string& name, const Config& c, int reps = 1) {
  Result best;
  best.seconds = 1e300;
  double spent = 0.0;
  for (int r = 0; r < reps && (r == 0 || spent < kRepeatBudget); ++r) {
    Result res;
    try {
      Scene sc = readSceneText(text, "study.yaml", name);
      IntegratorSettings set = sc.integrator;
      set.type = c.integrator;
      set.tEnd = c.tEnd;
      set.frameInterval = c.frame;
      set.newtonTol = 1e-12;
      if (c.integrator == "idas") {
        set.rtol = set.atol = c.dtOrTol;
        set.dt = 0.0;
      } else {
        set.dt = c.dtOrTol;
      }
      set.sensitivityMethod = c.method == "dq" ? "dq" : "dd";
      const auto t0 = std::clock();
      Assembler as(*sc.model, c.method == "ad" ? Derivatives::AutomaticDifferentiation : Derivatives::Analytic);
      const VecX p = sc.model->nominalParameters();
      StateWithSens start = initialState(as, p, sc.pimCase.get());
      if (c.method == "none") start.dp.clear();
      if (c.method == "nd" || c.method == "nd-forward") {
        const NdSettings nd{c.method == "nd" ? "central" : "forward", c.ndStep};
        res.stats = integrateFiniteDifferences(as, p, start, sc.pimCase.get(), set, nd, res.rec);
      } else {
        res.stats = integrate(as, p, start, set, res.rec);
      }
      res.seconds = double(std::clock() - t0) / CLOCKS_PER_SEC;
    } catch (const std::exception& e) {
      res.failure = e.what();
    }
    if (!res.failure.empty()) return res;
    spent += res.seconds;
    if (res.seconds < best.seconds) best = std::move(res);
  }
  return best;
}

/// The integrators and methods of a mechanism's cost table.
struct CostSetup {
  std::string integrator;
  double dt;
  std::vector<std::string> methods;
};

/// One mechanism of the study; every section iterates over a list of these.
struct Mechanism {
  std::string key;                            ///< file-name key (CSV, PNG)
  std::string title;                          ///< report heading
  std::string caseName;                       ///< PIM case ("" for the seed scenes)
  std::string output;                         ///< the studied output, named in the scene
  std::vector<std::string> params;            ///< parameter names, in the order they are added
  std::function<std::string(int)> scene;      ///< scene text with the first k parameters
  double costT;                               ///< horizon of the cost-table runs [s]
  double tEnd;                                ///< horizon of the error-over-time runs [s]
  double tPoint;                              ///< time of the work-precision and nd-sweep errors [s]
  std::vector<CostSetup> cost;
};

/// Evaluates the mechanism's output and its derivative (output gradient . q_p) on frames.
class Probe {
 public:
  Probe(const Mechanism& mech, const std::string& text) : scene_(readSceneText(text, "study.yaml", mech.caseName)) {
    for (size_t i = 0; i < scene_.outputs.size(); ++i)
      if (scene_.outputs[i].name == mech.output) index_ = int(i);
    if (index_ < 0) throw std::logic_error("study: scene of " + mech.key + " has no output " + mech.output);
  }
  double value(const StateWithSens& s) const { return out().value(*scene_.model, s.x); }
  double sens(const StateWithSens& s, int k = 0) const { return out().derivative(*scene_.model, s.x, s.dp[k]); }

 private:
  const OutputSpec& out() const { return scene_.outputs[index_]; }
  Scene scene_;
  int index_ = -1;
};

std::string fmt(double v, int prec = 3) {
  std::ostringstream os;
  os << std::setprecision(prec) << v;
  return os.str();
}

std::string sci(double v) {
  if (std::isnan(v)) return "-";
  std::ostringstream os;
  os << std::scientific << std::setprecision(2) << v;
  return os.str();
}

std::string shortFailure(const std::string& f) { return "stopped: " + f.substr(0, 120); }

/// What the sections share: the options, the mechanisms, the report and the files.
struct StudyRun {
  explicit StudyRun(const StudyOptions& options);
  void progress(const std::string& what) const {
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    std::cerr << "flexsens study [" << fmt(secs, 4) << " s]: " << what << "\n";
  }
  std::vector<const Mechanism*> all() const { return {&rigid, &flexible, &fourBar, &pendulum}; }

  const StudyOptions& opt;
  double otherCpu = 0.0;  ///< [s] CPU of sections run in other processes (the study over MPI ranks)
  const int reps;       ///< repetitions of a timed run (best of)
  const double seedT;   ///< seed mechanisms: error over time, work-precision [s]
  const double costT;   ///< seed mechanisms: cost tables (ratios per step; ad is slow) [s]
  std::chrono::steady_clock::time_point wall0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();
  Mechanism rigid, flexible, fourBar, pendulum;
  std::ostringstream md;                                   ///< the report
  std::vector<std::pair<std::string, std::string>> files;  ///< name, text
};

// The mechanisms. Five-bar: the PIM paper's cases R1 / F1, output z2 [m], 2 s. Seed 000:
// the 3D four-bar (output the joint-4 angle z4 [rad]) and double pendulum (joint-2 angle z2),
// parameters m, Ix of bar 1, c, k of joint 1, 5 s, both with the trapezoidal rule and with
// the seed's own scheme (coordinate partitioning, RK4 at 10 ms).
StudyRun::StudyRun(const StudyOptions& options)
    : opt(options), reps(opt.quick ? 1 : 5), seedT(opt.quick ? 1.0 : 5.0), costT(opt.quick ? 1.0 : 2.0) {
  const std::string src = opt.sourceDir;
  const std::vector<std::string> fiveBarMethods = {"dd", "ad", "nd", "nd-forward"};
  const std::vector<std::string> seedMethods = {"dd", "ad", "nd-forward"};
  const std::vector<CostSetup> seedCost = {{"trapezoidal", 1e-3, seedMethods}, {"maggi_rk4", 1e-2, seedMethods}};
  rigid = {"rigid", "rigid five-bar (R1)", "R1", "z2", {"L_A1", "m_12", "m_23", "g_z"},
           [src](int k) { return rigidScene(src, k); }, 2.0, opt.quick ? 0.5 : 2.0, 1.0,
           {{"trapezoidal", 1e-3, fiveBarMethods}}};
  flexible = {"flexible", "flexible five-bar (F1)", "F1", "z2", {"L_A1", "L_B1", "E", "g_z"},
              [src](int k) { return flexScene(src, k, 2); }, 2.0, opt.quick ? 0.5 : 2.0, 1.0,
              {{"trapezoidal", 1e-3, fiveBarMethods}}};
  fourBar = {"four_bar", "3D four-bar (seed 000)", "", "z4", {"m", "Ix", "c", "k"},
             [src](int k) { return seedScene(src, "four_bar.yaml", k); }, costT, seedT, seedT, seedCost};
  pendulum = {"double_pendulum", "3D double pendulum (seed 000)", "", "z2", {"m", "Ix", "c", "k"},
              [src](int k) { return seedScene(src, "double_pendulum.yaml", k); }, costT, seedT, seedT, seedCost};
}

/// A method of the error-over-time and nd-sweep sections.
struct Method {
  std::string label;
  Config c;
};

void studyHeader(StudyRun& run) {
  run.md << "# flexsens speed-versus-accuracy study\n\n"
     << "Generated by `bash scripts/run-study.sh` (`flexsens study`) in one run on this machine"
     << (run.opt.quick ? " (quick mode: shortened sweeps and horizons)" : "") << ". CPU times are process CPU seconds, "
     << "best of up to " << run.reps << " repetitions (fewer when they take over " << kRepeatBudget
     << " s together); ratios are "
     << "computed within this run. Models: the PIM paper's five-bar, output z2 [m] (height of node 2), "
     << "case R1 (rigid) and F1 (flexible) from `examples/fivebar/`; the seed paper's (000) 3D four-bar "
     << "and double pendulum from `examples/seed000/`, outputs the joint angles z4 and z2 [rad], parameters "
     << "m and Ix of bar 1, c and k of joint 1. Sensitivities of an output are its gradient times q_p "
     << "(for nd: times the difference quotient of q).\n\n";
}

// 1. cost per method
void costSection(StudyRun& run) {
  run.progress("cost tables");
  run.md << "## 1. CPU time of dynamics and sensitivities (like seed 000, Tables 1 and 2)\n\n"
     << "`dynamics` is the run without sensitivities; `sensitivities` = total - dynamics; "
     << "`sens./total` as the seed's last row; `total/dynamics` the cost factor. nd is central, "
     << "nd-forward the seed's forward scheme, both with relative step 1e-6. Simulated time: "
     << run.rigid.costT << " s (five-bar), " << run.costT << " s (seed mechanisms). Plot: `cost.png`.\n\n";
  std::ostringstream tcsv;
  tcsv << "model,integrator,dt,method,parameters,total_s,dynamics_s,sensitivity_s,ratio,sens_share\n";
  for (const Mechanism* mech : run.all()) {
    for (const CostSetup& cs : mech->cost) {
      const double dyn = runCase(mech->scene(1), mech->caseName, config(cs.integrator, cs.dt, "none", mech->costT, 0.05), run.reps).seconds;
      run.md << "### " << mech->title << ", " << cs.integrator << " dt = " << cs.dt * 1e3 << " ms: dynamics alone "
         << fmt(dyn * 1e3, 4) << " ms\n\n"
         << "| parameters | method | dynamics [ms] | sensitivities [ms] | total [ms] | sens./total | total/dynamics |\n"
         << "|---|---|---|---|---|---|---|\n";
      for (int k = 1; k <= 4; ++k)
        for (const std::string& method : cs.methods) {
          const Result r = runCase(mech->scene(k), mech->caseName, config(cs.integrator, cs.dt, method, mech->costT, 0.05), run.reps);
          run.md << "| " << join(mech->params, k) << " | " << method << " | " << fmt(dyn * 1e3, 4) << " | ";
          if (!r.failure.empty()) {
            run.md << "- | - | - | " << shortFailure(r.failure) << " |\n";
            continue;
          }
          const double sens = r.seconds - dyn;
          run.md << fmt(sens * 1e3, 4) << " | " << fmt(r.seconds * 1e3, 4) << " | " << fmt(100 * sens / r.seconds, 3)
             << "% | " << fmt(r.seconds / dyn, 3) << " |\n";
          tcsv << mech->key << "," << cs.integrator << "," << cs.dt << "," << method << "," << k << "," << r.seconds
               << "," << dyn << "," << sens << "," << r.seconds / dyn << "," << sens / r.seconds << "\n";
        }
      run.md << "\n";
    }
  }
  run.files.emplace_back("cost.csv", tcsv.str());
}

// 2. error over time per method
void errorOverTimeSection(StudyRun& run) {
  run.progress("error over time");
  run.md << "## 2. Error of each method over time\n\n"
     << "Against a converged reference: IDAS with analytic sensitivities at rtol = atol = 1e-10. "
     << "Error = |d(output)/dp - reference| for the first parameter (L_A1 for the five-bar, m for the seed "
     << "mechanisms). Plots: `error_time_<model>.png`.\n\n";
  const std::vector<Method> methods = {
      {"trapezoidal dd dt=1e-3", config("trapezoidal", 1e-3, "dd", 0, 0)},
      {"trapezoidal ad dt=1e-3", config("trapezoidal", 1e-3, "ad", 0, 0)},
      {"trapezoidal nd dt=1e-3 h=1e-6", config("trapezoidal", 1e-3, "nd", 0, 0)},
      {"trapezoidal nd-forward dt=1e-3 h=1e-6", config("trapezoidal", 1e-3, "nd-forward", 0, 0)},
      {"bdf1 dd dt=1e-3", config("bdf1", 1e-3, "dd", 0, 0)},
      {"maggi_rk4 dd dt=1e-2", config("maggi_rk4", 1e-2, "dd", 0, 0)},
      {"maggi_rk4 ad dt=1e-2", config("maggi_rk4", 1e-2, "ad", 0, 0)},
      {"maggi_rk4 nd-forward dt=1e-2 h=1e-6", config("maggi_rk4", 1e-2, "nd-forward", 0, 0)},
      {"idas dd rtol=1e-6", config("idas", 1e-6, "dd", 0, 0)},
      {"idas dq rtol=1e-4", config("idas", 1e-4, "dq", 0, 0)},
      {"idas nd rtol=1e-8 h=1e-6", config("idas", 1e-8, "nd", 0, 0)},
  };
  for (const Mechanism* mech : run.all()) {
    const std::string text = mech->scene(1);
    const Probe probe(*mech, text);
    const double frame = 0.05;
    const Result ref = runCase(text, mech->caseName, reference(mech->tEnd, frame));
    if (!ref.failure.empty()) throw NumericalError("study reference failed (" + mech->key + "): " + ref.failure);
    double refMax = 0.0;
    for (const auto& f : ref.rec.frames) refMax = std::max(refMax, std::abs(probe.sens(f)));
    std::ostringstream csv;
    csv << "t";
    for (const auto& m : methods) csv << "," << m.label;
    csv << "\n";
    std::vector<Result> res;
    for (const auto& m : methods) {
      Config c = m.c;
      c.tEnd = mech->tEnd;
      c.frame = frame;
      res.push_back(runCase(text, mech->caseName, c));
    }
    // error of method i at frame f (NaN when it has no such frame)
    auto err = [&](size_t i, size_t f) {
      const Result& r = res[i];
      if (!r.failure.empty() || f >= r.rec.frames.size() || std::abs(r.rec.frames[f].x.t - ref.rec.frames[f].x.t) > 1e-9)
        return double(NAN);
      return std::abs(probe.sens(r.rec.frames[f]) - probe.sens(ref.rec.frames[f]));
    };
    for (size_t f = 0; f < ref.rec.frames.size(); ++f) {
      csv << ref.rec.frames[f].x.t;
      for (size_t i = 0; i < res.size(); ++i) {
        const double e = err(i, f);
        csv << ",";
        if (!std::isnan(e)) csv << e;
      }
      csv << "\n";
    }
    run.md << "### " << mech->title << ": d" << mech->output << "/d" << mech->params[0] << ", 0.." << mech->tEnd
       << " s (reference " << fmt(ref.seconds, 3) << " s CPU, max |reference| " << sci(refMax) << ")\n\n"
       << "| method | CPU [s] | max error | error at t_end | note |\n|---|---|---|---|---|\n";
    for (size_t i = 0; i < methods.size(); ++i) {
      const Result& r = res[i];
      double worst = 0.0, last = NAN;
      for (size_t f = 0; f < ref.rec.frames.size(); ++f) {
        last = err(i, f);
        if (!std::isnan(last)) worst = std::max(worst, last);
      }
      const bool ok = r.failure.empty();
      run.md << "| " << methods[i].label << " | " << fmt(r.seconds, 3) << " | " << (ok ? sci(worst) : "-") << " | "
         << (ok ? sci(last) : "-") << " | " << (ok ? "" : shortFailure(r.failure)) << " |\n";
    }
    run.md << "\n";
    run.files.emplace_back("error_time_" + mech->key + ".csv", csv.str());
  }
}

// 3. work-precision
void workPrecisionSection(StudyRun& run) {
  run.progress("work-precision");
  run.md << "## 3. Work-precision (error of the output and of its derivative at one time versus CPU time)\n\n"
     << "Rigid five-bar R1 (z2, dz2/dL_A1 at t = 1 s) and four-bar (z4, dz4/dm at t = " << run.fourBar.tPoint
     << " s) against IDAS at rtol = atol = 1e-12 (analytic sensitivities); flexible F1 beam segment counts "
     << "against N = 32 (same integrator, trapezoidal dt = 1 ms). generalized_alpha runs at rho_inf = 0.9. "
     << "Plot: `work_precision.png`.\n\n"
     << "| model | integrator | setting | CPU [s] | output error | sensitivity error |\n|---|---|---|---|---|---|\n";
  std::ostringstream wcsv;
  wcsv << "model,integrator,setting,t,cpu_s,error,value_error\n";
  auto wrow = [&](const std::string& model, const std::string& integ, const std::string& set, double v, double t,
                  const Result& r, double verr, double serr) {
    run.md << "| " << model << " | " << integ << " | " << set << " | " << fmt(r.seconds, 3) << " | "
       << (r.failure.empty() ? sci(verr) : "-") << " | " << (r.failure.empty() ? sci(serr) : shortFailure(r.failure))
       << " |\n";
    if (r.failure.empty()) wcsv << model << "," << integ << "," << v << "," << t << "," << r.seconds << "," << serr << "," << verr << "\n";
  };
  const std::vector<double> dts = run.opt.quick ? std::vector<double>{1e-2, 1e-3}
                                            : std::vector<double>{1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4};
  const std::vector<std::pair<std::string, std::vector<double>>> sweeps = {
      {"idas", run.opt.quick ? std::vector<double>{1e-4, 1e-6}
                         : std::vector<double>{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10}},
      {"trapezoidal", dts},
      {"bdf1", dts},
      {"generalized_alpha", dts},  // rho_inf 0.9 (the default)
      {"maggi_rk4", run.opt.quick ? std::vector<double>{1e-2, 5e-3} : std::vector<double>{1e-2, 5e-3, 2.5e-3, 1.25e-3}}};
  for (const Mechanism* mech : {&run.rigid, &run.fourBar}) {
    const std::string text = mech->scene(1);
    const Probe probe(*mech, text);
    const double t = mech->tPoint;
    const Result refRun = runCase(text, mech->caseName, reference(t, t / 2, 1e-12));
    if (!refRun.failure.empty()) throw NumericalError("study reference failed (" + mech->key + "): " + refRun.failure);
    const StateWithSens& ref = refRun.rec.at(t);
    for (const auto& [integ, values] : sweeps)
      for (double v : values) {
        const Config c = config(integ, v, "dd", t, t / 2);
        const Result r = runCase(text, mech->caseName, c, run.reps);
        const bool ok = r.failure.empty();
        wrow(mech->key, integ, setting(c), v, t, r, ok ? std::abs(probe.value(r.rec.at(t)) - probe.value(ref)) : NAN,
             ok ? std::abs(probe.sens(r.rec.at(t)) - probe.sens(ref)) : NAN);
      }
  }
  {
    const std::vector<int> segs = run.opt.quick ? std::vector<int>{2, 4} : std::vector<int>{2, 4, 8, 16};
    const Config c = config("trapezoidal", 1e-3, "dd", 1.0, 0.5);
    const std::string refText = flexScene(run.opt.sourceDir, 1, 32);
    const StateWithSens ref = runCase(refText, "F1", c).rec.at(1.0);
    const Probe refProbe(run.flexible, refText);
    for (int N : segs) {
      const std::string text = flexScene(run.opt.sourceDir, 1, N);
      const Probe probe(run.flexible, text);
      const Result r = runCase(text, "F1", c, run.reps);
      const bool ok = r.failure.empty();
      wrow("flexible", "segments", "N = " + std::to_string(N) + " segments", N, 1.0, r,
           ok ? std::abs(probe.value(r.rec.at(1.0)) - refProbe.value(ref)) : NAN,
           ok ? std::abs(probe.sens(r.rec.at(1.0)) - refProbe.sens(ref)) : NAN);
    }
  }
  run.md << "\n";
  run.files.emplace_back("work_precision.csv", wcsv.str());
}

// 4. ND step sweep
void ndSweepSection(StudyRun& run) {
  run.progress("nd step sweep");
  run.md << "## 4. Finite-difference step sweep (truncation against round-off)\n\n"
     << "Error of nd with relative step h against dd of the same integrator and setting (for the fixed-step "
     << "integrators the exact derivative of the discrete solution; for IDAS rtol 1e-8, its own dd): "
     << "rigid five-bar dz2/dL_A1 at t = 1 s, four-bar dz4/dm at t = " << run.fourBar.tPoint << " s. "
     << "Plot: `nd_sweep.png`.\n\n";
  std::ostringstream ncsv;
  const std::vector<Method> schemes = {{"trapezoidal central", config("trapezoidal", 1e-3, "nd", 0, 0)},
                                       {"trapezoidal forward", config("trapezoidal", 1e-3, "nd-forward", 0, 0)},
                                       {"IDAS 1e-8 central", config("idas", 1e-8, "nd", 0, 0)},
                                       {"maggi_rk4 10 ms forward", config("maggi_rk4", 1e-2, "nd-forward", 0, 0)}};
  ncsv << "model,t,h";
  for (const auto& s : schemes) ncsv << "," << s.label;
  ncsv << "\n";
  for (const Mechanism* mech : {&run.rigid, &run.fourBar}) {
    const std::string text = mech->scene(1);
    const Probe probe(*mech, text);
    const double t = mech->tPoint;
    std::vector<double> exact;  // dd of each scheme's integrator and setting
    for (const auto& s : schemes) {
      const Result r = runCase(text, mech->caseName, config(s.c.integrator, s.c.dtOrTol, "dd", t, t / 2));
      exact.push_back(r.failure.empty() ? probe.sens(r.rec.at(t)) : NAN);
    }
    run.md << "### " << mech->title << "\n\n| h |";
    for (const auto& s : schemes) run.md << " " << s.label << " |";
    run.md << "\n|---|";
    for (size_t i = 0; i < schemes.size(); ++i) run.md << "---|";
    run.md << "\n";
    const int lo = run.opt.quick ? 6 : 12;
    for (int e = 1; e <= lo; ++e) {
      const double h = std::pow(10.0, -e);
      run.md << "| 1e-" << e << " |";
      ncsv << mech->key << "," << t << "," << h;
      for (size_t i = 0; i < schemes.size(); ++i) {
        const Config c = config(schemes[i].c.integrator, schemes[i].c.dtOrTol, schemes[i].c.method, t, t / 2, h);
        const Result r = runCase(text, mech->caseName, c);
        const double err = r.failure.empty() ? std::abs(probe.sens(r.rec.at(t)) - exact[i]) : NAN;
        run.md << " " << sci(err) << " |";
        ncsv << ",";
        if (!std::isnan(err)) ncsv << err;
      }
      run.md << "\n";
      ncsv << "\n";
    }
    run.md << "\n";
  }
  run.files.emplace_back("nd_sweep.csv", ncsv.str());
}

// 5. stability at the extremes
void stabilitySection(StudyRun& run) {
  // The full sweeps behind tests/test_extremes.cpp: every run ends in a result or a
  // diagnostic (time, step, quantity), never in NaN written as a result.
  run.progress("stability at the extremes");
  const double tStab = run.opt.quick ? 0.5 : 2.0;
  run.md << "## 5. Stability at the extremes\n\n"
     << "Each run ends complete (finite states and sensitivities) or stopped with a diagnostic; "
     << "`max |Phi|` is the largest constraint violation over the run.\n\n"
     << "### Beam stiffness: flexible five-bar (F1), trapezoidal dt = 1 ms, " << tStab << " s\n\n"
     << "| E [Pa] | outcome | dz2/dL_A1 at the end | max abs Phi | steps | Newton iterations | CPU [s] |\n"
     << "|---|---|---|---|---|---|---|\n";
  for (double E : {1e3, 1e5, 1e7, 1e9, 1e11, 1e12}) {
    std::string text = run.flexible.scene(1);
    std::ostringstream e;
    e << "E: " << E;
    replaceOnce(text, "E: 206.94e9", e.str());
    const Probe probe(run.flexible, text);
    const Result r = runCase(text, run.flexible.caseName, config("trapezoidal", 1e-3, "dd", tStab, tStab));
    run.md << "| " << sci(E) << " | " << (r.failure.empty() ? "complete" : shortFailure(r.failure)) << " | "
       << (r.failure.empty() ? sci(probe.sens(r.rec.at(tStab))) : "-") << " | " << sci(r.stats.maxConstraintViolation)
       << " | " << r.stats.steps << " | " << r.stats.newtonIterations << " | " << fmt(r.seconds) << " |\n";
  }
  const double tDt = run.opt.quick ? 0.1 : 0.5;
  run.md << "\n### Step size: rigid five-bar (R1), trapezoidal, " << tDt << " s (reference IDAS rtol 1e-10)\n\n"
     << "| dt [s] | outcome | error of z2 | error of dz2/dL_A1 | max abs Phi | Newton iterations | CPU [s] |\n"
     << "|---|---|---|---|---|---|---|\n";
  {
    const std::string text = run.rigid.scene(1);
    const Probe probe(run.rigid, text);
    const Result ref = runCase(text, run.rigid.caseName, reference(tDt, tDt));
    const auto& fr = ref.rec.at(tDt);
    for (double dt : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6}) {
      if (run.opt.quick && dt < 1e-4) continue;
      const Result r = runCase(text, run.rigid.caseName, config("trapezoidal", dt, "dd", tDt, tDt));
      const bool ok = r.failure.empty();
      run.md << "| " << sci(dt) << " | " << (ok ? "complete" : shortFailure(r.failure)) << " | "
         << (ok ? sci(std::abs(probe.value(r.rec.at(tDt)) - probe.value(fr))) : "-") << " | "
         << (ok ? sci(std::abs(probe.sens(r.rec.at(tDt)) - probe.sens(fr))) : "-") << " | "
         << sci(r.stats.maxConstraintViolation) << " | " << r.stats.newtonIterations << " | " << fmt(r.seconds) << " |\n";
    }
  }
  run.md << "\n";
}

/// The report's plots and timing; returns the plots scripts/plot_study.py draws.
std::vector<std::string> studyEnd(StudyRun& run) {
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - run.wall0).count();
  const double cpu = double(std::clock() - run.cpu0) / CLOCKS_PER_SEC + run.otherCpu;
  run.progress("done");
  run.md << "## Plots\n\n![cost](cost.png)\n\n";
  for (const Mechanism* mech : run.all())
    run.md << "![error over time, " << mech->title << "](error_time_" << mech->key << ".png)\n\n";
  run.md << "![work-precision](work_precision.png)\n\n![nd step sweep](nd_sweep.png)\n\n"
     << "This run took " << fmt(wall, 4) << " s wall clock, " << fmt(cpu, 4) << " s CPU.\n";
  run.files.emplace_back("study.md", run.md.str());
  std::vector<std::string> plots = {"cost.png", "work_precision.png", "nd_sweep.png"};
  for (const Mechanism* mech : run.all()) plots.push_back("error_time_" + mech->key + ".png");
  return plots;
}

/// The report's sections after its header, in order.
const std::vector<void (*)(StudyRun&)>& sections() {
  static const std::vector<void (*)(StudyRun&)> s = {costSection, errorOverTimeSection, workPrecisionSection,
                                                     ndSweepSection, stabilitySection};
  return s;
}

}  // namespace

std::string runStudy(const StudyOptions& opt) {
  // Locked and checked before minutes of computing; staged, every write checked, moved into
  // place at the end (output/RunDirectory.hpp).
  RunDirectory dir(opt.outDir, "study");
  StudyRun run(opt);
  studyHeader(run);
  for (const auto& section : sections()) section(run);
  const std::vector<std::string> plots = studyEnd(run);
  return writeStudyOutput(dir, run.files, plots);
}

int studySectionCount() { return static_cast<int>(sections().size()); }

StudyPart runStudySection(const StudyOptions& opt, int index) {
  StudyRun run(opt);
  sections().at(index)(run);
  return {run.md.str(), run.files, double(std::clock() - run.cpu0) / CLOCKS_PER_SEC};
}

std::string writeStudyParts(RunDirectory& dir, const StudyOptions& opt, const std::vector<StudyPart>& parts,
                            std::chrono::steady_clock::time_point started) {
  StudyRun run(opt);
  run.wall0 = started;
  studyHeader(run);
  for (const StudyPart& p : parts) {
    run.md << p.report;
    run.files.insert(run.files.end(), p.files.begin(), p.files.end());
    run.otherCpu += p.cpuSeconds;
  }
  const std::vector<std::string> plots = studyEnd(run);
  return writeStudyOutput(dir, run.files, plots);
}

std::string writeStudyOutput(RunDirectory& dir, const std::vector<std::pair<std::string, std::string>>& files,
                             const std::vector<std::string>& plots) {
  for (const auto& [name, text] : files) writeFileChecked(dir.staging() + "/" + name, dir.final() + "/" + name, text);
  for (const auto& p : plots) dir.keep(p);  // drawn by scripts/plot_study.py from the CSVs
  dir.commit();
  return dir.final() + "/study.md";
}

}  // namespace flexsens
