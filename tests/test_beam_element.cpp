// Tests of the positions-only beam: finite-difference checks of every analytic derivative,
// mass properties, hinge invariance, and a linear cantilever assembled from the elements.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "TestModels.hpp"
#include "elements/Beam.hpp"

using namespace flexsens;
using flexsens::test::explicitParams;
using flexsens::test::explicitSection;
using flexsens::test::squareParams;
using flexsens::test::squareSection;

namespace {

constexpr double kStep = 1e-6, kTol = 1e-6;

struct Fixture {
  VecX p, g;
  LocalState s;
  Fixture(int dim, VecX x, VecX params) : p(std::move(params)) {
    g = VecX::Zero(dim);
    g[1] = -9.81;
    if (dim == 3) g[2] = 1.3;  // gravity not along an axis
    s.dim = dim;
    s.x = std::move(x);
    s.v = VecX::Zero(s.x.size());
    s.p = &p;
    s.gravity = &g;
  }
};

/// Relative (norm-wise) difference, with a floor against all-zero references.
double relErr(const MatX& a, const MatX& b) {
  const double scale = std::max({a.norm(), b.norm(), 1e-300});
  return (a - b).norm() / scale;
}

/// Central difference of a vector function of x (columns = d/dx_j).
MatX fdJacobian(const std::function<VecX(const VecX&)>& f, const VecX& x0) {
  const VecX f0 = f(x0);
  MatX J(f0.size(), x0.size());
  for (int j = 0; j < x0.size(); ++j) {
    const double h = kStep * std::max(1.0, std::abs(x0[j]));
    VecX xp = x0, xm = x0;
    xp[j] += h;
    xm[j] -= h;
    J.col(j) = (f(xp) - f(xm)) / (2.0 * h);
  }
  return J;
}

VecX forceAt(const Element& e, LocalState s, const VecX& x) {
  s.x = x;
  VecX Q;
  e.force(s, Q);
  return Q;
}

/// Q = -grad(potential), dQ/dq, dQ/dv = 0, and dQ/dp_k, dM/dp_k for every parameter.
void checkElement(const Element& e, Fixture& f, bool hasMass) {
  const LocalState& s = f.s;
  VecX Q;
  e.force(s, Q);
  ASSERT_GT(Q.norm(), 0.0);

  // force vs -grad(potential) (potential includes gravity)
  const MatX gradU = fdJacobian([&](const VecX& x) {
    LocalState t = s;
    t.x = x;
    return VecX::Constant(1, e.potential(t));
  }, s.x);
  EXPECT_LT(relErr(Q, -gradU.transpose()), kTol) << e.kind() << " force vs -grad U";

  // forceJacobian vs FD of force
  MatX dQdq, dQdv;
  e.forceJacobian(s, dQdq, dQdv);
  const MatX fdQ = fdJacobian([&](const VecX& x) { return forceAt(e, s, x); }, s.x);
  EXPECT_LT(relErr(dQdq, fdQ), kTol) << e.kind() << " dQ/dq";
  EXPECT_LT(relErr(dQdq, dQdq.transpose()), 1e-12) << e.kind() << " conservative => symmetric";
  EXPECT_EQ(dQdv.rows(), s.x.size());
  EXPECT_EQ(dQdv.norm(), 0.0);

  // parameter derivatives vs FD in p
  for (int k = 0; k < f.p.size(); ++k) {
    VecX dQ;
    MatX dM;
    const bool dep = e.parameterDerivative(s, k, dQ, dM);
    auto atP = [&](double pk, VecX& Qk, MatX& Mk) {
      VecX pp = f.p;
      pp[k] = pk;
      LocalState t = s;
      t.p = &pp;
      e.force(t, Qk);
      if (!e.mass(t, Mk)) Mk.setZero(s.x.size(), s.x.size());
    };
    const double h = kStep * std::abs(f.p[k]);
    VecX Qp, Qm;
    MatX Mp, Mm;
    atP(f.p[k] + h, Qp, Mp);
    atP(f.p[k] - h, Qm, Mm);
    const VecX fdDQ = (Qp - Qm) / (2 * h);
    const MatX fdDM = (Mp - Mm) / (2 * h);
    if (!dep) {
      EXPECT_LT(fdDQ.norm(), 1e-9 * Q.norm() / f.p[k]) << e.kind() << " claims no dependence on " << k;
      EXPECT_EQ(fdDM.norm(), 0.0);
      continue;
    }
    EXPECT_LT(relErr(dQ, fdDQ), kTol) << e.kind() << " dQ/dp" << k;
    if (hasMass && fdDM.norm() > 0) {
      EXPECT_LT(relErr(dM, fdDM), kTol) << e.kind() << " dM/dp" << k;
    } else {
      EXPECT_EQ(dM.norm(), 0.0) << e.kind() << " dM/dp" << k;
    }
  }
}

/// Strained, rotated segment configuration (length 1.3 L) with random-ish direction.
VecX strainedSegment(int dim, double L, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VecX x(2 * dim), d(dim);
  for (int i = 0; i < dim; ++i) x[i] = u(rng), d[i] = u(rng);
  x.tail(dim) = x.head(dim) + 1.3 * L * d.normalized();
  return x;
}

}  // namespace

TEST(BeamSection, ValuesDerivativesAndProperties) {
  auto sq = squareSection();
  const VecX p = squareParams();
  EXPECT_DOUBLE_EQ(sq->A(p), 1e-4);
  EXPECT_DOUBLE_EQ(sq->I(p), 1e-8 / 12);
  EXPECT_DOUBLE_EQ(sq->dA(p, 2), 0.02);
  EXPECT_DOUBLE_EQ(sq->dI(p, 2), 1e-6 / 3);
  EXPECT_DOUBLE_EQ(sq->dEA(p, 0), 1e-4);
  EXPECT_EQ(sq->dEI(p, 1), 0.0);
  EXPECT_FALSE(sq->bendingDependsOn(1));
  EXPECT_TRUE(sq->axialDependsOn(2));
  BeamSegment seg("s", {0, 1}, sq, 0.5);
  BeamHinge hin("h", {0, 1, 2}, sq, (VecX(6) << 0, 0, 1, 0, 2, 0).finished());
  auto props = hin.properties();
  ASSERT_EQ(props.size(), 3u);
  EXPECT_EQ(props[2].first, "side");
  EXPECT_EQ(props[2].second, &sq->side);  // pointers into the shared section
  EXPECT_EQ(seg.properties()[0].second, &sq->E);
  auto ex = explicitSection();
  BeamSegment seg2("s2", {0, 1}, ex, 0.5);
  auto props2 = seg2.properties();
  ASSERT_EQ(props2.size(), 4u);
  EXPECT_EQ(props2[2].first, "area");
  EXPECT_EQ(props2[3].first, "inertia");
  EXPECT_EQ(props2[3].second, &ex->inertia);
  EXPECT_EQ(seg.kind(), "beam_segment");
  EXPECT_EQ(hin.kind(), "beam_hinge");
}

TEST(BeamSegment, FiniteDifference2DSquare) {
  BeamSegment e("s", {0, 1}, squareSection(), 0.7);
  Fixture f(2, strainedSegment(2, 0.7, 1), squareParams());
  checkElement(e, f, true);
}

TEST(BeamSegment, FiniteDifference3DSquare) {
  BeamSegment e("s", {0, 1}, squareSection(), 0.7);
  Fixture f(3, strainedSegment(3, 0.7, 2), squareParams());
  checkElement(e, f, true);
}

TEST(BeamSegment, FiniteDifference2DExplicitCompressed) {
  BeamSegment e("s", {0, 1}, explicitSection(), 0.7);
  VecX x = strainedSegment(2, 0.7, 3);
  x.tail(2) = x.head(2) + (0.6 / 1.3) * (x.tail(2) - x.head(2));  // compressed: l = 0.6 L
  Fixture f(2, x, explicitParams());
  checkElement(e, f, true);
}

TEST(BeamSegment, FiniteDifference3DExplicit) {
  BeamSegment e("s", {0, 1}, explicitSection(), 0.7);
  Fixture f(3, strainedSegment(3, 0.7, 4), explicitParams());
  checkElement(e, f, true);
}

TEST(BeamSegment, MassTotalSymmetricPositiveDefinite) {
  for (int dim : {2, 3}) {
    auto sec = explicitSection();
    const double L = 0.7;
    BeamSegment e("s", {0, 1}, sec, L);
    Fixture f(dim, strainedSegment(dim, L, 5), explicitParams());
    MatX M;
    ASSERT_TRUE(e.mass(f.s, M));
    const double rhoAL = f.p[1] * f.p[2] * L;
    // total mass: a rigid translation t gives kinetic energy 1/2 m |t|^2
    for (int c = 0; c < dim; ++c) {
      VecX t = VecX::Zero(2 * dim);
      t[c] = t[dim + c] = 1.0;
      EXPECT_NEAR(t.dot(M * t), rhoAL, 1e-12 * rhoAL);
    }
    EXPECT_NEAR(M.sum() / dim, rhoAL, 1e-12 * rhoAL);
    EXPECT_EQ((M - M.transpose()).norm(), 0.0);
    Eigen::SelfAdjointEigenSolver<MatX> es(M);
    EXPECT_GT(es.eigenvalues().minCoeff(), 0.0);
    EXPECT_NEAR(es.eigenvalues().minCoeff(), rhoAL / 6.0, 1e-12 * rhoAL);  // [[2,1],[1,2]]/6
    // consistent gravity: M [g; g] equals the nodal weights
    VecX Q, gg(2 * dim);
    gg << f.g, f.g;
    VecX Qg = M * gg;
    e.force(f.s, Q);
    LocalState noG = f.s;
    VecX zero = VecX::Zero(dim);
    noG.gravity = &zero;
    VecX Q0;
    e.force(noG, Q0);
    EXPECT_LT((Q - Q0 - Qg).norm(), 1e-14 * Q.norm());
  }
}

TEST(BeamSegment, OneSegmentIsAxialOnly) {
  // Straight, unstressed: stiffness only along the axis (paper: a one-segment beam deforms
  // only axially), zero transverse stiffness.
  BeamSegment e("s", {0, 1}, squareSection(), 1.0);
  Fixture f(2, (VecX(4) << 0, 0, 1, 0).finished(), squareParams());
  MatX K, D;
  e.forceJacobian(f.s, K, D);
  EXPECT_EQ(K.col(1).norm() + K.col(3).norm(), 0.0);
  EXPECT_GT(K.col(0).norm(), 0.0);
}

TEST(BeamHinge, FiniteDifferenceSquare) {
  // bent at rest (phi0 != 0), deformed further, unequal edges
  const VecX rest = (VecX(6) << 0, 0, 0.5, 0.1, 0.9, 0.4).finished();
  BeamHinge e("h", {0, 1, 2}, squareSection(), rest);
  const VecX x = (VecX(6) << 0.02, -0.03, 0.55, 0.08, 0.75, 0.6).finished();
  Fixture f(2, x, squareParams());
  EXPECT_GT(std::abs(BeamHinge::angle(x) - e.restAngle()), 0.2);
  checkElement(e, f, false);
}

TEST(BeamHinge, FiniteDifferenceExplicitStraightRestLargeTurn) {
  // straight at rest; turning angle of ~2.4 rad (beyond pi/2) and negative sign
  const VecX rest = (VecX(6) << 0, 0, 0.4, 0, 0.8, 0).finished();
  BeamHinge e("h", {0, 1, 2}, explicitSection(), rest);
  EXPECT_DOUBLE_EQ(e.voronoiLength(), 0.4);
  const VecX x = (VecX(6) << 0.1, 0.2, 0.5, 0.05, 0.15, -0.2).finished();
  EXPECT_LT(BeamHinge::angle(x), -2.0);
  Fixture f(2, x, explicitParams());
  checkElement(e, f, false);
}

TEST(BeamHinge, AngleWrapsAcrossPi) {
  // rest angle near +pi, current angle just past it (atan2 jumps to -pi): energy continuous
  const double a0 = M_PI - 0.05;
  const VecX rest = (VecX(6) << -1, 0, 0, 0, std::cos(a0), std::sin(a0)).finished();
  BeamHinge e("h", {0, 1, 2}, squareSection(), rest);
  Fixture f(2, rest, squareParams());
  const double a1 = M_PI + 0.05;
  f.s.x.tail(2) << std::cos(a1), std::sin(a1);
  const double kb = f.p[0] * std::pow(f.p[2], 4) / 12 / e.voronoiLength();
  EXPECT_NEAR(e.potential(f.s), 0.5 * kb * 0.1 * 0.1, 1e-9 * kb * 0.01);
}

TEST(BeamHinge, RigidMotionInvariance) {
  const VecX rest = (VecX(6) << 0, 0, 0.5, 0.1, 0.9, 0.4).finished();
  BeamHinge e("h", {0, 1, 2}, explicitSection(), rest);
  const VecX x = (VecX(6) << 0.02, -0.03, 0.55, 0.08, 0.75, 0.6).finished();
  Fixture f(2, x, explicitParams());
  const double U0 = e.potential(f.s);
  ASSERT_GT(U0, 0.0);
  VecX Q0;
  e.force(f.s, Q0);
  for (double th : {0.3, -1.7, 2.9, M_PI}) {
    const Eigen::Rotation2Dd R(th);
    const Eigen::Vector2d t(3.1, -0.7);
    LocalState s = f.s;
    for (int i = 0; i < 3; ++i) s.x.segment<2>(2 * i) = R * x.segment<2>(2 * i) + t;
    EXPECT_NEAR(e.potential(s), U0, 1e-12 * U0) << "theta = " << th;
    VecX Q;
    e.force(s, Q);
    for (int i = 0; i < 3; ++i)  // forces rotate with the body
      EXPECT_LT((Q.segment<2>(2 * i) - R * Q0.segment<2>(2 * i)).norm(), 1e-10 * Q0.norm());
  }
  // no net force or moment (internal element)
  EXPECT_LT((Q0.segment<2>(0) + Q0.segment<2>(2) + Q0.segment<2>(4)).norm(), 1e-12 * Q0.norm());
  double mom = 0;
  for (int i = 0; i < 3; ++i) mom += x[2 * i] * Q0[2 * i + 1] - x[2 * i + 1] * Q0[2 * i];
  EXPECT_LT(std::abs(mom), 1e-12 * Q0.norm());
}

TEST(BeamHinge, RejectsNonPlanar) {
  EXPECT_THROW(BeamHinge("h", {0, 1, 2}, squareSection(), VecX::Zero(9)), std::invalid_argument);
  const VecX rest = (VecX(6) << 0, 0, 1, 0, 2, 0).finished();
  BeamHinge e("h", {0, 1, 2}, squareSection(), rest);
  Fixture f(3, VecX::LinSpaced(9, 0.0, 1.0), squareParams());
  VecX Q;
  EXPECT_THROW(e.force(f.s, Q), std::invalid_argument);
}

// ---------------------------------------------------------------- linear cantilever
//
// N segments of h = L/N along x, node 0 clamped together with a ghost node at (-h, 0); hinges
// at nodes 0..N-1 (the one at node 0 uses the ghost). Linearized, the beam is a chain of rigid
// links with rotational springs k_i = EI/D_i at nodes i = 0..N-1. Under tip load P the spring
// at x_i = i h carries the moment P (L - x_i), so
//   v_tip = sum_i P (L - x_i)^2 / k_i.
// (a) D_0 = h/2 (the clamp's Voronoi cell inside the beam; ghost excluded), D_i = h otherwise:
//   v_tip = P h^3/EI [sum_{m=1}^{N-1} m^2 + N^2/2] = PL^3/(3EI) (1 + 1/(2N^2))   (the stated formula)
// (b) D_0 = (h_ghost + h)/2 = h from the rest shape (ghost counted as a full segment):
//   v_tip = P h^3/EI sum_{m=1}^{N} m^2 = PL^3/(3EI) (1 + 3/(2N) + 1/(2N^2)).
// So the stated formula needs the clamp hinge built with voronoiLength = h/2; (b) is checked too.
namespace {
double cantileverTip(int N, bool halfCellAtClamp, double L, double P, double* EI) {
  auto sec = squareSection();
  const VecX p = squareParams();
  *EI = sec->EI(p);
  const double h = L / N;
  const int nn = N + 2;  // local index 0 = ghost, 1 + i = beam node i
  VecX X = VecX::Zero(2 * nn);
  for (int i = -1; i <= N; ++i) X[2 * (i + 1)] = i * h;
  std::vector<std::unique_ptr<Element>> els;
  for (int i = 0; i < N; ++i)
    els.push_back(std::make_unique<BeamSegment>("s", std::vector<int>{i + 1, i + 2}, sec, h));
  for (int i = 0; i < N; ++i) {
    const std::vector<int> nd{i, i + 1, i + 2};
    VecX rest(6);
    for (int j = 0; j < 3; ++j) rest.segment<2>(2 * j) = X.segment<2>(2 * nd[j]);
    const double D = (i == 0 && halfCellAtClamp) ? h / 2 : 0.0;
    els.push_back(std::make_unique<BeamHinge>("h", nd, sec, rest, D));
  }
  MatX K = MatX::Zero(2 * nn, 2 * nn);
  const VecX g = VecX::Zero(2);
  for (const auto& e : els) {
    LocalState s;
    s.dim = 2;
    s.p = &p;
    s.gravity = &g;
    const auto& nd = e->nodes();
    s.x.resize(2 * nd.size());
    for (size_t j = 0; j < nd.size(); ++j) s.x.segment<2>(2 * j) = X.segment<2>(2 * nd[j]);
    s.v = VecX::Zero(s.x.size());
    MatX dQdq, dQdv;
    e->forceJacobian(s, dQdq, dQdv);
    for (size_t a = 0; a < nd.size(); ++a)
      for (size_t b = 0; b < nd.size(); ++b)
        K.block<2, 2>(2 * nd[a], 2 * nd[b]) -= dQdq.block<2, 2>(2 * a, 2 * b);
  }
  const int nf = 2 * N;  // free: beam nodes 1..N = local 2..N+1
  const MatX Kf = K.bottomRightCorner(nf, nf);
  VecX f = VecX::Zero(nf);
  f[nf - 1] = P;
  const VecX u = Kf.ldlt().solve(f);
  EXPECT_LT((Kf * u - f).norm(), 1e-10 * std::abs(P));
  EXPECT_LT(std::abs(u[nf - 2]), 1e-12 * std::abs(u[nf - 1]));  // no axial coupling, linear
  return u[nf - 1];
}
}  // namespace

TEST(BeamCantilever, TipDeflectionHalfCellClamp) {
  const double L = 1.2, P = -1.0e-5;
  for (int N : {2, 4, 8}) {
    double EI;
    const double v = cantileverTip(N, true, L, P, &EI);
    const double ref = P * L * L * L / (3 * EI) * (1 + 1.0 / (2.0 * N * N));
    std::printf("  N=%d  D0=h/2: tip %.10e  formula PL^3/3EI(1+1/2N^2) %.10e  rel.err %.2e\n", N, v,
                ref, std::abs(v - ref) / std::abs(ref));
    EXPECT_NEAR(v, ref, 1e-6 * std::abs(ref)) << "N = " << N;
  }
}

TEST(BeamCantilever, TipDeflectionGhostFullCell) {
  const double L = 1.2, P = -1.0e-5;
  for (int N : {2, 4, 8}) {
    double EI;
    const double v = cantileverTip(N, false, L, P, &EI);
    const double ref1 = P * L * L * L / (3 * EI) * (1 + 1.0 / (2.0 * N * N));
    const double ref = P * L * L * L / (3 * EI) * (1 + 3.0 / (2.0 * N) + 1.0 / (2.0 * N * N));
    std::printf("  N=%d  D0=h  : tip %.10e  (1+3/2N+1/2N^2) form %.10e  rel.err %.2e; "
                "vs (1+1/2N^2): ratio %.6f\n", N, v, ref, std::abs(v - ref) / std::abs(ref), v / ref1);
    EXPECT_NEAR(v, ref, 1e-6 * std::abs(ref)) << "N = " << N;
  }
}
