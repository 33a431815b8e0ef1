// A free meshed body in free flight (no gravity, no supports) with the trapezoidal rule: the
// exact solution conserves energy and linear and angular momentum. The scheme (Newmark
// beta = 1/4, gamma = 1/2) conserves linear momentum exactly (internal forces sum to zero);
// its energy error is O(dt^2) for nonlinear elasticity: halving dt must divide the largest
// energy deviation by ~4 (asserted: between 3 and 5). Angular momentum is not conserved by
// this scheme: its error is O(dt^2) as well (measured: 1.65e-5 and 4.15e-6 of L0 = 5.5e-2
// kg m^2/s at dt = 10 and 5 ms, ratio 3.98; energy 3.30e-5 and 8.29e-6 J of 0.109 J).
// Plus: an element turned inside out names the element (and, in a run, the time and step).
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "TestModels.hpp"
#include "core/Assembler.hpp"
#include "elements/Solid.hpp"
#include "integrators/FixedStep.hpp"
#include "integrators/InitialState.hpp"
#include "app/FiniteDifferences.hpp"
#include "app/Run.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;

namespace {

std::string dirOf() { return std::string(FLEXSENS_SOURCE_DIR) + "/tests/scenes/solid/"; }

/// A soft neo-Hookean plate (1 x 0.05 m, 6-node triangles) spinning at 2 rad/s about its
/// centre and translating: the centrifugal load stretches it (strain ~1e-2), which sets off
/// axial and bending vibration.
std::string spinningPlate(double dt, const std::string& type = "trapezoidal") {
  std::ostringstream s;
  s << "dimension: 2\nelements:\n  - {name: plate, type: solid, mesh: plate.geo, group: plate, size: 0.05, order: 2,"
       " material: neo_hookean, E: 1.0e6, nu: 0.3, density: 1000, thickness: 0.01,"
       " velocity: [0.3, -0.1], angular_velocity: 2, center: [0.5, 0.025]}\n"
    << "integrator: {type: " << type << ", t_end: 0.5, dt: " << dt << ", frame_interval: " << dt << "}\n";
  return s.str();
}

struct Flight {
  double maxEnergyDev = 0, maxP = 0, maxL = 0, E0 = 0, P0 = 0, L0 = 0;
};

/// The flight of the scene `text` (default: spinningPlate); maxP is measured against the plate's
/// m v0 when `text` is empty, else against the first frame's momentum.
Flight fly(double dt, const std::string& type = "trapezoidal", const std::string& text = "",
           const std::string& newton = "") {
  Scene sc = readSceneText(text.empty() ? spinningPlate(dt, type) : text, dirOf() + "scene.yaml");
  if (!newton.empty()) sc.integrator.newton = newton;
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = m.nominalParameters();
  StateWithSens start = initialState(as, p);
  start.dp.clear();
  test::Recorder rec;
  integrateFixedStep(as, p, start, sc.integrator, rec);
  const SpMat M = as.mass(p);
  Flight f;
  bool first = true;
  double P0x = 0, P0y = 0;
  for (const auto& fr : rec.frames) {
    const VecX Mv = M * fr.x.v;
    const double E = 0.5 * fr.x.v.dot(Mv) + as.potentialEnergy(fr.x.q, p);
    double Px = 0, Py = 0, L = 0;
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      const int d = m.dof(static_cast<int>(i), 0);
      Px += Mv[d];
      Py += Mv[d + 1];
      L += fr.x.q[d] * Mv[d + 1] - fr.x.q[d + 1] * Mv[d];
    }
    if (first) {
      f.E0 = E;
      f.P0 = std::hypot(Px, Py);
      f.L0 = L;
      P0x = text.empty() ? 0.3 * 0.5 : Px;  // m v0, m = 0.5 kg
      P0y = text.empty() ? -0.1 * 0.5 : Py;
      first = false;
    }
    f.maxEnergyDev = std::max(f.maxEnergyDev, std::abs(E - f.E0));
    f.maxP = std::max(f.maxP, std::hypot(Px - P0x, Py - P0y));
    f.maxL = std::max(f.maxL, std::abs(L - f.L0));
  }
  return f;
}

}  // namespace

TEST(SolidDynamics, FreeFlightConservesMomentumAndEnergyToSecondOrder) {
  const Flight a = fly(0.01), b = fly(0.005);
  std::printf("E0 %.6e J, |P0| %.6e, L0 %.6e; dt 0.01: max |dE| %.3e J, |dP| %.2e, |dL| %.3e; dt 0.005: %.3e, %.2e, %.3e; "
              "energy ratio %.2f, angular-momentum ratio %.2f\n",
              a.E0, a.P0, a.L0, a.maxEnergyDev, a.maxP, a.maxL, b.maxEnergyDev, b.maxP, b.maxL,
              a.maxEnergyDev / b.maxEnergyDev, a.maxL / std::max(b.maxL, 1e-300));
  EXPECT_LT(a.maxP, 1e-12);  // linear momentum: the mass 0.5 kg times the initial velocity, to round-off
  EXPECT_LT(b.maxP, 1e-12);
  const double ratio = a.maxEnergyDev / b.maxEnergyDev;
  EXPECT_GT(ratio, 3.0);
  EXPECT_LT(ratio, 5.0);
  EXPECT_LT(a.maxEnergyDev, 1e-2 * a.E0);
  const double ratioL = a.maxL / b.maxL;
  EXPECT_GT(ratioL, 3.0);
  EXPECT_LT(ratioL, 5.0);
}

// The plate welded by its root edge (attach) to a planar rigid body flying with it: the
// attachment rows (linear in the body's natural coordinates) and the body's distance row are
// frame-indifferent, so their forces have no net force or moment: the trapezoidal rule keeps
// the linear momentum to round-off and the energy and angular-momentum errors second order (a
// wrong attachment coefficient would make the start inconsistent: Phi(q0) = 0 is checked).
TEST(SolidDynamics, PlateAttachedToAFlyingRigidBodyConservesMomentum) {
  auto scene = [](double dt) {
    std::ostringstream s;
    s << "dimension: 2\nnodes:\n  - {name: A, position: [-0.1, 0], velocity: [0.35, -1.3]}\n"
         "  - {name: B, position: [-0.1, 0.05], velocity: [0.25, -1.3]}\nelements:\n"
         "  - {name: hub, type: planar_rigid_body, nodes: [A, B], mass: 0.4, center_of_mass: [-0.15, 0.025],"
         " inertia: 2e-3}\n"
         "  - {name: plate, type: solid, mesh: plate.geo, group: plate, size: 0.05, order: 2, material: neo_hookean,"
         " E: 1.0e6, nu: 0.3, density: 1000, thickness: 0.01, attach: [{group: root, body: hub}],"
         " velocity: [0.3, -0.1], angular_velocity: 2, center: [0.5, 0.025]}\n"
      << "integrator: {type: trapezoidal, t_end: 0.5, dt: " << dt << ", frame_interval: " << dt << "}\n";
    return s.str();
  };
  {
    const Scene sc = readSceneText(scene(0.01), dirOf() + "scene.yaml");
    Assembler as(*sc.model);
    EXPECT_LT(as.phi(sc.model->initialPositions(), sc.model->nominalParameters()).lpNorm<Eigen::Infinity>(), 1e-14);
  }
  const Flight a = fly(0.01, "trapezoidal", scene(0.01)), b = fly(0.005, "trapezoidal", scene(0.005));
  std::printf("attached: E0 %.6e J, |P0| %.6e, L0 %.6e; dt 0.01: max |dE| %.3e J, |dP| %.2e, |dL| %.3e; dt 0.005: "
              "%.3e, %.2e, %.3e\n", a.E0, a.P0, a.L0, a.maxEnergyDev, a.maxP, a.maxL, b.maxEnergyDev, b.maxP, b.maxL);
  EXPECT_LT(a.maxP, 1e-12 * a.P0);
  EXPECT_LT(b.maxP, 1e-12 * b.P0);
  EXPECT_GT(a.maxEnergyDev / b.maxEnergyDev, 3.0);
  EXPECT_LT(a.maxEnergyDev / b.maxEnergyDev, 5.0);
  EXPECT_GT(a.maxL / b.maxL, 3.0);
  EXPECT_LT(a.maxL / b.maxL, 5.0);
}

// The implicit midpoint rule (integrator midpoint) on the same free flight: a symplectic
// Runge-Kutta method conserves every quadratic invariant, so linear and angular momentum stay
// at their initial values to round-off (the internal forces of a frame-indifferent energy have
// no net force or moment at the midpoint configuration); the energy error stays bounded and
// second order (halving dt divides it by 3..5). Round-off needs full Newton: the modified
// Newton iteration a meshed body gets by default stops at the tolerance (|dL| 3e-11 .. 3e-10 of
// L0 5e-2 measured), the documented exception to that default.
TEST(SolidDynamics, MidpointRuleConservesAngularMomentumToRoundOff) {
  const Flight a = fly(0.01, "midpoint", "", "full"), b = fly(0.005, "midpoint", "", "full");
  std::printf("midpoint: L0 %.6e; dt 0.01: max |dE| %.3e J, |dP| %.2e, |dL| %.3e; dt 0.005: %.3e, %.2e, %.3e\n", a.L0,
              a.maxEnergyDev, a.maxP, a.maxL, b.maxEnergyDev, b.maxP, b.maxL);
  EXPECT_LT(a.maxP, 1e-12);
  EXPECT_LT(b.maxP, 1e-12);
  EXPECT_LT(a.maxL, 1e-12 * std::abs(a.L0));
  EXPECT_LT(b.maxL, 1e-12 * std::abs(b.L0));
  const double ratio = a.maxEnergyDev / b.maxEnergyDev;
  EXPECT_GT(ratio, 3.0);
  EXPECT_LT(ratio, 6.0);  // measured 4.95
}

// A scene with a meshed body and no `integrator.newton` gets modified Newton, one without
// keeps full Newton, and a given `newton` wins; modified Newton's free flight keeps the
// momentum to its tolerance and agrees with full Newton's energy error.
TEST(SolidDynamics, MeshedBodiesDefaultToModifiedNewton) {
  const Scene meshed = readSceneText(spinningPlate(0.01, "trapezoidal"), dirOf() + "scene.yaml");
  EXPECT_EQ(meshed.integrator.newton, "modified");
  std::string given = spinningPlate(0.01, "trapezoidal");
  given.replace(given.find("type: trapezoidal"), 17, "type: trapezoidal, newton: full");
  EXPECT_EQ(readSceneText(given, dirOf() + "scene.yaml").integrator.newton, "full");
  const Scene bar = readSceneText(
      "dimension: 2\nnodes:\n  - {name: A, position: [0, 0], ground: true}\n  - {name: B, position: [1, 0]}\n"
      "elements:\n  - {name: bar, type: rigid_bar, nodes: [A, B], mass: 1}\n"
      "integrator: {type: trapezoidal, t_end: 0.1, dt: 0.01}\n", dirOf() + "scene.yaml");
  EXPECT_EQ(bar.integrator.newton, "full");
  const Flight modified = fly(0.01), full = fly(0.01, "trapezoidal", "", "full");
  EXPECT_LT(modified.maxP, 1e-9 * modified.P0);
  EXPECT_NEAR(modified.maxEnergyDev, full.maxEnergyDev, 1e-3 * full.maxEnergyDev);
}

// The midpoint rule's dd sensitivities (forces at the midpoint: the step depends on q_n, v_n
// through them too) are the exact derivative of its discrete solution: central differences
// (relative step 1e-5) of whole runs, the planar model holding every 2D element type and the
// seed-000 four-bar (3D rigid bodies, joints, rotational spring-damper), 1e-6 relative.
TEST(SolidDynamics, MidpointSensitivitiesAreTheDerivativeOfTheDiscreteScheme) {
  for (const std::string name : {"mixed 2D", "four-bar 3D"}) {
    Scene sc = name == "mixed 2D" ? test::mixedScene() : readScene(test::sourceDir() + "/examples/seed000/four_bar.yaml");
    Assembler as(*sc.model);
    const VecX p = sc.model->nominalParameters();
    const StateWithSens start = initialState(as, p);
    const IntegratorSettings set = test::integratorSettings("midpoint", 2e-3, 0.5);
    test::Recorder dd, nd;
    integrate(as, p, start, set, dd);
    integrateFiniteDifferences(as, p, start, nullptr, set, {"central", 1e-5}, nd);
    ASSERT_EQ(dd.frames.size(), nd.frames.size());
    double worst = 0.0;
    for (size_t k = 0; k < dd.frames.back().dp.size(); ++k)
      worst = std::max(worst, test::relErr(dd.frames.back().dp[k].q, nd.frames.back().dp[k].q, 1.0));
    std::printf("  midpoint, %s: max relative |dd - nd| of dq/dp at 0.5 s: %.2e\n", name.c_str(), worst);
    EXPECT_LT(worst, 1e-6) << name;
  }
}

TEST(SolidDynamics, ElementTurnedInsideOutNamesTheElement) {
  auto pr = std::make_shared<SolidProperties>();
  pr->dim = 2;
  pr->law = {Law::NeoHookean, PlanarState::PlaneStrain};
  pr->E = {1e6, -1};
  pr->nu = {0.3, -1};
  pr->density = {1000, -1};
  pr->thickness = {0.01, -1};
  MatX X(2, 3);
  X << 0, 1, 0, 0, 0, 1;
  Solid e("plate.cell7", {0, 1, 2}, pr, Simplex::Tri3, X);
  VecX p(0), x(6);
  x << 0, 0, 1, 0, 0.2, -0.5;  // node 2 pushed through the opposite edge: det F < 0
  LocalState s;
  s.dim = 2;
  s.x = x;
  s.v = VecX::Zero(6);
  s.p = &p;
  VecX Q;
  try {
    e.force(s, Q);
    ADD_FAILURE() << "no NumericalError";
  } catch (const NumericalError& err) {
    EXPECT_NE(std::string(err.what()).find("plate.cell7"), std::string::npos) << err.what();
    EXPECT_NE(std::string(err.what()).find("inverted"), std::string::npos) << err.what();
  }
}
