#include "elements/PointForce.hpp"

#include <sstream>
#include <stdexcept>

#include "elements/KernelElementAD.hpp"

namespace flexsens {

PointForce::PointForce(std::string name, int node, std::vector<Quantity> components)
    : KernelElement(std::move(name), {node}), F_(std::move(components)) {
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
  for (int c = 0; c < s.dim; ++c) Q[c] = props[c];
  return Q;
}

bool PointForce::parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  checkDim(s);  // also when no component is bound to k
  return KernelElement::parameterDerivativeAD(s, k, dQ, dM);
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
  if (!dep) return false;
  // Q is linear in its components: dQ/dp_k is the sum of the unit vectors bound to k.
  dQ.setZero(s.dim);
  for (int c = 0; c < s.dim; ++c)
    if (F_[c].boundTo(k)) dQ[c] = 1.0;
  dM.setZero(s.dim, s.dim);  // massless
  return true;
}

double PointForce::potential(const LocalState& s) const {
  checkDim(s);
  double U = 0.0;
  for (int c = 0; c < s.dim; ++c) U -= s.value(F_[c]) * s.x[c];
  return U;  // [J]
}

std::vector<std::pair<std::string, Quantity*>> PointForce::properties() {
  static const char* names[] = {"x", "y", "z"};
  std::vector<std::pair<std::string, Quantity*>> r;
  for (size_t c = 0; c < F_.size(); ++c) r.emplace_back(names[c], &F_[c]);
  return r;
}

template class KernelElement<PointForce>;

}  // namespace flexsens
