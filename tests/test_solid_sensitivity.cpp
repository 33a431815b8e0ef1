// Sensitivities of a meshed body's motion (type: solid): a soft neo-Hookean cantilever plate
// (6-node triangles, plane stress) released from rest under gravity and a tip force (so that
// the thickness matters: gravity alone scales mass and stiffness alike), with Kelvin-Voigt and
// mass damping, every material property a parameter (E, nu, density, thickness, alpha,
// beta). The trapezoidal rule's dd sensitivities are the exact derivative of the discrete
// scheme: central differences of whole perturbed runs (step 1e-5 |p|) must agree to
// their own truncation and round-off (bound 1e-6 relative to the largest |dz/dp| of each
// parameter), and ad (AD of the element kernels) must equal dd to 1e-10. Linear triangles at
// element size 0.05 m (122 coordinates) keep the 14 runs short; locking does not matter here.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

#include "TestModels.hpp"
#include "app/Run.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

std::string plate() {
  std::ostringstream s;
  s << "dimension: 2\ngravity: [0, -9.81]\nelements:\n"
       "  - {name: plate, type: solid, mesh: plate.geo, group: plate, size: 0.05, order: 1, material: neo_hookean,"
       " E: 2.0e6, nu: 0.3, density: 1000, thickness: 0.01, damping: {alpha: 0.5, beta: 5.0e-4}, ground: [root]}\n"
       "  - {name: tip, type: point_force, node: tipmid, force: [0, -0.05]}\n"
       "parameters:\n";
  for (const char* p : {"E", "nu", "density", "thickness", "alpha", "beta"})
    s << "  - {name: " << p << ", of: plate, property: " << p << "}\n";
  s << "integrator: {type: trapezoidal, t_end: 0.06, dt: 0.002}\n";
  return s.str();
}

}  // namespace

TEST(SolidSensitivity, DirectDifferentiationMatchesCentralDifferencesAndAD) {
  const Scene sc = readSceneText(plate(), sourceDir() + "/tests/scenes/solid/scene.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  Assembler adAs(m, Derivatives::AutomaticDifferentiation);
  const VecX p = m.nominalParameters();
  const auto set = integratorSettings("trapezoidal", 0.002, 0.06);
  const StateWithSens start = initialState(as, p), adStart = initialState(adAs, p);
  Recorder dd, ad;
  integrate(as, p, start, set, dd);
  integrate(adAs, p, adStart, set, ad);
  const int z = m.dof(m.nodeIndex("tipmid"), 1);
  for (size_t k = 0; k < m.parameters.size(); ++k) {
    // Central differences of whole runs at +-h, h = 1e-5 |p_k| (relative to each parameter:
    // flexsens' --nd-step is relative to max(|p|, 1), too coarse for beta ~ 1e-4 s).
    const double h = 1e-5 * std::abs(p[k]);
    const auto [plus, minus] = runsAtPlusMinus(as, p, k, h, set);
    Recorder nd;
    ASSERT_EQ(plus.frames.size(), dd.frames.size());
    for (size_t f = 0; f < dd.frames.size(); ++f) {
      StateWithSens fr = dd.frames[f];
      fr.dp[k].q = (plus.frames[f].x.q - minus.frames[f].x.q) / (2 * h);
      nd.frames.push_back(fr);
    }
    double scale = 0.0, errNd = 0.0, errAd = 0.0;
    for (size_t f = 1; f < dd.frames.size(); ++f) scale = std::max(scale, std::abs(dd.frames[f].dp[k].q[z]));
    for (size_t f = 1; f < dd.frames.size(); ++f) {
      errNd = std::max(errNd, std::abs(dd.frames[f].dp[k].q[z] - nd.frames[f].dp[k].q[z]));
      errAd = std::max(errAd, std::abs(dd.frames[f].dp[k].q[z] - ad.frames[f].dp[k].q[z]));
    }
    const double tEnd = dd.frames.back().dp[k].q[z];
    std::printf("  d(tip y)/d%-9s at 0.06 s %+.6e; max |dd - nd| / max|dd| %.2e, |dd - ad| %.2e\n",
                m.parameters[k].name.c_str(), tEnd, errNd / scale, errAd / scale);
    EXPECT_GT(scale, 0.0) << m.parameters[k].name;
    EXPECT_LE(errNd, 1e-6 * scale) << m.parameters[k].name;
    EXPECT_LE(errAd, 1e-10 * scale) << m.parameters[k].name;
  }
}

// The 3D solid pendulum example (examples/solid/pendulum3d.yaml: quadratic tetrahedra, neo-
// Hookean, hinged along an edge, released under gravity), coarsened (element size 0.08 m) and
// cut to 10 steps of 5 ms for the test: dtip_y/dE and dtip_y/ddensity of the trapezoidal rule
// against central differences of whole runs at p (1 +- 1e-5), 1e-6 of the largest |dd| of each.
TEST(SolidSensitivity, PendulumExampleMatchesCentralDifferences) {
  std::ifstream in(sourceDir() + "/examples/solid/pendulum3d.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_NE(text.find("size: 0.04"), std::string::npos);
  text.replace(text.find("size: 0.04"), 10, "size: 0.08");
  const Scene sc = readSceneText(text, sourceDir() + "/examples/solid/pendulum3d.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = m.nominalParameters();
  const auto set = integratorSettings("trapezoidal", 0.005, 0.05);
  Recorder dd;
  integrate(as, p, initialState(as, p), set, dd);
  const int y = m.dof(m.nodeIndex("tip"), 1);
  for (size_t k = 0; k < m.parameters.size(); ++k) {
    const double h = 1e-5 * std::abs(p[k]);
    const auto [plus, minus] = runsAtPlusMinus(as, p, k, h, set);
    double scale = 0.0, err = 0.0;
    for (size_t f = 1; f < dd.frames.size(); ++f) {
      const double nd = (plus.frames[f].x.q[y] - minus.frames[f].x.q[y]) / (2 * h);
      scale = std::max(scale, std::abs(dd.frames[f].dp[k].q[y]));
      err = std::max(err, std::abs(dd.frames[f].dp[k].q[y] - nd));
    }
    std::printf("  pendulum3d (n = %d): dtip_y/d%s at 0.05 s %+.6e; max |dd - nd| / max |dd| %.2e\n", m.n,
                m.parameters[k].name.c_str(), dd.frames.back().dp[k].q[y], err / scale);
    EXPECT_GT(scale, 0.0);
    EXPECT_LE(err, 1e-6 * scale) << m.parameters[k].name;
  }
}
