// Gmsh bridge (meshes/GmshCurves.hpp) and the satellite geometry (examples/satellite/satellite.geo).
//
// Expected values come from the geometry as stated in /work/shared/reference/satellite.md and
// the task's reading of it (cube [0,2]x[0,2]x[-2,0], panels folded up to z = 10, springs
// 270-degree arcs of radius 1), or from hand calculation for the small test inputs in
// tests/scenes/gmsh/, never from the code under test.
#include <gmsh.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "meshes/GmshCurves.hpp"

namespace {

using flexsens::CurveMesh;
using flexsens::CurveRequest;
using flexsens::InputError;
using flexsens::NodeChain;
using flexsens::meshCurves;
using Eigen::Vector3d;

const double kPi = 3.14159265358979323846;

std::string satelliteGeo() { return std::string(FLEXSENS_SOURCE_DIR) + "/examples/satellite/satellite.geo"; }
std::string testGeo(const std::string& name) {
  return std::string(FLEXSENS_SOURCE_DIR) + "/tests/scenes/gmsh/" + name;
}

/// Gmsh 4.8 has no gmsh::isInitialized() (it came in a later SDK). An API call on an
/// uninitialized Gmsh returns without touching its outputs when Gmsh was never initialized in
/// this process, and throws std::string("Gmsh has not been initialized") after a finalize; so
/// an option read into a NaN tells.
bool gmshInitialized() {
  double v = std::numeric_limits<double>::quiet_NaN();
  try {
    gmsh::option::getNumber("General.Terminal", v);
  } catch (const std::string& e) {
    EXPECT_NE(e.find("not been initialized"), std::string::npos) << e;
    return false;
  }
  return !std::isnan(v);
}

const NodeChain& chainOf(const CurveMesh& m, const std::string& group) {
  for (const NodeChain& c : m.chains)
    if (c.group == group) return c;
  throw std::runtime_error("no chain " + group);
}

/// The message of the InputError `f` throws ("" and a test failure when it throws none).
template <class F> std::string inputErrorOf(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

bool startsWith(const std::string& s, const std::string& prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

// --- satellite.geo --------------------------------------------------------------------------

struct SpringSpec {
  std::string group, s, p;
  Vector3d centre, side;  ///< side: unit direction from the centre to the arc's 90-degree point
  int planeAxis;          ///< the coordinate that is constant on the spring's plane
  double planeValue;
};

// From the task: spring k runs from S_k on the top face through the 90-degree point
// centre + side and the 180-degree point centre + e_z to P_k = centre - side (the major arc).
const std::vector<SpringSpec> kSprings = {
    {"spring1", "S1", "P1", {1, 0, 1}, {1, 0, 0}, 1, 0.0},
    {"spring2", "S2", "P2", {1, 2, 1}, {-1, 0, 0}, 1, 2.0},
    {"spring3", "S3", "P3", {2, 1, 1}, {0, 1, 0}, 0, 2.0},
    {"spring4", "S4", "P4", {0, 1, 1}, {0, -1, 0}, 0, 0.0},
};

TEST(GmshSatellite, Spring1TwentySegmentsIsTheMajorArc) {
  const CurveMesh m = meshCurves(satelliteGeo(), {{"spring1", 20}}, "sat.yaml:3");
  ASSERT_EQ(m.chains.size(), 1u);
  const NodeChain& c = m.chains[0];
  EXPECT_EQ(c.group, "spring1");
  ASSERT_EQ(c.names.size(), 21u);
  ASSERT_EQ(c.positions.size(), 21u);
  EXPECT_EQ(c.names.front(), "S1");
  EXPECT_EQ(c.names.back(), "P1");
  const Vector3d centre(1, 0, 1);
  const double theta = 1.5 * kPi / 20;
  const double chord = 2 * std::sin(theta / 2);  // 0.23498...
  for (std::size_t i = 0; i < 21; ++i) {
    EXPECT_NEAR((c.positions[i] - centre).norm(), 1.0, 1e-9) << i;
    EXPECT_NEAR(c.positions[i].y(), 0.0, 1e-9) << i;
    if (i > 0) EXPECT_NEAR((c.positions[i] - c.positions[i - 1]).norm(), chord, 1e-9) << i;
    // Node i at angle i * theta from S1 = (1,0,0) towards (2,0,1): (1 + sin, 0, 1 - cos).
    const Vector3d expected(1 + std::sin(i * theta), 0, 1 - std::cos(i * theta));
    EXPECT_NEAR((c.positions[i] - expected).norm(), 0.0, 1e-9) << i;
  }
  EXPECT_NEAR((c.positions.front() - Vector3d(1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((c.positions.back() - Vector3d(0, 0, 1)).norm(), 0.0, 1e-12);
  for (std::size_t i = 1; i + 1 < 21; ++i) EXPECT_EQ(c.names[i], "spring1." + std::to_string(i));
}

TEST(GmshSatellite, EverySpringIsA270DegreeArcInItsPlane) {
  std::vector<CurveRequest> req;
  for (const SpringSpec& s : kSprings) req.push_back({s.group, 20});
  const CurveMesh m = meshCurves(satelliteGeo(), req, "sat");
  const double theta = 1.5 * kPi / 20;
  for (const SpringSpec& s : kSprings) {
    const NodeChain& c = chainOf(m, s.group);
    ASSERT_EQ(c.positions.size(), 21u) << s.group;
    EXPECT_EQ(c.names.front(), s.s) << s.group;
    EXPECT_EQ(c.names.back(), s.p) << s.group;
    const Vector3d ez(0, 0, 1);
    double length = 0.0;
    for (std::size_t i = 0; i < 21; ++i) {
      const Vector3d expected =
          s.centre + std::sin(i * theta) * s.side - std::cos(i * theta) * ez;
      EXPECT_NEAR((c.positions[i] - expected).norm(), 0.0, 1e-9) << s.group << " node " << i;
      EXPECT_NEAR(c.positions[i][s.planeAxis], s.planeValue, 1e-9) << s.group << " " << i;
      if (i > 0) length += (c.positions[i] - c.positions[i - 1]).norm();
    }
    // 20 chords of a 270-degree arc (a 90-degree arc would give about 1.57).
    EXPECT_NEAR(length, 40 * std::sin(theta / 2), 1e-9) << s.group;
    EXPECT_GT(length, 4.6) << s.group;
  }
}

TEST(GmshSatellite, PanelA1B1SharesP1WithSpring1) {
  const CurveMesh m =
      meshCurves(satelliteGeo(), {{"panel_A1B1", 10}, {"spring1", 20}}, "sat");
  const NodeChain& panel = chainOf(m, "panel_A1B1");
  ASSERT_EQ(panel.positions.size(), 11u);
  ASSERT_EQ(panel.names.size(), 11u);
  for (std::size_t i = 0; i < 11; ++i)
    EXPECT_NEAR((panel.positions[i] - Vector3d(0, 0, double(i))).norm(), 0.0, 1e-12) << i;
  for (std::size_t i = 1; i < 11; ++i)
    EXPECT_NEAR((panel.positions[i] - panel.positions[i - 1]).norm(), 1.0, 1e-12) << i;
  EXPECT_EQ(panel.names[0], "A1");
  EXPECT_EQ(panel.names[1], "P1");
  EXPECT_EQ(panel.names[10], "B1");
  EXPECT_EQ(panel.names[2], "panel_A1B1.2");
  EXPECT_EQ(panel.names[9], "panel_A1B1.9");
  const NodeChain& spring = chainOf(m, "spring1");
  EXPECT_EQ(spring.names.back(), panel.names[1]);
  EXPECT_NEAR((spring.positions.back() - panel.positions[1]).norm(), 0.0, 1e-12);
}

TEST(GmshSatellite, CoincidentBPointsStayDistinct) {
  const CurveMesh m = meshCurves(
      satelliteGeo(),
      {{"panel_A1B1", 10}, {"panel_A1B5", 10}, {"panel_A2B2", 10}, {"panel_A2B6", 10},
       {"panel_A3B3", 10}, {"panel_A3B7", 10}, {"panel_A4B4", 10}, {"panel_A4B8", 10}},
      "sat");
  const std::vector<std::pair<std::string, std::string>> pairs = {
      {"B1", "B5"}, {"B2", "B6"}, {"B3", "B7"}, {"B4", "B8"}};
  for (const auto& [a, b] : pairs) {
    ASSERT_TRUE(m.points.count(a) && m.points.count(b)) << a << b;
    EXPECT_NEAR((m.points.at(a) - m.points.at(b)).norm(), 0.0, 1e-12) << a << b;
  }
  const NodeChain& p1 = chainOf(m, "panel_A1B1");
  const NodeChain& p5 = chainOf(m, "panel_A1B5");
  EXPECT_EQ(p1.names.back(), "B1");
  EXPECT_EQ(p5.names.back(), "B5");
  EXPECT_NEAR((p1.positions.back() - Vector3d(0, 0, 10)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((p5.positions.back() - Vector3d(0, 0, 10)).norm(), 0.0, 1e-12);
  EXPECT_EQ(p1.names.front(), p5.names.front());  // both hinge at A1
  EXPECT_EQ(chainOf(m, "panel_A2B6").names.back(), "B6");
  EXPECT_EQ(chainOf(m, "panel_A3B7").names.back(), "B7");
  EXPECT_EQ(chainOf(m, "panel_A4B8").names.back(), "B8");
}

TEST(GmshSatellite, AllGroupsCountsAndEnds) {
  // name -> (segments, first node, last node)
  struct G { int segments; std::string first, last; };
  const std::map<std::string, G> groups = {
      {"panel_A1B1", {10, "A1", "B1"}}, {"panel_A2B2", {10, "A2", "B2"}},
      {"panel_A3B3", {10, "A3", "B3"}}, {"panel_A4B4", {10, "A4", "B4"}},
      {"panel_A1B5", {10, "A1", "B5"}}, {"panel_A3B7", {10, "A3", "B7"}},
      {"panel_A2B6", {10, "A2", "B6"}}, {"panel_A4B8", {10, "A4", "B8"}},
      {"bar_B1B2", {1, "B1", "B2"}},    {"bar_B3B4", {1, "B3", "B4"}},
      {"bar_B5B7", {1, "B5", "B7"}},    {"bar_B6B8", {1, "B6", "B8"}},
      {"diag_A1B2", {1, "A1", "B2"}},   {"diag_A2B8", {1, "A2", "B8"}},
      {"diag_A4B3", {1, "A4", "B3"}},   {"diag_A3B5", {1, "A3", "B5"}},
      {"spring1", {20, "S1", "P1"}},    {"spring2", {20, "S2", "P2"}},
      {"spring3", {20, "S3", "P3"}},    {"spring4", {20, "S4", "P4"}},
  };
  std::vector<CurveRequest> req;
  for (const auto& [name, g] : groups) req.push_back({name, g.segments});
  const CurveMesh m = meshCurves(satelliteGeo(), req, "sat");
  ASSERT_EQ(m.chains.size(), 20u);
  for (std::size_t k = 0; k < req.size(); ++k) EXPECT_EQ(m.chains[k].group, req[k].group);

  std::set<std::string> allNames;
  std::size_t total = 0;
  for (const NodeChain& c : m.chains) {
    const G& g = groups.at(c.group);
    ASSERT_EQ(c.names.size(), std::size_t(g.segments + 1)) << c.group;
    ASSERT_EQ(c.positions.size(), c.names.size()) << c.group;
    EXPECT_EQ(c.names.front(), g.first) << c.group;
    EXPECT_EQ(c.names.back(), g.last) << c.group;
    EXPECT_NEAR((c.positions.front() - m.points.at(g.first)).norm(), 0.0, 1e-12) << c.group;
    EXPECT_NEAR((c.positions.back() - m.points.at(g.last)).norm(), 0.0, 1e-12) << c.group;
    total += c.names.size();
    allNames.insert(c.names.begin(), c.names.end());
  }
  EXPECT_EQ(total, 8u * 11 + 8u * 2 + 4u * 21);  // 188 chain entries
  // 20 named points (A1-4, B1-8, S1-4, P1-4), 4 x 9 + 4 x 8 interior panel nodes, 4 x 19
  // interior spring nodes.
  EXPECT_EQ(allNames.size(), 20u + 36 + 32 + 76);

  // Physical Points: A1..A4, B1..B8, C1, S1..S4, P1..P4.
  EXPECT_EQ(m.points.size(), 21u);
  const std::map<std::string, Vector3d> expected = {
      {"A1", {0, 0, 0}},  {"A2", {0, 2, 0}},  {"A3", {2, 0, 0}},  {"A4", {2, 2, 0}},
      {"B1", {0, 0, 10}}, {"B2", {0, 2, 10}}, {"B3", {2, 0, 10}}, {"B4", {2, 2, 10}},
      {"B5", {0, 0, 10}}, {"B6", {0, 2, 10}}, {"B7", {2, 0, 10}}, {"B8", {2, 2, 10}},
      {"C1", {0, 0, -2}}, {"S1", {1, 0, 0}},  {"S2", {1, 2, 0}},  {"S3", {2, 1, 0}},
      {"S4", {0, 1, 0}},  {"P1", {0, 0, 1}},  {"P2", {2, 2, 1}},  {"P3", {2, 0, 1}},
      {"P4", {0, 2, 1}}};
  for (const auto& [name, x] : expected) {
    ASSERT_TRUE(m.points.count(name)) << name;
    EXPECT_NEAR((m.points.at(name) - x).norm(), 0.0, 1e-12) << name;
  }
  // Springs attach at P, 1 m along their panel beams.
  EXPECT_EQ(chainOf(m, "panel_A4B4").names[1], "P2");
  EXPECT_EQ(chainOf(m, "panel_A3B7").names[1], "P3");
  EXPECT_EQ(chainOf(m, "panel_A2B6").names[1], "P4");
  // Diagonal length 10.198 m (Table 2), bars 2 m.
  const NodeChain& diag = chainOf(m, "diag_A1B2");
  EXPECT_NEAR((diag.positions[1] - diag.positions[0]).norm(), std::sqrt(104.0), 1e-12);
  const NodeChain& bar = chainOf(m, "bar_B5B7");
  EXPECT_NEAR((bar.positions[1] - bar.positions[0]).norm(), 2.0, 1e-12);
}

// --- small chains with hand-computed nodes ------------------------------------------------

TEST(GmshChains, ReversedCurveIsOrientedAlongTheChain) {
  // Lengths 1 and 2, 6 segments -> 2 + 4, spacing 0.5; the second line is drawn B -> X.
  const CurveMesh m = meshCurves(testGeo("chains.geo"), {{"rod_reversed", 6}}, "t");
  const NodeChain& c = m.chains.at(0);
  const std::vector<std::string> names = {"A",  "rod_reversed.1", "rod_reversed.2",
                                          "rod_reversed.3", "rod_reversed.4",
                                          "rod_reversed.5", "B"};
  EXPECT_EQ(c.names, names);
  ASSERT_EQ(c.positions.size(), 7u);
  for (std::size_t i = 0; i < 7; ++i)
    EXPECT_NEAR((c.positions[i] - Vector3d(0.5 * i, 0, 0)).norm(), 0.0, 1e-12) << i;
}

TEST(GmshChains, UnnamedEndsAndLargestRemainderSplit) {
  // Lengths 1 and 2, 7 segments: ideal 2.33 + 4.67 -> 2 + 5. Curves are listed last-first;
  // the chain starts where a curve begins, (0,1,0).
  const CurveMesh m = meshCurves(testGeo("chains.geo"), {{"rod_unnamed", 7}}, "t");
  const NodeChain& c = m.chains.at(0);
  const std::vector<double> x = {0, 0.5, 1, 1.4, 1.8, 2.2, 2.6, 3};
  ASSERT_EQ(c.positions.size(), x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    EXPECT_NEAR((c.positions[i] - Vector3d(x[i], 1, 0)).norm(), 0.0, 1e-12) << i;
    EXPECT_EQ(c.names[i], "rod_unnamed." + std::to_string(i));
  }
  EXPECT_EQ(m.points.size(), 4u);  // A, B, C, D of the other groups
}

TEST(GmshChains, ShortCurveKeepsOneSegment) {
  // Lengths 0.1 and 10, 3 segments: ideal 0.03 + 2.97 -> 1 + 2.
  const CurveMesh m = meshCurves(testGeo("chains.geo"), {{"rod_short", 3}}, "t");
  const NodeChain& c = m.chains.at(0);
  const std::vector<double> x = {0, 0.1, 5.1, 10.1};
  ASSERT_EQ(c.positions.size(), x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    EXPECT_NEAR((c.positions[i] - Vector3d(x[i], 2, 0)).norm(), 0.0, 1e-12) << i;
  EXPECT_EQ(c.names.front(), "C");
  EXPECT_EQ(c.names[1], "rod_short.1");
  EXPECT_EQ(c.names.back(), "D");
}

// --- errors -------------------------------------------------------------------------------

TEST(GmshErrors, MissingGroupListsAvailableNames) {
  const std::string msg = inputErrorOf(
      [] { meshCurves(satelliteGeo(), {{"spring1", 20}, {"spring9", 20}}, "sat.yaml:12"); });
  EXPECT_TRUE(startsWith(msg, "sat.yaml:12: ")) << msg;
  EXPECT_NE(msg.find("'spring9'"), std::string::npos) << msg;
  for (const char* name : {"panel_A1B1", "bar_B6B8", "diag_A3B5", "spring4"})
    EXPECT_NE(msg.find(name), std::string::npos) << name << " in " << msg;
}

TEST(GmshErrors, ZeroOrNegativeSegments) {
  std::string msg = inputErrorOf([] { meshCurves(satelliteGeo(), {{"spring1", 0}}, "w0"); });
  EXPECT_TRUE(startsWith(msg, "w0: ")) << msg;
  EXPECT_NE(msg.find("zero segments"), std::string::npos) << msg;
  EXPECT_NE(msg.find("spring1"), std::string::npos) << msg;
  msg = inputErrorOf([] { meshCurves(satelliteGeo(), {{"panel_A2B2", -3}}, "w1"); });
  EXPECT_TRUE(startsWith(msg, "w1: ")) << msg;
  EXPECT_NE(msg.find("panel_A2B2"), std::string::npos) << msg;
}

TEST(GmshErrors, FewerSegmentsThanCurves) {
  // spring1 is two Circle arcs: one segment cannot cover both.
  const std::string msg =
      inputErrorOf([] { meshCurves(satelliteGeo(), {{"spring1", 1}}, "w"); });
  EXPECT_TRUE(startsWith(msg, "w: ")) << msg;
  EXPECT_NE(msg.find("2 curves"), std::string::npos) << msg;
}

TEST(GmshErrors, MissingFile) {
  const std::string file = testGeo("no_such_file.geo");
  const std::string msg = inputErrorOf([&] { meshCurves(file, {{"rod", 2}}, "scene.yaml:5"); });
  EXPECT_TRUE(startsWith(msg, "scene.yaml:5: ")) << msg;
  EXPECT_NE(msg.find(file), std::string::npos) << msg;
  EXPECT_NE(msg.find("cannot open"), std::string::npos) << msg;
}

TEST(GmshErrors, SyntaxErrorCarriesGmshText) {
  const std::string msg =
      inputErrorOf([] { meshCurves(testGeo("bad_syntax.geo"), {{"rod", 2}}, "s.yaml:7"); });
  EXPECT_TRUE(startsWith(msg, "s.yaml:7: ")) << msg;
  EXPECT_NE(msg.find("syntax error"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 3"), std::string::npos) << msg;
  EXPECT_FALSE(gmshInitialized());
}

TEST(GmshErrors, CurvesThatAreNotOneOpenChain) {
  const std::string geo = testGeo("bad_shapes.geo");
  std::string msg = inputErrorOf([&] { meshCurves(geo, {{"tee", 3}}, "w"); });
  EXPECT_TRUE(startsWith(msg, "w: ")) << msg;
  EXPECT_NE(msg.find("'tee'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'O'"), std::string::npos) << msg;  // where they branch
  EXPECT_NE(msg.find("branch"), std::string::npos) << msg;
  msg = inputErrorOf([&] { meshCurves(geo, {{"ring", 3}}, "w"); });
  EXPECT_NE(msg.find("closed loop"), std::string::npos) << msg;
  msg = inputErrorOf([&] { meshCurves(geo, {{"pieces", 4}}, "w"); });
  EXPECT_NE(msg.find("not connected"), std::string::npos) << msg;
  msg = inputErrorOf([&] { meshCurves(geo, {{"lasso", 4}}, "w"); });
  EXPECT_NE(msg.find("not connected"), std::string::npos) << msg;
  // Each of these groups is fine alone; requested together they claim the same curve.
  EXPECT_NO_THROW(meshCurves(geo, {{"left", 1}}, "w"));
  EXPECT_NO_THROW(meshCurves(geo, {{"right", 2}}, "w"));
  msg = inputErrorOf([&] { meshCurves(geo, {{"left", 1}, {"right", 2}}, "w"); });
  EXPECT_NE(msg.find("shares curve"), std::string::npos) << msg;
  msg = inputErrorOf([&] { meshCurves(geo, {{"left", 1}, {"left", 1}}, "w"); });
  EXPECT_NE(msg.find("twice"), std::string::npos) << msg;
}

TEST(GmshErrors, PhysicalPointWithTwoPoints) {
  const std::string msg =
      inputErrorOf([] { meshCurves(testGeo("bad_point.geo"), {{"rod", 1}}, "w"); });
  EXPECT_TRUE(startsWith(msg, "w: ")) << msg;
  EXPECT_NE(msg.find("'ends'"), std::string::npos) << msg;
}

// --- Gmsh lifetime ------------------------------------------------------------------------

TEST(GmshSession, NotInitializedAfterCallsAndRepeatable) {
  EXPECT_FALSE(gmshInitialized());
  const CurveMesh a = meshCurves(satelliteGeo(), {{"spring2", 20}}, "a");
  EXPECT_FALSE(gmshInitialized());
  // An error inside Gmsh (syntax) and one found after opening still finalize.
  EXPECT_THROW(meshCurves(testGeo("bad_syntax.geo"), {{"x", 1}}, "b"), InputError);
  EXPECT_FALSE(gmshInitialized());
  EXPECT_THROW(meshCurves(satelliteGeo(), {{"nope", 1}}, "b"), InputError);
  EXPECT_FALSE(gmshInitialized());
  const CurveMesh b = meshCurves(satelliteGeo(), {{"spring2", 20}}, "c");
  EXPECT_FALSE(gmshInitialized());
  ASSERT_EQ(a.chains.at(0).positions.size(), 21u);
  ASSERT_EQ(b.chains.at(0).positions.size(), 21u);
  EXPECT_EQ(a.chains[0].names, b.chains[0].names);
  for (std::size_t i = 0; i < 21; ++i)
    EXPECT_EQ(a.chains[0].positions[i], b.chains[0].positions[i]) << i;
}

TEST(GmshSession, PrintsNothing) {
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  meshCurves(satelliteGeo(), {{"spring3", 20}, {"panel_A3B7", 10}}, "q");
  try {
    meshCurves(testGeo("bad_syntax.geo"), {{"x", 1}}, "q");
  } catch (const InputError&) {
  }
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");
}

// Gmsh runs in a child process (meshes/GmshSandbox): a session the caller opened is neither
// refused nor touched, and the chains are the same as without it.
TEST(GmshSession, LeavesTheCallersSessionAlone) {
  const CurveMesh before = meshCurves(satelliteGeo(), {{"spring1", 20}}, "w");
  EXPECT_FALSE(gmshInitialized());  // the calling process never started Gmsh
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("Mesh.MeshSizeMax", 0.123);
  const CurveMesh during = meshCurves(satelliteGeo(), {{"spring1", 20}}, "w");
  EXPECT_TRUE(gmshInitialized());  // the caller's session is left alone
  double size = 0.0;
  gmsh::option::getNumber("Mesh.MeshSizeMax", size);
  EXPECT_EQ(size, 0.123);
  gmsh::finalize();
  EXPECT_FALSE(gmshInitialized());
  ASSERT_EQ(during.chains.at(0).positions.size(), 21u);
  for (std::size_t i = 0; i < 21; ++i) EXPECT_EQ(during.chains[0].positions[i], before.chains[0].positions[i]) << i;
}

}  // namespace
