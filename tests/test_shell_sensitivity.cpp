// Sensitivities of a discrete shell's motion (type: shell): examples/shell/panel.yaml, a thin
// panel hinged on one edge swinging and flapping under gravity, at a coarser mesh (size
// 0.05 m) and for 0.06 s to keep the runs short. Thickness and E act only through the
// flexure (membranes and hinges), density through mass and weight. The trapezoidal rule's dd
// sensitivities are the exact derivative of the discrete scheme: central differences of whole
// perturbed runs (step 1e-5 |p|) must agree to 1e-6 relative to the largest |d(tip z)/dp|,
// and ad (AD of the element kernels) must equal dd to 1e-10.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

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
  Assembler as(m);
  Assembler adAs(m, Derivatives::AutomaticDifferentiation);
  const VecX p = m.nominalParameters();
  auto set = integratorSettings("trapezoidal", 0.002, 0.06);
  set.frameInterval = 0.01;
  Recorder dd, ad;
  integrate(as, p, initialState(as, p), set, dd);
  integrate(adAs, p, initialState(adAs, p), set, ad);
  const int z = m.dof(m.nodeIndex("tip"), 2);
  for (size_t k = 0; k < m.parameters.size(); ++k) {
    const double h = 1e-5 * std::abs(p[k]);
    const auto [plus, minus] = runsAtPlusMinus(as, p, k, h, set);
    ASSERT_EQ(plus.frames.size(), dd.frames.size());
    double scale = 0.0, errNd = 0.0, errAd = 0.0;
    for (size_t f = 1; f < dd.frames.size(); ++f) scale = std::max(scale, std::abs(dd.frames[f].dp[k].q[z]));
    for (size_t f = 1; f < dd.frames.size(); ++f) {
      const double nd = (plus.frames[f].x.q[z] - minus.frames[f].x.q[z]) / (2 * h);
      errNd = std::max(errNd, std::abs(dd.frames[f].dp[k].q[z] - nd));
      errAd = std::max(errAd, std::abs(dd.frames[f].dp[k].q[z] - ad.frames[f].dp[k].q[z]));
    }
    std::printf("  d(tip z)/d%-4s at 0.06 s %+.6e; max |dd - nd| / max|dd| %.2e, |dd - ad| %.2e\n",
                m.parameters[k].name.c_str(), dd.frames.back().dp[k].q[z], errNd / scale, errAd / scale);
    EXPECT_GT(scale, 0.0) << m.parameters[k].name;
    EXPECT_LE(errNd, 1e-6 * scale) << m.parameters[k].name;
    EXPECT_LE(errAd, 1e-10 * scale) << m.parameters[k].name;
  }
}
