// Each PIM error has a scene asserting its message: wrong SDOF count, rank-deficient and
// near-singular A, unknown bodies and nodes, a rigidized body that starts deformed.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "TestModels.hpp"
#include "app/Run.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

/// The flexible five-bar with its cases replaced by `cases` (YAML text).
std::string flexWithCases(const std::string& cases) {
  std::ifstream in(sourceDir() + "/examples/fivebar/flexible.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string s = ss.str();
  const size_t a = s.find("cases:"), b = s.find("integrator:");
  return s.substr(0, a) + "cases:\n" + cases + s.substr(b);
}

std::string errorOf(const std::string& cases, const std::string& name) {
  try {
    Scene sc = readSceneText(flexWithCases(cases), "pim.yaml", name);
    Assembler as(*sc.model);
    PimReport rep;
    initialState(as, sc.model->nominalParameters(), sc.pimCase.get(), &rep);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(PimErrors, WrongSdofCountSaysHowManyAreRequired) {
  const std::string e = errorOf("  - {name: X, parameters: [L_A1], rigidize: [beam_12], sdofs: [{node: n3, component: x}]}\n", "X");
  EXPECT_NE(e.find("case 'X': 1 SDOF(s) given, but d - m_r = 5 - 3 = 2 are required"), std::string::npos) << e;
}

TEST(PimErrors, RankDeficientNamesTheRows) {
  const std::string e = errorOf(
      "  - {name: X, parameters: [L_A1], rigidize: [beam_12], sdofs: [{node: n3, component: x}, "
      "{combination: [[2.0, n3, x]]}]}\n", "X");
  EXPECT_NE(e.find("rank-deficient"), std::string::npos) << e;
  EXPECT_NE(e.find("[SDOF: x(n3)]"), std::string::npos) << e;
  EXPECT_NE(e.find("[SDOF: 2 x(n3)]"), std::string::npos) << e;
}

TEST(PimErrors, NearSingularGivesTheConditionEstimate) {
  const std::string e = errorOf(
      "  - {name: X, parameters: [L_A1], rigidize: [beam_12], sdofs: [{node: n3, component: x}, "
      "{combination: [[1.0, n3, x], [1.0e-9, n1, z]]}]}\n", "X");
  EXPECT_NE(e.find("near-singular (condition estimate"), std::string::npos) << e;
}

TEST(PimErrors, UnknownBodyAndNodeAndParameter) {
  std::string e = errorOf("  - {name: X, parameters: [L_A1], rigidize: [beam_99]}\n", "X");
  EXPECT_NE(e.find("key 'cases[0].rigidize[0]': no flexible body (beam or spring) named 'beam_99'"), std::string::npos) << e;
  e = errorOf("  - {name: X, parameters: [L_A1], rigidize: [beam_12], sdofs: [{node: n9, component: x}, {node: n3, component: x}]}\n", "X");
  EXPECT_NE(e.find("key 'cases[0].sdofs[0].node': no node named 'n9'"), std::string::npos) << e;
  e = errorOf("  - {name: X, parameters: [L_XX], rigidize: [beam_12, spring_B1, spring_B2]}\n", "X");
  EXPECT_NE(e.find("no parameter named 'L_XX'"), std::string::npos) << e;
  e = errorOf("  - {name: X, parameters: [L_A1], rigidize: [beam_12, spring_B1, spring_B2]}\n", "Y");
  EXPECT_NE(e.find("no case named 'Y'"), std::string::npos) << e;
}

TEST(PimErrors, RigidizedBodyMustStartUndeformed) {
  std::string s = flexWithCases("  - {name: X, parameters: [L_A1], rigidize: [beam_12, spring_B1, spring_B2]}\n");
  const std::string from = "nodes: [B, n1], stiffness: 1000, damping: 0}";
  const size_t at = s.find(from);
  ASSERT_NE(at, std::string::npos);
  s.replace(at, from.size(), "nodes: [B, n1], stiffness: 1000, damping: 0, natural_length: 2.0}");
  Scene sc = readSceneText(s, "pim.yaml", "X");
  Assembler as(*sc.model);
  try {
    initialState(as, sc.model->nominalParameters(), sc.pimCase.get());
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is not undeformed at t = 0"), std::string::npos) << e.what();
  }
}
