#include "elements/PointForce.hpp"

#include <sstream>
#include <stdexcept>

namespace flexsens {

PointForce::PointForce(std::string name, int node, std::vector<Quantity> components)
    : Element(std::move(name), {node}), F_(std::move(components)) {
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

void PointForce::force(const LocalState& s, VecX& Q) const {
  checkDim(s);
  Q.resize(s.dim);
  for (int c = 0; c < s.dim; ++c) Q[c] = s.value(F_[c]);
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

}  // namespace flexsens
