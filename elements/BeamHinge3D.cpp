#include "elements/BeamHinge3D.hpp"
#include "elements/BodyTriad.hpp"

#include <cmath>
#include <sstream>

#include "elements/KernelElementAD.hpp"

namespace flexsens {

// Notation (all in the edge variables u = (e1, e2), e1 = x_b - x_a, e2 = x_c - x_b [m]):
//   c = e1 x e2, s = |c|^2 [m^4], t = e1 . e2 [m^2], r = |e1||e2| [m^2], d = r + t [m^2],
//   f = |kb|^2 = 4 s / d^2 [-],  kappa = |kb| = sqrt(f).
// s and its derivatives use the cross product (not |e1|^2|e2|^2 - t^2), which keeps their
// relative accuracy near the straight state.
//   grad_e1 s = 2 e2 x c,  grad_e2 s = 2 c x e1
//   grad_e1 r = (|e2|/|e1|) e1,  grad_e2 r = (|e1|/|e2|) e2;  grad_e1 t = e2,  grad_e2 t = e1
//   grad f = 4 (grad s / d^2 - 2 s grad d / d^3)
// U = 1/2 k (kappa - psi0)^2, k = EI/D [N m]:
//   dU/df = k/2 (1 - psi0/kappa),  d2U/df2 = k psi0 / (4 kappa^3)   (psi0 = 0: k/2 and 0).
// x-derivatives through e1 = x_b - x_a, e2 = x_c - x_b: dU/dx_a = -dU/de1,
// dU/dx_b = dU/de1 - dU/de2, dU/dx_c = dU/de2.

namespace {

/// Relative size of d = |e1||e2|(1 + cos phi) below which phi counts as pi (folded).
constexpr double kFoldTol = 1e-12;

using triad::V3;
using triad::cross;  // written out for AD scalars (elements/BodyTriad.hpp)
using triad::skew;

/// f = |kb|^2 and its gradient in (e1, e2): gf1 = df/de1, gf2 = df/de2 [1/m].
/// Returns false (outputs unset beyond what was computed) if an edge has zero length or the
/// hinge is folded (phi = pi within kFoldTol); `why` says which.
template <class T>
bool curvatureSquaredT(const V3<T>& e1, const V3<T>& e2, T& f, V3<T>& gf1, V3<T>& gf2,
                       std::string& why) {
  using std::sqrt;
  const T a = e1.dot(e1), b = e2.dot(e2);
  if (!(ad::valueOf(a) > 0.0 && ad::valueOf(b) > 0.0)) {
    why = "zero edge length";
    return false;
  }
  const T l1 = sqrt(a), l2 = sqrt(b);
  const T r = l1 * l2, t = e1.dot(e2), d = r + t;
  if (!(ad::valueOf(d) > kFoldTol * ad::valueOf(r))) {
    why = "the turning angle reached pi (the beam folds back onto itself), where the curvature "
          "2 tan(phi/2) is infinite";
    return false;
  }
  const V3<T> c = cross(e1, e2);
  const T s = c.dot(c);
  // (constants enter through scalar-double operations only, see elements/AutoDiff.hpp)
  const V3<T> hs1 = cross(e2, c), hs2 = cross(c, e1);  // grad s / 2
  const V3<T> gd1 = (l2 / l1) * e1 + e2, gd2 = (l1 / l2) * e2 + e1;
  const T d2 = d * d, d3 = d2 * d;
  const T cs = 8.0 / d2, cd = 8.0 * s / d3;
  f = 4.0 * s / d2;
  gf1 = cs * hs1 - cd * gd1;
  gf2 = cs * hs2 - cd * gd2;
  return true;
}

}  // namespace

Eigen::Vector3d BeamHinge3D::curvatureBinormal(const VecX& x) {
  if (x.size() != 9) throw std::invalid_argument("beam_hinge3d: positions of 3 nodes in 3D (9 entries) expected");
  const Eigen::Vector3d e1 = x.segment<3>(3) - x.segment<3>(0), e2 = x.segment<3>(6) - x.segment<3>(3);
  const double r = e1.norm() * e2.norm(), d = r + e1.dot(e2);
  if (!(r > 0.0)) throw std::invalid_argument("beam_hinge3d: zero edge length");
  if (!(d > kFoldTol * r)) throw std::invalid_argument("beam_hinge3d: turning angle pi (folded)");
  return 2.0 * e1.cross(e2) / d;
}

BeamHinge3D::BeamHinge3D(std::string name, std::vector<int> nodes, std::shared_ptr<BeamSection> section,
                         const VecX& restX, double voronoiLength, std::shared_ptr<BeamSection> sectionB)
    : KernelElement(std::move(name), std::move(nodes)), sec_(std::move(section), std::move(sectionB)) {
  const std::string who = "beam_hinge3d " + this->name();
  if (this->nodes().size() != 3) throw std::invalid_argument(who + ": needs 3 nodes");
  if (!sec_.a) throw std::invalid_argument(who + ": no section");
  if (restX.size() != 9) throw std::invalid_argument(who + ": spatial only (dim must be 3, 9 rest coordinates)");
  const double L1 = (restX.segment<3>(3) - restX.segment<3>(0)).norm();
  const double L2 = (restX.segment<3>(6) - restX.segment<3>(3)).norm();
  if (!(L1 > 0.0 && L2 > 0.0)) throw std::invalid_argument(who + ": zero rest length");
  sec_.span(L1, L2);
  try {
    psi0_ = curvatureBinormal(restX).norm();
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument(who + ": the rest shape turns by pi at the middle node (folded back)");
  }
  if (psi0_ < kStraightRest) psi0_ = 0.0;
  D_ = voronoiLength > 0.0 ? voronoiLength : 0.5 * (L1 + L2);
}

void BeamHinge3D::checkDim(const LocalState& s) const {
  if (s.dim != 3 || s.x.size() != 9)
    throw std::invalid_argument("beam_hinge3d " + name() + ": spatial only (dim must be 3)");
}

double BeamHinge3D::dUdf(double EI, double f) const {
  const double k = EI / D_;  // [N m]
  if (psi0_ == 0.0) return 0.5 * k;
  const double kappa = std::sqrt(f);
  if (!(kappa >= kKinkTol)) {
    std::ostringstream os;
    os << "beam_hinge3d " << name() << ": the hinge is straight (|kb| = " << kappa
       << ") while its rest shape is bent (psi0 = " << psi0_
       << "); U = 1/2 k (|kb| - psi0)^2 has a kink there (no gradient). Start from a bent "
          "configuration, or make the rest shape straight (rest_shape: straight)";
    throw NumericalError(os.str());
  }
  return 0.5 * k * (1.0 - psi0_ / kappa);
}

double BeamHinge3D::curvatureSquared(const LocalState& s, VecX* g, MatX* H) const {
  checkDim(s);
  const Eigen::Vector3d e1 = s.x.segment<3>(3) - s.x.segment<3>(0), e2 = s.x.segment<3>(6) - s.x.segment<3>(3);
  double f;
  Eigen::Vector3d gf1, gf2;
  std::string why;
  if (!curvatureSquaredT<double>(e1, e2, f, gf1, gf2, why))
    throw NumericalError("beam_hinge3d " + name() + ": " + why);
  if (g) {
    g->resize(9);
    *g << -gf1, gf1 - gf2, gf2;
  }
  if (H) {
    // Hessian of f in u = (e1, e2), then B^T Hu B.
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const double a = e1.squaredNorm(), b = e2.squaredNorm(), l1 = std::sqrt(a), l2 = std::sqrt(b);
    const double t = e1.dot(e2), r = l1 * l2, d = r + t;
    const Eigen::Vector3d c = e1.cross(e2), n1 = e1 / l1, n2 = e2 / l2;
    const double sv = c.squaredNorm();
    // Fixed sizes: no heap traffic (this Hessian is assembled for every hinge at every Newton
    // matrix; with dynamic 6 x 6 temporaries it was ~10% of the satellite's run).
    using V6 = Eigen::Matrix<double, 6, 1>;
    using M6 = Eigen::Matrix<double, 6, 6>;
    V6 gs, gd;
    gs << 2.0 * e2.cross(c), 2.0 * c.cross(e1);
    gd << (l2 / l1) * e1 + e2, (l1 / l2) * e2 + e1;
    M6 Hs, Hd;
    Hs.block<3, 3>(0, 0) = 2.0 * (b * I - e2 * e2.transpose());
    Hs.block<3, 3>(3, 3) = 2.0 * (a * I - e1 * e1.transpose());
    Hs.block<3, 3>(0, 3) = 2.0 * (-skew(c) + e1 * e2.transpose() - t * I);
    Hs.block<3, 3>(3, 0) = Hs.block<3, 3>(0, 3).transpose();
    Hd.block<3, 3>(0, 0) = (l2 / l1) * (I - n1 * n1.transpose());
    Hd.block<3, 3>(3, 3) = (l1 / l2) * (I - n2 * n2.transpose());
    Hd.block<3, 3>(0, 3) = n1 * n2.transpose() + I;
    Hd.block<3, 3>(3, 0) = n2 * n1.transpose() + I;
    const double d2 = d * d, d3 = d2 * d, d4 = d2 * d2;
    const M6 sd = gs * gd.transpose();
    const M6 Hu = 4.0 * (Hs / d2 - 2.0 * (sd + sd.transpose()) / d3 - 2.0 * sv * Hd / d3 +
                         6.0 * sv * gd * gd.transpose() / d4);
    // B^T Hu B with B: x -> (e1, e2) = (x_b - x_a, x_c - x_b), written out block by block
    // (the product through Eigen's general gemm was ~5% of the satellite's run).
    const Eigen::Matrix3d H11 = Hu.block<3, 3>(0, 0), H12 = Hu.block<3, 3>(0, 3), H21 = Hu.block<3, 3>(3, 0),
                          H22 = Hu.block<3, 3>(3, 3);
    H->resize(9, 9);
    H->block<3, 3>(0, 0) = H11;
    H->block<3, 3>(0, 3) = H12 - H11;
    H->block<3, 3>(0, 6) = -H12;
    H->block<3, 3>(3, 0) = H21 - H11;
    H->block<3, 3>(3, 3) = H11 - H12 - H21 + H22;
    H->block<3, 3>(3, 6) = H12 - H22;
    H->block<3, 3>(6, 0) = -H21;
    H->block<3, 3>(6, 3) = H21 - H22;
    H->block<3, 3>(6, 6) = H22;
  }
  return f;
}

// Value template: props = (E, I source). Q = -dU/df grad f.
template <class T>
VecT<T> BeamHinge3D::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>&,
                            const VecT<T>& props) const {
  using std::sqrt;
  checkDim(s);
  const V3<T> e1 = x.template segment<3>(3) - x.template segment<3>(0);
  const V3<T> e2 = x.template segment<3>(6) - x.template segment<3>(3);
  T f;
  V3<T> gf1, gf2;
  std::string why;
  if (!curvatureSquaredT<T>(e1, e2, f, gf1, gf2, why)) throw NumericalError("beam_hinge3d " + name() + ": " + why);
  const T k = sec_.EIof(props) / D_;  // EI / D [N m]
  T dUdfT;
  if (psi0_ == 0.0) {
    dUdfT = 0.5 * k;
  } else {
    dUdf(1.0, ad::valueOf(f));  // kink check (throws with the suggestion)
    dUdfT = 0.5 * k * (1.0 - psi0_ / sqrt(f));
  }
  // Q = -dU/dx: Q_a = dU/df gf1, Q_b = dU/df (gf2 - gf1), Q_c = -dU/df gf2  [N]
  VecT<T> Q(9);
  for (int i = 0; i < 3; ++i) {
    Q[i] = dUdfT * gf1[i];
    Q[3 + i] = dUdfT * T(gf2[i] - gf1[i]);
    Q[6 + i] = -dUdfT * gf2[i];
  }
  return Q;
}

void BeamHinge3D::force(const LocalState& s, VecX& Q) const {
  // forceT<double> into Q's storage (see BeamSegment::force): Q = -dU/df grad f  [N]
  const double f = curvatureSquared(s, &Q, nullptr);  // grad f, in Q's storage
  Q *= -dUdf(sec_.EI(*s.p), f);
}

void BeamHinge3D::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  VecX g;
  const double f = curvatureSquared(s, &g, &dQdq);  // Hess f, in dQdq's storage
  const double EI = sec_.EI(*s.p), k = EI / D_;
  // dQ/dq = -Hess U = -(dU/df Hess f + d2U/df2 grad f grad f^T), d2U/df2 = k psi0 / (4 kappa^3)
  // [N/m]
  dQdq *= -dUdf(EI, f);
  if (psi0_ > 0.0) {
    const double kappa = std::sqrt(f);
    dQdq.noalias() -= (k * psi0_ / (4.0 * kappa * kappa * kappa)) * (g * g.transpose());
  }
  dQdv.setZero(9, 9);
}

bool BeamHinge3D::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  if (!sec_.bendingDependsOn(k)) return false;
  VecX g;
  const double f = curvatureSquared(s, &g, nullptr);
  // Q = -(EI/D) phi(f) grad f with phi = dU/df / k independent of EI: dQ = -(dEI/D) phi grad f
  dQ = -dUdf(sec_.dEI(*s.p, k), f) * g;
  dM.setZero(9, 9);
  return true;
}

double BeamHinge3D::potential(const LocalState& s) const {
  const double f = curvatureSquared(s, nullptr, nullptr);
  const double dev = std::sqrt(f) - psi0_;  // |kb| - psi0 [-]
  return 0.5 * (sec_.EI(*s.p) / D_) * dev * dev;  // [J]
}

template class KernelElement<BeamHinge3D>;

}  // namespace flexsens
