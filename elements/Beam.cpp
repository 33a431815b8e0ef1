#include "elements/Beam.hpp"

#include <cmath>

#include "elements/KernelElementAD.hpp"

namespace flexsens {

// ---------------------------------------------------------------- BeamSection
double BeamSection::A(const VecX& p) const { return areaOf(areaSource().value(p)); }
double BeamSection::I(const VecX& p) const { return inertiaOf(inertiaSource().value(p)); }
double BeamSection::dA(const VecX& p, int k) const {
  if (!square) return area.boundTo(k) ? 1.0 : 0.0;
  return side.boundTo(k) ? 2.0 * side.value(p) : 0.0;  // d(a^2)/da
}
double BeamSection::dI(const VecX& p, int k) const {
  if (!square) return inertia.boundTo(k) ? 1.0 : 0.0;
  const double a = side.value(p);
  return side.boundTo(k) ? a * a * a / 3.0 : 0.0;  // d(a^4/12)/da
}
double BeamSection::dEA(const VecX& p, int k) const {
  return (E.boundTo(k) ? A(p) : 0.0) + E.value(p) * dA(p, k);
}
double BeamSection::dEI(const VecX& p, int k) const {
  return (E.boundTo(k) ? I(p) : 0.0) + E.value(p) * dI(p, k);
}
double BeamSection::drhoA(const VecX& p, int k) const {
  return (density.boundTo(k) ? A(p) : 0.0) + density.value(p) * dA(p, k);
}
std::vector<std::pair<std::string, Quantity*>> BeamSection::properties() {
  std::vector<std::pair<std::string, Quantity*>> r{{"E", &E}};
  if (!massless) r.push_back({"density", &density});
  if (square) {
    r.push_back({"side", &side});
  } else {
    r.push_back({"area", &area});
    r.push_back({"inertia", &inertia});
  }
  return r;
}

namespace {
VecUpTo3 gravityOf(const LocalState& s) {
  return s.gravity ? VecUpTo3(*s.gravity) : VecUpTo3(VecUpTo3::Zero(s.dim));
}
}  // namespace

// ---------------------------------------------------------------- BeamSegment
BeamSegment::BeamSegment(std::string name, std::vector<int> nodes,
                         std::shared_ptr<BeamSection> section, double restLength)
    : KernelElement(std::move(name), std::move(nodes)), sec_(std::move(section)), L_(restLength) {
  if (this->nodes().size() != 2) throw std::invalid_argument("beam_segment " + this->name() + ": needs 2 nodes");
  if (!sec_) throw std::invalid_argument("beam_segment " + this->name() + ": no section");
  if (!(L_ > 0.0)) throw std::invalid_argument("beam_segment " + this->name() + ": rest length must be > 0");
}

namespace {
/// Unit axis n and current length l of a segment; throws on bad dim or zero length.
double segmentAxis(const Element& e, const LocalState& s, VecUpTo3& n) {
  if (s.dim != 2 && s.dim != 3) throw std::invalid_argument("beam_segment " + e.name() + ": dim must be 2 or 3");
  n = s.x.segment(s.dim, s.dim) - s.x.segment(0, s.dim);
  const double l = n.norm();
  if (!(l > 0.0)) throw NumericalError("beam_segment " + e.name() + ": zero current length");
  n /= l;
  return l;
}
}  // namespace

// Value templates: props = (E, density, A source).
template <class T>
MatT<T> BeamSegment::massT(const LocalState& s, const VecT<T>& props) const {
  const int d = s.dim;
  const T rhoA = props[1] * sec_->areaOf(props[2]);  // [kg/m]
  const T m6 = rhoA * L_ / 6.0;                      // [kg]
  MatT<T> M = MatT<T>::Zero(2 * d, 2 * d);
  for (int i = 0; i < d; ++i) {
    M(i, i) = M(d + i, d + i) = 2.0 * m6;
    M(i, d + i) = M(d + i, i) = m6;
  }
  return M;
}

template <class T>
VecT<T> BeamSegment::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>&,
                            const VecT<T>& props) const {
  using std::sqrt;
  if (s.dim != 2 && s.dim != 3) throw std::invalid_argument("beam_segment " + name() + ": dim must be 2 or 3");
  const int d = s.dim;
  Eigen::Matrix<T, Eigen::Dynamic, 1, 0, 3, 1> n = x.segment(d, d) - x.segment(0, d);  // on the stack
  const T l = sqrt(n.squaredNorm());
  if (!(ad::valueOf(l) > 0.0)) throw NumericalError("beam_segment " + name() + ": zero current length");
  n /= l;                                             // unit axis
  const T A = sec_->areaOf(props[2]);
  const T EA = props[0] * A, rhoA = props[1] * A;
  const T N = EA * (l - L_) / L_;                     // axial force dU/dl [N]
  const T w = 0.5 * rhoA * L_;                        // nodal mass [kg]
  const VecUpTo3 g = gravityOf(s);
  VecT<T> Q(2 * d);
  for (int i = 0; i < d; ++i) {
    Q[i] = N * n[i] + w * g[i];
    Q[d + i] = -N * n[i] + w * g[i];
  }
  return Q;
}

void BeamSegment::force(const LocalState& s, VecX& Q) const {
  // forceT<double> into Q's storage: the residual evaluates every element at every Newton
  // iteration, and the kernel's property and result vectors were ~1% of the satellite's run.
  VecUpTo3 n;
  const double l = segmentAxis(*this, s, n);
  const int d = s.dim;
  const double N = sec_->EA(*s.p) * (l - L_) / L_;  // axial force [N]
  const VecUpTo3 G = 0.5 * sec_->rhoA(*s.p) * L_ * gravityOf(s);  // nodal weight [N]
  Q.resize(2 * d);
  Q.head(d) = N * n + G;
  Q.tail(d) = -N * n + G;
}

void BeamSegment::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  VecUpTo3 n;
  const double l = segmentAxis(*this, s, n);
  const int d = s.dim;
  const double EA = sec_->EA(*s.p), N = EA * (l - L_) / L_;
  // K = d(N n)/d(x_b - x_a) = (EA/L) n n^T + (N/l)(I - n n^T)   [N/m]
  const MatUpTo3 nn = n * n.transpose();
  const MatUpTo3 K = (EA / L_) * nn + (N / l) * (MatUpTo3::Identity(d, d) - nn);
  dQdq.resize(2 * d, 2 * d);
  dQdq << -K, K, K, -K;
  dQdv.setZero(2 * d, 2 * d);
}

bool BeamSegment::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  if (!sec_->axialDependsOn(k)) return false;
  VecUpTo3 n;
  const double l = segmentAxis(*this, s, n);
  const int d = s.dim;
  const double dN = sec_->dEA(*s.p, k) * (l - L_) / L_;
  const double drhoA = sec_->drhoA(*s.p, k);
  const VecUpTo3 dG = 0.5 * drhoA * L_ * gravityOf(s);
  dQ.resize(2 * d);
  dQ.head(d) = dN * n + dG;
  dQ.tail(d) = -dN * n + dG;
  const double dm6 = drhoA * L_ / 6.0;
  dM.setZero(2 * d, 2 * d);
  for (int i = 0; i < d; ++i) {
    dM(i, i) = dM(d + i, d + i) = 2.0 * dm6;
    dM(i, d + i) = dM(d + i, i) = dm6;
  }
  return true;
}

double BeamSegment::potential(const LocalState& s) const {
  VecUpTo3 n;
  const double l = segmentAxis(*this, s, n);
  const int d = s.dim;
  const double eps = (l - L_) / L_;
  const double mNode = 0.5 * sec_->rhoA(*s.p) * L_;
  const VecX g = gravityOf(s);  // (dynamic: the stack-sized one trips GCC 12's -Warray-bounds in the dot below)
  // elastic energy minus work of gravity: U - sum m_node g . x_i  [J]
  return 0.5 * sec_->EA(*s.p) * L_ * eps * eps -
         mNode * g.dot(s.x.segment(0, d) + s.x.segment(d, d));
}

// ---------------------------------------------------------------- BeamHinge
double BeamHinge::angle(const VecX& x) {
  const Eigen::Vector2d e1 = x.segment<2>(2) - x.segment<2>(0), e2 = x.segment<2>(4) - x.segment<2>(2);
  return std::atan2(e1.x() * e2.y() - e1.y() * e2.x(), e1.dot(e2));
}

std::vector<std::pair<std::string, Quantity*>> HingeSections::properties() const {
  auto out = a->properties();
  if (b != a)
    for (const auto& q : b->properties()) out.push_back(q);
  return out;
}

BeamHinge::BeamHinge(std::string name, std::vector<int> nodes, std::shared_ptr<BeamSection> section,
                     const VecX& restX, double voronoiLength, std::shared_ptr<BeamSection> sectionB)
    : KernelElement(std::move(name), std::move(nodes)), sec_(std::move(section), std::move(sectionB)) {
  const std::string who = "beam_hinge " + this->name();
  if (this->nodes().size() != 3) throw std::invalid_argument(who + ": needs 3 nodes");
  if (!sec_.a) throw std::invalid_argument(who + ": no section");
  if (restX.size() != 6) throw std::invalid_argument(who + ": planar only (dim must be 2)");
  const double L1 = (restX.segment<2>(2) - restX.segment<2>(0)).norm();
  const double L2 = (restX.segment<2>(4) - restX.segment<2>(2)).norm();
  if (!(L1 > 0.0 && L2 > 0.0)) throw std::invalid_argument(who + ": zero rest length");
  sec_.span(L1, L2);
  phi0_ = angle(restX);
  D_ = voronoiLength > 0.0 ? voronoiLength : 0.5 * (L1 + L2);
}

double BeamHinge::deviation(const LocalState& s, VecX* g, MatX* H) const {
  if (s.dim != 2) throw std::invalid_argument("beam_hinge " + name() + ": planar only (dim must be 2)");
  const double dphi = std::remainder(angle(s.x) - phi0_, 2.0 * M_PI);
  if (!g && !H) return dphi;
  // phi = theta(e2) - theta(e1), theta(e) = atan2(e_y, e_x):
  //   dtheta/de = J e / |e|^2,  d2theta/de2 = -(J e e^T + e (J e)^T) / |e|^4,  J = rot(+90 deg).
  const Eigen::Vector2d e1 = s.x.segment<2>(2) - s.x.segment<2>(0), e2 = s.x.segment<2>(4) - s.x.segment<2>(2);
  const double r1 = e1.squaredNorm(), r2 = e2.squaredNorm();
  if (!(r1 > 0.0 && r2 > 0.0)) throw NumericalError("beam_hinge " + name() + ": zero edge length");
  const Eigen::Vector2d J1(-e1.y(), e1.x()), J2(-e2.y(), e2.x());
  const Eigen::Vector2d g1 = -J1 / r1, g2 = J2 / r2;  // dphi/de1, dphi/de2 [1/m]
  if (g) {
    g->resize(6);
    *g << -g1, g1 - g2, g2;  // e1 = x_b - x_a, e2 = x_c - x_b
  }
  if (H) {
    const Eigen::Matrix2d H1 = (J1 * e1.transpose() + e1 * J1.transpose()) / (r1 * r1);   // d2phi/de1^2
    const Eigen::Matrix2d H2 = -(J2 * e2.transpose() + e2 * J2.transpose()) / (r2 * r2);  // d2phi/de2^2
    H->setZero(6, 6);
    H->block<2, 2>(0, 0) = H1;
    H->block<2, 2>(0, 2) = -H1;
    H->block<2, 2>(2, 0) = -H1;
    H->block<2, 2>(2, 2) = H1 + H2;
    H->block<2, 2>(2, 4) = -H2;
    H->block<2, 2>(4, 2) = -H2;
    H->block<2, 2>(4, 4) = H2;
  }
  return dphi;
}

// Value template: props = (E, I source). Q = -k_b (phi - phi0) dphi/dx, k_b = EI / D.
template <class T>
VecT<T> BeamHinge::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>&,
                          const VecT<T>& props) const {
  using std::atan2;
  if (s.dim != 2) throw std::invalid_argument("beam_hinge " + name() + ": planar only (dim must be 2)");
  // e1 = x_b - x_a, e2 = x_c - x_b; phi = atan2(e1 x e2, e1 . e2)
  const T e1x = x[2] - x[0], e1y = x[3] - x[1], e2x = x[4] - x[2], e2y = x[5] - x[3];
  const T cross = e1x * e2y - e1y * e2x, dot = e1x * e2x + e1y * e2y;
  const T phi = atan2(cross, dot);
  const T dphi = ad::wrapAngle(T(phi - phi0_));
  // dphi/de1 = -J e1 / |e1|^2, dphi/de2 = J e2 / |e2|^2, J = rot(+90 deg)
  const T r1 = e1x * e1x + e1y * e1y, r2 = e2x * e2x + e2y * e2y;
  if (!(ad::valueOf(r1) > 0.0 && ad::valueOf(r2) > 0.0))
    throw NumericalError("beam_hinge " + name() + ": zero edge length");
  const T g1x = e1y / r1, g1y = -e1x / r1, g2x = -e2y / r2, g2y = e2x / r2;  // [1/m]
  const T EI = sec_.EIof(props);
  const T c = -(EI / D_) * dphi;  // -dU/dphi [N m]
  VecT<T> Q(6);
  Q << c * -g1x, c * -g1y, c * T(g1x - g2x), c * T(g1y - g2y), c * g2x, c * g2y;  // [N]
  return Q;
}

void BeamHinge::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  VecX g;
  const double dphi = deviation(s, &g, &dQdq);  // Hess phi, in dQdq's storage (no temporaries)
  // dQ/dq = -Hess U = -k_b (g g^T + (phi - phi0) Hess phi), k_b = EI / D [N m]
  const double kb = sec_.EI(*s.p) / D_;
  dQdq *= -kb * dphi;
  dQdq.noalias() -= kb * (g * g.transpose());
  dQdv.setZero(6, 6);
}

bool BeamHinge::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  if (!sec_.bendingDependsOn(k)) return false;
  VecX g;
  const double dphi = deviation(s, &g, nullptr);
  dQ = -(sec_.dEI(*s.p, k) / D_) * dphi * g;
  dM.setZero(6, 6);
  return true;
}

double BeamHinge::potential(const LocalState& s) const {
  const double dphi = deviation(s, nullptr, nullptr);
  return 0.5 * (sec_.EI(*s.p) / D_) * dphi * dphi;  // [J]
}

template class KernelElement<BeamSegment>;
template class KernelElement<BeamHinge>;

}  // namespace flexsens
