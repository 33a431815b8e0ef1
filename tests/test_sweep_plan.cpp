// The samples of `flexsens sweep` (app/SweepPlan.hpp), the byte strings that carry results
// between processes (parallel/Packer.hpp) and parameter values applied to a scene
// (scene/Scene.hpp). The command itself: tests/scripts/sweep_cli.sh, sweep_mpi.sh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "app/SweepPlan.hpp"
#include "parallel/Packer.hpp"

using namespace flexsens;

namespace {

SweepDesign design(const std::vector<std::string>& specs, int samples = 0, std::vector<std::string> cases = {""}) {
  SweepDesign d;
  for (const auto& s : specs) d.ranges.push_back(parseParameterRange(s));
  d.samples = samples;
  d.cases = std::move(cases);
  return d;
}

/// The message of the InputError `f` throws ("" when it throws none).
template <class F>
std::string inputError(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SweepPlan, ParsesTheThreeFormsOfAParameter) {
  const ParameterRange grid = parseParameterRange("k=10:30:5");
  EXPECT_EQ(grid.name, "k");
  EXPECT_EQ(grid.low, 10.0);
  EXPECT_EQ(grid.high, 30.0);
  EXPECT_EQ(grid.count, 5);
  const ParameterRange cube = parseParameterRange("E=1e9:2.5e11");
  EXPECT_EQ(cube.count, 0);
  EXPECT_EQ(cube.high, 2.5e11);
  const ParameterRange fixed = parseParameterRange("m=-0.5");
  EXPECT_TRUE(fixed.fixed());
  EXPECT_EQ(fixed.low, -0.5);
}

TEST(SweepPlan, RefusesMalformedParametersNamingTheOption) {
  for (const char* bad : {"k", "=1:2:3", "k=a:2:3", "k=1:2:0", "k=1:2:2.5", "k=2:1:3", "k=1:2:3:4", "k=nan:1:2",
                          "k=1:2:1", "k=1:1"}) {
    const std::string e = inputError([&] { parseParameterRange(bad); });
    EXPECT_NE(e.find("option --parameter"), std::string::npos) << bad << ": " << e;
  }
}

TEST(SweepPlan, GridHasEveryCombinationFirstParameterSlowestEndsExact) {
  const auto samples = planSamples(design({"a=0:1:3", "b=10:20:2", "c=7"}));
  ASSERT_EQ(samples.size(), 6u);
  const double a[] = {0, 0, 0.5, 0.5, 1, 1}, b[] = {10, 20, 10, 20, 10, 20};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(samples[i].index, i);
    EXPECT_EQ(samples[i].values.at("a"), a[i]) << i;
    EXPECT_EQ(samples[i].values.at("b"), b[i]) << i;
    EXPECT_EQ(samples[i].values.at("c"), 7.0) << i;
  }
  // 0.1 * 3 is not 0.3 in binary; the last grid value is HIGH exactly.
  EXPECT_EQ(gridValue(parseParameterRange("x=0:0.3:4"), 3), 0.3);
}

TEST(SweepPlan, CasesRunForEveryPointInTurn) {
  const auto samples = planSamples(design({"a=1:2:2"}, 0, {"F1", "F4", "F6"}));
  ASSERT_EQ(samples.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(samples[i].caseName, (std::vector<std::string>{"F1", "F4", "F6"})[i % 3]);
    EXPECT_EQ(samples[i].values.at("a"), i < 3 ? 1.0 : 2.0);
  }
}

TEST(SweepPlan, LatinHypercubeUsesEachStratumOnceAndRepeatsForTheSameSeed) {
  const int n = 40;
  SweepDesign d = design({"p=2:4", "q=-1:1", "r=5"}, n);
  d.seed = 7;
  const auto samples = planSamples(d);
  ASSERT_EQ(samples.size(), static_cast<size_t>(n));
  for (const auto& [name, lo, hi] : {std::tuple{"p", 2.0, 4.0}, std::tuple{"q", -1.0, 1.0}}) {
    std::set<int> strata;
    for (const Sample& s : samples) {
      const double v = s.values.at(name);
      EXPECT_GE(v, lo);
      EXPECT_LE(v, hi);
      strata.insert(std::min(n - 1, static_cast<int>(std::floor((v - lo) / (hi - lo) * n))));
    }
    EXPECT_EQ(strata.size(), static_cast<size_t>(n)) << name << ": every one of the n strata once";
  }
  for (const Sample& s : samples) EXPECT_EQ(s.values.at("r"), 5.0);
  const auto again = planSamples(d);
  for (int i = 0; i < n; ++i) EXPECT_EQ(again[i].values, samples[i].values);
  d.seed = 8;
  EXPECT_NE(planSamples(d)[0].values, samples[0].values);
}

TEST(SweepPlan, RefusesADesignThatIsNeitherGridNorHypercube) {
  EXPECT_NE(inputError([] { planSamples(design({"a=1:2:3", "b=0:1"}, 5)); }).find("one or the other"), std::string::npos);
  EXPECT_NE(inputError([] { planSamples(design({"b=0:1"})); }).find("--samples"), std::string::npos);
  EXPECT_NE(inputError([] { planSamples(design({"a=1:2:3"}, 5)); }).find("--samples"), std::string::npos);
  EXPECT_NE(inputError([] { planSamples(design({"a=1"})); }).find("at least one parameter"), std::string::npos);
  EXPECT_NE(inputError([] { planSamples(design({"a=1:2:3", "a=1:2:3"})); }).find("given twice"), std::string::npos);
  EXPECT_NE(inputError([] { planSamples(design({"a=0:1:1000", "b=0:1:1001"})); }).find("at most"), std::string::npos);
  SweepDesign seeded = design({"a=1:2:3"});
  seeded.seedGiven = true;
  EXPECT_NE(inputError([&] { planSamples(seeded); }).find("--seed"), std::string::npos);
}

TEST(Packer, CarriesTextAndNumbersBitForBit) {
  const std::string binary("a\0b:12:\n", 8);
  const double values[] = {0.1, -1.0 / 3.0, 5e-324, 1.7976931348623157e308, -0.0};
  Packer p;
  p.text(binary).integer(-42).text("");
  for (double v : values) p.number(v);
  p.number(std::numeric_limits<double>::quiet_NaN());
  Unpacker u(p.bytes());
  EXPECT_EQ(u.text(), binary);
  EXPECT_EQ(u.integer(), -42);
  EXPECT_EQ(u.text(), "");
  for (double v : values) {
    const double back = u.number();
    EXPECT_EQ(std::memcmp(&back, &v, sizeof v), 0) << v;
  }
  EXPECT_TRUE(std::isnan(u.number()));
  EXPECT_TRUE(u.atEnd());
  EXPECT_THROW(u.text(), std::runtime_error);
  EXPECT_THROW(Unpacker("5:abc").text(), std::runtime_error);
}

// A value given for a parameter is the value the scene would hold if it said it: the scene
// text with the number edited is the independent reference.
TEST(ParameterValues, AreTheSceneWithTheNumberEdited) {
  const std::string scene =
      "dimension: 2\ngravity: [0, -9.81]\n"
      "nodes:\n  - {name: A, position: [0, 0], ground: true}\n  - {name: tip, position: [1, 0]}\n"
      "elements:\n  - {name: bar, type: rigid_bar, nodes: [A, tip], mass: MASS}\n"
      "parameters:\n  - {name: m, of: bar, property: mass}\n  - {name: g, of: gravity, property: y}\n"
      "integrator: {type: trapezoidal, t_end: 0.1, dt: 0.01}\n";
  auto withMass = [&](const std::string& m) {
    std::string s = scene;
    s.replace(s.find("MASS"), 4, m);
    return s;
  };
  const Scene edited = readSceneText(withMass("2.5"), "edited.yaml");
  const Scene given = readSceneText(withMass("1"), "given.yaml", "", {{"m", 2.5}, {"g", -1.62}});
  EXPECT_EQ(given.model->nominalParameters()[0], edited.model->nominalParameters()[0]);
  EXPECT_EQ(given.model->nominalParameters()[1], -1.62);
  EXPECT_EQ(given.model->gravity[1], -1.62);
  const std::string e = inputError([&] { readSceneText(withMass("1"), "s.yaml", "", {{"L", 2.0}}); });
  EXPECT_NE(e.find("'L'"), std::string::npos) << e;
  EXPECT_NE(e.find("its parameters: m, g"), std::string::npos) << e;
}
