// `flexsens static` and the beam's scene clamp: a cantilever written as a scene (ground root,
// `clamp: start`, `point_force` at the tip) against the elastica reference table
// (beams-and-checks.md, Mattiasson 1981) and the linear self-weight deflection q L^4 / (8 EI);
// static sensitivities against central differences of the static solution.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/StaticRun.hpp"
#include "core/Interrupt.hpp"
#include "integrators/Static.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;
namespace fs = std::filesystem;

namespace {

constexpr double kL = 1.0;       // [m]
constexpr double kSide = 1e-3;   // square section [m]: slender, the axial strain is negligible
constexpr double kE = 2.1e11;    // [Pa]
constexpr double kRho = 7800.0;  // [kg/m^3]
double EI() { return kE * std::pow(kSide, 4) / 12.0; }

/// A straight cantilever along x (planar) or along x in 3D, N segments, clamped at the root,
/// tip load (0, -P) [N], self-weight from `g` [m/s^2]; parameters E and the load's y component.
std::string cantileverScene(int N, double P, int dim = 2, double g = 0.0, double E = kE) {
  std::ostringstream s;
  s.precision(17);
  const std::string zero = dim == 3 ? ", 0" : "";
  s << "dimension: " << dim << "\n";
  s << "gravity: [0, " << -g << zero << "]\n";
  s << "nodes:\n  - {name: root, position: [0, 0" << zero << "], ground: true}\n";
  for (int i = 1; i <= N; ++i) s << "  - {name: n" << i << ", position: [" << kL * i / N << ", 0" << zero << "]}\n";
  s << "elements:\n  - {name: beam, type: beam, clamp: start, E: " << E << ", density: " << kRho
    << ", section: {side: " << kSide << "}, nodes: [root";
  for (int i = 1; i <= N; ++i) s << ", n" << i;
  s << "]}\n";
  s << "  - {name: load, type: point_force, node: n" << N << ", force: [0, " << -P << zero << "]}\n";
  s << "parameters:\n  - {name: E, of: beam, property: E}\n  - {name: Fy, of: load, property: y}\n";
  s << "static: {load_steps: 10}\n";
  s << "outputs:\n  - {name: tip_x, node: n" << N << ", component: x}\n  - {name: tip_y, node: n" << N
    << ", component: y}\n";
  return s.str();
}

struct Equilibrium {
  VecX q, lambda, p;
  double tipX = 0, tipY = 0;
  Scene scene;
};

/// The scene's equilibrium through the same solver `flexsens static` uses (load factor stepped).
Equilibrium solve(const std::string& text, int steps = 10) {
  Equilibrium e;
  e.scene = readSceneText(text, "cantilever.yaml");
  const Model& m = *e.scene.model;
  Assembler as(m);
  e.p = m.nominalParameters();
  StaticSettings set;
  set.steps = steps;
  set.stepLoadFactor = true;
  StaticReport rep;
  e.q = solveStatic(as, e.p, m.initialPositions(), set, &rep);
  e.lambda = rep.lambda;
  const int tip = m.nodeIndex("n" + std::to_string(m.nodes.size() - 2));  // last beam node
  e.tipX = e.q[m.dof(tip, 0)];
  e.tipY = e.q[m.dof(tip, 1)];
  return e;
}

}  // namespace

// alpha = P L^2 / EI = 1: v/L = 0.301721, u/L = 0.056433 (table, +-5e-7). The scene clamp is
// the half-cell root condition, so the error falls as 1/N^2: observed orders between N = 8, 16,
// 32, 64 are asserted in [1.8, 2.2], and the N = 64 error is below 0.6/N^2 (the constant the
// hand-built clamp of test_cantilever.cpp shows).
TEST(SceneClamp, ElasticaConvergesAsOneOverNSquaredIn2DAnd3D) {
  const double P = EI() / (kL * kL);
  for (int dim : {2, 3}) {
    double prev = 0.0;
    for (int N : {8, 16, 32, 64}) {
      const Equilibrium e = solve(cantileverScene(N, P, dim));
      const double err = std::abs(-e.tipY / kL - 0.301721);
      const double errU = std::abs((kL - e.tipX) / kL - 0.056433);
      std::printf("  dim %d N = %2d: v/L error %.3e, u/L error %.3e\n", dim, N, err, errU);
      if (prev > 0) {
        const double order = std::log2(prev / err);
        EXPECT_GE(order, 1.8) << "dim " << dim << " N " << N;
        EXPECT_LE(order, 2.2) << "dim " << dim << " N " << N;
      }
      if (N == 64) {
        EXPECT_LT(err, 0.6 / (N * N));
        EXPECT_LT(errU, 0.6 / (N * N));
      }
      prev = err;
    }
  }
}

// Self-weight, linear range: tip deflection q L^4 / (8 EI) with q = rho A g [N/m]; gravity is
// stepped by the same load factor as the point loads.
TEST(SceneClamp, SelfWeightMatchesLinearBeamTheory) {
  const double g = 1e-3;  // small: deflection/L ~ 5e-4, the linear theory holds to ~1e-7
  const double q = kRho * kSide * kSide * g;
  const double exact = q * std::pow(kL, 4) / (8.0 * EI());
  double prev = 0.0;
  for (int N : {16, 32}) {
    const Equilibrium e = solve(cantileverScene(N, 0.0, 2, g), 1);
    const double err = std::abs(-e.tipY - exact) / exact;
    std::printf("  N = %d: tip %.9e m, q L^4/8EI %.9e m, relative error %.3e\n", N, -e.tipY, exact, err);
    EXPECT_LT(err, 2.0 / (N * N));
    if (prev > 0) EXPECT_NEAR(std::log2(prev / err), 2.0, 0.25);
    prev = err;
  }
}

// dq/dE and dq/dFy from staticSensitivities against central differences of whole static
// solutions (E and the load perturbed in the scene text), relative step 1e-5.
TEST(StaticSensitivity, MatchesCentralDifferencesOfTheEquilibrium) {
  const int N = 16;
  const double P = 2.0 * EI() / (kL * kL);  // alpha = 2: well into the nonlinear range
  const Equilibrium e = solve(cantileverScene(N, P));
  Assembler as(*e.scene.model);
  const StaticSensitivity d = staticSensitivities(as, e.q, e.lambda, e.p);
  ASSERT_EQ(d.qp.cols(), 2);
  const double h = 1e-5;
  // E
  const Equilibrium eP = solve(cantileverScene(N, P, 2, 0.0, kE * (1 + h)));
  const Equilibrium eM = solve(cantileverScene(N, P, 2, 0.0, kE * (1 - h)));
  const VecX fdE = (eP.q - eM.q) / (2 * h * kE);
  // Fy (the load is -P; the parameter is Fy = -P)
  const Equilibrium fP = solve(cantileverScene(N, P * (1 - h)));
  const Equilibrium fM = solve(cantileverScene(N, P * (1 + h)));
  const VecX fdF = (fP.q - fM.q) / (2 * h * P);
  const double relE = (d.qp.col(0) - fdE).lpNorm<Eigen::Infinity>() / fdE.lpNorm<Eigen::Infinity>();
  const double relF = (d.qp.col(1) - fdF).lpNorm<Eigen::Infinity>() / fdF.lpNorm<Eigen::Infinity>();
  std::printf("  |dq/dE| %.3e, rel. error %.2e; |dq/dFy| %.3e, rel. error %.2e\n", fdE.lpNorm<Eigen::Infinity>(),
              relE, fdF.lpNorm<Eigen::Infinity>(), relF);
  EXPECT_GT(fdE.lpNorm<Eigen::Infinity>(), 0.0);
  EXPECT_LT(relE, 1e-6);
  EXPECT_LT(relF, 1e-6);
  // ad: the same solve with AD partials (and an AD-assembled matrix). Element kernels agree
  // to 1e-10 (test_autodiff); through the solve the slender beam's static matrix (axial over
  // bending stiffness EA L^2 / EI = 1.2e7) amplifies their round-off differences: observed
  // 4e-9 relative per column.
  as.setDerivatives(Derivatives::AutomaticDifferentiation);
  const StaticSensitivity a = staticSensitivities(as, e.q, e.lambda, e.p);
  for (int k = 0; k < 2; ++k)
    EXPECT_LT((a.qp.col(k) - d.qp.col(k)).lpNorm<Eigen::Infinity>(), 1e-7 * d.qp.col(k).lpNorm<Eigen::Infinity>()) << k;
}

// The command line: series.csv gets one row per load step (first column load_factor) with the
// outputs and their sensitivities; the last row equals the in-process solution; summary.json
// says complete. A static-only scene cannot be `run`; `--case` on a scene without cases fails.
TEST(StaticCommand, WritesLoadStepsAndSensitivitiesAndRefusesWrongUse) {
  const fs::path dir = fs::temp_directory_path() / ("flexsens_static_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const double P = EI() / (kL * kL);
  const std::string text = cantileverScene(8, P);
  { std::ofstream(dir / "cantilever.yaml") << text; }
  const std::string exe = FLEXSENS_EXE;
  const std::string scene = (dir / "cantilever.yaml").string();
  ASSERT_EQ(std::system((exe + " static " + scene + " --out " + (dir / "out").string() + " > /dev/null 2>&1").c_str()), 0);
  std::ifstream csv(dir / "out" / "series.csv");
  std::string header, line, last;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("load_factor,tip_x,tip_y,dtip_x/dE,dtip_x/dFy,dtip_y/dE,dtip_y/dFy", 0), 0u) << header;
  int rows = 0;
  while (std::getline(csv, line)) last = line, ++rows;
  EXPECT_EQ(rows, 10);
  std::vector<double> v;
  std::stringstream ss(last);
  for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
  ASSERT_EQ(v.size(), 7u);
  const Equilibrium e = solve(text);
  EXPECT_DOUBLE_EQ(v[0], 1.0);
  EXPECT_NEAR(v[2], e.tipY, 1e-12);
  std::ifstream js(dir / "out" / "summary.json");
  std::stringstream all;
  all << js.rdbuf();
  EXPECT_NE(all.str().find("\"status\": \"complete\""), std::string::npos);
  // Staged like a run: a rerun replaces the earlier output and leaves no staging copy; a file
  // flexsens did not write makes it refuse (exit 4) and stays.
  { std::ofstream(dir / "out" / "mine.txt") << "the user's"; }
  const int refused = std::system((exe + " static " + scene + " --out " + (dir / "out").string() + " > /dev/null 2>&1").c_str());
  EXPECT_TRUE(WIFEXITED(refused) && WEXITSTATUS(refused) == 4);
  EXPECT_TRUE(fs::exists(dir / "out" / "mine.txt"));
  fs::remove(dir / "out" / "mine.txt");
  { std::ofstream(dir / "out" / "series.csv") << "old"; }
  ASSERT_EQ(std::system((exe + " static " + scene + " --out " + (dir / "out").string() + " > /dev/null 2>&1").c_str()), 0);
  std::ifstream again(dir / "out" / "series.csv");
  std::string first;
  std::getline(again, first);
  EXPECT_EQ(first.rfind("load_factor", 0), 0u) << first;  // written again
  EXPECT_TRUE(fs::exists(dir / "out" / "summary.json"));
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".out.staging"), std::string::npos) << e.path();
  EXPECT_NE(std::system((exe + " run " + scene + " --out " + (dir / "run").string() + " 2> " + (dir / "err").string()).c_str()), 0);
  std::ifstream err(dir / "err");
  std::stringstream es;
  es << err.rdbuf();
  EXPECT_NE(es.str().find(":1:1: key 'integrator'"), std::string::npos) << es.str();
  EXPECT_FALSE(fs::exists(dir / "run"));
  { std::ofstream(dir / "dynamic.yaml") << text << "integrator: {type: trapezoidal, t_end: 0.01, dt: 0.001}\n"; }
  const int st = std::system((exe + " run " + (dir / "dynamic.yaml").string() + " --case R9 --out " +
                              (dir / "case").string() + " 2> " + (dir / "err2").string()).c_str());
  EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 1);
  std::ifstream err2(dir / "err2");
  std::stringstream es2;
  es2 << err2.rdbuf();
  EXPECT_NE(es2.str().find("key 'cases': no case named 'R9'"), std::string::npos) << es2.str();
  EXPECT_FALSE(fs::exists(dir / "case"));
  fs::remove_all(dir);
}

// SIGINT during `flexsens static`: it stops after the converged load step, writes that step
// and a summary that says interrupted (not complete), and moves the directory into place.
TEST(StaticCommand, InterruptStopsAfterTheLoadStepWithAnInterruptedSummary) {
  const fs::path dir = fs::temp_directory_path() / ("flexsens_static_int_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const Scene sc = readSceneText(cantileverScene(8, EI() / (kL * kL)), "cantilever.yaml");
  requestInterrupt(SIGINT);
  try {
    runStaticScene(sc, dir.string(), 10);
    ADD_FAILURE() << "static ignored the interrupt";
  } catch (const Interrupted& e) {
    EXPECT_EQ(e.signal, SIGINT);
    EXPECT_DOUBLE_EQ(e.t, 0.1);  // the first of 10 load steps
  }
  clearInterrupt();
  std::ifstream csv(dir / "series.csv");
  std::string header, line;
  std::getline(csv, header);
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 1);
  std::stringstream all;
  all << std::ifstream(dir / "summary.json").rdbuf();
  EXPECT_NE(all.str().find("\"status\": \"interrupted\""), std::string::npos) << all.str();
  EXPECT_EQ(all.str().find("\"complete\""), std::string::npos);
  fs::remove_all(dir);
}

// summary.json counts the direct solver's work: full Newton factorizes once per iteration and
// the sensitivities once per load step (the cantilever has two parameters), and the counts,
// the fill and the time agree with what the solve returned.
TEST(StaticCommand, SummaryCountsFactorizationsOfNewtonAndSensitivities) {
  const fs::path dir = fs::temp_directory_path() / ("flexsens_static_fact_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const Scene sc = readSceneText(cantileverScene(8, EI() / (kL * kL)), "cantilever.yaml");
  const StaticResult r = runStaticScene(sc, dir.string(), 10);
  EXPECT_EQ(r.loadSteps, 10);
  EXPECT_EQ(r.newtonFactor.factorizations, r.newtonIterations);
  EXPECT_EQ(r.sensitivityFactor.factorizations, 10);
  EXPECT_GE(r.newtonFactor.maxFill, 1.0);
  EXPECT_GT(r.newtonFactor.seconds + r.sensitivityFactor.seconds, 0.0);
  std::stringstream all;
  all << std::ifstream(dir / "summary.json").rdbuf();
  const std::string expected = "\"factorizations\": " + std::to_string(r.newtonIterations + 10) +
                               ", \"sensitivity_factorizations\": 10, \"lu_fill\": ";
  EXPECT_NE(all.str().find(expected), std::string::npos) << all.str();
  EXPECT_NE(all.str().find("\"factorization_seconds\": "), std::string::npos);
  fs::remove_all(dir);
}
