// Supports of meshed bodies per direction (`support: {group, fix}`) and planes of symmetry
// (`symmetry: {group, normal}`), and the node groups `flexsens check` lists:
//  - a planar plate clamped at its root, its tip edge held in y only, pulled in x and pushed in
//    y: it stretches by F L / (E A) (nu = 0: uniform stress, exact on linear triangles; observed
//    to 1.5e-6) and does not move in y (0 to round-off); without the support the same push bends it;
//  - a clamped shell plate under a tip point load: the half plate with a symmetry plane (the
//    normal displacement held and the mirror hinges) gives the full plate's deflection (the
//    meshes are mirror images; observed equal to 10 digits, -4.174802235e-3 m); holding only the
//    normal displacement (rotation free) does not (-5.21e-3 m, 25% more).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "TestModels.hpp"
#include "app/Commands.hpp"
#include "integrators/Static.hpp"

using namespace flexsens;

namespace {

VecX solveScene(const Scene& sc, int steps) {
  Assembler as(*sc.model);
  StaticSettings set;
  set.steps = steps;
  set.stepLoadFactor = true;
  return solveStatic(as, sc.model->nominalParameters(), sc.model->initialPositions(), set);
}

int nodeNamed(const Model& m, const std::string& name) {
  for (size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodes[i].name == name) return static_cast<int>(i);
  return -1;
}

constexpr double kF = 5e-3;  // [N]: x strain F / (E A) = 1e-6

std::string plateScene(bool support) {
  return std::string("dimension: 2\nelements:\n  - {name: plate, type: solid, mesh: plate.geo, group: plate, size: 0.025,"
                     " E: 1.0e7, nu: 0, density: 1000, thickness: 0.01, ground: [root],\n") +
         (support ? "     support: [{group: tip, fix: [y]}],\n" : "") +
         "     traction: [{group: tip, force: [0.005, 0.005]}]}\nstatic: {load_steps: 1}\n";
}

}  // namespace

TEST(Supports, SolidSupportHoldsItsDirectionAndLeavesTheOtherFree) {
  const std::string name = test::sourceDir() + "/tests/scenes/solid/plate_support.yaml";
  const Scene sc = readSceneText(plateScene(true), name);
  const Model& m = *sc.model;
  const VecX q = solveScene(sc, 1);
  const int tip = nodeNamed(m, "tipmid");
  ASSERT_GE(tip, 0);
  const double ux = q[m.dof(tip, 0)] - m.nodes[tip].position[0], uy = q[m.dof(tip, 1)] - m.nodes[tip].position[1];
  const double expected = kF * 1.0 / (1.0e7 * 0.05 * 0.01);  // F L / (E H t) [m]
  std::printf("tip held in y: ux %.6e (F L / E A = %.6e), uy %.3e\n", ux, expected, uy);
  EXPECT_NEAR(ux, expected, 1e-3 * expected);  // the free direction moves as the bar stretches
  EXPECT_LT(std::abs(uy), 1e-12);             // the fixed one does not
  int held = 0;
  for (const auto& c : m.constraints) held += c->kind() == "support";
  EXPECT_GE(held, 3);  // the tip edge's nodes (at least its ends and midpoint)

  const Scene free = readSceneText(plateScene(false), name);
  const VecX qf = solveScene(free, 1);
  const int tipf = nodeNamed(*free.model, "tipmid");
  const double uyFree = qf[free.model->dof(tipf, 1)] - free.model->nodes[tipf].position[1];
  const double beam = kF / (3 * 1.0e7 * 0.01 * std::pow(0.05, 3) / 12);  // F L^3 / (3 E I)
  std::printf("tip not held: uy %.6e (beam theory %.6e)\n", uyFree, beam);
  // Observed 1.05e-3 m, 0.66 of beam theory: linear triangles two or three across the depth are
  // too stiff in bending (locking); what matters here is that the unsupported tip moves.
  EXPECT_GT(uyFree, 0.5 * beam);
}

namespace {

std::string shellPlate(const std::string& mesh, const std::string& edge, double load) {
  return "dimension: 3\nelements:\n  - {name: plate, type: shell, mesh: " + mesh +
         ", group: plate, E: 1.0e9, nu: 0.3, density: 1000, thickness: 0.01, clamp: [root]" + edge +
         "}\n  - {name: load, type: point_force, node: tipmid, force: [0, 0, " + std::to_string(load) +
         "]}\nstatic: {load_steps: 2}\n";
}

double tipDeflection(const std::string& text) {
  const Scene sc = readSceneText(text, test::sourceDir() + "/tests/scenes/shell/symmetry.yaml");
  const VecX q = solveScene(sc, 2);
  const int tip = nodeNamed(*sc.model, "tipmid");
  return q[sc.model->dof(tip, 2)];
}

}  // namespace

TEST(Supports, ShellSymmetryPlaneReproducesTheFullPlate) {
  const double full = tipDeflection(shellPlate("plate_full.msh", "", -1.0));
  const double half = tipDeflection(shellPlate("plate_half.msh", ", symmetry: [{group: sym, normal: y}]", -0.5));
  const double pinned = tipDeflection(shellPlate("plate_half.msh", ", support: [{group: sym, fix: [y]}]", -0.5));
  std::printf("tip deflection: full %.9e, half with symmetry %.9e, half with y held only %.9e\n", full, half, pinned);
  EXPECT_LT(full, -1e-3);
  EXPECT_NEAR(half, full, 1e-7 * std::abs(full));
  EXPECT_GT(std::abs(pinned - full), 0.01 * std::abs(full));  // the rotation the plane forbids matters
}

TEST(Supports, CheckListsTheMeshNodeGroups) {
  const std::string name = test::sourceDir() + "/tests/scenes/shell/symmetry.yaml";
  const CheckResult r = checkCommand(name, shellPlate("plate_half.msh", ", symmetry: [{group: sym, normal: y}]", -0.5));
  const std::string report = checkReport(r);
  // plate_half.msh: root and sym edges of 5 and 9 nodes, the point tipmid.
  EXPECT_NE(report.find("node groups of plate"), std::string::npos) << report;
  EXPECT_NE(report.find("root (5 nodes)"), std::string::npos) << report;
  EXPECT_NE(report.find("sym (9 nodes)"), std::string::npos) << report;
  EXPECT_NE(report.find("tipmid (1 node)"), std::string::npos) << report;
}

// A shell edge held in z only (a diaphragm-like support): the edge's point pushed in z and
// pulled in x stays at z = 0 and moves in x (membrane stretch of the plate, x free).
TEST(Supports, ShellSupportHoldsItsDirectionAndLeavesTheOtherFree) {
  const std::string text =
      "dimension: 3\nelements:\n  - {name: plate, type: shell, mesh: plate_half.msh, group: plate, E: 1.0e9, nu: 0.3,"
      " density: 1000, thickness: 0.01, clamp: [root], support: [{group: sym, fix: [z]}]}\n"
      "  - {name: load, type: point_force, node: tipmid, force: [1000, 0, -1]}\nstatic: {load_steps: 1}\n";
  const Scene sc = readSceneText(text, test::sourceDir() + "/tests/scenes/shell/support.yaml");
  const Model& m = *sc.model;
  const VecX q = solveScene(sc, 1);
  const int tip = nodeNamed(m, "tipmid");
  const double ux = q[m.dof(tip, 0)] - 1.0, uz = q[m.dof(tip, 2)];
  std::printf("shell edge held in z: tip ux %.6e, uz %.3e\n", ux, uz);
  EXPECT_LT(std::abs(uz), 1e-12);
  // At least the uniform stretch F L / (E t b) = 1000 / (1e9 0.01 0.5) = 2e-4 m; observed 8.2e-4 m,
  // the load concentrated at one node stretching the membrane around it more.
  EXPECT_GT(ux, 2e-4);
}
