// Fixed-size total-Lagrangian kernel pieces of the continuum elements (elements/Solid.hpp:
// DS = DM = 2 or 3; elements/ShellTriangle.hpp: DS = 3 spatial coordinates on a DM = 2 rest
// plane), N nodes, all on the stack. With node positions X (DS x N, one column per node) and
// the shape gradients G (N x DM, dN_i/dX) of a quadrature point of weight w:
//   F = X G,  E = (F^T F - I) / 2,  internal force  f = w B^T S_v = w (F S) G^T (column i: node i),
//   B = dE_v/dx (NV x DS N; E_v with engineering shears): B_(AB),(j c) = F_cA G_jB + F_cB G_jA
//   (one term for A = B), and the tangent df/dx = w (B^T D B + (G S G^T) (x) I_DS), D = dS_v/dE_v
//   (elements/MaterialPoint.hpp), the second term the geometric (initial stress) stiffness.
// Units: positions [m], G [1/m], w [m^3] (or [m^2] times a thickness [m]), S, D [Pa].
#pragma once

#include <Eigen/Dense>

#include "elements/MaterialPoint.hpp"

namespace flexsens::continuum {

template <int DS, int DM, int N>
struct Kernel {
  static constexpr int ND = DS * N;                       ///< coordinates of the element
  static constexpr int NV = material::voigtSize(DM);      ///< strain components
  using Nodal = Eigen::Matrix<double, DS, N>;             ///< one column per node
  using Grad = Eigen::Matrix<double, N, DM>;              ///< dN_i/dX [1/m]
  using Def = Eigen::Matrix<double, DS, DM>;              ///< F [-] or its rate [1/s]
  using Sym = material::Sym<DM>;
  using StrainMatrix = Eigen::Matrix<double, NV, ND>;     ///< B [1/m]
  using Tangent = Eigen::Matrix<double, ND, ND>;

  /// B = dE_v/dx at deformation F (with Fd in place of F: d(dE/dt)_v/dx).
  static void strainMatrix(const Def& F, const Grad& G, StrainMatrix& B) {
    for (int j = 0; j < N; ++j)
      for (int c = 0; c < DS; ++c)
        for (int I = 0; I < NV; ++I) {
          const int A = material::voigtRow(DM, I), Bc = material::voigtCol(DM, I);
          B(I, DS * j + c) = A == Bc ? F(c, A) * G(j, A) : F(c, A) * G(j, Bc) + F(c, Bc) * G(j, A);
        }
  }

  /// Green-Lagrange strain rate sym(F^T Fd) [1/s].
  static Sym strainRate(const Def& F, const Def& Fd) {
    const Sym A = F.transpose() * Fd;
    return 0.5 * (A + A.transpose());
  }

  /// Q -= w (F S) G^T: the internal force of stress S at one point on the nodal forces Q [N].
  template <class QMap>
  static void subtractStressForce(double w, const Def& F, const Sym& S, const Grad& G, QMap& Q) {
    const Def P = w * (F * S);
    Q.noalias() -= P * G.transpose();
  }

  /// K += s (G S G^T) (x) I_DS: the geometric stiffness of stress S scaled by s.
  template <class KMap>
  static void addGeometric(double s, const Grad& G, const Sym& S, KMap& K) {
    const Eigen::Matrix<double, N, DM> GS = G * S;
    const Eigen::Matrix<double, N, N> GSG = s * (GS * G.transpose());
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i)
        for (int a = 0; a < DS; ++a) K(DS * i + a, DS * j + a) += GSG(i, j);
  }

  /// K += s B^T DB (DB = D B or a sum of such).
  template <class KMap>
  static void addMaterial(double s, const StrainMatrix& B, const StrainMatrix& DB, KMap& K) {
    K.noalias() += (s * B.transpose()) * DB;
  }
};

}  // namespace flexsens::continuum
