#include "elements/PlanarFollowerForce.hpp"

#include <stdexcept>

namespace flexsens {

PlanarFollowerForce::PlanarFollowerForce(std::string name, int p, int a, int b, const VecX& d0,
                                         std::vector<Quantity> F0, std::unique_ptr<TimeFunction> f)
    : Element(std::move(name), {p, a, b}), d0_(d0.head<2>()), F0_(std::move(F0)), f_(std::move(f)) {
  if (F0_.size() != 2 || !(d0_.norm() > 0))
    throw std::invalid_argument("follower force '" + this->name() + "': planar, with A and B apart");
}

VecX PlanarFollowerForce::forceFor(const LocalState& s, const Eigen::Vector2d& c, double fac) const {
  const Eigen::Vector2d Rd0(-d0_[1], d0_[0]);
  const double alpha = c.dot(d0_) / d0_.squaredNorm(), beta = c.dot(Rd0) / d0_.squaredNorm();
  const Eigen::Vector2d d = s.x.segment<2>(4) - s.x.segment<2>(2), Rd(-d[1], d[0]);
  VecX Q = VecX::Zero(6);
  Q.head<2>() = fac * (alpha * d + beta * Rd);
  return Q;
}

void PlanarFollowerForce::force(const LocalState& s, VecX& Q) const {
  if (s.dim != 2) throw std::invalid_argument("follower force '" + name() + "' needs a planar model");
  Q = forceFor(s, Eigen::Vector2d(s.value(F0_[0]), s.value(F0_[1])), factor(s));
}

void PlanarFollowerForce::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  const Eigen::Vector2d c(s.value(F0_[0]), s.value(F0_[1])), Rd0(-d0_[1], d0_[0]);
  const double alpha = c.dot(d0_) / d0_.squaredNorm(), beta = c.dot(Rd0) / d0_.squaredNorm();
  Eigen::Matrix2d K;
  K << alpha, -beta, beta, alpha;  // alpha I + beta R
  K *= factor(s);
  dQdq.setZero(6, 6);
  dQdq.block<2, 2>(0, 2) = -K;
  dQdq.block<2, 2>(0, 4) = K;
  dQdv.setZero(6, 6);
}

bool PlanarFollowerForce::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  TimeValue d;
  const bool fn = f_ && f_->parameterDerivative(s.t, *s.p, k, d);
  const bool comp = F0_[0].boundTo(k) || F0_[1].boundTo(k);
  if (!fn && !comp) return false;
  dQ = VecX::Zero(6);
  // Q is linear in F0 and in f: d/dF0_c gives the unit vector's image, d/dp of f the rest.
  const Eigen::Vector2d unit(F0_[0].boundTo(k) ? 1.0 : 0.0, F0_[1].boundTo(k) ? 1.0 : 0.0);
  if (comp) dQ += forceFor(s, unit, factor(s));
  if (fn) dQ += forceFor(s, Eigen::Vector2d(s.value(F0_[0]), s.value(F0_[1])), d.f);
  dM.setZero(6, 6);  // massless
  return true;
}

std::vector<std::pair<std::string, Quantity*>> PlanarFollowerForce::properties() {
  std::vector<std::pair<std::string, Quantity*>> r{{"x", &F0_[0]}, {"y", &F0_[1]}};
  if (f_)
    for (auto& pr : f_->properties()) r.push_back(pr);
  return r;
}

}  // namespace flexsens
