#include "elements/RigidBar.hpp"

#include <cmath>
#include <sstream>

#include "elements/KernelElementAD.hpp"

namespace flexsens {

// ------------------------------------------------------------------------------ rigid bar
// Value templates: props = (m).
template <class T>
MatT<T> RigidBar::massT(const LocalState& s, const VecT<T>& props) const {
  const int d = s.dim;
  const T& m = props[0];
  MatT<T> M = MatT<T>::Zero(2 * d, 2 * d);
  for (int i = 0; i < d; ++i) {
    M(i, i) = M(d + i, d + i) = m / 3.0;
    M(i, d + i) = M(d + i, i) = m / 6.0;
  }
  return M;
}

template <class T>
VecT<T> RigidBar::forceT(const LocalState& s, const VecT<T>&, const VecT<T>&,
                         const VecT<T>& props) const {
  const int d = s.dim;
  const T& m = props[0];
  const VecX& g = *s.gravity;
  VecT<T> Q(2 * d);
  for (int i = 0; i < d; ++i) Q[i] = Q[d + i] = 0.5 * m * g[i];
  return Q;
}

// The double paths of force() (here and the spring-damper's) write into the caller's
// storage: the residual evaluates every element at every Newton iteration, and the kernels'
// property and result vectors were a malloc/free pair each (n = 8 flexible five-bar).
void RigidBar::force(const LocalState& s, VecX& Q) const {
  const int d = s.dim;
  const double w = 0.5 * s.value(mass_);  // half the mass [kg]: w g on each end
  Q.resize(2 * d);
  for (int i = 0; i < d; ++i) Q[i] = Q[d + i] = w * (*s.gravity)[i];
}

void RigidBar::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  dQdq.setZero(2 * s.dim, 2 * s.dim);
  dQdv.setZero(2 * s.dim, 2 * s.dim);
}

bool RigidBar::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  if (!mass_.boundTo(k)) return false;
  // Q and M are linear in the mass: their mass derivatives are the unit-mass values.
  const int d = s.dim;
  dQ.resize(2 * d);
  dQ.head(d) = 0.5 * (*s.gravity);
  dQ.tail(d) = 0.5 * (*s.gravity);
  mass(s, dM);
  dM /= s.value(mass_);
  return true;
}

double RigidBar::potential(const LocalState& s) const {
  const int d = s.dim;
  const double m = s.value(mass_);
  return -0.5 * m * s.gravity->dot(s.x.head(d) + s.x.tail(d));
}

// --------------------------------------------------------------------------- spring-damper
// Inline-storage VecUpTo3 / MatUpTo3: heap-allocated temporaries were most of these kernels'
// cost on the flexible five-bar.
struct SpringDamper::Geometry {
  VecUpTo3 u;   ///< unit vector from a to b
  double l;     ///< current length [m]
  double ldot;  ///< elongation rate [m/s]
  VecUpTo3 w;   ///< relative velocity v_b - v_a
  /// Coincident nodes of a spring with zero natural length and no damping: the force k dx is
  /// smooth there although its direction is not; u is then unused (zero).
  bool zeroLength = false;
  VecUpTo3 dx;  ///< x_b - x_a [m]
};

SpringDamper::Geometry SpringDamper::geometry(const LocalState& s) const {
  const int d = s.dim;
  Geometry g;
  g.dx = s.x.tail(d) - s.x.head(d);
  g.l = g.dx.norm();
  g.w = s.v.tail(d) - s.v.head(d);
  if (!(g.l > 1e-12)) {
    if (!(s.value(L0_) == 0.0 && s.value(c_) == 0.0)) coincidentNodes(g.l);
    g.zeroLength = true;
    g.u = VecUpTo3::Zero(d);
    g.ldot = 0.0;
    return g;
  }
  g.u = g.dx / g.l;
  g.ldot = g.u.dot(g.w);
  return g;
}

void SpringDamper::coincidentNodes(double l) const {
  std::ostringstream os;
  os << "spring-damper '" << name() << "': its two nodes coincide (length " << l
     << " m), so its direction is undefined; check the node positions";
  throw NumericalError(os.str());
}

// Value template: props = (k, c, L0).
template <class T>
VecT<T> SpringDamper::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v,
                             const VecT<T>& props) const {
  using std::sqrt;
  const int d = s.dim;
  const VecT<T> dx = x.tail(d) - x.head(d);
  if (!(ad::valueOf(T(dx.norm())) > 1e-12)) {  // coincident nodes: only k dx is defined
    if (!(ad::valueOf(props[2]) == 0.0 && ad::valueOf(props[1]) == 0.0)) coincidentNodes(ad::valueOf(T(dx.norm())));
    VecT<T> Q(2 * d);
    Q.head(d) = props[0] * dx;
    Q.tail(d) = -props[0] * dx;
    return Q;
  }
  const T l = sqrt(dx.squaredNorm());  // current length [m]
  const VecT<T> u = dx / l;
  const VecT<T> w = v.tail(d) - v.head(d);
  const T ldot = u.dot(w);                                       // elongation rate [m/s]
  const T f = props[0] * (l - props[2]) + props[1] * ldot;      // tension [N]
  VecT<T> Q(2 * d);
  Q.head(d) = f * u;
  Q.tail(d) = -f * u;
  return Q;
}

void SpringDamper::force(const LocalState& s, VecX& Q) const {
  const int d = s.dim;
  const Geometry g = geometry(s);
  Q.resize(2 * d);
  if (g.zeroLength) {  // coincident nodes: only k dx is defined (geometry checked it may be)
    Q.head(d) = s.value(k_) * g.dx;
    Q.tail(d) = -s.value(k_) * g.dx;
    return;
  }
  const double f = s.value(k_) * (g.l - s.value(L0_)) + s.value(c_) * g.ldot;  // tension [N]
  Q.head(d) = f * g.u;
  Q.tail(d) = -f * g.u;
}

void SpringDamper::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  const int d = s.dim;
  const Geometry g = geometry(s);
  const double k = s.value(k_), c = s.value(c_);
  const double f = k * (g.l - s.value(L0_)) + c * g.ldot;
  // G = d(f u)/d(x_b - x_a), Cm = d(f u)/d(v_b - v_a); at zero length f u = k dx.
  MatUpTo3 G(d, d), Cm(d, d);
  if (g.zeroLength) {
    G.setIdentity();
    G *= k;
  } else {
    const MatUpTo3 P = MatUpTo3::Identity(d, d) - g.u * g.u.transpose();
    const VecUpTo3 Pw = P * g.w;
    G.noalias() = g.u * (k * g.u + (c / g.l) * Pw).transpose();
    G += (f / g.l) * P;
  }
  Cm.noalias() = c * g.u * g.u.transpose();
  dQdq.resize(2 * d, 2 * d);
  dQdq.topLeftCorner(d, d) = -G;
  dQdq.topRightCorner(d, d) = G;
  dQdq.bottomLeftCorner(d, d) = G;
  dQdq.bottomRightCorner(d, d) = -G;
  dQdv.resize(2 * d, 2 * d);
  dQdv.topLeftCorner(d, d) = -Cm;
  dQdv.topRightCorner(d, d) = Cm;
  dQdv.bottomLeftCorner(d, d) = Cm;
  dQdv.bottomRightCorner(d, d) = -Cm;
}

bool SpringDamper::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  const int d = s.dim;
  const Geometry g = geometry(s);
  if (g.zeroLength) {  // Q = k dx: only the stiffness has a derivative there
    if (c_.boundTo(k) || L0_.boundTo(k)) coincidentNodes(g.l);
    if (!k_.boundTo(k)) return false;
    dQ.resize(2 * d);
    dQ.head(d) = g.dx;
    dQ.tail(d) = -g.dx;
    dM.resize(0, 0);
    return true;
  }
  double df = 0.0;  // partial of the tension
  bool any = false;
  if (k_.boundTo(k)) { df += g.l - s.value(L0_); any = true; }
  if (c_.boundTo(k)) { df += g.ldot; any = true; }
  if (L0_.boundTo(k)) { df -= s.value(k_); any = true; }
  if (!any) return false;
  dQ.resize(2 * d);
  dQ.head(d) = df * g.u;
  dQ.tail(d) = -df * g.u;
  dM.resize(0, 0);
  return true;
}

double SpringDamper::potential(const LocalState& s) const {
  const int d = s.dim;
  const double e = (s.x.tail(d) - s.x.head(d)).norm() - s.value(L0_);
  return 0.5 * s.value(k_) * e * e;
}

template class KernelElement<RigidBar>;
template class KernelElement<SpringDamper>;

}  // namespace flexsens
