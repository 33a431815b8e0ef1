#include "app/Study.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "app/FiniteDifferences.hpp"
#include "app/Run.hpp"

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

std::string paramList(const std::vector<std::string>& names, int k) {
  std::string r = "[";
  for (int i = 0; i < k; ++i) r += (i ? ", " : "") + names[i];
  return r + "]";
}

/// Rigid five-bar, case R1 with the first k of: L_A1, m_12, m_23, g_z.
std::string rigidScene(const std::string& src, int k) {
  std::string s = slurp(src + "/examples/fivebar/rigid.yaml");
  replaceOnce(s, "  - {name: L_A1, of: bar_A1, property: length}\n",
              "  - {name: L_A1, of: bar_A1, property: length}\n  - {name: m_12, of: bar_12, property: mass}\n"
              "  - {name: m_23, of: bar_23, property: mass}\n  - {name: g_z, of: gravity, property: z}\n");
  replaceOnce(s, "parameters: [L_A1]", "parameters: " + paramList({"L_A1", "m_12", "m_23", "g_z"}, k));
  return s;
}

/// Flexible five-bar, case F1 with the first k of: L_A1, L_B1, E, g_z; beam in N segments.
std::string flexScene(const std::string& src, int k, int segments) {
  std::string s = slurp(src + "/examples/fivebar/flexible.yaml");
  replaceOnce(s, "  - {name: L_B1, of: spring_B1, property: natural_length}  # cases F4-F6\n",
              "  - {name: L_B1, of: spring_B1, property: natural_length}\n  - {name: E, of: beam_12, property: E}\n"
              "  - {name: g_z, of: gravity, property: z}\n");
  replaceOnce(s, "{name: F1, parameters: [L_A1]", "{name: F1, parameters: " + paramList({"L_A1", "L_B1", "E", "g_z"}, k));
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

struct Config {
  std::string integrator = "trapezoidal";
  double dtOrTol = 1e-3;
  std::string method = "dd";  ///< dd | dq | nd | nd-forward | none
  double ndStep = 1e-6;
  double tEnd = 2.0;
  double frame = 0.05;
};

struct Result {
  FrameRecorder rec;
  double seconds = 0.0;
  IntegratorStats stats;
  std::string failure;
};

/// Runs case `name` of scene text `text`; the best CPU time of `reps` repetitions.
Result runCase(const std::string& text, const std::string& name, const Config& c, int reps = 1) {
  Result best;
  best.seconds = 1e300;
  for (int r = 0; r < reps; ++r) {
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
    if (res.seconds < best.seconds) best = std::move(res);
  }
  return best;
}

int z2Index(const std::string& text, const std::string& name) {
  Scene sc = readSceneText(text, "study.yaml", name);
  return sc.model->dof(sc.model->nodeIndex("n2"), 1);
}

std::string fmt(double v, int prec = 3) {
  std::ostringstream os;
  os << std::setprecision(prec) << v;
  return os.str();
}

std::string sci(double v) {
  std::ostringstream os;
  os << std::scientific << std::setprecision(2) << v;
  return os.str();
}

}  // namespace

std::string runStudy(const StudyOptions& opt) {
  namespace fs = std::filesystem;
  fs::create_directories(opt.outDir);
  const std::string& src = opt.sourceDir;
  const int reps = opt.quick ? 1 : 3;
  std::ostringstream md;
  auto progress = [](const std::string& what) { std::cerr << "flexsens study: " << what << "\n"; };
  md << "# flexsens speed-versus-accuracy study\n\n"
     << "Generated by `bash scripts/run-study.sh` (`flexsens study`) in one run on this machine"
     << (opt.quick ? " (quick mode: shortened sweeps)" : "") << ". CPU times are process CPU seconds, "
     << "best of " << reps << "; ratios are computed within this run. Model: the PIM paper's five-bar, "
     << "output z2, case R1 (rigid) and F1 (flexible) from `examples/fivebar/`.\n\n";

  // ---------------------------------------------------------------- 1. cost per method
  progress("cost table");
  md << "## 1. CPU time of dynamics and sensitivities (like seed 000, Table 1)\n\n"
     << "Trapezoidal rule, dt = 1 ms, 2 s. `dynamics` is the run without sensitivities; "
     << "`sensitivities` = total - dynamics; `ratio` = total / dynamics.\n\n";
  std::ofstream tcsv(opt.outDir + "/cost.csv");
  tcsv << "model,method,parameters,total_s,dynamics_s,sensitivity_s,ratio\n";
  for (const std::string model : {"rigid", "flexible"}) {
    auto scene = [&](int k) { return model == "rigid" ? rigidScene(src, k) : flexScene(src, k, 2); };
    const std::string cs = model == "rigid" ? "R1" : "F1";
    Config base;
    base.method = "none";
    const double dyn = runCase(scene(1), cs, base, reps).seconds;
    md << "### " << model << " five-bar (" << cs << "), dynamics alone " << fmt(dyn * 1e3, 4) << " ms\n\n"
       << "| method | params | total [ms] | sensitivities [ms] | total / dynamics |\n|---|---|---|---|---|\n";
    for (const std::string method : {"dd", "ad", "nd", "nd-forward"}) {
      for (int k = 1; k <= 4; ++k) {
        Config c;
        c.method = method;
        c.ndStep = 1e-6;
        const Result r = runCase(scene(k), cs, c, reps);
        md << "| " << method << " | " << k << " | " << fmt(r.seconds * 1e3, 4) << " | "
           << fmt((r.seconds - dyn) * 1e3, 4) << " | " << fmt(r.seconds / dyn, 3) << " |\n";
        tcsv << model << "," << method << "," << k << "," << r.seconds << "," << dyn << "," << r.seconds - dyn
             << "," << r.seconds / dyn << "\n";
      }
    }
    md << "\n";
  }

  // ---------------------------------------------------- 2. error over time per method
  progress("error over time");
  md << "## 2. Error of each method over time\n\n"
     << "Against a converged reference: IDAS with analytic sensitivities at rtol = atol = 1e-10. "
     << "Error = |dz2/dp - reference|. Plot: `error_time_rigid.png`, `error_time_flexible.png`.\n\n";
  struct Method { std::string label; Config c; };
  const std::vector<Method> methods = {
      {"trapezoidal dd dt=1e-3", {"trapezoidal", 1e-3, "dd"}},
      {"trapezoidal ad dt=1e-3", {"trapezoidal", 1e-3, "ad"}},
      {"trapezoidal nd dt=1e-3 h=1e-6", {"trapezoidal", 1e-3, "nd", 1e-6}},
      {"bdf1 dd dt=1e-3", {"bdf1", 1e-3, "dd"}},
      {"idas dd rtol=1e-6", {"idas", 1e-6, "dd"}},
      {"idas dq rtol=1e-4", {"idas", 1e-4, "dq"}},
      {"idas nd rtol=1e-8 h=1e-6", {"idas", 1e-8, "nd", 1e-6}},
  };
  for (const std::string model : {"rigid", "flexible"}) {
    const std::string text = model == "rigid" ? rigidScene(src, 1) : flexScene(src, 1, 2);
    const std::string cs = model == "rigid" ? "R1" : "F1";
    const double tEnd = opt.quick ? 0.5 : 2.0;
    const int z2 = z2Index(text, cs);
    Config refc{"idas", 1e-10, "dd"};
    refc.tEnd = tEnd;
    const Result ref = runCase(text, cs, refc);
    if (!ref.failure.empty()) throw NumericalError("study reference failed: " + ref.failure);
    std::ofstream csv(opt.outDir + "/error_time_" + model + ".csv");
    csv << "t";
    for (const auto& m : methods) csv << "," << m.label;
    csv << "\n";
    std::vector<Result> res;
    md << "### " << model << " (" << cs << ", reference " << fmt(ref.seconds, 3) << " s CPU)\n\n"
       << "| method | CPU [s] | max error | error at t_end | note |\n|---|---|---|---|---|\n";
    for (const auto& m : methods) {
      Config c = m.c;
      c.tEnd = tEnd;
      res.push_back(runCase(text, cs, c));
    }
    for (size_t f = 0; f < ref.rec.frames.size(); ++f) {
      const double t = ref.rec.frames[f].x.t;
      csv << t;
      for (const auto& r : res) {
        if (!r.failure.empty() || f >= r.rec.frames.size()) { csv << ","; continue; }
        csv << "," << std::abs(r.rec.frames[f].dp[0].q[z2] - ref.rec.frames[f].dp[0].q[z2]);
      }
      csv << "\n";
    }
    for (size_t i = 0; i < methods.size(); ++i) {
      const Result& r = res[i];
      double worst = 0.0, last = 0.0;
      for (size_t f = 0; f < r.rec.frames.size() && f < ref.rec.frames.size(); ++f) {
        last = std::abs(r.rec.frames[f].dp[0].q[z2] - ref.rec.frames[f].dp[0].q[z2]);
        worst = std::max(worst, last);
      }
      md << "| " << methods[i].label << " | " << fmt(r.seconds, 3) << " | " << (r.failure.empty() ? sci(worst) : "-")
         << " | " << (r.failure.empty() ? sci(last) : "-") << " | "
         << (r.failure.empty() ? "" : "stopped: " + r.failure.substr(0, 120)) << " |\n";
    }
    md << "\n";
  }

  // ------------------------------------------------------------- 3. work-precision
  progress("work-precision");
  md << "## 3. Work-precision (error of dz2/dp at t = 1 s versus CPU time)\n\n"
     << "Rigid R1 against the IDAS rtol 1e-10 reference; flexible F1 segment counts against "
     << "N = 32 (same integrator, trapezoidal dt = 1 ms). Plot: `work_precision.png`.\n\n"
     << "| model | integrator | setting | CPU [s] | error |\n|---|---|---|---|---|\n";
  std::ofstream wcsv(opt.outDir + "/work_precision.csv");
  wcsv << "model,integrator,setting,cpu_s,error\n";
  {
    const std::string text = rigidScene(src, 1);
    const int z2 = z2Index(text, "R1");
    Config refc{"idas", 1e-10, "dd"};
    refc.tEnd = 1.0;
    refc.frame = 0.5;
    const double ref = runCase(text, "R1", refc).rec.at(1.0).dp[0].q[z2];
    std::vector<std::pair<std::string, std::vector<double>>> sweeps = {
        {"idas", opt.quick ? std::vector<double>{1e-4, 1e-6} : std::vector<double>{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9}},
        {"trapezoidal", opt.quick ? std::vector<double>{1e-2, 1e-3} : std::vector<double>{1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4}},
        {"bdf1", opt.quick ? std::vector<double>{1e-2, 1e-3} : std::vector<double>{1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4}}};
    for (const auto& [integ, values] : sweeps)
      for (double v : values) {
        Config c{integ, v, "dd"};
        c.tEnd = 1.0;
        c.frame = 0.5;
        const Result r = runCase(text, "R1", c, reps);
        const double err = r.failure.empty() ? std::abs(r.rec.at(1.0).dp[0].q[z2] - ref) : NAN;
        md << "| rigid | " << integ << " | " << (integ == "idas" ? "rtol " : "dt ") << v << " | " << fmt(r.seconds, 3)
           << " | " << (r.failure.empty() ? sci(err) : "stopped") << " |\n";
        if (r.failure.empty()) wcsv << "rigid," << integ << "," << v << "," << r.seconds << "," << err << "\n";
      }
    const std::vector<int> segs = opt.quick ? std::vector<int>{2, 4} : std::vector<int>{2, 4, 8, 16};
    Config c{"trapezoidal", 1e-3, "dd"};
    c.tEnd = 1.0;
    c.frame = 0.5;
    const std::string refText = flexScene(src, 1, 32);
    const double fref = runCase(refText, "F1", c).rec.at(1.0).dp[0].q[z2Index(refText, "F1")];
    for (int N : segs) {
      const std::string t = flexScene(src, 1, N);
      const Result r = runCase(t, "F1", c, reps);
      const double err = std::abs(r.rec.at(1.0).dp[0].q[z2Index(t, "F1")] - fref);
      md << "| flexible | trapezoidal | N = " << N << " segments | " << fmt(r.seconds, 3) << " | " << sci(err) << " |\n";
      wcsv << "flexible,segments," << N << "," << r.seconds << "," << err << "\n";
    }
    md << "\n";
  }

  // ------------------------------------------------------------------ 4. ND step sweep
  progress("nd step sweep");
  md << "## 4. Finite-difference step sweep (truncation against round-off)\n\n"
     << "Rigid R1, t = 1 s: central and forward nd with relative step h against dd of the same "
     << "integrator (the exact derivative of the discrete trapezoidal solution; for IDAS rtol 1e-8, "
     << "its own dd). Plot: `nd_sweep.png`.\n\n| h | trapezoidal central | trapezoidal forward | IDAS 1e-8 central |\n|---|---|---|---|\n";
  std::ofstream ncsv(opt.outDir + "/nd_sweep.csv");
  ncsv << "h,trapezoidal_central,trapezoidal_forward,idas_central\n";
  {
    const std::string text = rigidScene(src, 1);
    const int z2 = z2Index(text, "R1");
    Config dd{"trapezoidal", 1e-3, "dd"};
    dd.tEnd = 1.0;
    dd.frame = 0.5;
    const double exact = runCase(text, "R1", dd).rec.at(1.0).dp[0].q[z2];
    Config idd{"idas", 1e-8, "dd"};
    idd.tEnd = 1.0;
    idd.frame = 0.5;
    const double iexact = runCase(text, "R1", idd).rec.at(1.0).dp[0].q[z2];
    const int lo = opt.quick ? 6 : 12;
    for (int e = 1; e <= lo; ++e) {
      const double h = std::pow(10.0, -e);
      double errs[3];
      int i = 0;
      for (const auto& [integ, method] : std::vector<std::pair<std::string, std::string>>{
               {"trapezoidal", "nd"}, {"trapezoidal", "nd-forward"}, {"idas", "nd"}}) {
        Config c{integ, integ == "idas" ? 1e-8 : 1e-3, method, h};
        c.tEnd = 1.0;
        c.frame = 0.5;
        const Result r = runCase(text, "R1", c);
        errs[i++] = r.failure.empty() ? std::abs(r.rec.at(1.0).dp[0].q[z2] - (integ == "idas" ? iexact : exact)) : NAN;
      }
      md << "| 1e-" << e << " | " << sci(errs[0]) << " | " << sci(errs[1]) << " | " << sci(errs[2]) << " |\n";
      ncsv << h << "," << errs[0] << "," << errs[1] << "," << errs[2] << "\n";
    }
    md << "\n";
  }
  md << "## Plots\n\n![error over time, rigid](error_time_rigid.png)\n\n![error over time, flexible](error_time_flexible.png)\n\n"
     << "![work-precision](work_precision.png)\n\n![nd step sweep](nd_sweep.png)\n";
  const std::string report = opt.outDir + "/study.md";
  std::ofstream(report) << md.str();
  return report;
}

}  // namespace flexsens
