// PIM parts the satellite cases (SAT1, SAT2) need: SDOFs of a 3D rigid body (centre of mass,
// Tait-Bryan orientation angles) and rigidization rows that the model's constraints already
// imply (left out of A, checked after the solve).
#include <gtest/gtest.h>

#include <regex>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "core/Assembler.hpp"
#include "pim/Pim.hpp"

using namespace flexsens;
using namespace flexsens::test;

namespace {

// ------------------------------------------------------------------ body SDOF scene
/// Two rigid bodies: `body` (four free basic points) and `hinged` (basic point G on the
/// ground); a case listing every body SDOF (not solved: only the SDOF objects are used).
const char* kBodiesScene = R"(
dimension: 3
nodes:
  - {name: A, position: [0.1, 0.2, 0.3]}
  - {name: B, position: [1.2, 0.1, 0.4]}
  - {name: C, position: [0.3, 1.1, 0.2]}
  - {name: D, position: [0.2, 0.4, 1.3]}
  - {name: G, position: [0, 0, 0], ground: true}
  - {name: H, position: [1, 0.2, 0]}
  - {name: I, position: [0.1, 1, 0.1]}
  - {name: J, position: [0.2, 0.1, 0.9]}
elements:
  - {name: body, type: rigid_body, nodes: [A, B, C, D], mass: 2, center_of_mass: [0.4, 0.45, 0.55], inertia: [0.2, 0.25, 0.3]}
  - {name: hinged, type: rigid_body, nodes: [G, H, I, J], mass: 1, center_of_mass: [0.3, 0.35, 0.25], inertia: [0.1, 0.1, 0.1]}
parameters:
  - {name: m, of: body, property: mass}
cases:
  - name: S
    parameters: [m]
    sdofs:
      - {rotation: body, axis: z}
      - {rotation: body, axis: y}
      - {rotation: body, axis: x}
      - {center_of_mass: body, component: x}
      - {center_of_mass: body, component: y}
      - {center_of_mass: body, component: z}
      - {rotation: hinged, axis: z}
      - {rotation: hinged, axis: y}
      - {rotation: hinged, axis: x}
      - {center_of_mass: hinged, component: x}
      - {center_of_mass: hinged, component: y}
      - {center_of_mass: hinged, component: z}
integrator: {type: trapezoidal, t_end: 1, dt: 0.01}
)";

/// Known rotation, z-y'-x'' (yaw, pitch, roll), built independently of the SDOF formulas.
Eigen::Matrix3d taitBryan(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// q with every node of `nodes` moved rigidly: r = pivot + t + R (X - pivot).
void moveRigidly(const Model& m, VecX& q, const std::vector<std::string>& nodes, const Eigen::Matrix3d& R,
                 const Eigen::Vector3d& pivot, const Eigen::Vector3d& t) {
  for (const auto& name : nodes) {
    const int i = m.nodeIndex(name);
    const Eigen::Vector3d r = pivot + t + R * (Eigen::Vector3d(m.nodes[i].position) - pivot);
    for (int c = 0; c < 3; ++c)
      if (m.dof(i, c) >= 0) q[m.dof(i, c)] = r[c];
  }
}

std::string errorOfSdof(const std::string& sdof) {
  std::string s = kBodiesScene;
  const size_t a = s.find("    sdofs:\n"), b = s.find("integrator:");
  s = s.substr(0, a) + "    sdofs:\n      - " + sdof + "\n" + s.substr(b);
  try {
    readSceneText(s, "bodies.yaml", "S");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

// -------------------------------------------------------------- redundancy scene
// A free rigid plate (basic points A, B, C, D; member E) and a beam E-P2-P3-P4 whose nodes
// the model keeps on the plate's plane z = 0 (point_on_plane fixed to the plate; E lies on
// it as a member of the plate). Counts by hand:
//   n = 3 * 8 = 24 (A, B, C, D, E, P2, P3, P4 free);
//   m = 6 (plate distances) + 3 (E attached to the plate) + 3 (P2, P3, P4 on the plane) = 12
//       [+ 1 with the distance constraint dEP3];  d = 12 [11].
// Rigidizing the beam (a 2D cloud: basic points E, P3 (farthest from E), P4 (farthest from
// the line E-P3), attached point P2) generates 3 distances + 3 attached-point rows = 6. The
// cloud's coordinates relative to the plate are 6 in-plane ones (the plane takes the
// out-of-plane ones), of which the rigid cloud keeps 1 (the turn about the plate normal at E),
// so 5 rows are independent: the z row of P2's attached-point equation is implied
// (n . Lambda_P2 is a combination of the plane equations of P2, P3, P4 and of E's), m_r = 5,
// d_s = 12 - 5 = 7. With dEP3 (the model fixes |E P3| already) d(E,P3) is implied as well:
// m_r = 4, dropped 2, d_s = 11 - 4 = 7.
// SDOFs: the plate's centre of mass and angles (6) and x(P3) (the cloud's turn about E).
std::string redundancyScene(bool withDistance, bool rigidVelocity = true) {
  std::string s = R"(
dimension: 3
nodes:
  - {name: A, position: [0, 0, 0]}
  - {name: B, position: [1, 0, 0]}
  - {name: C, position: [0, 1, 0]}
  - {name: D, position: [0, 0, 1]}
  - {name: E, position: [0.5, 0.5, 0]}
  - {name: P2, position: [1.5, 0.5, 0]}
  - {name: P3, position: [1.6, 1.4, 0]}
  - {name: P4, position: [0.6, 1.8, 0]}
elements:
  - {name: plate, type: rigid_body, nodes: [A, B, C, D, E], mass: 3, center_of_mass: [0.3, 0.3, 0.2],
     inertia: [0.2, 0.25, 0.3], angular_velocity: [0.3, -0.2, 0.5], velocity: [0.1, 0, 0.05]}
  - {name: beam, type: beam, nodes: [E, P2, P3, P4], E: 1.0e7, density: 100, section: {area: 1.0e-3, inertia: 1.0e-7}}
constraints:
  - {name: onplate, type: point_on_plane, nodes: [P2, P3, P4], body: plate, point: [0, 0, 0], normal: [0, 0, 1]}
DISTANCE
parameters:
  - {name: mp, of: plate, property: mass}
PARAMETER
cases:
  - name: OK
    parameters: [mp]
    rigidize: [beam]
    sdofs:
      - {center_of_mass: plate, component: x, dp: 1.0}
      - {center_of_mass: plate, component: y, dp: -0.5}
      - {center_of_mass: plate, component: z, dp: 0.2}
      - {rotation: plate, axis: x, dp: 0.3, dv: 0.1}
      - {rotation: plate, axis: y, dp: -0.2}
      - {rotation: plate, axis: z, dp: 0.4, dv: -0.2}
      - {node: P3, component: x, dp: 0.1}
CASE_BAD
  - name: COUNT
    parameters: [mp]
    rigidize: [beam]
    sdofs: [{node: P3, component: x}]
integrator: {type: trapezoidal, t_end: 0.01, dt: 0.01}
output: {vtk: false, plots: false}
)";
  auto put = [&](const std::string& key, const std::string& text) { s.replace(s.find(key), key.size(), text); };
  // Initial velocities: the plate's twist on every node (the beam moves rigidly with it, so
  // the rigidized cloud starts undeformed at the velocity level too).
  const Eigen::Vector3d vG(0.1, 0, 0.05), w(0.3, -0.2, 0.5), com(0.3, 0.3, 0.2);
  if (rigidVelocity)
  for (const auto& [name, r] : {std::make_pair("P2", Eigen::Vector3d(1.5, 0.5, 0)),
                                std::make_pair("P3", Eigen::Vector3d(1.6, 1.4, 0)),
                                std::make_pair("P4", Eigen::Vector3d(0.6, 1.8, 0))}) {
    const Eigen::Vector3d v = vG + w.cross(r - com);
    std::ostringstream os;
    os.precision(17);
    os << "velocity: [" << v[0] << ", " << v[1] << ", " << v[2] << "]}";
    const std::string key = std::string("{name: ") + name + ",";
    const size_t at = s.find(key);
    const size_t end = s.find("}", at);
    s.replace(end, 1, ", " + os.str());
  }
  put("DISTANCE\n", withDistance ? "  - {name: dEP3, type: distance, nodes: [E, P3]}\n" : "");
  put("PARAMETER\n", withDistance ? "  - {name: L, of: dEP3, property: length}\n" : "");
  put("CASE_BAD\n", withDistance ? R"(  - name: BAD
    parameters: [L]
    rigidize: [beam]
    sdofs:
      - {center_of_mass: plate, component: x}
      - {center_of_mass: plate, component: y}
      - {center_of_mass: plate, component: z}
      - {rotation: plate, axis: x}
      - {rotation: plate, axis: y}
      - {rotation: plate, axis: z}
      - {node: P3, component: x}
)" : "");
  return s;
}

}  // namespace

TEST(PimSatBodySdof, RotationAndCentreOfMassOfARigidlyMovedBody) {
  Scene sc = readSceneText(kBodiesScene, "bodies.yaml", "S");
  const Model& m = *sc.model;
  const auto& z = sc.pimCase->sdofs;
  ASSERT_EQ(z.size(), 12u);
  EXPECT_EQ(z[0]->name, "yaw(body)");
  EXPECT_EQ(z[3]->name, "com.x(body)");
  const VecX q0 = m.initialPositions();
  for (const auto& s : z) {
    if (s->name.rfind("com", 0) == 0) continue;
    EXPECT_NEAR(s->value(m, q0), 0.0, 1e-14) << s->name;  // R = I at t = 0
  }
  const Eigen::Vector3d com0(0.4, 0.45, 0.55), comH(0.3, 0.35, 0.25);
  for (const auto& angles : {Eigen::Vector3d(0.7, -0.4, 1.1), Eigen::Vector3d(-2.5, 1.2, -0.3),
                             Eigen::Vector3d(3.0, 0.05, 2.9)}) {
    const double yaw = angles[0], pitch = angles[1], roll = angles[2];
    const Eigen::Matrix3d R = taitBryan(yaw, pitch, roll);
    const Eigen::Vector3d t(0.3, -0.2, 0.5), XA(0.1, 0.2, 0.3);
    VecX q = q0;
    moveRigidly(m, q, {"A", "B", "C", "D"}, R, XA, t);
    moveRigidly(m, q, {"H", "I", "J"}, R, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());  // about ground G
    const double expected[3] = {yaw, pitch, roll};
    for (int b = 0; b < 2; ++b) {
      for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(z[6 * b + a]->value(m, q), expected[a], 1e-12) << z[6 * b + a]->name << " " << angles.transpose();
      const Eigen::Vector3d G = b == 0 ? Eigen::Vector3d(XA + t + R * (com0 - XA)) : Eigen::Vector3d(R * comH);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(z[6 * b + 3 + c]->value(m, q), G[c], 1e-12) << z[6 * b + 3 + c]->name;
    }
  }
}

TEST(PimSatBodySdof, GradientAndHessianMatchFiniteDifferences) {
  Scene sc = readSceneText(kBodiesScene, "bodies.yaml", "S");
  const Model& m = *sc.model;
  VecX q = m.initialPositions();
  moveRigidly(m, q, {"A", "B", "C", "D"}, taitBryan(0.7, -0.4, 1.1), Eigen::Vector3d(0.1, 0.2, 0.3),
              Eigen::Vector3d(0.3, -0.2, 0.5));
  moveRigidly(m, q, {"H", "I", "J"}, taitBryan(-1.2, 0.5, 0.4), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  std::srand(7);
  // At the rigidly moved configuration and at a deformed one (R not orthogonal).
  for (const VecX& x : {q, VecX(q + 0.03 * VecX::Random(m.n))}) {
    for (const auto& z : sc.pimCase->sdofs) {
      const VecX g = z->gradient(m, x);
      const MatX fg = fdJacobian([&](const VecX& y) { return VecX::Constant(1, z->value(m, y)); }, x);
      EXPECT_LT(relErr(g, VecX(fg.transpose())), 1e-8) << z->name;
      EXPECT_GT(g.norm(), 0.1) << z->name;  // not trivially zero
      const MatX H = z->hessian(m, x);
      EXPECT_LT(relErr(H, fdJacobian([&](const VecX& y) { return z->gradient(m, y); }, x)), 1e-7) << z->name;
      EXPECT_LT((H - H.transpose()).lpNorm<Eigen::Infinity>(), 1e-12) << z->name;
      // Ground basic point G carries no coordinates: the hinged body's SDOFs touch H, I, J only.
      if (z->name.find("hinged") != std::string::npos)
        for (const char* nd : {"A", "B", "C", "D"})
          for (int c = 0; c < 3; ++c) EXPECT_EQ(g[m.dof(m.nodeIndex(nd), c)], 0.0) << z->name;
    }
  }
}

TEST(PimSatBodySdof, UnknownBodyAndBadComponentNameTheKey) {
  std::string e = errorOfSdof("{rotation: nobody, axis: z}");
  EXPECT_NE(e.find("bodies.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("key 'cases[0].sdofs[0].rotation': no rigid_body named 'nobody'"), std::string::npos) << e;
  EXPECT_NE(e.find("the scene has: body, hinged"), std::string::npos) << e;
  e = errorOfSdof("{center_of_mass: nobody, component: x}");
  EXPECT_NE(e.find("key 'cases[0].sdofs[0].center_of_mass': no rigid_body named 'nobody'"), std::string::npos) << e;
  e = errorOfSdof("{rotation: body, axis: w}");
  EXPECT_NE(e.find("key 'cases[0].sdofs[0].axis': expected x (roll), y (pitch) or z (yaw)"), std::string::npos) << e;
  e = errorOfSdof("{rotation: body}");
  EXPECT_NE(e.find("cases[0].sdofs[0]"), std::string::npos) << e;
  EXPECT_NE(e.find("axis"), std::string::npos) << e;
  e = errorOfSdof("{center_of_mass: body, component: q}");
  EXPECT_NE(e.find("key 'cases[0].sdofs[0].component': expected one of x, y, z"), std::string::npos) << e;
  e = errorOfSdof("{rotation: body, axis: x, node: A}");
  EXPECT_NE(e.find("give one SDOF kind"), std::string::npos) << e;
}

namespace {

struct RedundancyRun {
  Scene sc;
  std::unique_ptr<Assembler> as;
  PimReport rep;
  StateWithSens s;
};

std::unique_ptr<RedundancyRun> solveCase(bool withDistance, const std::string& name) {
  auto r = std::make_unique<RedundancyRun>();
  r->sc = readSceneText(redundancyScene(withDistance), "redundant.yaml", name);
  r->as = std::make_unique<Assembler>(*r->sc.model);
  r->s = initialState(*r->as, r->sc.model->nominalParameters(), r->sc.pimCase.get(), &r->rep);
  return r;
}

/// q_p0 and q'_p0 satisfy EVERY generated rigidization equation (dropped ones included) and
/// q_p0 equals central differences of the nonlinear perturbed initial model.
void checkSolution(const RedundancyRun& r) {
  const Model& m = *r.sc.model;
  const VecX p0 = m.nominalParameters();
  const Assembler lam(m, &r.sc.pimCase->lambda);
  const MatX L = lam.phiQDense(r.s.x.q, p0);
  ASSERT_GT(r.s.x.v.norm(), 0.1);  // the plate turns: the velocity level is not trivial
  ASSERT_LT((L * r.s.x.v).lpNorm<Eigen::Infinity>(), 1e-12);  // ... and the cloud moves rigidly
  for (int k = 0; k < static_cast<int>(p0.size()); ++k) {
    const State& d = r.s.dp[k];
    const VecX pos = L * d.q + lam.phiParamDerivative(r.s.x.q, p0, k);
    const VecX vel = L * d.v + lam.hessianRowsTimes(r.s.x.q, p0, r.s.x.v, d.q) +
                     lam.phiQParamDerivativeTimes(r.s.x.q, p0, k, r.s.x.v);
    EXPECT_LT(pos.lpNorm<Eigen::Infinity>(), 1e-12);
    EXPECT_LT(vel.lpNorm<Eigen::Infinity>(), 1e-12);
    EXPECT_LT((r.as->phiQDense(r.s.x.q, p0) * d.q + r.as->phiParamDerivative(r.s.x.q, p0, k)).lpNorm<Eigen::Infinity>(),
              1e-12);
    const double h = 1e-6;
    VecX pp = p0, pm = p0;
    pp[k] += h;
    pm[k] -= h;
    const VecX fd = (perturbedConfiguration(*r.as, *r.sc.pimCase, r.s.x.q, p0, pp, k) -
                     perturbedConfiguration(*r.as, *r.sc.pimCase, r.s.x.q, p0, pm, k)) / (2 * h);
    std::printf("  case %s: |q_p0|_inf = %.4f, |q_p0 - FD|_inf = %.2e, |Lambda_q q_p0 + Lambda_p|_inf = %.1e\n",
                r.sc.pimCase->name.c_str(), d.q.lpNorm<Eigen::Infinity>(), (d.q - fd).lpNorm<Eigen::Infinity>(),
                pos.lpNorm<Eigen::Infinity>());
    EXPECT_GT(d.q.lpNorm<Eigen::Infinity>(), 0.1);
    EXPECT_LT((d.q - fd).lpNorm<Eigen::Infinity>(), 1e-8);
    // The perturbed configuration satisfies all generated rows, dropped ones included.
    EXPECT_LT(lam.phi(perturbedConfiguration(*r.as, *r.sc.pimCase, r.s.x.q, p0, pp, k), pp).lpNorm<Eigen::Infinity>(),
              1e-12);
  }
}

}  // namespace

TEST(PimSatRedundancy, PlanarCloudOnABodyPlaneDropsItsOutOfPlaneRow) {
  auto r = solveCase(false, "OK");
  EXPECT_EQ(r->rep.n, 24);
  EXPECT_EQ(r->rep.m, 12);
  EXPECT_EQ(r->rep.d, 12);
  EXPECT_EQ(r->rep.lambdaGenerated, 6);
  EXPECT_EQ(r->rep.mr, 5);
  EXPECT_EQ(r->rep.lambdaDropped, 1);
  EXPECT_EQ(r->rep.ds, 7);
  // The dropped row is the z row of P2's attached-point equation (the last one generated).
  const Assembler lam(*r->sc.model, &r->sc.pimCase->lambda);
  const LambdaSelection sel = selectRigidizationRows(*r->as, lam, r->s.x.q, r->sc.model->nominalParameters());
  ASSERT_EQ(sel.dropped.size(), 1u);
  EXPECT_EQ(sel.dropped[0], 5);
  EXPECT_NE(lam.rowLabel(5).find("point(P2)"), std::string::npos) << lam.rowLabel(5);
  EXPECT_LT(r->rep.condition, 1e8);
  const PimReport counts = pimCounts(*r->as, *r->sc.pimCase, r->s.x.q, r->sc.model->nominalParameters());
  EXPECT_EQ(counts.mr, 5);
  EXPECT_EQ(counts.ds, 7);
  EXPECT_EQ(counts.lambdaDropped, 1);
  checkSolution(*r);
}

TEST(PimSatRedundancy, DistanceTheModelFixesIsDroppedToo) {
  auto r = solveCase(true, "OK");
  EXPECT_EQ(r->rep.m, 13);
  EXPECT_EQ(r->rep.d, 11);
  EXPECT_EQ(r->rep.lambdaGenerated, 6);
  EXPECT_EQ(r->rep.mr, 4);
  EXPECT_EQ(r->rep.lambdaDropped, 2);
  EXPECT_EQ(r->rep.ds, 7);
  checkSolution(*r);
}

TEST(PimSatRedundancy, ParameterTheKeptRowsCannotAbsorbIsAnOverConstraint) {
  // L changes |E P3|, which the rigidized beam keeps (its dropped row d(E,P3)).
  try {
    solveCase(true, "BAD");
    FAIL() << "expected an over-constraint error";
  } catch (const InputError& e) {
    const std::string w = e.what();
    // Located at the case: "redundant.yaml:<line>:<col>: key 'cases[1]': case 'BAD': ..."
    EXPECT_TRUE(std::regex_search(w, std::regex(R"(redundant\.yaml:[0-9]+:[0-9]+: key 'cases\[1\]': case 'BAD': )"
                                                R"(the rigidized bodies over-constrain the mechanism for parameter 'L')")))
        << w;
    EXPECT_NE(w.find("[beam.rigid.d(E,P3)]"), std::string::npos) << w;
    EXPECT_NE(w.find("rigidize fewer bodies"), std::string::npos) << w;
  }
}

TEST(PimSatRedundancy, SdofCountUsesTheIndependentRows) {
  try {
    solveCase(false, "COUNT");
    FAIL() << "expected a count error";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("case 'COUNT': 1 SDOF(s) given, but d - m_r = 12 - 5 = 7 are required"), std::string::npos) << w;
    EXPECT_NE(w.find("of 6 generated; 1 are implied by the constraints"), std::string::npos) << w;
  }
}

TEST(PimSatRedundancy, SummaryReportsGeneratedAndDroppedRows) {
  namespace fs = std::filesystem;
  const fs::path out = fs::temp_directory_path() / ("flexsens_pimsat_" + std::to_string(::getpid()));
  fs::remove_all(out);
  Scene sc = readSceneText(redundancyScene(false), "redundant.yaml", "OK");
  runScene(sc, out.string());
  std::ifstream in(out / "summary.json");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string js = ss.str();
  EXPECT_NE(js.find("\"m_r\": 5, \"d_s\": 7, \"lambda_generated\": 6, \"lambda_dropped\": 1"), std::string::npos) << js.substr(0, 600);
  fs::remove_all(out);
}

TEST(PimSatRedundancy, NonRigidInitialVelocityOfTheCloudIsReported) {
  // Without their twist the beam nodes start at rest (projected onto the plane's velocity
  // constraint) while E turns with the plate: the cloud deforms at t = 0, and the implied
  // out-of-plane row cannot hold at the velocity level.
  try {
    Scene sc = readSceneText(redundancyScene(false, false), "redundant.yaml", "OK");
    Assembler as(*sc.model);
    initialState(as, sc.model->nominalParameters(), sc.pimCase.get());
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("velocity (q'_p0) sensitivities: [beam.rigid.point(P2)[2]]"), std::string::npos) << w;
    EXPECT_NE(w.find("give the rigidized bodies a rigid initial velocity"), std::string::npos) << w;
  }
}
