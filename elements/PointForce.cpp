#include "elements/PointForce.hpp"

#include <sstream>
#include <stdexcept>

#include "elements/KernelElementAD.hpp"

namespace flexsens {

PointForce::PointForce(std::string name, int node, std::vector<Quantity> components,
                       std::unique_ptr<TimeFunction> f)
    : KernelElement(std::move(name), {node}), F_(std::move(components)), f_(std::move(f)) {
  if (F_.size() != 2 && F_.size() != 3) {
    std::ostringstream os;
    os << "point force '" << this->name() << "': expected 2 (planar) or 3 (spatial) components, got "
       << F_.size();
    throw std::invalid_argument(os.str());
  }
}

void PointForce::checkDim(const LocalState& s) const {
  if (s.dim != components()) {
    std::ostringstream os;
    os << "point force '" << name() << "' has " << components() << " components but the model has "
       << s.dim << " coordinates per node";
    throw std::invalid_argument(os.str());
  }
}

std::vector<const Quantity*> PointForce::kernelProperties() const {
  std::vector<const Quantity*> r;
  for (const auto& f : F_) r.push_back(&f);
  return r;
}

// Value template: props = the components (F_x, F_y(, F_z)).
template <class T>
VecT<T> PointForce::forceT(const LocalState& s, const VecT<T>&, const VecT<T>&,
                           const VecT<T>& props) const {
  checkDim(s);
  VecT<T> Q(s.dim);
  const double f = factor(s);
  for (int c = 0; c < s.dim; ++c) Q[c] = props[c] * f;
  return Q;
}

bool PointForce::parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  checkDim(s);  // also when no component is bound to k
  // AD through the components; the time function's constants (F df/dp_k) are analytic.
  const bool comp = KernelElement::parameterDerivativeAD(s, k, dQ, dM);
  TimeValue d;
  if (!f_ || !f_->parameterDerivative(s.t, *s.p, k, d)) return comp;
  if (!comp) dQ.setZero(s.dim);
  for (int c = 0; c < s.dim; ++c) dQ[c] += s.value(F_[c]) * d.f;
  dM.resize(0, 0);  // massless
  return true;
}

void PointForce::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  checkDim(s);
  dQdq.setZero(s.dim, s.dim);
  dQdv.setZero(s.dim, s.dim);
}

bool PointForce::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  checkDim(s);
  bool dep = false;
  for (const auto& f : F_) dep = dep || f.boundTo(k);
  TimeValue d;
  const bool fn = f_ && f_->parameterDerivative(s.t, *s.p, k, d);
  if (!dep && !fn) return false;
  // Q = F f(t) is linear in its components: dQ/dp_k = f (units bound to k) + F df/dp_k.
  dQ.setZero(s.dim);
  const double f = factor(s);
  for (int c = 0; c < s.dim; ++c) {
    if (F_[c].boundTo(k)) dQ[c] = f;
    if (fn) dQ[c] += s.value(F_[c]) * d.f;
  }
  dM.setZero(s.dim, s.dim);  // massless
  return true;
}

double PointForce::potential(const LocalState& s) const {
  checkDim(s);
  if (f_) return 0.0;  // varying in time: no potential (external work)
  double U = 0.0;
  for (int c = 0; c < s.dim; ++c) U -= s.value(F_[c]) * s.x[c];
  return U;  // [J]
}

std::vector<std::pair<std::string, Quantity*>> PointForce::properties() {
  static const char* names[] = {"x", "y", "z"};
  std::vector<std::pair<std::string, Quantity*>> r;
  for (size_t c = 0; c < F_.size(); ++c) r.emplace_back(names[c], &F_[c]);
  if (f_)
    for (auto& pr : f_->properties()) r.push_back(pr);
  return r;
}

template class KernelElement<PointForce>;

}  // namespace flexsens
