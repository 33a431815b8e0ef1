// `flexsens static`'s convergence test: a constrained shell whose internal forces dwarf its load
// converges (its residual is round-off of the internal forces, ~1e-6 N beside a 1 N load: the
// old absolute bound on the multipliers' update refused it for ever), integrator.newton_tol is
// honoured, and a step that cannot converge names the failing update, its bound, the load step
// and the load factor; a snap-through step plain Newton cannot take is taken with the line search.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "app/StaticRun.hpp"
#include "integrators/Static.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;

namespace {

constexpr double kL = 1.0, kSide = 1e-3, kE = 2.1e11;  // [m], [m], [Pa]
double EI() { return kE * std::pow(kSide, 4) / 12.0; }

/// A planar cantilever of 8 beam segments clamped at the root, tip load P [N] down, in
/// `steps` load steps, with the given `integrator` mapping (may be empty).
std::string cantilever(double P, int steps, const std::string& integrator) {
  std::ostringstream s;
  s.precision(17);
  s << "dimension: 2\nnodes:\n  - {name: root, position: [0, 0], ground: true}\n";
  for (int i = 1; i <= 8; ++i) s << "  - {name: n" << i << ", position: [" << kL * i / 8 << ", 0]}\n";
  s << "elements:\n  - {name: beam, type: beam, clamp: start, E: " << kE << ", density: 7800, section: {side: "
    << kSide << "}, nodes: [root, n1, n2, n3, n4, n5, n6, n7, n8]}\n";
  s << "  - {name: load, type: point_force, node: n8, force: [0, " << -P << "]}\n";
  s << "static: {load_steps: " << steps << "}\n" << integrator;
  s << "outputs:\n  - {name: tip_y, node: n8, component: y}\n";
  return s.str();
}

std::string sceneFile(const std::string& name) { return std::string(FLEXSENS_SOURCE_DIR) + "/tests/scenes/statics/" + name; }

}  // namespace

// The pinched cylinder (R 300 m, E 3e6 Pa, P = 1 N, 8 x 32 lattice, diaphragms held by
// prescribed_coordinate): internal force round-off ~ eps k |q| ~ 1e-6 N. It converges in a few
// iterations, and the equilibrium balances: the vertical reactions of the diaphragms and the
// two pinching loads sum to zero (an independent check of the converged multipliers).
TEST(StaticConvergence, ConstrainedShellConvergedToRoundOffIsAccepted) {
  const Scene sc = readScene(sceneFile("cylinder_8.yaml"));
  StaticResult r;
  ASSERT_NO_THROW(r = runStaticScene(sc, "", 1));
  EXPECT_LE(r.newtonIterations, 6);
  EXPECT_LT(r.residualNorm, 1e-4);  // [N], beside loads of 1 N
  // Equilibrium of the model: Q(q) = Phi_q^T lambda. Sum of the z components of the
  // reactions Phi_q^T lambda = the z resultant of the applied loads (0: two opposite loads).
  const Model& m = *sc.model;
  Assembler as(m);
  StaticSettings set;
  set.stepLoadFactor = true;
  set.steps = 1;
  StaticReport rep;
  const VecX q = solveStatic(as, m.nominalParameters(), m.initialPositions(), set, &rep);
  const VecX reaction = as.phiQTransposeTimes(q, m.nominalParameters(), rep.lambda);
  double fz = 0.0, fzAbs = 0.0;
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    if (m.nodes[i].ground) continue;
    fz += reaction[m.dof(static_cast<int>(i), 2)];
    fzAbs += std::abs(reaction[m.dof(static_cast<int>(i), 2)]);
  }
  EXPECT_GT(fzAbs, 1.0);      // the diaphragms carry the two unit loads ...
  EXPECT_NEAR(fz, 0.0, 1e-4); // ... and balance
}

// newton_tol: a loose tolerance stops Newton earlier on a large-deflection cantilever (tip
// load 2 EI/L^2 in one step: several iterations), and the two answers agree to the loose one.
TEST(StaticConvergence, NewtonTolIsHonoured) {
  const double P = 2.0 * EI() / (kL * kL);
  const Scene tight = readSceneText(cantilever(P, 1, "integrator: {type: bdf1, t_end: 1, dt: 0.1, newton_tol: 1e-12}\n"), "tight.yaml");
  const Scene loose = readSceneText(cantilever(P, 1, "integrator: {type: bdf1, t_end: 1, dt: 0.1, newton_tol: 1e-3}\n"), "loose.yaml");
  const StaticResult rt = runStaticScene(tight, "", 1);
  const StaticResult rl = runStaticScene(loose, "", 1);
  EXPECT_LT(rl.newtonIterations, rt.newtonIterations);
  EXPECT_GE(rt.newtonIterations, 4);
  EXPECT_LT(rt.residualNorm, rl.residualNorm);
}

// A step Newton cannot solve in its iterations (two iterations for a large deflection in one
// step, then two more with the line search) fails naming the update, its bound, the load step,
// the load factor and what to change.
TEST(StaticConvergence, FailureNamesTheQuantityItsBoundAndTheLoadStep) {
  const double P = 2.0 * EI() / (kL * kL);
  const Scene sc = readSceneText(cantilever(P, 2, "integrator: {type: bdf1, t_end: 1, dt: 0.1, max_newton_iterations: 2}\n"), "bad.yaml");
  try {
    runStaticScene(sc, "", 2);
    ADD_FAILURE() << "two iterations solved a large deflection";
  } catch (const NumericalError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("load step 1/2 (load factor 0.5)"), std::string::npos) << msg;
    // two plain iterations, then two with the line search from the same start
    EXPECT_NE(msg.find("in 4 iterations (plain, then with a backtracking line search)"), std::string::npos) << msg;
    EXPECT_NE(msg.find("the positions' update |dq|_inf = "), std::string::npos) << msg;
    EXPECT_NE(msg.find("exceeds its bound"), std::string::npos) << msg;
    EXPECT_NE(msg.find("newton_tol 1e-10"), std::string::npos) << msg;
    EXPECT_NE(msg.find("static.load_steps, e.g. 4"), std::string::npos) << msg;
    EXPECT_NE(msg.find("max_newton_iterations, now 2"), std::string::npos) << msg;
  }
}

// The Scordelis-Lo roof written as a user would (8 x 6 lattice, diaphragms by
// prescribed_coordinate, gravity load) through the command line: exit 0, summary complete, and
// the free edge's midpoint goes down (0.19 m on this mesh; the series is in bench/statics).
TEST(StaticConvergence, ScordelisLoRoofCompletesThroughTheCommandLine) {
  const std::string out = ::testing::TempDir() + "flexsens_roof_" + std::to_string(::getpid());
  const std::string cmd = std::string(FLEXSENS_EXE) + " static " + sceneFile("roof_8.yaml") + " --out " + out + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream js(out + "/summary.json");
  std::stringstream all;
  all << js.rdbuf();
  EXPECT_NE(all.str().find("\"status\": \"complete\""), std::string::npos) << all.str();
  const size_t at = all.str().find("\"midside_z\": ");
  ASSERT_NE(at, std::string::npos);
  const double z = std::stod(all.str().substr(at + 13));
  EXPECT_GT(19.1511 - z, 0.1);
  EXPECT_LT(19.1511 - z, 0.3);
  std::filesystem::remove_all(out);
}

// The line search: a shallow two-spring (von Mises) truss pushed through its limit point in one
// load step with 6 iterations per attempt. Plain Newton does not take the snap-through in 6
// iterations; the line search from the same start does. The equilibrium satisfies the spring
// forces' balance written out here (k (l - l0) along each spring, l0 = sqrt(1 + h^2)).
TEST(StaticConvergence, LineSearchTakesTheSnapThroughStep) {
  const double k = 100.0, Fx = 0.001, Fy = -3.0, h = 0.1;
  std::ostringstream s;
  s << "dimension: 2\nnodes:\n  - {name: a, position: [0, 0], ground: true}\n  - {name: c, position: [2, 0], ground: true}\n"
    << "  - {name: b, position: [1, " << h << "]}\nelements:\n"
    << "  - {name: s1, type: spring_damper, nodes: [a, b], stiffness: " << k << "}\n"
    << "  - {name: s2, type: spring_damper, nodes: [c, b], stiffness: " << k << "}\n"
    << "  - {name: m, type: point_force, node: b, force: [" << Fx << ", " << Fy << "]}\n"
    << "static: {load_steps: 1}\noutputs:\n  - {name: by, node: b, component: y}\n";
  const Scene sc = readSceneText(s.str(), "truss.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  StaticSettings set;
  set.steps = 1;
  set.stepLoadFactor = true;
  set.maxIterations = 6;
  StaticReport rep;
  const VecX q = solveStatic(as, m.nominalParameters(), m.initialPositions(), set, &rep);
  ASSERT_EQ(rep.iterationsPerStep.size(), 1u);
  EXPECT_GT(rep.iterationsPerStep[0], set.maxIterations);  // the plain attempt's 6, then the line search's
  const int b = m.nodeIndex("b");
  const double x = q[m.dof(b, 0)], y = q[m.dof(b, 1)], l0 = std::sqrt(1.0 + h * h);
  const double la = std::hypot(x, y), lc = std::hypot(x - 2.0, y);
  const double fx = -k * (la - l0) * x / la - k * (lc - l0) * (x - 2.0) / lc + Fx;
  const double fy = -k * (la - l0) * y / la - k * (lc - l0) * y / lc + Fy;
  EXPECT_LT(y, 0.0);  // snapped through
  EXPECT_NEAR(fx, 0.0, 1e-10);
  EXPECT_NEAR(fy, 0.0, 1e-10);
}
