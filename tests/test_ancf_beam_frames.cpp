// Frames of spatial ANCF beams (elements/AncfBeam3D, constraints/FrameJointReader): general
// sections (area, Iy, Iz, J, rotary inertia) against the beam formulas, the weld and the
// hinge between beam ends at an angle against a single bent beam and the free rotation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "TestModels.hpp"
#include "app/Run.hpp"
#include "core/Assembler.hpp"
#include "integrators/Static.hpp"
#include "scene/Scene.hpp"

using namespace flexsens;

namespace {

/// A straight clamped shaft along x of length 2 in 4 elements with a general section; the tip
/// carries `loads` (point_force / point_torque items).
std::string shaft(const std::string& section, const std::string& loads, const std::string& extra = "") {
  return "dimension: 3\ngravity: [0, 0, 0]\nnodes:\n"
         "  - {name: A, position: [0, 0, 0], ground: true, clamped: true}\n"
         "  - {name: n1, position: [0.5, 0, 0]}\n  - {name: n2, position: [1, 0, 0]}\n"
         "  - {name: n3, position: [1.5, 0, 0]}\n  - {name: tip, position: [2, 0, 0]}\n"
         "elements:\n"
         "  - {name: s, type: ancf_beam, nodes: [A, n1, n2, n3, tip], E: 1.0e6, nu: -0.5, density: 1.0,\n"
         "     section: " + section + extra + "}\n" + loads + "static: {load_steps: 1}\n";
}

VecX solve(const Scene& sc) {
  Assembler as(*sc.model);
  StaticSettings set;
  set.steps = 1;
  set.tol = 1e-13;
  return solveStatic(as, sc.model->nominalParameters(), sc.model->initialPositions(), set);
}

}  // namespace

// A general section {area, Iy, Iz, J} with G = E (nu = -0.5): the twist under a tip torque is
// T L / (G J) (not G (Iy + Iz)); the tip deflections under forces along y and z are the
// Timoshenko cantilever's P L^3 / (3 E I) + P L / (G A) with I = Iz and Iy, less the element's
// bending error 1 / (4 N^2) at N = 4 (test_ancf_beam3d measures it on rectangles).
TEST(AncfBeamFrames, GeneralSectionGivesItsStiffnesses) {
  const double E = 1e6, G = 1e6, A = 2.0, Iy = 3e-3, Iz = 1e-3, J = 1.5e-3, L = 2.0;
  const std::string sec = "{area: 2.0, Iy: 3.0e-3, Iz: 1.0e-3, J: 1.5e-3}";
  const double T = 1e-6 * G * J / L;
  const Scene twist = readSceneText(shaft(sec, "  - {name: t, type: point_torque, node: tip, torque: [" +
                                                   std::to_string(T) + ", 0, 0]}\n"),
                                    "shaft.yaml");
  const VecX q = solve(twist);
  const Model& m = *twist.model;
  const int tip = m.nodeIndex("tip");
  const double theta = std::atan2(q[m.dof(tip, 8)], q[m.dof(tip, 7)]);  // r_y's z over its y
  std::printf("twist / (T L / (G J)) = %.8f\n", theta / (T * L / (G * J)));
  // point_torque's couple on r_y, r_z leaves an end effect of ~1e-3 (8.3e-4 on a 0.1 m square
  // without J, where the consistent end torque of test_ancf_beam3d gives 1e-6); J = Iy + Iz
  // would give 2.67 here
  EXPECT_NEAR(theta / (T * L / (G * J)), 1.0, 1.5e-3);
  for (int axis : {1, 2}) {  // a 1 N force along y, then z: linear response
    const double I = axis == 1 ? Iz : Iy;
    const Scene bend = readSceneText(
        shaft(sec, std::string("  - {name: p, type: point_force, node: tip, force: ") +
                       (axis == 1 ? "[0, 1, 0]" : "[0, 0, 1]") + "}\n"),
        "shaft.yaml");
    const VecX qb = solve(bend);
    const double w = qb[bend.model->dof(tip, axis)], ref = L * L * L / (3 * E * I) + L / (G * A);
    std::printf("bending along %c: w / Timoshenko = %.5f\n", axis == 1 ? 'y' : 'z', w / ref);
    EXPECT_NEAR(w / ref, 1.0 - 1.0 / 64, 1e-3) << "axis " << axis;  // the element's 1 / (4 N^2), N = 4
  }
}

// The mass of an element of a general section with given rotary inertia: a translation u has
// kinetic energy rho A L u^2 / 2, a spin w about the axis (gradient rates w x r_y, w x r_z)
// (rho Iy + rho Iz) L w^2 / 2; without rotary_inertia the spin's is density (Iy + Iz) L w^2 / 2.
TEST(AncfBeamFrames, GeneralSectionMass) {
  for (const bool given : {true, false}) {
    const Scene sc = readSceneText(
        shaft("{area: 2.0, Iy: 3.0e-3, Iz: 1.0e-3, J: 1.5e-3}", "", given ? ", rotary_inertia: [7.0, 5.0]" : ""),
        "shaft.yaml");
    const Model& m = *sc.model;
    Assembler as(m);
    const VecX q = m.initialPositions(), v = VecX::Zero(m.n), p = m.nominalParameters();
    const Element& el = *m.elements[1];  // n1-n2, both free
    const LocalState s = as.localState(el, q, v, p);
    MatX M;
    el.mass(s, M);
    VecX u = VecX::Zero(24), spin = VecX::Zero(24);
    for (int end : {0, 12}) {
      u[end] = 1.0;                   // positions along x
      spin.segment<3>(end + 6) << 0, 0, 1;   // d r_y / dt = x x y = z
      spin.segment<3>(end + 9) << 0, -1, 0;  // d r_z / dt = x x z = -y
    }
    const double L = 0.5;
    EXPECT_NEAR(u.dot(M * u), 1.0 * 2.0 * L, 1e-12);
    const double rotary = given ? 7.0 + 5.0 : 1.0 * (3e-3 + 1e-3);
    EXPECT_NEAR(spin.dot(M * spin), rotary * L, 1e-12 * rotary) << (given ? "given" : "from density");
  }
}

namespace {

/// An L-frame: leg 1 along x from the clamped origin, leg 2 along y from the elbow, each of
/// length 1 in N elements, joined at the elbow by `joint` (between nodes e1, e2); a force P
/// along z at leg 2's tip.
std::string lFrame(int N, const std::string& joint, double P) {
  std::string nodes = "  - {name: A, position: [0, 0, 0], ground: true, clamped: true}\n", leg1 = "A", leg2 = "e2";
  char buf[160];
  for (int i = 1; i <= N; ++i) {
    const std::string n = i == N ? "e1" : "a" + std::to_string(i);
    std::snprintf(buf, sizeof buf, "  - {name: %s, position: [%.17g, 0, 0]}\n", n.c_str(), double(i) / N);
    nodes += buf;
    leg1 += ", " + n;
  }
  nodes += "  - {name: e2, position: [1, 0, 0]}\n";
  for (int i = 1; i <= N; ++i) {
    const std::string n = i == N ? "tip" : "b" + std::to_string(i);
    std::snprintf(buf, sizeof buf, "  - {name: %s, position: [1, %.17g, 0]}\n", n.c_str(), double(i) / N);
    nodes += buf;
    leg2 += ", " + n;
  }
  const std::string sec = "E: 1.0e6, nu: -0.5, density: 1.0, section: {area: 1.0, Iy: 1.0e-3, Iz: 2.0e-3, J: 1.5e-3}";
  return "dimension: 3\ngravity: [0, 0, 0]\nnodes:\n" + nodes + "elements:\n  - {name: leg1, type: ancf_beam, nodes: [" +
         leg1 + "], " + sec + "}\n  - {name: leg2, type: ancf_beam, nodes: [" + leg2 + "], " + sec +
         "}\n  - {name: p, type: point_force, node: tip, force: [0, 0, " + std::to_string(P) + "]}\n" +
         "constraints:\n  - {name: corner, " + joint + ", nodes: [e1, e2]}\nstatic: {load_steps: 1}\n";
}

}  // namespace

// A welded right-angle frame under a small out-of-plane tip load: the tip deflection is both
// legs' bending about their y axes, leg 1's twist by the moment P L2 (times L2) and both legs'
// shear: P (L1^3 + L2^3) / (3 E Iy) + P L2^2 L1 / (G J) + P (L1 + L2) / (G A), less the
// elements' O(1/N^2) bending error. The weld passes the moment on as the sections' gradients,
// which distorts the sections at the joint a little (as a point_torque on a node does): the
// frame is 0.2% (N = 4) to 0.4% (N = 8) more flexible than with a rigid joint, growing on
// meshes much finer than the section (1.5% at N = 64, section 0.11 x 0.15 on legs of 1;
// docs/known-limits.md).
TEST(AncfBeamFrames, WeldedRightAngleFrame) {
  const double E = 1e6, G = 1e6, A = 1.0, Iy = 1e-3, J = 1.5e-3, P = 1e-6;
  const double bending = P * 2 / (3 * E * Iy), twist = P / (G * J), shear = P * 2 / (G * A);
  for (int N : {4, 8}) {
    const Scene sc = readSceneText(lFrame(N, "type: weld", P), "frame.yaml");
    const Model& m = *sc.model;
    const VecX q = solve(sc);
    const double w = q[m.dof(m.nodeIndex("tip"), 2)], ref = bending + twist + shear;
    const double bendingError = 1.0 / (4.0 * N * N) * bending;  // the element's, per test_ancf_beam3d
    std::printf("welded L-frame N = %d: w / analytic = %.6f (bending error alone %.6f)\n", N, w / ref,
                1.0 - bendingError / ref);
    EXPECT_NEAR(w / ref, 1.0 - bendingError / ref, 6e-3) << "N = " << N;
  }
}

// The hinge's rows leave exactly the rotation about its axis to leg 2's end: at the start,
// d/dt of (r, J) of e2 for a spin w about the axis (dJ = w x J) is in the null space of the
// hinge's Jacobian, spins about the two other axes are not; the weld blocks all three.
TEST(AncfBeamFrames, HingeFreesOnlyItsAxis) {
  for (const bool hinge : {true, false}) {
    const Scene sc = readSceneText(lFrame(2, hinge ? "type: hinge, axis: [0, 0, 1]" : "type: weld", 1.0), "frame.yaml");
    const Model& m = *sc.model;
    Assembler as(m);
    const VecX q = m.initialPositions(), p = m.nominalParameters();
    const MatX Jq = as.phiQDense(q, p);
    const int e2 = m.nodeIndex("e2");
    for (int axis = 0; axis < 3; ++axis) {
      VecX v = VecX::Zero(m.n);
      const Eigen::Vector3d w = Eigen::Vector3d::Unit(axis);
      for (int g = 0; g < 3; ++g) {
        const int d = m.dof(e2, 3 + 3 * g);
        v.segment<3>(d) = w.cross(Eigen::Vector3d(q.segment<3>(d)));
      }
      const double residual = (Jq * v).norm();
      const bool free = hinge && axis == 2;
      EXPECT_EQ(residual < 1e-12, free) << (hinge ? "hinge" : "weld") << ", spin about axis " << axis << ": " << residual;
    }
  }
}

// A general section with given rotary inertia: dQ/dp and dM/dp of E, nu and density against AD
// (1e-10) and central differences (1e-6) at a deformed state (the rotary inertia does not move
// with the density).
TEST(AncfBeamFrames, GeneralSectionParameterDerivatives) {
  const Scene sc = readSceneText(shaft("{area: 2.0, Iy: 3.0e-3, Iz: 1.0e-3, J: 1.5e-3}", "",
                                       ", rotary_inertia: [7.0, 5.0]}\nparameters:\n"
                                       "  - {name: E, of: s, property: E}\n  - {name: nu, of: s, property: nu}\n"
                                       "  - {name: rho, of: s, property: density"),
                                 "shaft.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  std::srand(3);
  VecX p = m.nominalParameters();
  const VecX q = m.initialPositions() + 0.02 * VecX::Random(m.n), v = VecX::Zero(m.n);
  LocalState s = as.localState(*m.elements[1], q, v, p);
  s.p = &p;
  test::expectParameterDerivatives(*m.elements[1], s, p, 3);
}

namespace {

/// The welded or hinged L-frame of lFrame (N = 3 per leg) swinging under a tip force of 20 N
/// for 0.3 s (trapezoidal, dt 0.005, a frame every step), E and density parameters: max over the
/// frames of |dd - central difference (h = 1e-4 |p|)| / max |dd| of the tip's z, per parameter.
std::vector<double> frameRunErrors(const std::string& joint) {
  const Scene sc = readSceneText(lFrame(3, joint, 20.0) +
                                     "parameters:\n  - {name: E, of: leg1, property: E}\n"
                                     "  - {name: rho, of: leg2, property: density}\n",
                                 "frame.yaml");
  const Model& m = *sc.model;
  Assembler as(m);
  const VecX p = m.nominalParameters();
  auto set = test::integratorSettings("trapezoidal", 0.005, 0.3);
  set.frameInterval = 0.005;
  test::Recorder dd;
  integrate(as, p, initialState(as, p), set, dd);
  const int z = m.dof(m.nodeIndex("tip"), 2);
  std::vector<double> errors;
  for (size_t k = 0; k < m.parameters.size(); ++k) {
    const double h = 1e-4 * std::abs(p[k]);
    const auto [plus, minus] = test::runsAtPlusMinus(as, p, k, h, set);
    double scale = 0.0, err = 0.0;
    for (size_t f = 1; f < dd.frames.size(); ++f) {
      const double nd = (plus.frames[f].x.q[z] - minus.frames[f].x.q[z]) / (2 * h);
      scale = std::max(scale, std::abs(dd.frames[f].dp[k].q[z]));
      err = std::max(err, std::abs(dd.frames[f].dp[k].q[z] - nd));
    }
    std::printf("  %s: dtip_z/d%s at 0.3 s %+.6e, max |dd - nd| / max |dd| %.2e\n", joint.c_str(),
                m.parameters[k].name.c_str(), dd.frames.back().dp[k].q[z], err / scale);
    errors.push_back(scale > 0.0 ? err / scale : 1.0);
  }
  return errors;
}

}  // namespace

// Sensitivities of a welded and of a hinged frame's motion against central differences of whole
// runs (1e-6 of the largest |dz/dp|).
TEST(AncfBeamFrames, JointSensitivitiesMatchCentralDifferences) {
  for (const std::string joint : {"type: weld", "type: hinge, axis: [0, 1, 0]"})
    for (const double e : frameRunErrors(joint)) EXPECT_LT(e, 1e-6) << joint;
}

// An i_beam section equals the general section of its A, Iy, Iz and thin-walled J computed here
// (IPE 200-like: h 0.2, b 0.1, web 5.6 mm, flanges 8.5 mm): the same elastic force on a deformed
// shaft and the same mass.
TEST(AncfBeamFrames, IBeamIsItsGeneralSection) {
  const double h = 0.2, b = 0.1, tw = 0.0056, tf = 0.0085, hw = h - 2 * tf;
  const double A = 2 * b * tf + hw * tw;
  const double Iy = (b * h * h * h - (b - tw) * hw * hw * hw) / 12, Iz = (2 * tf * b * b * b + hw * tw * tw * tw) / 12;
  const double J = (2 * b * tf * tf * tf + hw * tw * tw * tw) / 3;
  char general[200];
  std::snprintf(general, sizeof general, "{area: %.17g, Iy: %.17g, Iz: %.17g, J: %.17g}", A, Iy, Iz, J);
  const Scene ib = readSceneText(shaft("{i_beam: {height: 0.2, width: 0.1, web: 0.0056, flange: 0.0085}}", ""), "i.yaml");
  const Scene gs = readSceneText(shaft(general, ""), "g.yaml");
  std::srand(5);
  const VecX q = ib.model->initialPositions() + 0.01 * VecX::Random(ib.model->n), v = VecX::Zero(ib.model->n);
  Assembler ai(*ib.model), ag(*gs.model);
  const VecX pi = ib.model->nominalParameters(), pg = gs.model->nominalParameters();
  const LocalState si = ai.localState(*ib.model->elements[1], q, v, pi), sg = ag.localState(*gs.model->elements[1], q, v, pg);
  VecX Qi, Qg;
  MatX Mi, Mg;
  ib.model->elements[1]->force(si, Qi);
  gs.model->elements[1]->force(sg, Qg);
  ib.model->elements[1]->mass(si, Mi);
  gs.model->elements[1]->mass(sg, Mg);
  EXPECT_GT(Qi.norm(), 0.0);
  EXPECT_LT(test::relMax(Qi, Qg), 1e-12);
  EXPECT_LT(test::relMax(Mi, Mg), 1e-12);
}
