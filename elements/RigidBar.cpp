#include "elements/RigidBar.hpp"

#include <cmath>
#include <sstream>

namespace flexsens {

// ------------------------------------------------------------------------------ rigid bar
bool RigidBar::mass(const LocalState& s, MatX& M) const {
  const int d = s.dim;
  const double m = s.value(mass_);
  M.setZero(2 * d, 2 * d);
  for (int i = 0; i < d; ++i) {
    M(i, i) = M(d + i, d + i) = m / 3.0;
    M(i, d + i) = M(d + i, i) = m / 6.0;
  }
  return true;
}

void RigidBar::force(const LocalState& s, VecX& Q) const {
  const int d = s.dim;
  const double m = s.value(mass_);
  Q.resize(2 * d);
  Q.head(d) = 0.5 * m * (*s.gravity);
  Q.tail(d) = 0.5 * m * (*s.gravity);
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
struct SpringDamper::Geometry {
  VecX u;       ///< unit vector from a to b
  double l;     ///< current length [m]
  double ldot;  ///< elongation rate [m/s]
  VecX w;       ///< relative velocity v_b - v_a
};

SpringDamper::Geometry SpringDamper::geometry(const LocalState& s) const {
  const int d = s.dim;
  Geometry g;
  const VecX dx = s.x.tail(d) - s.x.head(d);
  g.l = dx.norm();
  if (!(g.l > 1e-12)) {
    std::ostringstream os;
    os << "spring-damper '" << name() << "': its two nodes coincide (length " << g.l
       << " m), so its direction is undefined; check the node positions";
    throw NumericalError(os.str());
  }
  g.u = dx / g.l;
  g.w = s.v.tail(d) - s.v.head(d);
  g.ldot = g.u.dot(g.w);
  return g;
}

void SpringDamper::force(const LocalState& s, VecX& Q) const {
  const int d = s.dim;
  const Geometry g = geometry(s);
  const double f = s.value(k_) * (g.l - s.value(L0_)) + s.value(c_) * g.ldot;  // tension [N]
  Q.resize(2 * d);
  Q.head(d) = f * g.u;
  Q.tail(d) = -f * g.u;
}

void SpringDamper::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  const int d = s.dim;
  const Geometry g = geometry(s);
  const double k = s.value(k_), c = s.value(c_);
  const double f = k * (g.l - s.value(L0_)) + c * g.ldot;
  const MatX P = MatX::Identity(d, d) - g.u * g.u.transpose();
  // G = d(f u)/d(x_b - x_a), Cm = d(f u)/d(v_b - v_a)
  const MatX G = g.u * (k * g.u + c * P * g.w / g.l).transpose() + f * P / g.l;
  const MatX Cm = c * g.u * g.u.transpose();
  dQdq.resize(2 * d, 2 * d);
  dQdq << -G, G, G, -G;
  dQdv.resize(2 * d, 2 * d);
  dQdv << -Cm, Cm, Cm, -Cm;
}

bool SpringDamper::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  const int d = s.dim;
  const Geometry g = geometry(s);
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

}  // namespace flexsens
