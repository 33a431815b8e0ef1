#include "elements/PlanarRigidBody.hpp"

#include <stdexcept>

#include "elements/KernelElementAD.hpp"

namespace flexsens {

namespace {
/// The +90 degree rotation applied to a 2-vector.
template <class V>
V rot90(const V& u) {
  V r(2);
  r << -u[1], u[0];
  return r;
}
}  // namespace

Eigen::Vector2d PlanarRigidBody::bodyCoordinates(const VecX& xA, const VecX& xB, const VecX& x) {
  const Eigen::Vector2d u = xB - xA, d = x - xA;
  const double L2 = u.squaredNorm();
  if (!(L2 > 0)) throw std::invalid_argument("the two basic points coincide");
  return {d.dot(u) / L2, d.dot(rot90(u)) / L2};
}

PlanarRigidBody::PlanarRigidBody(std::string name, int a, int b, const VecX& xA, const VecX& xB, const VecX& com,
                                 Quantity mass, Quantity inertia)
    : KernelElement(std::move(name), {a, b}), mass_(mass), inertia_(inertia) {
  const Eigen::Vector2d c = bodyCoordinates(xA, xB, com);
  xiG_ = c[0];
  etaG_ = c[1];
  L2_ = (xB - xA).squaredNorm();
}

// Value templates: props = (m, I_G).
template <class T>
MatT<T> PlanarRigidBody::massT(const LocalState&, const VecT<T>& props) const {
  const T& m = props[0];
  const T j = props[1] / L2_ + m * (xiG_ * xiG_ + etaG_ * etaG_);
  const T aa = m - 2.0 * m * xiG_ + j, ab = m * xiG_ - j, rb = m * etaG_;
  MatT<T> M = MatT<T>::Zero(4, 4);
  // R = [[0, -1], [1, 0]]: M_AB = ab I + rb R, M_BA = M_AB^T.
  M(0, 0) = M(1, 1) = aa;
  M(2, 2) = M(3, 3) = j;
  M(0, 2) = M(1, 3) = M(2, 0) = M(3, 1) = ab;
  M(0, 3) = -rb;
  M(1, 2) = rb;
  M(3, 0) = -rb;
  M(2, 1) = rb;
  return M;
}

template <class T>
VecT<T> PlanarRigidBody::forceT(const LocalState& s, const VecT<T>&, const VecT<T>&, const VecT<T>& props) const {
  // Q = M [g; g] in closed form: Q_A = m (1 - xi_G) g + m eta_G R g, Q_B = m xi_G g - m eta_G R g
  // (the inertia drops out: a body's weight does not depend on it). Every entry is m times a
  // constant, which also keeps AD's derivative vectors non-empty.
  const VecX& g = *s.gravity;
  const T& m = props[0];
  const double Rg[2] = {-g[1], g[0]};
  VecT<T> Q(4);
  for (int i = 0; i < 2; ++i) {
    Q[i] = m * ((1.0 - xiG_) * g[i] + etaG_ * Rg[i]);
    Q[2 + i] = m * (xiG_ * g[i] - etaG_ * Rg[i]);
  }
  return Q;
}

void PlanarRigidBody::forceJacobian(const LocalState&, MatX& dQdq, MatX& dQdv) const {
  dQdq.setZero(4, 4);
  dQdv.setZero(4, 4);
}

bool PlanarRigidBody::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  const bool bm = mass_.boundTo(k), bi = inertia_.boundTo(k);
  if (!bm && !bi) return false;
  // M (and Q = M [g; g]) is linear in (m, I_G): the derivative is M at the unit property.
  const VecX unit = (VecX(2) << (bm ? 1.0 : 0.0), (bi ? 1.0 : 0.0)).finished();
  dM = massT<double>(s, unit);
  dQ = forceT<double>(s, s.x, s.v, unit);
  return true;
}

double PlanarRigidBody::potential(const LocalState& s) const {
  const VecX xA = s.x.head(2), xB = s.x.tail(2);
  const VecX rG = (1.0 - xiG_) * xA + xiG_ * xB + etaG_ * rot90(VecX(xB - xA));
  return -s.value(mass_) * s.gravity->dot(rG);
}

template class KernelElement<PlanarRigidBody>;

}  // namespace flexsens
