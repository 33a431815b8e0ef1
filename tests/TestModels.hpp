// Small models and finite-difference helpers shared by the tests.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "app/FiniteDifferences.hpp"
#include "app/Run.hpp"
#include "elements/Beam.hpp"
#include "integrators/State.hpp"
#include "scene/Scene.hpp"

namespace flexsens::test {

inline std::string sourceDir() { return FLEXSENS_SOURCE_DIR; }

/// A bar O-T (2 kg, 1 m, planar, gravity -y) turned about the ground node O by a motor,
/// theta(t) = 0.5 sin(3t) from the ground direction O-X: closed forms for a driver's reaction,
/// its work and velocity outputs. Tests append `parameters`, `integrator`, `outputs`.
inline const char* kMotorBarScene = R"(dimension: 2
gravity: [0, -9.81]
nodes:
  - {name: O, position: [0, 0], ground: true}
  - {name: X, position: [1, 0], ground: true}
  - {name: T, position: [1, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [O, T], mass: 2.0}
constraints:
  - {name: motor, type: motor, nodes: [O, X, O, T], function: {type: harmonic, amplitude: 0.5, omega: 3}}
)";

/// Central finite-difference Jacobian of f at x (columns = d f / d x_j).
inline MatX fdJacobian(const std::function<VecX(const VecX&)>& f, const VecX& x, double h = 1e-6) {
  const VecX f0 = f(x);
  MatX J(f0.size(), x.size());
  for (int j = 0; j < x.size(); ++j) {
    VecX xp = x, xm = x;
    const double s = h * std::max(1.0, std::abs(x[j]));
    xp[j] += s;
    xm[j] -= s;
    J.col(j) = (f(xp) - f(xm)) / (2 * s);
  }
  return J;
}

/// Beam sections with every property bound to a parameter: 0 = E, 1 = density, 2 = side
/// (square) or area (explicit), 3 = inertia (explicit only); values from squareParams() /
/// explicitParams(). Soft (polymer-like) materials: at 30% strain the elastic force is then
/// only ~1e2..1e3 times the weight, so a central difference in the density is not swamped by
/// round-off of the elastic part.
inline std::shared_ptr<BeamSection> squareSection() {
  auto s = std::make_shared<BeamSection>();
  s->square = true;
  s->E.param = 0;
  s->density.param = 1;
  s->side.param = 2;
  return s;
}
inline std::shared_ptr<BeamSection> explicitSection() {
  auto s = std::make_shared<BeamSection>();
  s->E.param = 0;
  s->density.param = 1;
  s->area.param = 2;
  s->inertia.param = 3;
  return s;
}
inline VecX squareParams() { return (VecX(3) << 5.0e6, 1100.0, 0.01).finished(); }
inline VecX explicitParams() { return (VecX(4) << 2.0e6, 1400.0, 3.0e-4, 2.5e-8).finished(); }

/// Records the full state (and sensitivities) at every output frame.
struct Recorder : Observer {
  std::vector<StateWithSens> frames;
  void frame(const StateWithSens& s) override { frames.push_back(s); }
  const StateWithSens& at(double t) const {
    for (const auto& f : frames)
      if (std::abs(f.x.t - t) < 1e-9) return f;
    throw std::runtime_error("no frame at t = " + std::to_string(t));
  }
};

/// Whole runs of the scheme at p + h e_k and p - h e_k, each from its own initial state and
/// without sensitivities: (plus - minus) / 2h at a frame is the central difference of the
/// discrete solution (h absolute, so a test can take it relative to |p_k|, unlike
/// app/FiniteDifferences' step relative to max(|p|, 1)).
struct PlusMinusRuns {
  Recorder plus, minus;
};
inline PlusMinusRuns runsAtPlusMinus(const Assembler& as, const VecX& p, size_t k, double h,
                                     const IntegratorSettings& set) {
  PlusMinusRuns r;
  for (const double sgn : {1.0, -1.0}) {
    VecX pp = p;
    pp[k] += sgn * h;
    StateWithSens st = initialState(as, pp);
    st.dp.clear();
    integrate(as, pp, st, set, sgn > 0 ? r.plus : r.minus);
  }
  return r;
}

/// The direct (dd) and AD sensitivities of coordinate z over a run of m with `set`, against
/// central differences of whole runs at p +- 1e-5 |p_k| for each parameter: |dd - nd| <= 1e-6
/// and |dd - ad| <= 1e-10 of the largest |dz/dp_k| over the frames (printed). Returns the dd run.
inline Recorder expectCoordinateSensitivities(const Model& m, const IntegratorSettings& set, int z) {
  Assembler as(m);
  Assembler adAs(m, Derivatives::AutomaticDifferentiation);
  const VecX p = m.nominalParameters();
  Recorder dd, ad;
  integrate(as, p, initialState(as, p), set, dd);
  integrate(adAs, p, initialState(adAs, p), set, ad);
  for (size_t k = 0; k < m.parameters.size(); ++k) {
    const double h = 1e-5 * std::abs(p[k]);
    const auto [plus, minus] = runsAtPlusMinus(as, p, k, h, set);
    EXPECT_EQ(plus.frames.size(), dd.frames.size());
    if (plus.frames.size() != dd.frames.size() || minus.frames.size() != dd.frames.size()) continue;
    double scale = 0.0, errNd = 0.0, errAd = 0.0;
    for (size_t f = 1; f < dd.frames.size(); ++f) scale = std::max(scale, std::abs(dd.frames[f].dp[k].q[z]));
    for (size_t f = 1; f < dd.frames.size(); ++f) {
      const double nd = (plus.frames[f].x.q[z] - minus.frames[f].x.q[z]) / (2 * h);
      errNd = std::max(errNd, std::abs(dd.frames[f].dp[k].q[z] - nd));
      errAd = std::max(errAd, std::abs(dd.frames[f].dp[k].q[z] - ad.frames[f].dp[k].q[z]));
    }
    std::printf("  d(%s)/d%-4s at %.3g s %+.6e; max |dd - nd| / max|dd| %.2e, |dd - ad| %.2e\n",
                m.coordinateLabel(z).c_str(), m.parameters[k].name.c_str(), dd.frames.back().x.t,
                dd.frames.back().dp[k].q[z], errNd / scale, errAd / scale);
    EXPECT_GT(scale, 0.0) << m.parameters[k].name;
    EXPECT_LE(errNd, 1e-6 * scale) << m.parameters[k].name;
    EXPECT_LE(errAd, 1e-10 * scale) << m.parameters[k].name;
  }
  return dd;
}

/// Settings for tests: IDAS at rtol = atol = dtOrTol, or a fixed-step scheme at dt = dtOrTol;
/// frames every 0.5 s, Newton to 1e-14.
inline IntegratorSettings integratorSettings(const std::string& type, double dtOrTol, double tEnd) {
  IntegratorSettings s;
  s.type = type;
  s.tEnd = tEnd;
  s.frameInterval = 0.5;
  s.newtonTol = 1e-14;
  if (type == "idas") {
    s.rtol = s.atol = dtOrTol;
    s.dt = 0.0;
  } else {
    s.dt = dtOrTol;
  }
  return s;
}

/// Symmetric relative difference |a - b| / max(|a|, |b|) in the max norm (0 for two zeros).
inline double relMax(const MatX& a, const MatX& b) {
  const double s = std::max(a.lpNorm<Eigen::Infinity>(), b.lpNorm<Eigen::Infinity>());
  return s == 0.0 ? 0.0 : (a - b).lpNorm<Eigen::Infinity>() / s;
}

/// Element e's analytic parameter derivatives at s for the parameters p[0 .. np) its quantities
/// read (k = np: bound to nothing, so no derivative): dQ/dp and dM/dp equal AD's to 1e-10 and
/// central differences of force and mass (step 1e-6 |p_k|, p perturbed in place) to 1e-6.
inline void expectParameterDerivatives(const Element& e, const LocalState& s, VecX& p, int np) {
  for (int k = 0; k <= np; ++k) {
    SCOPED_TRACE("parameter " + std::to_string(k));
    VecX dQ, dQad;
    MatX dM, dMad;
    const bool dep = e.parameterDerivative(s, k, dQ, dM);
    ASSERT_EQ(dep, e.parameterDerivativeAD(s, k, dQad, dMad));
    ASSERT_EQ(dep, k < np);
    if (!dep) continue;
    EXPECT_LT(relMax(dQad, dQ), 1e-10) << "AD vs analytic dQ/dp";
    EXPECT_LT(relMax(dMad, dM), 1e-10) << "AD vs analytic dM/dp";
    const double h = 1e-6 * std::abs(p[k]);
    const VecX p0 = p;
    VecX Qp, Qm;
    MatX Mp, Mm;
    p[k] = p0[k] + h;
    e.force(s, Qp);
    e.mass(s, Mp);
    p[k] = p0[k] - h;
    e.force(s, Qm);
    e.mass(s, Mm);
    p = p0;
    EXPECT_LT(relMax((Qp - Qm) / (2 * h), dQ), 1e-6) << "FD vs analytic dQ/dp";
    EXPECT_LT(relMax((Mp - Mm) / (2 * h), dM), 1e-6) << "FD vs analytic dM/dp";
  }
}

/// Element e's analytic force Jacobians at s (positions and velocities): dQ/dq and dQ/dv
/// equal AD's to 1e-10 and central differences of the force to 1e-6 (neither may be zero),
/// then its parameter derivatives (expectParameterDerivatives). For damped kernels.
inline void expectDampedKernels(const Element& e, const LocalState& s, VecX& p, int np) {
  MatX K, Kv, Kad, Kvad;
  e.forceJacobian(s, K, Kv);
  e.forceJacobianAD(s, Kad, Kvad);
  EXPECT_GT(K.norm(), 0.0);
  EXPECT_GT(Kv.norm(), 0.0);
  EXPECT_LT(relMax(Kad, K), 1e-10) << "AD vs analytic dQ/dq";
  EXPECT_LT(relMax(Kvad, Kv), 1e-10) << "AD vs analytic dQ/dv";
  auto fq = [&](const VecX& q) { LocalState t = s; t.x = q; VecX Q; e.force(t, Q); return Q; };
  auto fv = [&](const VecX& w) { LocalState t = s; t.v = w; VecX Q; e.force(t, Q); return Q; };
  EXPECT_LT(relMax(fdJacobian(fq, s.x), K), 1e-6) << "FD vs analytic dQ/dq";
  EXPECT_LT(relMax(fdJacobian(fv, s.v, 1e-4), Kv), 1e-6) << "FD vs analytic dQ/dv";
  expectParameterDerivatives(e, s, p, np);
}

/// A conservative element's kernels at s (positions s.x): dQ/dq analytic equals AD's to 1e-10
/// and central differences of the force to 1e-6 (and is not zero), the force is not zero and
/// equals -dU/dq by central differences of potential() to 1e-6, then its parameter derivatives
/// (expectParameterDerivatives). Returns dQ/dq; the analytic and AD dQ/dv go to Kv, Kvad.
inline MatX expectConservativeKernels(const Element& e, const LocalState& s, VecX& p, int np, MatX& Kv, MatX& Kvad) {
  MatX K, Kad;
  e.forceJacobian(s, K, Kv);
  e.forceJacobianAD(s, Kad, Kvad);
  EXPECT_GT(K.norm(), 0.0);
  EXPECT_LT(relMax(Kad, K), 1e-10) << "AD vs analytic dQ/dq";
  auto force = [&](const VecX& q) { LocalState t = s; t.x = q; VecX Q; e.force(t, Q); return Q; };
  EXPECT_LT(relMax(fdJacobian(force, s.x, 1e-6), K), 1e-6) << "FD vs analytic dQ/dq";
  auto energy = [&](const VecX& q) { LocalState t = s; t.x = q; return VecX::Constant(1, e.potential(t)); };
  VecX Q;
  e.force(s, Q);
  EXPECT_GT(Q.norm(), 0.0);
  EXPECT_LT(relMax(-fdJacobian(energy, s.x, 1e-6).transpose(), Q), 1e-6) << "-dU/dq vs Q";
  expectParameterDerivatives(e, s, p, np);
  return K;
}

/// An element's force() (its fixed-size kernel) against kernelForce() (the value template the
/// AD kernels differentiate) at s, and again without velocities (s.v empty, read as zero) and
/// gravity, where its analytic Jacobians must equal AD's too.
template <class E>
void expectForceMatchesTemplate(const E& e, const LocalState& s) {
  VecX Q;
  e.force(s, Q);
  EXPECT_GT(Q.norm(), 0.0);
  EXPECT_LT(relMax(Q, e.kernelForce(s)), 1e-13) << "force() vs the value template";
  LocalState still = s;
  still.v.resize(0);
  still.gravity = nullptr;
  e.force(still, Q);
  EXPECT_LT(relMax(Q, e.kernelForce(still)), 1e-13) << "force() vs the value template, no v, no gravity";
  MatX K, Kv, Kad, Kvad;
  e.forceJacobian(still, K, Kv);
  e.forceJacobianAD(still, Kad, Kvad);
  EXPECT_LT(relMax(Kad, K), 1e-10) << "AD vs analytic dQ/dq, no v";
  EXPECT_LT(relMax(Kvad, Kv), 1e-10) << "AD vs analytic dQ/dv, no v";
}

/// Relative error |a - b| / max(|b|, floor) in the max norm.
inline double relErr(const MatX& a, const MatX& b, double floor = 1.0) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(b.lpNorm<Eigen::Infinity>(), floor);
}

/// A planar model with every element and constraint type of the foundation, all
/// properties bound to parameters so that every parameter derivative is exercised.
inline Scene mixedScene() {
  return readSceneText(R"(
dimension: 2
plane: xz
gravity: [0.3, -9.81]
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: n1, position: [-1, -1]}
  - {name: n2, position: [0.5, -2]}
  - {name: n3, position: [2, -1]}
  - {name: n4, position: [2.5, 0.3]}
  - {name: n5, position: [-1.5, -1.4]}
  - {name: n6, position: [-2.1, -1.5]}
elements:
  - {name: bA1, type: rigid_bar, nodes: [A, n1], mass: 1.0}
  - {name: b12, type: rigid_bar, nodes: [n1, n2], mass: 1.5}
  - {name: s23, type: spring_damper, nodes: [n2, n3], stiffness: 50, damping: 3, natural_length: 1.3}
  - {name: s3A, type: spring_damper, nodes: [n3, A], stiffness: 20, damping: 0.5}
  - {name: b34, type: rigid_bar, nodes: [n3, n4], mass: 0.7}
  - {name: beam, type: beam, nodes: [n1, n5, n6], E: 2.0e6, density: 500, section: {side: 0.05}}
constraints:
  - {name: d24, type: distance, nodes: [n2, n4], length: 2.9}
  - {name: fx, type: fixed, node: n4, position: [2.5, 0.3]}
parameters:
  - {name: L, of: bA1, property: length}
  - {name: mass, of: b12, property: mass}
  - {name: k, of: s23, property: stiffness}
  - {name: c, of: s23, property: damping}
  - {name: L0, of: s23, property: natural_length}
  - {name: Ld, of: d24, property: length}
  - {name: gz, of: gravity, property: z}
  - {name: E, of: beam, property: E}
  - {name: rho, of: beam, property: density}
integrator: {type: idas, t_end: 1}
)", "mixed.yaml");
}

}  // namespace flexsens::test

namespace flexsens::test {

/// A spatial model with every 3D kernel: rigid bodies in natural coordinates (a revolute to
/// the ground, a universal joint, an attached point), rotational spring-dampers (to the
/// ground and between bodies), point-on-plane constraints (a plane fixed to a body, one fixed
/// in space), a spherical joint, all properties bound to parameters.
inline Scene mixedScene3D() {
  return readSceneText(R"(
dimension: 3
gravity: [0.2, -0.3, -9.81]
nodes:
  - {name: O,  position: [0, 0, 0], ground: true}
  - {name: OX, position: [1, 0, 0], ground: true}
  - {name: R,  position: [0, 1, 0], ground: true}
  - {name: P,  position: [0, 1, 0]}
  - {name: PX, position: [0.3, 1, 0]}
  - {name: E1, position: [0, 0.5, 0.2]}
  - {name: S,  position: [0.1, 1.1, -0.9]}
  - {name: PY, position: [0, 1.2, 0]}
  - {name: E2, position: [0.2, 1, -0.5]}
  - {name: Q,  position: [0.42, 0.4, 0.1]}
  - {name: F,  position: [1.53, 0.2, -0.3]}
  - {name: F2, position: [1.53, 0.2, -0.3]}
elements:
  - {name: bar1, type: rigid_body, nodes: [O, OX, P, E1, PX], mass: 1.2, center_of_mass: [0.1, 0.5, 0.05],
     inertia: [0.09, 0.03, 0.08, 0.001, -0.002, 0.003]}
  - {name: bar2, type: rigid_body, nodes: [P, S, PY, E2], mass: 0.8, center_of_mass: [0.05, 1.05, -0.45],
     inertia: [0.06, 0.058, 0.004]}
  - {name: j1, type: rotational_spring_damper, axis: [O, OX], from: [O, R], to: [O, P], stiffness: 2, damping: 0.5}
  - {name: j2, type: rotational_spring_damper, axis: [P, PX], from: [O, P], to: [P, S], stiffness: 3,
     damping: 0.2, rest_angle: 0.4}
  - {name: sQF, type: spring_damper, nodes: [Q, F], stiffness: 30, damping: 1}
  - {name: sF2S, type: spring_damper, nodes: [F2, S], stiffness: 20}
constraints:
  - {name: cross, type: perpendicular, nodes: [P, PX, P, PY]}
  - {name: onbody, type: point_on_plane, nodes: [Q], body: bar1, point: [0.5, 0, 0], normal: [1, 0.2, 0]}
  - {name: inspace, type: point_on_plane, nodes: [F], point: [1.5, 0, 0], normal: [1, 0, 0.1]}
  - {name: ball, type: spherical, nodes: [F, F2]}
parameters:
  - {name: m1, of: bar1, property: mass}
  - {name: Ixx, of: bar1, property: Ixx}
  - {name: Ixy2, of: bar2, property: Ixy}   # (Ixy of bar1 cannot act: it turns about a fixed axis)
  - {name: Izz2, of: bar2, property: Izz}
  - {name: k1, of: j1, property: stiffness}
  - {name: c1, of: j1, property: damping}
  - {name: k2, of: j2, property: stiffness}
  - {name: gz, of: gravity, property: z}
integrator: {type: trapezoidal, t_end: 1, dt: 0.001}
)", "mixed3d.yaml");
}

/// The discrete sensitivities of a run against central differences of whole perturbed runs
/// (relative step relStep, parameter 0): at each time, max_i |dd - nd| / max(|nd|, 1e-12) over
/// all coordinates must stay below bound. Returns the dd run's statistics.
inline IntegratorStats expectDdMatchesCentralDifferences(const Assembler& as, const VecX& p,
                                                          const StateWithSens& start, const PimCase* pim,
                                                          const IntegratorSettings& set, double relStep,
                                                          const std::vector<double>& times, double bound,
                                                          const std::string& label) {
  Recorder dd, nd;
  const IntegratorStats st = integrate(as, p, start, set, dd);
  integrateFiniteDifferences(as, p, start, pim, set, {"central", relStep}, nd);
  for (double t : times) {
    const double e = relErr(dd.at(t).dp[0].q, nd.at(t).dp[0].q, 1e-12);
    std::printf("  %s, t = %.2g s (%ld steps in all): max relative |dd - nd| = %.2e\n", label.c_str(), t, st.steps, e);
    EXPECT_LT(e, bound) << label << " t = " << t;
  }
  return st;
}

}  // namespace flexsens::test

