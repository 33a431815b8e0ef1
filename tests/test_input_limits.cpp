// What a scene may make flexsens read and allocate (issue 34, item 8): files named by a scene
// only from its folder and below (or --allow-path), never quoted in errors; scene and table
// files only regular and bounded; the memory budget refused before dense work; `modes` on
// models with no dynamic direction; no non-finite number in series.csv; a subnormal parameter.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "TestModels.hpp"
#include "app/Modes.hpp"
#include "core/MemoryBudget.hpp"
#include "integrators/InitialState.hpp"
#include "output/ResultWriter.hpp"
#include "scene/InputFiles.hpp"

using namespace flexsens;
namespace fs = std::filesystem;

namespace {

/// The test binary reads meshes of the source tree from scenes written elsewhere (as text or in
/// temporary folders): the tree is allowed for every test, as --allow-path would allow it.
struct AllowSourceTree : ::testing::Environment {
  void SetUp() override { allowInputDirectory(FLEXSENS_SOURCE_DIR); }
};
const auto* const kAllowSourceTree = ::testing::AddGlobalTestEnvironment(new AllowSourceTree);

/// A fresh folder under the system's temporary one (outside the source tree).
fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("flexsens_limits_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

std::string tableScene(const std::string& file) {
  return "dimension: 2\ngravity: [0, -9.81]\nnodes:\n  - {name: A, position: [0, 0], ground: true}\n"
         "  - {name: B, position: [1, 0]}\nelements:\n  - {name: bar, type: rigid_bar, nodes: [A, B], mass: 1}\n"
         "  - {name: push, type: point_force, node: B, force: [0, 1], function: {type: table, file: " + file + "}}\n"
         "integrator: {type: trapezoidal, t_end: 0.01, dt: 0.001}\n";
}

/// The InputError message of reading scene `file`, or "" when it reads.
std::string readError(const fs::path& file) {
  try {
    readScene(file.string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

struct Shell {
  int status;
  std::string err;
};
Shell runCli(const std::string& args, const fs::path& errFile) {
  const int st = std::system((std::string(FLEXSENS_EXE) + " " + args + " > /dev/null 2> " + errFile.string()).c_str());
  std::ifstream in(errFile);
  std::stringstream ss;
  ss << in.rdbuf();
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, ss.str()};
}

}  // namespace

TEST(SceneFiles, TableOutsideTheScenesFolderIsRefusedInsideIsRead) {
  const fs::path d = scratch("outside");
  fs::create_directories(d / "scene" / "data");
  fs::create_directories(d / "other");
  const std::string table = "t, f\n0, 0\n1, 2\n";
  write(d / "scene" / "data" / "f.csv", table);
  write(d / "other" / "f.csv", table);
  fs::create_symlink(d / "other" / "f.csv", d / "scene" / "link.csv");
  write(d / "scene" / "in.yaml", tableScene("data/f.csv"));
  write(d / "scene" / "up.yaml", tableScene("../other/f.csv"));
  write(d / "scene" / "abs.yaml", tableScene((d / "other" / "f.csv").string()));
  write(d / "scene" / "link.yaml", tableScene("link.csv"));
  write(d / "scene" / "dotdot.yaml", tableScene("data/../../other/f.csv"));
  EXPECT_EQ(readError(d / "scene" / "in.yaml"), "");
  for (const char* s : {"up.yaml", "abs.yaml", "link.yaml", "dotdot.yaml"}) {
    const std::string e = readError(d / "scene" / s);
    EXPECT_NE(e.find(std::string(s) + ":8:"), std::string::npos) << e;
    EXPECT_NE(e.find("key 'elements[1].function.file'"), std::string::npos) << e;
    EXPECT_NE(e.find("outside the scene's folder"), std::string::npos) << e;
    EXPECT_NE(e.find("--allow-path"), std::string::npos) << e;
  }
  // --allow-path of the other folder admits it (the policy is process-wide: restored after).
  const InputPolicy saved = inputPolicy();
  allowInputDirectory((d / "other").string());
  EXPECT_EQ(readError(d / "scene" / "up.yaml"), "");
  EXPECT_EQ(readError(d / "scene" / "link.yaml"), "");
  inputPolicy() = saved;
  fs::remove_all(d);
}

TEST(SceneFiles, TableErrorsNameTheLineButNeverQuoteTheFile) {
  const fs::path d = scratch("quote");
  write(d / "f.csv", "t, f\nsecret-password-hash:x:1:1\n");
  write(d / "s.yaml", tableScene("f.csv"));
  const std::string e = readError(d / "s.yaml");
  EXPECT_NE(e.find("f.csv:2: expected two numbers"), std::string::npos) << e;
  EXPECT_EQ(e.find("secret"), std::string::npos) << e;
  write(d / "f.csv", "t, f\n0, 0, hidden-third-column\n1, 1\n");
  const std::string e3 = readError(d / "s.yaml");
  EXPECT_NE(e3.find("f.csv:2: expected two numbers 't, f', got a third column"), std::string::npos) << e3;
  EXPECT_EQ(e3.find("hidden"), std::string::npos) << e3;
  fs::remove_all(d);
}

TEST(SceneFiles, NonRegularOrOversizedFilesAreRefusedBeforeReading) {
  const fs::path d = scratch("special");
  ASSERT_EQ(::mkfifo((d / "fifo.csv").c_str(), 0600), 0);  // reading it would block forever
  write(d / "s.yaml", tableScene("fifo.csv"));
  std::string e = readError(d / "s.yaml");
  EXPECT_NE(e.find("not a regular file"), std::string::npos) << e;
  // A table over the limit (here lowered to 64 bytes) is refused by its size.
  std::string rows = "t, f\n";
  for (int i = 0; i < 20; ++i) rows += std::to_string(i) + ", " + std::to_string(i) + "\n";
  write(d / "big.csv", rows);
  write(d / "s.yaml", tableScene("big.csv"));
  const InputPolicy saved = inputPolicy();
  EXPECT_EQ(readError(d / "s.yaml"), "");
  inputPolicy().maxTableBytes = 64;
  e = readError(d / "s.yaml");
  EXPECT_NE(e.find("more than the limit of"), std::string::npos) << e;
  // The scene file itself: a device or a FIFO ends at once with a clear error.
  e = readError("/dev/zero");
  EXPECT_NE(e.find("/dev/zero: cannot read the scene file"), std::string::npos) << e;
  EXPECT_NE(e.find("not a regular file"), std::string::npos) << e;
  EXPECT_NE(readError(d / "fifo.csv").find("not a regular file"), std::string::npos);
  inputPolicy().maxSceneBytes = 100;
  e = readError(d / "s.yaml");
  EXPECT_NE(e.find("more than the limit of"), std::string::npos) << e;
  inputPolicy() = saved;
  fs::remove_all(d);
}

TEST(SceneFiles, CliAllowPathAndDevZero) {
  const fs::path d = scratch("cli");
  fs::create_directories(d / "scene");
  fs::create_directories(d / "tables");
  write(d / "tables" / "f.csv", "0, 0\n1, 1\n");
  write(d / "scene" / "s.yaml", tableScene("../tables/f.csv"));
  const std::string scene = (d / "scene" / "s.yaml").string();
  Shell r = runCli("check " + scene, d / "err");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("outside the scene's folder"), std::string::npos) << r.err;
  r = runCli("check " + scene + " --allow-path " + (d / "tables").string(), d / "err");
  EXPECT_EQ(r.status, 0) << r.err;
  r = runCli("check " + scene + " --allow-path " + (d / "missing").string(), d / "err");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("option --allow-path"), std::string::npos) << r.err;
  r = runCli("check /dev/zero", d / "err");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
  fs::remove_all(d);
}

namespace {
/// The modes of a scene given as text (as `flexsens modes` computes them).
ModalAnalysis modesOf(const std::string& text) {
  Scene sc = readSceneText(text, "modes.yaml");
  sc.requireDynamics();
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  return analyzeModes(as, consistentState(as, p), p, 5);
}
}  // namespace

TEST(ModesWithoutDynamics, ZeroDofAndAllMasslessGiveNoModesWithTheReason) {
  // d = 0: a node held by a fixed constraint (n = m = 2).
  const ModalAnalysis fixed = modesOf(
      "dimension: 2\ngravity: [0, -9.81]\nnodes:\n  - {name: A, position: [0, 0], ground: true}\n"
      "  - {name: B, position: [1, 0]}\nelements:\n  - {name: bar, type: rigid_bar, nodes: [A, B], mass: 1}\n"
      "constraints:\n  - {name: hold, type: fixed, node: B}\nintegrator: {type: trapezoidal, t_end: 0.01, dt: 0.001}\n");
  EXPECT_EQ(fixed.n, 2);
  EXPECT_EQ(fixed.tangent, 0);
  EXPECT_TRUE(fixed.modes.empty());
  EXPECT_NE(fixed.noModes.find("d = n - m = 0"), std::string::npos) << fixed.noModes;
  EXPECT_NE(modesReport(fixed, 5).find("no modes: no dynamic direction"), std::string::npos);
  EXPECT_NE(modesJson(fixed, 5).find("\"no_modes\""), std::string::npos);
  // Every free coordinate massless: a beam with inertia: none between two ground nodes.
  const ModalAnalysis massless = modesOf(
      "dimension: 2\ngravity: [0, -9.81]\nnodes:\n  - {name: A, position: [0, 0], ground: true}\n"
      "  - {name: B, position: [0.5, 0]}\n  - {name: C, position: [1, 0], ground: true}\n"
      "elements:\n  - {name: b, type: beam, nodes: [A, B, C], E: 2.0e9, inertia: none, section: {side: 0.01}}\n"
      "integrator: {type: bdf1, t_end: 0.01, dt: 0.001}\n");
  EXPECT_EQ(massless.tangent, 2);  // x and y of B
  EXPECT_EQ(massless.massless, 2);
  EXPECT_TRUE(massless.modes.empty());
  EXPECT_NE(massless.noModes.find("massless"), std::string::npos) << massless.noModes;
  EXPECT_NE(modesReport(massless, 5).find("no modes: every one of the 2 free directions is massless"),
            std::string::npos);
}

TEST(ModesWithoutDynamics, CliExitsZeroWithTheReason) {
  const fs::path d = scratch("modes_cli");
  write(d / "s.yaml",
        "dimension: 2\ngravity: [0, -9.81]\nnodes:\n  - {name: A, position: [0, 0], ground: true}\n"
        "  - {name: B, position: [1, 0]}\nelements:\n  - {name: bar, type: rigid_bar, nodes: [A, B], mass: 1}\n"
        "constraints:\n  - {name: hold, type: fixed, node: B}\nintegrator: {type: trapezoidal, t_end: 0.01, dt: 0.001}\n");
  const int st = std::system((std::string(FLEXSENS_EXE) + " modes " + (d / "s.yaml").string() + " > " +
                              (d / "out").string() + " 2>&1").c_str());
  ASSERT_TRUE(WIFEXITED(st));
  EXPECT_EQ(WEXITSTATUS(st), 0);
  std::ifstream in(d / "out");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("no modes: no dynamic direction"), std::string::npos) << ss.str();
  fs::remove_all(d);
}

TEST(MemoryBudget, DenseModesAreRefusedAboveTheBudgetNamingTheOptionThePimIsNot) {
  // A 20-segment planar beam: n = 40 coordinates (x, y of 20 free nodes); its modes need
  // ~8 n^2 doubles = 102 kB, the PIM case below ~79 kB.
  std::string beam = "dimension: 2\ngravity: [0, -9.81]\nnodes:\n";
  for (int i = 0; i <= 20; ++i)
    beam += "  - {name: N" + std::to_string(i) + ", position: [" + std::to_string(0.05 * i) + ", 0]" +
            (i == 0 ? ", ground: true" : "") + "}\n";
  beam += "elements:\n  - {name: b, type: beam, nodes: [";
  for (int i = 0; i <= 20; ++i) beam += (i ? ", N" : "N") + std::to_string(i);
  beam += "], E: 2.0e9, density: 1000, section: {side: 0.01}}\nintegrator: {type: bdf1, t_end: 0.01, dt: 0.001}\n";
  const double saved = memoryBudget();
  EXPECT_EQ(modesOf(beam).n, 40);
  setMemoryBudget(50e3);
  try {
    modesOf(beam);
    ADD_FAILURE() << "modes ran above the memory budget";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("n = 40 coordinates"), std::string::npos) << m;
    EXPECT_NE(m.find("--max-memory"), std::string::npos) << m;
  }
  // A PIM case rigidizing the beam: its matrix is sparse (pim/PimMatrix.hpp), so it runs under
  // the budget that refuses the dense modes, and gives what it gives under the default budget.
  const std::string cased = beam + "parameters:\n  - {name: E, of: b, property: E}\ncases:\n"
                                   "  - {name: R, parameters: [E], rigidize: [b], sdofs: [{node: N20, component: y}]}\n";
  Scene sc = readSceneText(cased, "pim.yaml", "R");
  Assembler as(*sc.model);
  PimReport small;
  const StateWithSens underBudget = initialState(as, sc.model->nominalParameters(), sc.pimCase.get(), &small);
  setMemoryBudget(saved);
  PimReport full;
  const StateWithSens withDefault = initialState(as, sc.model->nominalParameters(), sc.pimCase.get(), &full);
  EXPECT_EQ(small.mr, full.mr);
  EXPECT_EQ((underBudget.dp[0].q - withDefault.dp[0].q).norm(), 0.0);
}

TEST(FiniteResults, WriterRefusesANonFiniteColumnNamingItAndTheTime) {
  Scene sc = readSceneText(std::string(test::kMotorBarScene) +
                               "parameters:\n  - {name: m, of: bar, property: mass}\n"
                               "integrator: {type: trapezoidal, t_end: 0.01, dt: 0.001}\n"
                               "outputs:\n  - {name: ty, node: T, component: y}\n",
                           "nan.yaml");
  const fs::path d = scratch("nan");
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  StateWithSens s = initialState(as, p, nullptr, nullptr);
  ResultWriter w(sc, d.string(), "");
  EXPECT_NO_THROW(w.frame(s));
  s.x.t = 0.25;
  s.dp.at(0).q.setConstant(std::nan(""));  // a derivative gone NaN, the state itself finite
  try {
    w.frame(s);
    ADD_FAILURE() << "a NaN derivative was written";
  } catch (const NumericalError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("column 'dty/dm'"), std::string::npos) << m;
    EXPECT_NE(m.find("t = 0.25"), std::string::npos) << m;
    EXPECT_NE(m.find("--method nd"), std::string::npos) << m;
  }
  w.close();
  std::ifstream in(d / "series.csv");
  std::string line, all;
  while (std::getline(in, line)) all += line + "\n";
  EXPECT_EQ(all.find("nan"), std::string::npos) << all;
  fs::remove_all(d);
}

TEST(FiniteResults, EnergyDerivativeOfASubnormalParameterIsFinite) {
  // A rigid bar (mass p) hanging at 45 degrees: V = p g y_c with y_c = -0.5 sin(45 deg) m, so
  // dE/dp at rest is g y_c whatever p is; p = 5e-324 gave (V - V) / 0 = NaN before.
  Scene sc = readSceneText(
      "dimension: 2\ngravity: [0, -9.81]\nnodes:\n  - {name: A, position: [0, 0], ground: true}\n"
      "  - {name: B, position: [0.7071067811865476, -0.7071067811865476]}\nelements:\n"
      "  - {name: bar, type: rigid_bar, nodes: [A, B], mass: 1}\nparameters:\n  - {name: m, of: bar, property: mass}\n"
      "integrator: {type: trapezoidal, t_end: 0.01, dt: 0.001}\n",
      "denormal.yaml");
  Assembler as(*sc.model);
  for (const double pm : {1.0, 1e-300, 5e-324}) {
    VecX p(1);
    p[0] = pm;
    const EnergyMeter meter(as, p);
    State x;
    x.t = 0;
    x.q = sc.model->initialPositions();
    x.v = VecX::Zero(x.q.size());
    State dp = x;
    dp.q.setZero();
    const std::vector<double> dE = meter.sensitivities(x, {dp});
    ASSERT_EQ(dE.size(), 1u);
    EXPECT_NEAR(dE[0], 9.81 * -0.5 * 0.7071067811865476, 1e-9) << "p = " << pm;
  }
}

// A meshed body is sized by memory, not by a node count: a quadratic Cook's membrane at
// h = 0.5 (27508 nodes, 0.51 GiB at 20 kB per node) is read under the default budget; under a
// budget of 0.3 GiB it is refused naming the node count, the group and --max-memory, while
// h = 1 (7k nodes, 0.13 GiB) still fits.
TEST(MemoryBudget, MeshedBodyIsSizedByTheBudgetNotANodeCount) {
  auto cook = [](double h) {
    return "dimension: 2\nelements:\n  - {name: panel, type: solid, mesh: cook.geo, group: cook, size: " +
           std::to_string(h) + ", order: 2, E: 1, nu: 0.3333, density: 1, thickness: 1, ground: [clamp],\n"
           "     traction: [{group: load, force: [0, 1]}]}\nstatic: {load_steps: 1}\n";
  };
  const std::string name = test::sourceDir() + "/tests/scenes/solid/cook_budget.yaml";
  const double saved = memoryBudget();
  const Scene fine = readSceneText(cook(0.5), name);
  EXPECT_GT(fine.model->n, 2 * 20000);  // above the former limit of 20000 nodes
  setMemoryBudget(0.3 * (1ull << 30));
  try {
    readSceneText(cook(0.5), name);
    ADD_FAILURE() << "a mesh above the memory budget was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("key 'elements[0].mesh'"), std::string::npos) << m;
    EXPECT_NE(m.find("Physical Surface 'cook' of " + std::to_string(fine.model->nodes.size()) + " nodes"), std::string::npos) << m;
    EXPECT_NE(m.find("larger size"), std::string::npos) << m;
    EXPECT_NE(m.find("--max-memory"), std::string::npos) << m;
  }
  EXPECT_NO_THROW(readSceneText(cook(1.0), name));
  setMemoryBudget(saved);
}
