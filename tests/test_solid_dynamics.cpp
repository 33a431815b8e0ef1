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
#include "app/Run.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;

namespace {

std::string dirOf() { return std::string(FLEXSENS_SOURCE_DIR) + "/tests/scenes/solid/"; }

/// A soft neo-Hookean plate (1 x 0.05 m, 6-node triangles) spinning at 2 rad/s about its
/// centre and translating: the centrifugal load stretches it (strain ~1e-2), which sets off
/// axial and bending vibration.
std::string spinningPlate(double dt) {
  std::ostringstream s;
  s << "dimension: 2\nelements:\n  - {name: plate, type: solid, mesh: plate.geo, group: plate, size: 0.05, order: 2,"
       " material: neo_hookean, E: 1.0e6, nu: 0.3, density: 1000, thickness: 0.01,"
       " velocity: [0.3, -0.1], angular_velocity: 2, center: [0.5, 0.025]}\n"
    << "integrator: {type: trapezoidal, t_end: 0.5, dt: " << dt << ", frame_interval: " << dt << "}\n";
  return s.str();
}

struct Flight {
  double maxEnergyDev = 0, maxP = 0, maxL = 0, E0 = 0, P0 = 0, L0 = 0;
};

Flight fly(double dt) {
  const Scene sc = readSceneText(spinningPlate(dt), dirOf() + "scene.yaml");
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
      first = false;
    }
    f.maxEnergyDev = std::max(f.maxEnergyDev, std::abs(E - f.E0));
    f.maxP = std::max(f.maxP, std::hypot(Px - 0.3 * 0.5, Py + 0.1 * 0.5));  // m v0, m = 0.5 kg
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
