#include "elements/ShellPatchMembrane.hpp"

#include "elements/ContinuumKernel.hpp"
#include "elements/KernelElementAD.hpp"

namespace flexsens {

namespace {
using Patch = continuum::Kernel<3, 2, 6>;
[[noreturn]] void throwUndefined(const std::string& name) {
  throw NumericalError("shell patch membrane " + name + ": inverted (det F^T F <= 0): the neo-Hookean law is undefined");
}
}  // namespace

ShellPatchMembrane::ShellPatchMembrane(std::string name, std::vector<int> nodes, std::shared_ptr<ShellProperties> props,
                                       const VecX& restX, const Eigen::Matrix<double, 6, 2>& G, double area)
    : KernelElement(std::move(name), std::move(nodes)), props_(std::move(props)), G_(G), A_(area) {
  if (!props_) throw std::invalid_argument("shell patch membrane " + this->name() + ": no material");
  if (this->nodes().size() != 6 || restX.size() != 18)
    throw std::invalid_argument("shell patch membrane " + this->name() + ": needs 6 nodes in 3D");
  const Patch::Def F0 = Eigen::Map<const Patch::Nodal>(restX.data()) * G_;
  C0_ = F0.transpose() * F0;
}

void ShellPatchMembrane::checkDim(const LocalState& s) const {
  if (s.dim != 3 || s.x.size() != 18)
    throw std::invalid_argument("shell patch membrane " + name() + ": spatial only (dim must be 3)");
}

// props = (E, nu, thickness)
template <class T>
VecT<T> ShellPatchMembrane::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>&, const VecT<T>& props) const {
  checkDim(s);
  const T mu = material::mu(props[0], props[1]), lam = material::lambda(props[0], props[1]);
  MatT<T> F = MatT<T>::Zero(3, 2);
  for (int a = 0; a < 6; ++a) F += x.template segment<3>(3 * a) * G_.row(a).template cast<T>();
  const MatT<T> E = 0.5 * (F.transpose() * F - C0_.cast<T>());
  const MatT<T> S = props_->law.stress<T>(E, mu, lam, "shell patch membrane " + name());
  const MatT<T> P = F * S;
  VecT<T> Q = VecT<T>::Zero(18);
  for (int a = 0; a < 6; ++a) Q.template segment<3>(3 * a) -= (A_ * props[2]) * (P * G_.row(a).transpose().template cast<T>());
  return Q;
}

void ShellPatchMembrane::force(const LocalState& s, VecX& Q) const {
  checkDim(s);
  const VecX& p = *s.p;
  const double mu = material::mu(props_->E.value(p), props_->nu.value(p));
  const double lam = material::lambda(props_->E.value(p), props_->nu.value(p));
  const Patch::Def F = Eigen::Map<const Patch::Nodal>(s.x.data()) * G_;
  material::PointStress<2> ps;  // the law at C = I + 2 E
  if (!material::pointStress<2>(props_->law, F.transpose() * F - C0_ + Eigen::Matrix2d::Identity(), mu, lam, false, ps))
    throwUndefined(name());
  Q.setZero(18);
  Eigen::Map<Patch::Nodal> Qn(Q.data());
  Patch::subtractStressForce(A_ * props_->thickness.value(p), F, ps.S, G_, Qn);
}

void ShellPatchMembrane::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  checkDim(s);
  const VecX& p = *s.p;
  const double mu = material::mu(props_->E.value(p), props_->nu.value(p));
  const double lam = material::lambda(props_->E.value(p), props_->nu.value(p));
  const Patch::Def F = Eigen::Map<const Patch::Nodal>(s.x.data()) * G_;
  material::PointStress<2> ps;
  if (!material::pointStress<2>(props_->law, F.transpose() * F - C0_ + Eigen::Matrix2d::Identity(), mu, lam, true, ps))
    throwUndefined(name());
  dQdq.setZero(18, 18);
  dQdv.setZero(18, 18);
  Eigen::Map<Patch::Tangent> K(dQdq.data());
  Patch::StrainMatrix B, DB;
  Patch::strainMatrix(F, G_, B);
  DB.noalias() = ps.D * B;
  const double At = A_ * props_->thickness.value(p);
  Patch::addMaterial(-At, B, DB, K);
  Patch::addGeometric(-At, G_, ps.S, K);
}

double ShellPatchMembrane::potential(const LocalState& s) const {
  checkDim(s);
  const VecX& p = *s.p;
  const double mu = material::mu(props_->E.value(p), props_->nu.value(p));
  const double lam = material::lambda(props_->E.value(p), props_->nu.value(p));
  const Patch::Def F = Eigen::Map<const Patch::Nodal>(s.x.data()) * G_;
  return A_ * props_->thickness.value(p) *
         material::pointEnergy<2>(props_->law, F.transpose() * F - C0_ + Eigen::Matrix2d::Identity(), mu, lam);
}

template class KernelElement<ShellPatchMembrane>;

}  // namespace flexsens
