// Redundant constraints found when a scene is read (core/RedundantRows, named by `check`, left
// out of the model, watched during runs): a closed parallelogram loop whose
// fourth bar repeats what the other three and the ground fix (the classic redundant loop),
// and an independent four-bar as the control. Expected ranks by hand: the parallelogram with
// ground nodes A, B and free C, D has n = 4, bars AC, CD, DB, plus a diagonal-free duplicate.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "core/RedundantRows.hpp"
#include "integrators/InitialState.hpp"
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
  EXPECT_EQ(sc.model->m, 3);
  EXPECT_TRUE(sc.model->redundantRows.empty());
  const DependentRows r = dependentRows(*sc.model, sc.model->initialPositions(), sc.model->nominalParameters());
  EXPECT_TRUE(r.checked);
  EXPECT_EQ(r.rank, 3);
  EXPECT_TRUE(r.rows.empty());
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
  // 4 rows written, rank 3: one row left out of the model, named.
  EXPECT_EQ(sc.model->m, 3);
  ASSERT_EQ(sc.model->redundantRows.size(), 1u);
  const std::string& l = sc.model->redundantRows[0];
  EXPECT_TRUE(l == "again" || l == "CD.length") << l;
  EXPECT_TRUE(dependentRows(*sc.model, sc.model->initialPositions(), sc.model->nominalParameters()).rows.empty());
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
  // n = 6, 6 rows written; the mechanism moves (1 dof), so rank = 5: one dependent row.
  EXPECT_EQ(sc.model->n, 6);
  EXPECT_EQ(sc.model->m, 5);
  EXPECT_EQ(sc.model->redundantRows.size(), 1u);
}

// Running with a redundant row left out: a parallelogram with a third crank, the coupler a
// planar rigid body on C, D with H attached (n = 6, 7 rows, rank 6 at every configuration).
// The coupler translates on circles of radius L, so the mechanism is a pendulum in the crank
// angle theta: J theta'' = -W sin theta with J = 3 (m_c L^2 / 3) + m_k L^2 and
// W = g (3 m_c L / 2 + m_k L). The reference integrates that ODE by RK4 here, and its
// derivative in m_k by central differences of it.
namespace {

constexpr double kG = 9.81, kMc = 1.0, kMk = 2.0, kTheta0 = 0.5;

std::string parallelogram(double mk) {
  const double s = std::sin(kTheta0), c = std::cos(kTheta0);
  std::ostringstream os;
  os.precision(17);
  os << "dimension: 2\ngravity: [0, " << -kG << "]\nnodes:\n"
     << "  - {name: A, position: [0, 0], ground: true}\n  - {name: G, position: [1, 0], ground: true}\n"
     << "  - {name: B, position: [2, 0], ground: true}\n"
     << "  - {name: C, position: [" << s << ", " << -c << "]}\n"
     << "  - {name: H, position: [" << 1 + s << ", " << -c << "]}\n"
     << "  - {name: D, position: [" << 2 + s << ", " << -c << "]}\n"
     << "elements:\n"
     << "  - {name: AC, type: rigid_bar, nodes: [A, C], mass: " << kMc << "}\n"
     << "  - {name: GH, type: rigid_bar, nodes: [G, H], mass: " << kMc << "}\n"
     << "  - {name: BD, type: rigid_bar, nodes: [B, D], mass: " << kMc << "}\n"
     << "  - {name: coupler, type: planar_rigid_body, nodes: [C, D, H], mass: " << mk << ", center_of_mass: ["
     << 1 + s << ", " << -c << "], inertia: 0.7}\n"
     << "parameters:\n  - {name: mk, of: coupler, property: mass}\n"
     << "integrator: {type: trapezoidal, t_end: 2, dt: 0.001}\n";
  return os.str();
}

/// theta(t) of the equivalent pendulum (RK4, 1e-4 s steps: error ~1e-13 rad over 2 s).
double pendulumAngle(double mk, double t) {
  const double J = kMc + mk, W = kG * (1.5 * kMc + mk);
  const int n = static_cast<int>(std::lround(t / 1e-4));
  const double h = t / n;
  double th = kTheta0, om = 0.0;
  auto acc = [&](double a) { return -W / J * std::sin(a); };
  for (int i = 0; i < n; ++i) {
    const double k1t = om, k1o = acc(th);
    const double k2t = om + 0.5 * h * k1o, k2o = acc(th + 0.5 * h * k1t);
    const double k3t = om + 0.5 * h * k2o, k3o = acc(th + 0.5 * h * k2t);
    const double k4t = om + h * k3o, k4o = acc(th + h * k3t);
    th += h / 6 * (k1t + 2 * k2t + 2 * k3t + k4t);
    om += h / 6 * (k1o + 2 * k2o + 2 * k3o + k4o);
  }
  return th;
}

}  // namespace

TEST(Redundancy, ParallelogramWithThirdCrankRunsOnEveryIntegratorAgainstThePendulum) {
  const Scene sc = readSceneText(parallelogram(kMk), "parallelogram.yaml");
  const Model& m = *sc.model;
  ASSERT_EQ(m.n, 6);
  ASSERT_EQ(m.m, 5);  // 6 rows written (3 bars, the coupler's C-D and H's two): one left out
  ASSERT_EQ(m.redundantRows.size(), 1u);
  const VecX p = m.nominalParameters();
  // Reference x_C = L sin theta and its m_k derivative (central differences of the ODE).
  const double dm = 1e-4;
  struct Case { const char* type; double dtOrTol, tolX, tolDx; };
  for (const Case& c : {Case{"trapezoidal", 1e-3, 1e-4, 1e-4}, Case{"generalized_alpha", 1e-3, 1e-4, 1e-4},
                        Case{"maggi_rk4", 1e-3, 1e-6, 1e-6}, Case{"idas", 1e-9, 1e-6, 1e-5},
                        Case{"bdf1", 1e-4, 3e-2, 3e-2}}) {
    Assembler as(m);
    test::Recorder rec;
    IntegratorSettings set = test::integratorSettings(c.type, c.dtOrTol, 2.0);
    integrate(as, p, initialState(as, p), set, rec);
    for (double t : {1.0, 2.0}) {
      const StateWithSens& f = rec.at(t);
      const double xC = f.x.q[0];  // C is the first free node: x(C) is coordinate 0
      EXPECT_NEAR(xC, std::sin(pendulumAngle(kMk, t)), c.tolX) << c.type << " t = " << t;
      const double dref = (std::sin(pendulumAngle(kMk + dm, t)) - std::sin(pendulumAngle(kMk - dm, t))) / (2 * dm);
      ASSERT_EQ(f.dp.size(), 1u);
      EXPECT_NEAR(f.dp[0].q[0], dref, c.tolDx) << c.type << " dx_C/dm_k at t = " << t;
    }
    for (const auto& f : rec.frames) {  // every row, the left-out one included
      EXPECT_LT(as.phi(f.x.q, p).lpNorm<Eigen::Infinity>(), 1e-8) << c.type << " t = " << f.x.t;
      EXPECT_LT(leftOutViolation(m, as, f.x.q, p), 1e-8) << c.type << " t = " << f.x.t;
    }
  }
}

// The monitor can fail: positions off the mechanism violate the left-out row too.
TEST(Redundancy, LeftOutRowsAreEvaluatedOnTheFullConstraint) {
  const Scene sc = readSceneText(parallelogram(kMk), "parallelogram.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = m.nominalParameters();
  const VecX q0 = m.initialPositions();
  EXPECT_LT(leftOutViolation(m, as, q0, p), 1e-14);
  // Moving H alone by 1e-3 m along x breaks the coupler (H's rows) and stretches GH.
  VecX q = q0;
  q[2] += 1e-3;
  EXPECT_GT(leftOutViolation(m, as, q, p) + as.phi(q, p).lpNorm<Eigen::Infinity>(), 5e-4);
  // Every node off by a generic amount: the left-out row itself is violated.
  VecX r(6);
  r << 0.013, -0.007, 0.021, 0.004, -0.017, 0.009;
  EXPECT_GT(leftOutViolation(m, as, q0 + r, p), 1e-4);
}

// A planar four-bar of general planar rigid bodies against the same mechanism built in 3D:
// three rigid_body links in natural coordinates hinged by shared axis points (a revolute
// joint is two shared points on its axis), each link with a point off its plane. The 3D
// loop is the classic redundant one (each revolute joint fixes what the planar loop already
// fixes); after the dependent rows are left out it has d = 1. Same masses, same moment about
// the hinge axes, both at rest under gravity; the 3D coordinates are linear functions of the
// planar ones on the motion, so the trapezoidal steps agree to Newton's round-off.
TEST(Redundancy, FourBarBuiltIn3DWithRevoluteJointsEqualsThePlanarOne) {
  const Eigen::Vector2d A(0, 0), D(2, 0), B(0.3, 1.0), C(1.9, 1.2);
  const double masses[3] = {1.0, 2.0, 1.5}, s = 1e-3;  // s: second moment off the link axis [kg m^2]
  const Eigen::Vector2d ends[3][2] = {{A, B}, {B, C}, {C, D}};
  const char* names[3][2] = {{"A", "B"}, {"B", "C"}, {"C", "D"}};
  std::ostringstream planar, spatial;
  planar.precision(17);
  spatial.precision(17);
  planar << "dimension: 2\ngravity: [0, -9.81]\nnodes:\n  - {name: A, position: [0, 0], ground: true}\n"
            "  - {name: D, position: [2, 0], ground: true}\n  - {name: B, position: [0.3, 1.0]}\n"
            "  - {name: C, position: [1.9, 1.2]}\nelements:\n";
  spatial << "dimension: 3\ngravity: [0, -9.81, 0]\nnodes:\n";
  for (const char* nd : {"A", "D", "B", "C"}) {
    const Eigen::Vector2d x = nd[0] == 'A' ? A : nd[0] == 'D' ? D : nd[0] == 'B' ? B : C;
    const std::string g = (nd[0] == 'A' || nd[0] == 'D') ? ", ground: true" : "";
    spatial << "  - {name: " << nd << ", position: [" << x[0] << ", " << x[1] << ", 0]" << g << "}\n"
            << "  - {name: " << nd << "z, position: [" << x[0] << ", " << x[1] << ", 1]" << g << "}\n";
  }
  std::ostringstream bodies;
  bodies.precision(17);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d a = ends[k][0], b = ends[k][1], mid = 0.5 * (a + b);
    const double L = (b - a).norm(), mL2 = masses[k] * L * L / 12.0;
    const Eigen::Vector3d u((b - a)[0] / L, (b - a)[1] / L, 0), n(-u[1], u[0], 0), z(0, 0, 1);
    const Eigen::Vector2d off = mid + 0.1 * Eigen::Vector2d(n[0], n[1]);
    planar << "  - {name: L" << k << ", type: planar_rigid_body, nodes: [" << names[k][0] << ", " << names[k][1]
           << "], mass: " << masses[k] << ", center_of_mass: [" << mid[0] << ", " << mid[1]
           << "], inertia: " << mL2 + s << "}\n";
    // Second moments: mL^2/12 along the link, s across it in the plane and along z; the
    // moment about z is then mL^2/12 + s, the planar body's.
    const Eigen::Matrix3d S = mL2 * u * u.transpose() + s * n * n.transpose() + s * z * z.transpose();
    const Eigen::Matrix3d I = S.trace() * Eigen::Matrix3d::Identity() - S;
    spatial << "  - {name: X" << k << ", position: [" << off[0] << ", " << off[1] << ", 0]}\n";
    bodies << "  - {name: L" << k << ", type: rigid_body, nodes: [" << names[k][0] << ", " << names[k][0] << "z, "
           << names[k][1] << ", " << names[k][1] << "z, X" << k << "], mass: " << masses[k] << ", center_of_mass: ["
           << mid[0] << ", " << mid[1] << ", 0], inertia: [" << I(0, 0) << ", " << I(1, 1) << ", " << I(2, 2) << ", "
           << I(0, 1) << ", " << I(0, 2) << ", " << I(1, 2) << "]}\n";
  }
  spatial << "elements:\n" << bodies.str();
  const std::string tail = "integrator: {type: trapezoidal, t_end: 1.0, dt: 0.001}\n";
  const Scene p2 = readSceneText(planar.str() + tail, "fourbar2d.yaml");
  const Scene p3 = readSceneText(spatial.str() + tail, "fourbar3d.yaml");
  EXPECT_TRUE(p2.model->redundantRows.empty());
  EXPECT_FALSE(p3.model->redundantRows.empty());
  EXPECT_EQ(p3.model->n - p3.model->m, 1) << "left out: " << p3.model->redundantRows.size();
  struct Last : Observer {
    VecX q;
    double worstLeftOut = 0;
    const Model* m = nullptr;
    const Assembler* as = nullptr;
    const VecX* p = nullptr;
    void frame(const StateWithSens& st) override {
      q = st.x.q;
      worstLeftOut = std::max(worstLeftOut, leftOutViolation(*m, *as, q, *p));
    }
  };
  Last out[2];
  const Scene* scenes[2] = {&p2, &p3};
  for (int i = 0; i < 2; ++i) {
    const Model& m = *scenes[i]->model;
    Assembler as(m);
    const VecX p = m.nominalParameters();
    out[i].m = &m, out[i].as = &as, out[i].p = &p;
    IntegratorSettings set = scenes[i]->integrator;
    set.newtonTol = 1e-14;
    integrate(as, p, initialState(as, p), set, out[i]);
    EXPECT_LT(out[i].worstLeftOut, 1e-9);
    EXPECT_LT(as.phi(out[i].q, p).lpNorm<Eigen::Infinity>(), 1e-9);
  }
  const Model& m3 = *p3.model;
  auto at3 = [&](const char* nd, int c) { return out[1].q[m3.nodes[m3.nodeIndex(nd)].firstDof + c]; };
  const Eigen::Vector4d planarEnd(out[0].q[0], out[0].q[1], out[0].q[2], out[0].q[3]);
  const Eigen::Vector4d spatialEnd(at3("B", 0), at3("B", 1), at3("C", 0), at3("C", 1));
  EXPECT_GT((planarEnd - Eigen::Vector4d(B[0], B[1], C[0], C[1])).norm(), 0.1);  // it did move
  EXPECT_LT((planarEnd - spatialEnd).lpNorm<Eigen::Infinity>(), 1e-10) << planarEnd.transpose() << "\n"
                                                                       << spatialEnd.transpose();
  EXPECT_LT(std::abs(at3("B", 2)) + std::abs(at3("Bz", 2) - 1.0), 1e-10);  // it stayed planar
}
