// Sensitivities of a discrete shell's motion (type: shell): examples/shell/panel.yaml, a thin
// panel hinged on one edge swinging and flapping under gravity, at a coarser mesh (size
// 0.05 m) and for 0.06 s to keep the runs short. Thickness and E act only through the
// flexure (membranes and hinges), density through mass and weight. The trapezoidal rule's dd
// sensitivities are the exact derivative of the discrete scheme: central differences of whole
// perturbed runs (step 1e-5 |p|) must agree to 1e-6 relative to the largest |d(tip z)/dp|,
// and ad (AD of the element kernels) must equal dd to 1e-10.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "StaticFrames.hpp"
#include "TestModels.hpp"
#include "app/Run.hpp"

using namespace flexsens;
using namespace flexsens::test;

TEST(ShellSensitivity, PanelDirectDifferentiationMatchesCentralDifferencesAndAD) {
  const std::string file = sourceDir() + "/examples/shell/panel.yaml";
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const auto at = text.find("size: 0.025");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 11, "size: 0.05");
  const Scene sc = readSceneText(text, file);
  const Model& m = *sc.model;
  ASSERT_EQ(m.parameters.size(), 3u);
  auto set = integratorSettings("trapezoidal", 0.002, 0.06);
  set.frameInterval = 0.01;
  expectCoordinateSensitivities(m, set, m.dof(m.nodeIndex("tip"), 2));
}

// Membrane stress sensitivities written to the .vtu cells (dstress_cauchy/dp, dvon_mises/dp:
// ShellTriangle::membraneStressDerivative): a thin simply supported plate sagging under its
// own weight (deflection ~2 thicknesses, so the membrane stresses are those of the large
// deflection) in `flexsens static`, against five-point central differences of whole static runs
// in E, nu and thickness. Relative step 4e-3: the differences' error is the static solve's
// Newton tolerance over 12 h (it fell 4x from h = 1e-3 to 4e-3; truncation O(h^4) ~ 3e-10).
// Measured: <= 2.6e-8 of the scale (1.2e-7 at h = 1e-3).
TEST(ShellSensitivity, MembraneStressSensitivitiesMatchCentralDifferencesOfRuns) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("flexsens_shell_dstress_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string names[] = {"E", "nu", "thickness"};
  const double nominal[] = {2.1e11, 0.3, 0.001};
  auto run = [&](int which, double factor, const std::string& tag) {
    double v[3] = {nominal[0], nominal[1], nominal[2]};
    if (which >= 0) v[which] *= factor;
    std::ostringstream t;
    t.precision(17);
    t << "dimension: 3\ngravity: [0, 0, -9.81]\nelements:\n  - {name: plate, type: shell, mesh: " << sourceDir()
      << "/tests/scenes/shell/square.geo, group: plate, size: 0.25, E: " << v[0] << ", nu: " << v[1]
      << ", density: 7800, thickness: " << v[2] << ", ground: [edges]}\n"
      << "parameters:\n  - {name: E, of: plate, property: E}\n  - {name: nu, of: plate, property: nu}\n"
      << "  - {name: thickness, of: plate, property: thickness}\nstatic: {load_steps: 2}\n";
    { std::ofstream(dir / (tag + ".yaml")) << t.str(); }
    const auto g = staticLastFrame(dir / (tag + ".yaml"), dir / tag);
    EXPECT_NE(g, nullptr) << t.str();
    return g;
  };
  const auto g0 = run(-1, 1.0, "nominal");
  ASSERT_NE(g0, nullptr);
  const double h = 4e-3;
  for (int k = 0; k < 3; ++k) {
    std::vector<vtkSmartPointer<vtkUnstructuredGrid>> at;  // p (1 + j h), j = -2, -1, 1, 2
    for (int j : {-2, -1, 1, 2}) {
      at.push_back(run(k, 1.0 + j * h, names[k] + std::to_string(j)));
      ASSERT_NE(at.back(), nullptr);
    }
    for (const std::string base : {"green_lagrange_strain", "stress_cauchy", "von_mises"}) {
      const auto c = checkCellDerivative(g0, at, base, names[k], nominal[k], h);
      std::printf("  d%s/d%s: max |analytic - central difference| = %.2e, scale %.3e\n", base.c_str(),
                  names[k].c_str(), c.worst, c.scale);
      ASSERT_GE(c.worst, 0.0) << "arrays missing: " << base << " " << names[k];
      EXPECT_GT(c.scale, 0.0);
      EXPECT_LT(c.worst, 1e-6 * c.scale) << base << " " << names[k];
    }
  }
  fs::remove_all(dir);
}
