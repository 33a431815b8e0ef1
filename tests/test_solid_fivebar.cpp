// The five-bar of the PIM paper with link 1-2 as a meshed plate (examples/fivebar/
// meshed_link.yaml): the PIM counts of the paper's Table 1 (d_s = 0, 2, 1, 0, 1, 1 for
// F1-F6, the link rigidized as a 2D cloud of its 700+ mesh nodes), and F1's initial
// position sensitivities of the joints, which the rigidized link fixes by rigid kinematics
// alone, equal to the paper's printed q_p0 (4 decimals).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "pim/Pim.hpp"

using namespace flexsens;

TEST(SolidFiveBar, MeshedLinkKeepsTheCountsAndTheInitialSensitivities) {
  // The example's mesh, coarsened (linear triangles of size 0.05 m): the counts and the
  // rigid-kinematics sensitivities do not depend on the mesh, and the dense rank tests stay short.
  const std::string file = test::sourceDir() + "/examples/fivebar/meshed_link.yaml";
  std::stringstream text;
  text << std::ifstream(file).rdbuf();
  std::string coarse = text.str();
  const std::string fine = "size: 0.025, order: 2";
  ASSERT_NE(coarse.find(fine), std::string::npos);
  coarse.replace(coarse.find(fine), fine.size(), "size: 0.05, order: 1");
  const std::vector<std::pair<std::string, int>> ds = {{"F1", 0}, {"F2", 2}, {"F3", 1}, {"F4", 0}, {"F5", 1}, {"F6", 1}};
  for (const auto& [name, expected] : ds) {
    const Scene sc = readSceneText(coarse, file, name);
    const Model& m = *sc.model;
    Assembler as(m);
    const PimReport r = pimCounts(as, *sc.pimCase, m.initialPositions(), m.nominalParameters());
    EXPECT_EQ(r.m, 3) << name;
    EXPECT_EQ(r.ds, expected) << name;
    EXPECT_EQ(r.mr, r.d - expected) << name;
    if (name != "F1") continue;
    const VecX p = m.nominalParameters();
    const StateWithSens s = initialState(as, p, sc.pimCase.get());
    const double paper[6] = {1.4142, -2.8284, 2.8284, -0.7071, 1.4142, 1.4142};  // x1 z1 x2 z2 x3 z3
    int k = 0;
    for (const char* nd : {"n1", "n2", "n3"})
      for (int c = 0; c < 2; ++c, ++k)
        EXPECT_NEAR(s.dp[0].q[m.dof(m.nodeIndex(nd), c)], paper[k], 1e-4) << nd << " " << c;
  }
}
