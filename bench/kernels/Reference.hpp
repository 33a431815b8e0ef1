// Plain fixed-size reference kernels for bench/kernels: the force and the tangent of the
// continuum and shell elements written here independently of elements/, in the most direct
// fixed-size form: stack matrices of the element's size, the material's C, C^-1, det C once
// per quadrature point, and the tangent column by column as the directional derivative of
// P = F S along each coordinate (dE = sym(F^T dF), dS = a C^-1 dE C^-1 + b tr(C^-1 dE) C^-1).
// The hinge: the dihedral angle theta = atan2(|e| det(e, a, b), n1 . n2) in the edge
// variables u = (e, a, b), its gradient and Hessian there and B^T (.) B to the positions.
// Elastic terms only (no gravity, no damping: the bench's elements have none).
// Units: positions [m], forces [N], stiffness [N/m], moduli [Pa].
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <vector>

namespace ref {

enum class Law { SaintVenantKirchhoff, NeoHookean };

/// Material of a reference continuum kernel: Lame constants [Pa], law, plane stress (DM = 2).
struct Material {
  double mu, lam;
  Law law;
  bool planeStress;
};

/// The stress S and the tangent coefficients of dS = a C^-1 dE C^-1 + b tr(C^-1 dE) C^-1 at one
/// point (SVK: dS = a dE + b tr(dE) I, a = 2 mu, b = lambda used).
template <int DM>
struct PointLaw {
  using Sym = Eigen::Matrix<double, DM, DM>;
  Sym S, Ci;
  double a, b;
  bool linear;  ///< St. Venant-Kirchhoff: dS = a dE + b tr(dE) I
  Sym dS(const Sym& dE) const {
    if (linear) return a * dE + b * dE.trace() * Sym::Identity();
    return a * Ci * dE * Ci + b * (Ci * dE).trace() * Ci;
  }
};

/// C33 of plane-stress neo-Hookean: mu (c - 1) + lambda/2 (ln det C + ln c) = 0 by Newton.
inline double thicknessStretch2(double mu, double lam, double lnD) {
  double c = 1.0;
  for (int it = 0; it < 50; ++it) {
    const double f = mu * (c - 1.0) + 0.5 * lam * (lnD + std::log(c)), dc = f / (mu + 0.5 * lam / c);
    c -= dc;
    if (std::abs(dc) < 1e-15 * c) break;
  }
  return c;
}

template <int DM>
PointLaw<DM> pointLaw(const Material& m, const Eigen::Matrix<double, DM, DM>& C) {
  using Sym = Eigen::Matrix<double, DM, DM>;
  const Sym I = Sym::Identity();
  PointLaw<DM> r;
  if (m.law == Law::SaintVenantKirchhoff) {
    const double lu = m.planeStress ? 2.0 * m.lam * m.mu / (m.lam + 2.0 * m.mu) : m.lam;
    const Sym E = 0.5 * (C - I);
    r.S = lu * E.trace() * I + 2.0 * m.mu * E;
    r.Ci = I;
    r.a = 2.0 * m.mu;
    r.b = lu;
    r.linear = true;
    return r;
  }
  const double detC = C.determinant();
  r.Ci = C.inverse();
  r.linear = false;
  if (!m.planeStress) {
    const double lnJ = 0.5 * std::log(detC);
    r.S = m.mu * (I - r.Ci) + m.lam * lnJ * r.Ci;
    r.a = 2.0 * (m.mu - m.lam * lnJ);
    r.b = m.lam;
    return r;
  }
  const double c = thicknessStretch2(m.mu, m.lam, std::log(detC));
  r.S = m.mu * (I - c * r.Ci);
  r.a = 2.0 * m.mu * c;
  r.b = m.mu * m.lam / (m.mu + 0.5 * m.lam / c);
  return r;
}

/// Total-Lagrangian element with N nodes of DS coordinates on a DM-dimensional rest domain
/// (DS = DM: solids; DS = 3, DM = 2: membranes), NP quadrature points.
template <int DS, int DM, int N, int NP>
struct Continuum {
  static constexpr int ND = DS * N;
  using Grad = Eigen::Matrix<double, N, DM>;
  using Vec = Eigen::Matrix<double, ND, 1>;
  using Mat = Eigen::Matrix<double, ND, ND>;
  Grad G[NP];      ///< dN_i/dX at each point [1/m]
  double w[NP];    ///< weight times rest measure (times thickness) [m^3]
  Material mat;

  void forceAndTangent(const double* xData, Vec& Q, Mat& K) const {
    using Def = Eigen::Matrix<double, DS, DM>;
    using Sym = Eigen::Matrix<double, DM, DM>;
    const Eigen::Map<const Eigen::Matrix<double, DS, N>> X(xData);
    Q.setZero();
    K.setZero();
    for (int g = 0; g < NP; ++g) {
      const Def F = X * G[g];
      const PointLaw<DM> pl = pointLaw<DM>(mat, F.transpose() * F);
      const Def P = F * pl.S;
      for (int i = 0; i < N; ++i) Q.template segment<DS>(DS * i) -= w[g] * P * G[g].row(i).transpose();
      for (int j = 0; j < N; ++j)
        for (int c = 0; c < DS; ++c) {
          Def dF = Def::Zero();
          dF.row(c) = G[g].row(j);
          const Sym B = F.transpose() * dF, dE = 0.5 * (B + B.transpose());
          const Def dP = dF * pl.S + F * pl.dS(dE);
          for (int i = 0; i < N; ++i)
            K.template block<DS, 1>(DS * i, DS * j + c) -= w[g] * dP * G[g].row(i).transpose();
        }
    }
  }
};

/// Bending hinge (4 nodes, 12 coordinates): Q = -k (theta - theta0) grad theta and its
/// Jacobian -k (g g^T + (theta - theta0) H), k = D w [N m].
struct Hinge {
  using V3 = Eigen::Vector3d;
  using M3 = Eigen::Matrix3d;
  using Vec12 = Eigen::Matrix<double, 12, 1>;
  using Mat12 = Eigen::Matrix<double, 12, 12>;
  double k, theta0;

  static M3 skew(const V3& v) {
    M3 S;
    S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    return S;
  }

  /// theta, its gradient g and Hessian H at positions x (12).
  static double angle(const Vec12& x, Vec12& g, Mat12& H) {
    using V9 = Eigen::Matrix<double, 9, 1>;
    using M9 = Eigen::Matrix<double, 9, 9>;
    const V3 x0 = x.segment<3>(0), e = x.segment<3>(3) - x0, a = x.segment<3>(6) - x0, b = x.segment<3>(9) - x0;
    const double ee = e.dot(e), ea = e.dot(a), eb = e.dot(b), ab = a.dot(b), L = std::sqrt(ee);
    const double det = e.dot(a.cross(b)), X = ea * eb - ee * ab, Y = L * det, R = X * X + Y * Y;
    const M3 I = M3::Identity();
    V9 gX, gD, gL = V9::Zero();
    gX << eb * a + ea * b - 2.0 * ab * e, eb * e - ee * b, ea * e - ee * a;
    gD << a.cross(b), b.cross(e), e.cross(a);
    gL.head<3>() = e / L;
    const V9 gY = det * gL + L * gD;
    M9 HX = M9::Zero(), HD = M9::Zero(), HL = M9::Zero();
    HX.block<3, 3>(0, 0) = a * b.transpose() + b * a.transpose() - 2.0 * ab * I;
    HX.block<3, 3>(0, 3) = eb * I + b * e.transpose() - 2.0 * e * b.transpose();
    HX.block<3, 3>(0, 6) = a * e.transpose() + ea * I - 2.0 * e * a.transpose();
    HX.block<3, 3>(3, 6) = e * e.transpose() - ee * I;
    HD.block<3, 3>(0, 3) = -skew(b);
    HD.block<3, 3>(0, 6) = skew(a);
    HD.block<3, 3>(3, 6) = -skew(e);
    for (M9* M : {&HX, &HD})
      for (int r = 0; r < 3; ++r)
        for (int c = r + 1; c < 3; ++c) M->block<3, 3>(3 * c, 3 * r) = M->block<3, 3>(3 * r, 3 * c).transpose();
    HL.block<3, 3>(0, 0) = (I - e * e.transpose() / ee) / L;
    const M9 HY = gL * gD.transpose() + gD * gL.transpose() + det * HL + L * HD;
    const V9 gT = (X * gY - Y * gX) / R;
    const M9 Hu = (X * HY - Y * HX + gY * gX.transpose() - gX * gY.transpose()) / R -
                  gT * (2.0 * X * gX + 2.0 * Y * gY).transpose() / R;
    Eigen::Matrix<double, 9, 12> B = Eigen::Matrix<double, 9, 12>::Zero();
    for (int q = 0; q < 3; ++q) {
      B.block<3, 3>(3 * q, 0) = -I;
      B.block<3, 3>(3 * q, 3 * (q + 1)) = I;
    }
    g = B.transpose() * gT;
    H = B.transpose() * Hu * B;
    return std::atan2(Y, X);
  }

  void forceAndTangent(const Vec12& x, Vec12& Q, Mat12& K) const {
    Vec12 g;
    Mat12 H;
    const double dev = std::remainder(angle(x, g, H) - theta0, 2.0 * M_PI);
    Q = -k * dev * g;
    K = -k * (g * g.transpose() + dev * H);
  }
};

/// Clamped edge (3 nodes): the hinge with a fixed fourth node, its 9 x 9 block.
struct Clamp {
  using Vec9 = Eigen::Matrix<double, 9, 1>;
  using Mat9 = Eigen::Matrix<double, 9, 9>;
  Hinge hinge;
  Eigen::Vector3d ghost;

  void forceAndTangent(const Vec9& x, Vec9& Q, Mat9& K) const {
    Hinge::Vec12 y, Qy;
    Hinge::Mat12 Ky;
    y << x, ghost;
    hinge.forceAndTangent(y, Qy, Ky);
    Q = Qy.head<9>();
    K = Ky.topLeftCorner<9, 9>();
  }
};

}  // namespace ref
