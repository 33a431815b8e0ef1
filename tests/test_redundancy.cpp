// Redundant constraints found by `check` (app/Redundancy): a closed parallelogram loop whose
// fourth bar repeats what the other three and the ground fix (the classic redundant loop),
// and an independent four-bar as the control. Expected ranks by hand: the parallelogram with
// ground nodes A, B and free C, D has n = 4, bars AC, CD, DB, plus a diagonal-free duplicate.
#include <gtest/gtest.h>

#include "app/Redundancy.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;

namespace {
const char* kFourBar = R"(dimension: 2
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: B, position: [2, 0], ground: true}
  - {name: C, position: [0, 1]}
  - {name: D, position: [2.5, 1.2]}
elements:
  - {name: AC, type: rigid_bar, nodes: [A, C], mass: 1}
  - {name: CD, type: rigid_bar, nodes: [C, D], mass: 1}
  - {name: DB, type: rigid_bar, nodes: [D, B], mass: 1}
integrator: {type: trapezoidal, t_end: 0.1, dt: 0.001}
)";
}  // namespace

TEST(Redundancy, IndependentFourBarHasFullRank) {
  const Scene sc = readSceneText(kFourBar, "fourbar.yaml");
  const Assembler as(*sc.model);
  const RedundancyReport r = constraintRedundancy(as, sc.model->initialPositions(), sc.model->nominalParameters());
  EXPECT_TRUE(r.checked);
  EXPECT_EQ(r.rows, 3);
  EXPECT_EQ(r.rank, 3);
  EXPECT_TRUE(r.dependent.empty());
}

// Parallelogram A(0,0) B(2,0) C(0,1) D(2,1) with bars AC, CD, DB: 1 dof. A second coupler
// E-F parallel to CD (E on AC's line at (0, 0.5) attached by bars, F likewise) is the textbook
// redundant loop; here simply: a distance constraint C-D repeating the coupler's length, which
// is the same row up to a factor: rank 3 of 4, one dependent row named.
TEST(Redundancy, RepeatedLoopClosureIsNamed) {
  std::string text = kFourBar;
  text.replace(text.find("[2.5, 1.2]"), 10, "[2, 1]");
  text += "constraints:\n  - {name: again, type: distance, nodes: [C, D]}\n";
  const Scene sc = readSceneText(text, "parallelogram.yaml");
  const Assembler as(*sc.model);
  const RedundancyReport r = constraintRedundancy(as, sc.model->initialPositions(), sc.model->nominalParameters());
  EXPECT_EQ(r.rows, 4);
  EXPECT_EQ(r.rank, 3);
  ASSERT_EQ(r.dependent.size(), 1u);
  EXPECT_TRUE(r.dependent[0] == "again" || r.dependent[0] == "CD.length") << r.dependent[0];
}

// Parallelogram with a middle bar: E(0, 0.5) on AC... built with ground G(1, 0) and a third
// crank G-H, H(1, 1) on the coupler line joined to C and D: H's position is fixed twice over
// (by G-H and by the rigid coupler triangle C-H-D), the standard redundant parallelogram.
TEST(Redundancy, ParallelogramWithThirdCrankIsRedundant) {
  const char* text = R"(dimension: 2
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: G, position: [1, 0], ground: true}
  - {name: B, position: [2, 0], ground: true}
  - {name: C, position: [0, 1]}
  - {name: H, position: [1, 1]}
  - {name: D, position: [2, 1]}
elements:
  - {name: AC, type: rigid_bar, nodes: [A, C], mass: 1}
  - {name: GH, type: rigid_bar, nodes: [G, H], mass: 1}
  - {name: BD, type: rigid_bar, nodes: [B, D], mass: 1}
  - {name: CH, type: rigid_bar, nodes: [C, H], mass: 1}
  - {name: HD, type: rigid_bar, nodes: [H, D], mass: 1}
  - {name: CD, type: rigid_bar, nodes: [C, D], mass: 1}
integrator: {type: trapezoidal, t_end: 0.1, dt: 0.001}
)";
  const Scene sc = readSceneText(text, "parallelogram3.yaml");
  const Assembler as(*sc.model);
  const RedundancyReport r = constraintRedundancy(as, sc.model->initialPositions(), sc.model->nominalParameters());
  // n = 6, m = 6; the mechanism moves (1 dof), so rank = 5: one dependent row.
  EXPECT_EQ(sc.model->n, 6);
  EXPECT_EQ(r.rows, 6);
  EXPECT_EQ(r.rank, 5);
  EXPECT_EQ(r.dependent.size(), 1u);
}
