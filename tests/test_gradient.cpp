// flexsens gradient (app/Gradient.hpp) and the discrete adjoint (integrators/Adjoint.hpp):
//  (a) a free-falling bar, whose objectives are closed forms in the gravity parameter;
//  (b) the flexible five-bar of the PIM paper (trapezoidal rule): the adjoint gradient equals the
//      forward one to 1e-8 relative and central differences of whole runs to 1e-5, for the plain
//      model (least-norm initial sensitivities) and the PIM case F2; checkpointing changes
//      nothing; BDF-1, generalized-alpha and the midpoint rule agree the same way;
//  (c) a mass on a massless beam (massless coordinates in every step); per-element thicknesses of
//      a solid plate; angle and angle-rate outputs; static equilibria (linear, load-stepped);
//  (d) the errors: a method without an adjoint, projections, an unknown objective.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "GradientChecks.hpp"
#include "app/Gradient.hpp"
#include "app/Objectives.hpp"
#include "output/GradientVtu.hpp"
#include "integrators/FixedStepper.hpp"
#include "integrators/InitialState.hpp"
#include "integrators/TimeGrid.hpp"

namespace flexsens {
namespace {

std::string fileText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Scene sceneWith(const std::string& text, const std::string& name, const std::string& caseName, double tEnd = 0.0,
                const std::string& integrator = "") {
  Scene sc = readSceneText(text, name, caseName);
  RunOptions opt;
  if (tEnd > 0) opt.tEnd = tEnd;
  if (!integrator.empty()) opt.integrator = integrator;
  applyOptions(sc, opt);
  return sc;
}

using test::gradients;

/// Objective values of a whole run with parameter k moved by d, from the initial state the
/// scene's PIM case (or the least-norm rule) gives the perturbed model (as `--method nd`).
std::vector<double> perturbedValues(const Scene& sc, int k, double d) {
  Assembler as(*sc.model);
  const VecX p0 = sc.model->nominalParameters();
  const StateWithSens start = initialState(as, p0, sc.pimCase.get());
  VecX p = p0;
  p[k] += d;
  StateWithSens s;
  as.setTime(start.x.t);
  s.x.q = sc.pimCase ? perturbedConfiguration(as, *sc.pimCase, start.x.q, p0, p, k) : projectPositions(as, start.x.q, p);
  s.x.v = projectVelocities(as, s.x.q, start.x.v + d * start.dp[size_t(k)].v, p);
  equilibrateMassless(as, s.x, p);
  solveAccelerations(as, s.x, p);
  const IntegratorSettings& set = sc.integrator;
  const StepGrid g{0.0, set.dt, set.tEnd, fixedStepCount(set.tEnd, set.dt)};
  MatX samples(g.steps + 1, Eigen::Index(sc.outputs.size()));
  FixedStepper stepper(as, p, s, set);
  for (long n = 0;; ++n) {
    for (size_t o = 0; o < sc.outputs.size(); ++o)
      samples(n, Eigen::Index(o)) = sc.outputs[o].value(*sc.model, stepper.current().x);
    if (stepper.done()) break;
    stepper.step();
  }
  std::vector<double> J;
  for (size_t i = 0; i < sc.objectives.size(); ++i) J.push_back(objectiveValue(sc.objectives, i, g, samples));
  return J;
}

using test::worstRelative;

// ------------------------------------------------------------------ (a) free fall
const char* kFreeFall = R"(dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: A, position: [0, 0]}
  - {name: T, position: [1, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [A, T], mass: 1.0}
parameters:
  - {name: gy, of: gravity, property: y}
integrator: {type: trapezoidal, t_end: 1.0, dt: 0.01}
outputs:
  - {name: yT, node: T, component: y}
objectives:
  - {name: end, terminal: {output: yT}}
  - {name: mid, terminal: {output: yT, at: 0.505}}
  - {name: area, integral: {output: yT}}
  - {name: track, tracking: {output: yT, target: {type: linear, slope: 0}}}
  - {name: both, sum: [{objective: end, weight: 2}, {objective: area, weight: -1}]}
)";

TEST(Gradient, FreeFallObjectivesAreClosedFormsInGravity) {
  // y(t) = g t^2 / 2 exactly (the trapezoidal rule integrates a constant acceleration
  // exactly). end = g/2; mid = g/4 (0.5^2 + 0.51^2)/2 (interpolated); area = (g/2)(1/3 + h^2/6)
  // (the trapezoidal sum of t^2); track = (g^2/4) sum_n w_n t_n^4, trapezoidal sum of t^4 =
  // 1/5 + h^2/3 - h^4/30 (Euler-Maclaurin).
  const Scene sc = sceneWith(kFreeFall, "fall.yaml", "");
  const double g = -9.81, h = 0.01;
  const double area = 1.0 / 3.0 + h * h / 6.0, quartic = 0.2 + h * h / 3.0 - std::pow(h, 4) / 30.0;
  const double value[] = {g / 2, g * (0.25 + 0.2601) / 4, g / 2 * area, g * g / 4 * quartic, g - g / 2 * area};
  const double slope[] = {0.5, (0.25 + 0.2601) / 4, area / 2, g / 2 * quartic, 1.0 - area / 2};
  for (const std::string method : {"forward", "adjoint"}) {
    const GradientResult r = gradients(sc, method);
    ASSERT_EQ(r.objectives.size(), 5u);
    for (size_t i = 0; i < 5; ++i) {
      EXPECT_NEAR(r.objectives[i].value, value[i], 1e-12 * std::abs(value[i])) << method << " " << r.objectives[i].name;
      EXPECT_NEAR(r.objectives[i].gradient[0], slope[i], 1e-11 * std::abs(slope[i])) << method << " " << r.objectives[i].name;
    }
  }
}

// ------------------------------------------------------------------ (b) the flexible five-bar
const char* kFiveBarObjectives = R"(
objectives:
  - {name: z2_end, terminal: {output: z2}}
  - {name: z2_sq, integral: {output: z2, power: 2, from: 0.1, to: 0.75}}
  - {name: z2_track, tracking: {output: z2, target: {type: harmonic, amplitude: 0.3, omega: 4, offset: -2}}}
  - {name: z2_peak, max: {output: z2, rho: 20}}
  - {name: mix, sum: [{objective: z2_end, weight: 2}, {objective: z2_peak, weight: -1}]}
)";

/// The example five-bar with the objectives above in place of its own.
std::string fiveBarText() {
  std::string text = fileText(std::string(FLEXSENS_SOURCE_DIR) + "/examples/fivebar/flexible.yaml");
  const size_t from = text.find("\nobjectives:\n"), to = text.find("\noutput:", from);
  if (from != std::string::npos && to != std::string::npos) text.erase(from, to - from);
  return text + kFiveBarObjectives;
}

/// Adjoint against forward (1e-8) and against central differences of whole runs (1e-5; the
/// relative step 1e-5: at 1e-4 the difference's truncation error was 2e-5 of dz2_end/dL_A1).
void checkFiveBar(const std::string& caseName, const std::string& integrator, bool differences) {
  const Scene sc = sceneWith(fiveBarText(), "flexible.yaml", caseName, 1.0, integrator);
  const GradientResult fw = gradients(sc, "forward"), adj = gradients(sc, "adjoint");
  ASSERT_EQ(adj.objectives.size(), 5u);
  for (size_t i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(adj.objectives[i].value, fw.objectives[i].value);
  EXPECT_LT(worstRelative(adj, fw, 1e-6), 1e-8) << caseName << " " << integrator;
  if (!differences) return;
  for (int k = 0; k < int(sc.model->parameters.size()); ++k) {
    const double d = 1e-5 * std::max(1.0, std::abs(sc.model->nominalParameters()[k]));
    const std::vector<double> plus = perturbedValues(sc, k, d), minus = perturbedValues(sc, k, -d);
    for (size_t i = 0; i < 5; ++i) {
      const double nd = (plus[i] - minus[i]) / (2 * d), ref = adj.objectives[i].gradient[k];
      EXPECT_NEAR(ref, nd, 1e-5 * std::max(std::abs(nd), 1e-3))
          << caseName << " " << adj.objectives[i].name << " d/d" << sc.model->parameters[size_t(k)].name;
    }
  }
}

TEST(Gradient, FiveBarAdjointEqualsForwardAndDifferencesLeastNorm) { checkFiveBar("", "trapezoidal", true); }
TEST(Gradient, FiveBarAdjointEqualsForwardAndDifferencesPimCaseF2) { checkFiveBar("F2", "trapezoidal", true); }
TEST(Gradient, FiveBarAdjointEqualsForwardBdf1) { checkFiveBar("F5", "bdf1", false); }
TEST(Gradient, FiveBarAdjointEqualsForwardGeneralizedAlpha) { checkFiveBar("F2", "generalized_alpha", false); }
TEST(Gradient, FiveBarAdjointEqualsForwardMidpoint) { checkFiveBar("", "midpoint", false); }

TEST(Gradient, CheckpointingRecomputesTheSameGradient) {
  // Every state kept (k = N) against k = 7 (143 checkpoints, every segment but the last
  // recomputed): the recomputed steps are the same steps, so the gradients agree to round-off.
  const Scene sc = sceneWith(fiveBarText(), "flexible.yaml", "", 1.0);
  const GradientResult all = gradients(sc, "adjoint"), k7 = gradients(sc, "adjoint", 7);
  EXPECT_EQ(all.adjoint.checkpointEvery, 1000);
  EXPECT_EQ(all.adjoint.recomputedSteps, 0);
  EXPECT_EQ(k7.adjoint.checkpointEvery, 7);
  EXPECT_EQ(k7.adjoint.checkpoints, 143);
  EXPECT_EQ(k7.adjoint.recomputedSteps, 1000 - 1000 % 7);  // the last segment (6 steps) is kept
  EXPECT_LT(k7.adjoint.peakStates, 143 + 9);
  EXPECT_LT(worstRelative(k7, all, 1e-6), 1e-12);
}

// ------------------------------------------------------------------ (c) massless coordinates
const char* kMasslessSpring = R"(dimension: 2
gravity: [0, -2]
nodes:
  - {name: root, position: [0, 0], ground: true}
  - {name: n1, position: [0.25, 0]}
  - {name: n2, position: [0.5, 0]}
  - {name: n3, position: [0.75, 0]}
  - {name: tip, position: [1, 0], velocity: [0.01, 0]}
  - {name: anchor, position: [1, -1], ground: true}
elements:
  - {name: spring, type: beam, nodes: [root, n1, n2, n3, tip], E: 1.0e6, inertia: none,
     section: {area: 1.0e-4, inertia: 1.0e-9}}
  - {name: mass, type: rigid_bar, nodes: [tip, anchor], mass: 3.0}
parameters:
  - {name: A, of: spring, property: area}
  - {name: m, of: mass, property: mass}
integrator: {type: trapezoidal, t_end: 0.5, dt: 0.005}
outputs:
  - {name: x_tip, node: tip, component: x}
  - {name: x_n2, node: n2, component: x}
objectives:
  - {name: x_end, terminal: {output: x_tip}}
  - {name: x_n2_sq, integral: {output: x_n2, power: 2}}
)";

TEST(Gradient, MasslessCoordinatesAdjointEqualsForwardAndDifferences) {
  for (const std::string integrator : {"trapezoidal", "bdf1"}) {
    const Scene sc = sceneWith(kMasslessSpring, "massless.yaml", "", 0.0, integrator);
    const GradientResult fw = gradients(sc, "forward"), adj = gradients(sc, "adjoint", 13);
    EXPECT_LT(worstRelative(adj, fw, 1e-12), 1e-8) << integrator;
    for (int k = 0; k < 2; ++k) {
      const double d = 1e-4 * std::abs(sc.model->nominalParameters()[k]);
      const std::vector<double> plus = perturbedValues(sc, k, d), minus = perturbedValues(sc, k, -d);
      for (size_t i = 0; i < 2; ++i) {
        const double nd = (plus[i] - minus[i]) / (2 * d);
        EXPECT_NEAR(adj.objectives[i].gradient[k], nd, 1e-5 * std::abs(nd) + 1e-12) << integrator << " " << i << " " << k;
      }
    }
  }
}

// ------------------------------------------------------------------ (c1) per-element parameters
/// The per-element tests' integrator, tip output along `axis` and two objectives of it.
std::string tipObjectives(const std::string& axis) {
  return "integrator: {type: trapezoidal, t_end: 0.05, dt: 0.001, newton: full}\noutputs:\n"
         "  - {name: tip_" + axis + ", node: tip, component: " + axis + "}\nobjectives:\n"
         "  - {name: tip_end, terminal: {output: tip_" + axis + "}}\n"
         "  - {name: tip_sq, integral: {output: tip_" + axis + ", power: 2}}\n";
}

/// Adjoint against forward for every parameter, and against central differences of whole runs
/// (relative step `rel` of the nominal value) for the parameters with the largest and the
/// smallest adjoint gradient of objective 0.
void checkPerElementGradients(const Scene& sc, double rel) {
  const GradientResult fw = gradients(sc, "forward"), adj = gradients(sc, "adjoint", 7);
  EXPECT_LT(worstRelative(adj, fw, 1e-6 * fw.objectives[0].gradient.cwiseAbs().maxCoeff()), 1e-8);
  Eigen::Index largest, smallest;
  adj.objectives[0].gradient.cwiseAbs().maxCoeff(&largest);
  adj.objectives[0].gradient.cwiseAbs().minCoeff(&smallest);
  for (const Eigen::Index k : {largest, smallest}) {
    const double d = rel * sc.model->parameters[size_t(k)].nominal;
    const std::vector<double> plus = perturbedValues(sc, int(k), d), minus = perturbedValues(sc, int(k), -d);
    for (size_t i = 0; i < adj.objectives.size(); ++i) {
      const double nd = (plus[i] - minus[i]) / (2 * d), scale = adj.objectives[i].gradient.cwiseAbs().maxCoeff();
      std::printf("%s, objective %zu: adjoint %.9e, central differences %.9e (largest %.3e)\n",
                  sc.model->parameters[size_t(k)].name.c_str(), i, adj.objectives[i].gradient[k], nd, scale);
      EXPECT_NEAR(adj.objectives[i].gradient[k], nd, 1e-5 * scale) << sc.model->parameters[size_t(k)].name << " " << i;
    }
  }
}

TEST(Gradient, PerElementThicknessOfASolidPlate) {
  // A planar cantilever plate of linear triangles under gravity, one thickness parameter per
  // cell: the adjoint equals the forward gradient for every cell, and central differences of
  // whole runs for a cell at the root and one at the tip.
  const std::string text = R"(dimension: 2
gravity: [0, -9.81]
elements:
  - {name: plate, type: solid, mesh: plate.geo, group: plate, size: 0.05, E: 2.0e6, nu: 0.3, density: 1000,
     thickness: 0.01, ground: [root]}
parameters:
  - {name: t, of: plate, property: thickness, per: element}
integrator: {type: trapezoidal, t_end: 0.05, dt: 0.001, newton: full}
outputs:
  - {name: tip_y, node: tipmid, component: y}
objectives:
  - {name: tip_end, terminal: {output: tip_y}}
  - {name: tip_sq, integral: {output: tip_y, power: 2}}
)";
  const Scene sc = sceneWith(text, std::string(FLEXSENS_SOURCE_DIR) + "/tests/scenes/solid/per_element.yaml", "");
  const Model& m = *sc.model;
  int cells = 0;
  for (const auto& e : m.elements) cells += e->kind() == "solid";
  ASSERT_GT(cells, 20);
  ASSERT_EQ(int(m.parameters.size()), cells);
  EXPECT_EQ(m.parameters[3].name, "t[3]");
  EXPECT_EQ(m.parameters[3].boundTo, "plate.thickness[3]");
  const GradientResult adj = gradients(sc, "adjoint", 9);
  // gradient.vtu: each solid cell carries the gradient of its own parameter.
  const std::string vtu = testing::TempDir() + "flexsens_gradient_field.vtu";
  writeGradientVtu(vtu, vtu, m, {{"tip_end", adj.objectives[0].gradient}});
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(vtu.c_str());
  reader->Update();
  vtkUnstructuredGrid* grid = reader->GetOutput();
  auto* field = grid->GetCellData()->GetArray("dtip_end/dt");
  auto* ids = grid->GetCellData()->GetArray("element_id");
  ASSERT_NE(field, nullptr);
  ASSERT_NE(ids, nullptr);
  int matched = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    for (size_t k = 0; k < m.parameters.size(); ++k)
      if (m.parameters[k].element == int(ids->GetTuple1(c))) {
        EXPECT_EQ(field->GetTuple1(c), adj.objectives[0].gradient[Eigen::Index(k)]);
        ++matched;
      }
  EXPECT_EQ(matched, cells);
  std::filesystem::remove(vtu);
  checkPerElementGradients(sc, 1e-5);
}

TEST(Gradient, PerElementThicknessOfAKirchhoffShell) {
  // A clamped strip of Kirchhoff shell triangles sagging under gravity, one thickness per
  // triangle (its membrane, bending and mass): each triangle's three elements share the
  // parameter, which the strip's gradient field (gradient.vtu) shows on the triangle.
  const std::string text = R"(dimension: 3
gravity: [0, 0, -9.81]
elements:
  - {name: strip, type: shell, mesh: strip.geo, group: strip, size: 0.25, bending: kirchhoff,
     E: 2.0e8, nu: 0.3, density: 1000, thickness: 0.01, clamp: [root]}
parameters:
  - {name: t, of: strip, property: thickness, per: element}
integrator: {type: trapezoidal, t_end: 0.02, dt: 0.001, newton: full}
outputs:
  - {name: tip_z, node: tip, component: z}
objectives:
  - {name: tip_end, terminal: {output: tip_z}}
  - {name: tip_sq, integral: {output: tip_z, power: 2}}
)";
  const Scene sc = sceneWith(text, std::string(FLEXSENS_SOURCE_DIR) + "/tests/scenes/shell/per_element.yaml", "");
  const Model& m = *sc.model;
  int triangles = 0;
  for (const auto& e : m.elements) triangles += e->name().find(".tri") != std::string::npos;
  ASSERT_GT(triangles, 10);
  ASSERT_EQ(int(m.parameters.size()), triangles);
  for (const auto& par : m.parameters) EXPECT_NE(m.elements[size_t(par.element)]->name().find(".tri"), std::string::npos);
  checkPerElementGradients(sc, 1e-5);
}

TEST(Gradient, PerElementModulusOfAncfChains) {
  // A 3D ancf_beam cantilever (E per element) and a planar ancf_cable one (density per
  // element) under gravity.
  const std::string beam = R"(dimension: 3
gravity: [0, 0, -9.81]
nodes:
  - {name: A, position: [0, 0, 0], ground: true, clamped: true}
  - {name: n1, position: [0.25, 0, 0]}
  - {name: n2, position: [0.5, 0, 0]}
  - {name: n3, position: [0.75, 0, 0]}
  - {name: tip, position: [1, 0, 0]}
elements:
  - {name: arm, type: ancf_beam, nodes: [A, n1, n2, n3, tip], E: 2.0e7, nu: 0.3, density: 1000,
     section: {width: 0.02, height: 0.03}}
parameters:
  - {name: E, of: arm, property: E, per: element}
)" + tipObjectives("z");
  const Scene b = sceneWith(beam, "beam_per_element.yaml", "");
  ASSERT_EQ(b.model->parameters.size(), 4u);
  EXPECT_EQ(b.model->parameters[2].boundTo, "arm.E[2]");
  checkPerElementGradients(b, 1e-6);
  const std::string cable = R"(dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: A, position: [0, 0], ground: true, clamped: true}
  - {name: n1, position: [0.3, 0]}
  - {name: n2, position: [0.6, 0]}
  - {name: tip, position: [0.9, 0]}
elements:
  - {name: rope, type: ancf_cable, nodes: [A, n1, n2, tip], E: 5.0e6, density: 800, section: {side: 0.02}}
parameters:
  - {name: rho, of: rope, property: density, per: element}
)" + tipObjectives("y");
  const Scene c = sceneWith(cable, "cable_per_element.yaml", "");
  ASSERT_EQ(c.model->parameters.size(), 3u);
  checkPerElementGradients(c, 1e-6);
}

TEST(Gradient, PerElementParametersOfPositionsOnlyBeams) {
  // Planar and spatial positions-only beams clamped at the start, one E (planar) or side
  // (spatial) per segment: a hinge bends with its two segments' length-weighted mean EI.
  const std::string planar = R"(dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: n1, position: [0.2, 0]}
  - {name: n2, position: [0.45, 0]}
  - {name: n3, position: [0.7, 0]}
  - {name: tip, position: [1.0, 0]}
elements:
  - {name: arm, type: beam, nodes: [A, n1, n2, n3, tip], E: 2.0e7, density: 1000, section: {side: 0.02}, clamp: start}
parameters:
  - {name: E, of: arm, property: E, per: element}
)" + tipObjectives("y");
  const Scene b2 = sceneWith(planar, "beam2d_per_element.yaml", "");
  ASSERT_EQ(b2.model->parameters.size(), 4u);
  EXPECT_EQ(b2.model->parameters[3].boundTo, "arm.E[3]");
  checkPerElementGradients(b2, 1e-6);
  std::string spatial = planar;
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"dimension: 2", "dimension: 3"}, {"gravity: [0, -9.81]", "gravity: [0, 0, -9.81]"},
           {", 0]}", ", 0, 0]}"}, {"[0, 0], ground", "[0, 0, 0], ground"},
           {"{name: E, of: arm, property: E, per", "{name: a, of: arm, property: side, per"}, {"component: y}", "component: z}"}})
    for (size_t at = spatial.find(from); at != std::string::npos; at = spatial.find(from, at + to.size()))
      spatial.replace(at, from.size(), to);
  const Scene b3 = sceneWith(spatial, "beam3d_per_element.yaml", "");
  ASSERT_EQ(b3.model->parameters.size(), 4u);
  checkPerElementGradients(b3, 1e-6);
}

// ------------------------------------------------------------------ (c3) angle outputs
const char* kChain3d = R"(dimension: 3
gravity: [0, 0, -9.81]
nodes:
  - {name: O, position: [0, 0, 0], ground: true}
  - {name: P, position: [0, 0, 1]}
  - {name: Q, position: [1, 0, 1]}
  - {name: R, position: [1, 1, 1.2]}
elements:
  - {name: b1, type: rigid_bar, nodes: [O, P], mass: 1}
  - {name: b2, type: rigid_bar, nodes: [P, Q], mass: 1}
  - {name: b3, type: rigid_bar, nodes: [Q, R], mass: 1}
parameters:
  - {name: L3, of: b3, property: length}
  - {name: m2, of: b2, property: mass}
integrator: {type: trapezoidal, t_end: 0.5, dt: 0.005}
outputs:
  - {name: th, angle: {axis: [O, P], from: [P, Q], to: [Q, R]}}
  - {name: thd, angle: {axis: [O, P], from: [P, Q], to: [Q, R]}, quantity: velocity}
objectives:
  - {name: rate_end, terminal: {output: thd}}
  - {name: th_sq, integral: {output: th, power: 2}}
)";

TEST(Gradient, AngleAndAngleRateOutputs) {
  // The outputs' gradients in q and v (the adjoint's sources) against their derivative along a
  // direction, then the adjoint against the forward gradient through them.
  const Scene sc = sceneWith(kChain3d, "chain.yaml", "");
  const Model& m = *sc.model;
  Assembler as(m);
  const StateWithSens start = initialState(as, m.nominalParameters());
  State x = start.x, dx;
  x.v = VecX::LinSpaced(m.n, -1.0, 2.0);
  dx.q = VecX::LinSpaced(m.n, 0.3, -0.7);
  dx.v = VecX::LinSpaced(m.n, 1.1, 0.2);
  for (const OutputSpec& o : sc.outputs) {
    VecX gq = VecX::Zero(m.n), gv = VecX::Zero(m.n);
    o.addGradient(m, x, 1.0, gq, gv);
    EXPECT_NEAR(gq.dot(dx.q) + gv.dot(dx.v), o.derivative(m, x, dx), 1e-13) << o.name;
  }
  const GradientResult fw = gradients(sc, "forward"), adj = gradients(sc, "adjoint", 11);
  EXPECT_LT(worstRelative(adj, fw, 1e-6), 1e-8);
  EXPECT_GT(adj.objectives[0].gradient.cwiseAbs().maxCoeff(), 1e-3);  // the rate does depend on L3
}

// ------------------------------------------------------------------ (c2) statics
/// A planar cantilever of 8 beam segments, clamped, tip load Fy; parameters E and Fy.
std::string cantilever(const std::string& statics, double P) {
  std::ostringstream s;
  s << "dimension: 2\nnodes:\n  - {name: root, position: [0, 0], ground: true}\n";
  for (int i = 1; i <= 8; ++i) s << "  - {name: n" << i << ", position: [" << i / 8.0 << ", 0]}\n";
  s << "elements:\n  - {name: beam, type: beam, clamp: start, E: 2.0e9, density: 1000, section: {side: 0.01}, nodes: [root";
  for (int i = 1; i <= 8; ++i) s << ", n" << i;
  s << "]}\n  - {name: load, type: point_force, node: n8, force: [0, " << -P << "]}\n"
    << "parameters:\n  - {name: E, of: beam, property: E}\n  - {name: Fy, of: load, property: y}\n"
    << "static: " << statics << "\noutputs:\n  - {name: tip_y, node: n8, component: y}\n"
    << "objectives:\n  - {name: tip, terminal: {output: tip_y}}\n  - {name: twice, sum: [{objective: tip, weight: 2}]}\n";
  return s.str();
}

TEST(Gradient, StaticTerminalObjectiveOfALinearCantilever) {
  // Linear statics: K u = f with K proportional to E and f to Fy, so J = tip_y is exactly
  // proportional to Fy / E: dJ/dE = -J/E, dJ/dFy = J/Fy.
  const Scene sc = readSceneText(cantilever("{linear: true}", 2.0), "cantilever.yaml");
  const GradientResult r = gradients(sc, "adjoint");
  ASSERT_EQ(r.objectives.size(), 2u);
  const double J = r.objectives[0].value;
  EXPECT_LT(J, 0.0);
  EXPECT_NEAR(r.objectives[0].gradient[0], -J / 2.0e9, 1e-9 * std::abs(J / 2.0e9));
  EXPECT_NEAR(r.objectives[0].gradient[1], J / -2.0, 1e-9 * std::abs(J / 2.0));
  EXPECT_DOUBLE_EQ(r.objectives[1].value, 2.0 * J);
  EXPECT_EQ(r.method, "static");
}

TEST(Gradient, StaticTerminalObjectiveAgainstDifferencesOfEquilibria) {
  // Large deflection (load steps): dJ/dp against central differences of whole static solves.
  const std::string text = cantilever("{load_steps: 5}", 20.0);
  const Scene sc = readSceneText(text, "cantilever.yaml");
  const GradientResult r = gradients(sc, "adjoint");
  const VecX p0 = sc.model->nominalParameters();
  for (int k = 0; k < 2; ++k) {
    const double d = 1e-5 * std::abs(p0[k]);
    double J[2];
    for (int s = 0; s < 2; ++s) {
      const Scene moved = readSceneText(text, "cantilever.yaml", "", {{k ? "Fy" : "E", p0[k] + (s ? -d : d)}});
      J[s] = gradients(moved, "adjoint").objectives[0].value;
    }
    const double nd = (J[0] - J[1]) / (2 * d);
    EXPECT_NEAR(r.objectives[0].gradient[k], nd, 1e-6 * std::abs(nd)) << k;
  }
  // A static-only scene has no time: an integral objective is an input error when read.
  EXPECT_THROW(readSceneText(text + "  - {name: area, integral: {output: tip_y}}\n", "cantilever.yaml"), InputError);
}

// ------------------------------------------------------------------ (d) errors
TEST(Gradient, MethodWithoutAdjointIsAnInputErrorNamingThoseWithOne) {
  const Scene sc = sceneWith(kFreeFall, "fall.yaml", "", 0.0, "maggi_rk4");
  try {
    gradients(sc, "adjoint");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("maggi_rk4"), std::string::npos) << what;
    EXPECT_NE(what.find(kAdjointIntegrators), std::string::npos) << what;
  }
  Scene projected = sceneWith(kFreeFall, "fall.yaml", "");
  projected.integrator.projections = true;
  EXPECT_THROW(gradients(projected, "adjoint"), InputError);
  GradientRequest unknown;
  unknown.objective = "nothing";
  EXPECT_THROW(computeGradients(sceneWith(kFreeFall, "fall.yaml", ""), unknown), InputError);
}

/// Runs `flexsens <args>` with stdout and stderr into files of `dir`; returns the exit status.
int flexsensCli(const std::string& args, const std::string& dir, std::string& err) {
  const std::string cmd = std::string(FLEXSENS_EXE) + " " + args + " >" + dir + "/out.txt 2>" + dir + "/err.txt";
  const int st = std::system(cmd.c_str());
  err = fileText(dir + "/err.txt");
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

TEST(GradientCli, WritesGradientJsonAndRefusesAMethodWithoutAdjoint) {
  const std::string dir = testing::TempDir() + "flexsens_gradient_cli";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/fall.yaml") << kFreeFall;
  std::string err;
  ASSERT_EQ(flexsensCli("gradient " + dir + "/fall.yaml --objective end --out " + dir + "/g", dir, err), 0) << err;
  const std::string json = fileText(dir + "/g/gradient.json");
  EXPECT_EQ(json.rfind("{\"objective\": \"end\", \"value\": -4.905, \"gradient\": {\"gy\": 0.5}, \"statistics\": {", 0), 0u) << json;
  // maggi_rk4 has no discrete adjoint: exit 1, the message names the integrators that have one.
  EXPECT_EQ(flexsensCli("gradient " + dir + "/fall.yaml --integrator maggi_rk4 --out " + dir + "/h", dir, err), 1);
  EXPECT_NE(err.find(std::string("has no discrete adjoint; the methods that have one: ") + kAdjointIntegrators), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/h"));
  EXPECT_EQ(flexsensCli("gradient " + dir + "/fall.yaml --objective nothing --out " + dir + "/h", dir, err), 1);
  EXPECT_NE(err.find("its objectives: end, mid, area, track, both"), std::string::npos) << err;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace flexsens
