// Displacement outputs and the linear (small-displacement) static mode, on a plane-stress patch
// under a uniform end traction whose linear solution is exact on any triangle mesh (constant
// strain): u_x = sigma x / E, u_y = -nu sigma y / E with sigma = F / (H t). The sensitivities
// are checked against that closed form and against central differences of the solution.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "app/StaticRun.hpp"
#include "integrators/Static.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;

namespace {

constexpr double kE = 1000.0, kNu = 0.25, kT = 0.1, kL = 2.0, kH = 1.0;  // [Pa], [-], [m], [m], [m]

/// The patch (tests/scenes/statics/patch.geo) held at its left corners, traction F [N] on the
/// right edge; parameters E and nu; outputs of the corner C = (L, H).
std::string patchScene(double F, const std::string& statics) {
  std::ostringstream s;
  s.precision(17);
  s << "dimension: 2\nelements:\n  - {name: patch, type: solid, mesh: " << FLEXSENS_SOURCE_DIR
    << "/tests/scenes/statics/patch.geo, group: patch, size: 0.5, E: " << kE << ", nu: " << kNu
    << ", density: 1, thickness: " << kT << ", traction: [{group: right, force: [" << F << ", 0]}]}\n";
  s << "constraints:\n";
  for (const char* c : {"A x", "A y", "B x"}) {
    const std::string cs(c);
    s << "  - {name: " << cs[0] << cs[2] << ", type: prescribed_coordinate, node: " << cs[0] << ", axis: " << cs[2]
      << ", function: {type: constant, value: 0}}\n";
  }
  s << "parameters:\n  - {name: E, of: patch, property: E}\n  - {name: nu, of: patch, property: nu}\n";
  s << "static: " << statics << "\n";
  s << "outputs:\n  - {name: ux, node: C, component: x, quantity: displacement}\n"
    << "  - {name: uy, node: C, component: y, quantity: displacement}\n  - {name: y, node: C, component: y}\n";
  return s.str();
}

/// The last row of a static run, by column name.
struct LastRow : RunListener {
  std::vector<std::string> columns;
  std::vector<double> row;
  void started(const std::vector<std::string>& c) override { columns = c; }
  void frame(const StateWithSens&, const std::vector<double>& r) override { row = r; }
  double operator[](const std::string& name) const {
    for (size_t i = 0; i < columns.size(); ++i)
      if (columns[i] == name) return row.at(i);
    ADD_FAILURE() << "no column " << name;
    return NAN;
  }
};

LastRow runScene(const std::string& text, int steps) {
  const Scene sc = readSceneText(text, "patch.yaml");
  LastRow last;
  runStaticScene(sc, "", steps, &last);
  return last;
}

/// The outputs ux, uy of the linear or nonlinear solution at parameters p.
Eigen::Vector2d outputsAt(const Scene& sc, const VecX& p, bool linear) {
  const Model& m = *sc.model;
  Assembler as(m);
  StaticSettings set;
  set.steps = 1;
  set.stepLoadFactor = true;
  const VecX q = linear ? solveLinearStatic(as, p, m.initialPositions(), 0.0)
                        : solveStatic(as, p, m.initialPositions(), set);
  State x;
  x.q = q;
  x.v = VecX::Zero(m.n);
  return Eigen::Vector2d(sc.outputs[0].value(m, x), sc.outputs[1].value(m, x));
}

/// Central differences of (ux, uy) with respect to parameter k (relative step 1e-5).
Eigen::Vector2d centralDifference(const Scene& sc, int k, bool linear) {
  const VecX p = sc.model->nominalParameters();
  const double h = 1e-5 * std::abs(p[k]);
  VecX pp = p, pm = p;
  pp[k] += h;
  pm[k] -= h;
  return (outputsAt(sc, pp, linear) - outputsAt(sc, pm, linear)) / (2.0 * h);
}

}  // namespace

// linear: true reproduces the constant-strain solution and its closed-form sensitivities, and
// they agree with central differences of the linear solve.
TEST(LinearStatic, PatchMatchesTheClosedFormAndItsDerivatives) {
  const double F = 50.0, sigma = F / (kH * kT);
  const std::string text = patchScene(F, "{linear: true}");
  const LastRow r = runScene(text, 1);
  const double ux = sigma * kL / kE, uy = -kNu * sigma * kH / kE;
  EXPECT_NEAR(r["ux"], ux, 1e-12 * std::abs(ux));
  EXPECT_NEAR(r["uy"], uy, 1e-12 * std::abs(uy));
  EXPECT_NEAR(r["y"] - kH, uy, 1e-12 * std::abs(uy));  // displacement = position - rest
  EXPECT_NEAR(r["dux/dE"], -ux / kE, 1e-9 * std::abs(ux / kE));
  EXPECT_NEAR(r["duy/dE"], -uy / kE, 1e-9 * std::abs(uy / kE));
  EXPECT_NEAR(r["dux/dnu"], 0.0, 1e-9 * std::abs(ux));
  EXPECT_NEAR(r["duy/dnu"], -sigma * kH / kE, 1e-9 * sigma * kH / kE);
  const Scene sc = readSceneText(text, "patch.yaml");
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d fd = centralDifference(sc, k, true);
    const std::string par = k ? "nu" : "E";
    EXPECT_NEAR(r["dux/d" + par], fd[0], 1e-6 * std::abs(ux / (k ? kNu : kE)) + 1e-12) << par;
    EXPECT_NEAR(r["duy/d" + par], fd[1], 1e-6 * std::abs(uy / (k ? kNu : kE))) << par;
  }
}

// The nonlinear solve at a small load (strain 1e-6) agrees with the linear one to the strain's
// order; at a strain of 5% they differ by more than 1% (the linear mode is not the nonlinear).
TEST(LinearStatic, AgreesWithTheNonlinearSolveAtSmallLoads) {
  const double small = 1e-6 * kE * kH * kT, large = 0.05 * kE * kH * kT;
  const LastRow ls = runScene(patchScene(small, "{linear: true}"), 1);
  const LastRow ns = runScene(patchScene(small, "{load_steps: 1}"), 1);
  EXPECT_NEAR(ns["ux"], ls["ux"], 1e-5 * std::abs(ls["ux"]));
  EXPECT_NEAR(ns["uy"], ls["uy"], 1e-5 * std::abs(ls["uy"]));
  EXPECT_NEAR(ns["dux/dE"], ls["dux/dE"], 1e-5 * std::abs(ls["dux/dE"]));
  const LastRow ll = runScene(patchScene(large, "{linear: true}"), 1);
  const LastRow nl = runScene(patchScene(large, "{load_steps: 5}"), 5);
  EXPECT_NEAR(ll["ux"], 50.0 * ls["ux"] * 1000.0, 1e-9 * std::abs(ll["ux"]));  // linear in the load
  EXPECT_GT(std::abs(nl["ux"] - ll["ux"]), 0.01 * std::abs(ll["ux"]));
}

// Displacement outputs of the nonlinear static solve: the position minus the rest position,
// with sensitivities equal to central differences of the displacements.
TEST(DisplacementOutput, NonlinearSensitivitiesMatchCentralDifferences) {
  const double F = 0.02 * kE * kH * kT;
  const std::string text = patchScene(F, "{load_steps: 1}");
  const LastRow r = runScene(text, 1);
  EXPECT_NEAR(r["uy"], r["y"] - kH, 1e-14);
  const Scene sc = readSceneText(text, "patch.yaml");
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d fd = centralDifference(sc, k, false);
    const std::string par = k ? "nu" : "E";
    const double scale = std::abs(r["ux"]) / (k ? kNu : kE);
    EXPECT_NEAR(r["dux/d" + par], fd[0], 1e-6 * scale) << par;
    EXPECT_NEAR(r["duy/d" + par], fd[1], 1e-6 * scale) << par;
    EXPECT_NEAR(r["dy/d" + par], r["duy/d" + par], 1e-15 * scale) << par;
  }
}

// The linear sensitivities where the stiffness is not proportional to the parameter (a shell's
// thickness: membrane ~ t, bending ~ t^3, so Q_qp u matters) and a constraint's value is one
// (the prescribed axial position of the loaded point: Phi_p): against central differences of
// the linear solve of the pinched cylinder (8 x 32 lattice).
TEST(LinearStatic, ShellThicknessAndDriverSensitivitiesMatchCentralDifferences) {
  const std::string file = std::string(FLEXSENS_SOURCE_DIR) + "/tests/scenes/statics/cylinder_8.yaml";
  std::stringstream all;
  all << std::ifstream(file).rdbuf();
  std::string text = all.str();
  const std::string steps = "static: {load_steps: 1}";
  ASSERT_NE(text.find(steps), std::string::npos);
  text.replace(text.find(steps), steps.size(),
               "static: {linear: true}\nparameters:\n  - {name: t, of: shell, property: thickness}\n"
               "  - {name: d, of: axial_top, property: value}");
  const Scene sc = readSceneText(text, file);
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = m.nominalParameters(), q0 = m.initialPositions();
  StaticReport rep;
  const VecX q = solveLinearStatic(as, p, q0, 0.0, &rep);
  const StaticSensitivity d = linearStaticSensitivities(as, q0, q, rep.lambda, p);
  for (int k = 0; k < 2; ++k) {
    // q ~ 300 m carries round-off ~7e-14 m: the steps keep it and the truncation below 1e-5.
    const double h = k == 0 ? 5e-4 * p[0] : 1e-6;
    VecX pp = p, pm = p;
    pp[k] += h;
    pm[k] -= h;
    const VecX fd = (solveLinearStatic(as, pp, q0, 0.0) - solveLinearStatic(as, pm, q0, 0.0)) / (2.0 * h);
    const double scale = fd.lpNorm<Eigen::Infinity>();
    ASSERT_GT(scale, 0.0) << k;
    EXPECT_LT((d.qp.col(k) - fd).lpNorm<Eigen::Infinity>(), 1e-5 * scale) << "parameter " << k;
  }
}
