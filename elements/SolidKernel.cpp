// The fixed-size force, force Jacobian, parameter derivative and potential of the continuum elements (elements/Solid.hpp),
// one instance per simplex: stack matrices of the element's size, the material's C, C^-1 and
// det C once per quadrature point (elements/MaterialPoint.hpp), the tangent as B^T D B plus
// the geometric term (elements/ContinuumKernel.hpp). No heap allocation once the outputs have
// their size (the assembler keeps them from call to call). The value template forceT stays
// the reference: the AD Jacobians and the tests (tests/test_solid.cpp) differentiate it.
#include <string>

#include "elements/ContinuumKernel.hpp"
#include "elements/Solid.hpp"

namespace flexsens {

Solid::Coefficients Solid::coefficients(const VecX& p) const {
  Coefficients c;
  const double E0 = props_->E.value(p), nu = props_->nu.value(p);
  c.mu = material::mu(E0, nu);
  c.lam = material::lambda(E0, nu);
  c.lamV = lambdaRest(c.mu, c.lam);
  c.t = props_->thickness.value(p);
  c.rt = props_->density.value(p) * c.t;
  c.alpha = props_->alpha.value(p);
  c.beta = props_->beta.value(p);
  return c;
}

void Solid::checkState(const LocalState& s) const {
  if (s.dim != dim_ || s.x.size() != dim_ * n_)
    throw std::invalid_argument("solid element " + name() + ": needs positions of dimension " + std::to_string(dim_));
}

namespace {
[[noreturn]] void throwUndefinedLaw(const std::string& name) {
  throw NumericalError("solid element " + name + ": inverted (det F <= 0): the neo-Hookean law is undefined");
}
}  // namespace

// Q = M G - alpha M v - sum_points w t F S G^T (Solid.hpp), M = rho t massShape (x) I.
template <int D, int N>
void Solid::forceFixed(const LocalState& s, VecX& Q) const {
  using K = continuum::Kernel<D, D, N>;
  checkState(s);
  const Coefficients c = coefficients(*s.p);
  const bool hasV = s.v.size() == s.x.size();
  const Eigen::Map<const typename K::Nodal> X(s.x.data());
  const Eigen::Map<const Eigen::Matrix<double, N, N>> M(massShape_.data());
  Q.resize(K::ND);
  Eigen::Map<typename K::Nodal> Qn(Q.data());
  Qn.setZero();
  if (s.gravity) Qn.noalias() += Eigen::Matrix<double, D, 1>(c.rt * *s.gravity) * M.colwise().sum();
  if (hasV && c.alpha != 0.0) Qn.noalias() -= (c.alpha * c.rt) * Eigen::Map<const typename K::Nodal>(s.v.data()) * M;
  material::PointStress<D> ps;
  for (const Point& P : pts_) {
    const Eigen::Map<const typename K::Grad> G(P.G.data());
    const typename K::Def F = X * G;
    checkOrientation(F.determinant());
    if (!material::pointStress<D>(props_->law, F.transpose() * F, c.mu, c.lam, false, ps)) throwUndefinedLaw(name());
    if (hasV && c.beta != 0.0) {
      const typename K::Def Fd = Eigen::Map<const typename K::Nodal>(s.v.data()) * G;
      ps.S += c.beta * material::restElasticity<D>(c.mu, c.lamV, K::strainRate(F, Fd));
    }
    K::subtractStressForce(P.w * c.t, F, ps.S, G, Qn);
  }
}

// dQ/dq = -sum w t (B^T (D B + beta D0 Bd) + (G S G^T) (x) I), S with its Kelvin-Voigt part;
// dQ/dv = -alpha M - sum w t beta B^T D0 B (D0 the rest elasticity, Bd = B of Fd).
template <int D, int N>
void Solid::forceJacobianFixed(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  using K = continuum::Kernel<D, D, N>;
  checkState(s);
  const Coefficients c = coefficients(*s.p);
  const bool hasV = s.v.size() == s.x.size();
  const Eigen::Map<const typename K::Nodal> X(s.x.data());
  dQdq.resize(K::ND, K::ND);
  dQdv.resize(K::ND, K::ND);
  Eigen::Map<typename K::Tangent> Kq(dQdq.data()), Kv(dQdv.data());
  Kq.setZero();
  Kv.setZero();
  if (c.alpha != 0.0)
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < N; ++i)
        for (int a = 0; a < D; ++a) Kv(D * i + a, D * j + a) = -c.alpha * c.rt * massShape_(i, j);
  const material::VoigtMatrix<D> D0 = material::isotropicTangent<D>(material::Sym<D>::Identity(), 2.0 * c.mu, c.lamV);
  material::PointStress<D> ps;
  typename K::StrainMatrix B, DB, Bd;
  for (const Point& P : pts_) {
    const Eigen::Map<const typename K::Grad> G(P.G.data());
    const typename K::Def F = X * G;
    const double wt = P.w * c.t;
    checkOrientation(F.determinant());
    if (!material::pointStress<D>(props_->law, F.transpose() * F, c.mu, c.lam, true, ps)) throwUndefinedLaw(name());
    K::strainMatrix(F, G, B);
    DB.noalias() = ps.D * B;
    if (c.beta != 0.0) {
      const typename K::StrainMatrix D0B = (c.beta * D0) * B;
      K::addMaterial(-wt, B, D0B, Kv);
      if (hasV) {
        const typename K::Def Fd = Eigen::Map<const typename K::Nodal>(s.v.data()) * G;
        ps.S += c.beta * material::restElasticity<D>(c.mu, c.lamV, K::strainRate(F, Fd));
        K::strainMatrix(Fd, G, Bd);
        DB.noalias() += (c.beta * D0) * Bd;
      }
    }
    K::addMaterial(-wt, B, DB, Kq);
    K::addGeometric(-wt, G, ps.S, Kq);
  }
}

// dQ/dp_k at fixed q, v: the chain rule through rho t (gravity, mass damping), alpha, and the
// stress t F S with S(mu, lambda) + beta C0(mu, lambda0) : Edot (sums when several properties
// are bound to the same parameter).
template <int D, int N>
void Solid::parameterDerivativeFixed(const LocalState& s, int k, VecX& dQ) const {
  using K = continuum::Kernel<D, D, N>;
  checkState(s);
  const VecX& p = *s.p;
  const Coefficients c = coefficients(p);
  const double dT = props_->thickness.boundTo(k), dAlpha = props_->alpha.boundTo(k), dBeta = props_->beta.boundTo(k);
  const double rho = props_->density.value(p), drt = props_->density.boundTo(k) * c.t + rho * dT;
  const material::LameDerivative dl = material::lameDerivative(
      props_->E.value(p), props_->nu.value(p), props_->E.boundTo(k), props_->nu.boundTo(k), props_->law.planeStress());
  const bool hasV = s.v.size() == s.x.size();
  const Eigen::Map<const typename K::Nodal> X(s.x.data()), V(s.v.data());  // V read only when hasV
  const Eigen::Map<const Eigen::Matrix<double, N, N>> M(massShape_.data());
  dQ.resize(K::ND);
  Eigen::Map<typename K::Nodal> Qn(dQ.data());
  Qn.setZero();
  if (s.gravity) Qn.noalias() += Eigen::Matrix<double, D, 1>(drt * *s.gravity) * M.colwise().sum();
  if (hasV) Qn.noalias() -= (drt * c.alpha + rho * c.t * dAlpha) * V * M;
  material::PointStress<D> ps;
  for (const Point& P : pts_) {
    const Eigen::Map<const typename K::Grad> G(P.G.data());
    const typename K::Def F = X * G;
    checkOrientation(F.determinant());
    const material::Sym<D> C = F.transpose() * F;
    if (!material::pointStress<D>(props_->law, C, c.mu, c.lam, false, ps)) throwUndefinedLaw(name());
    const material::Sym<D> Ed = hasV ? K::strainRate(F, V * G) : material::Sym<D>::Zero();
    const material::Sym<D> S = ps.S + c.beta * material::restElasticity<D>(c.mu, c.lamV, Ed);
    const material::Sym<D> dS = material::stressParameterDerivative<D>(props_->law, C, c.mu, c.lam, dl.mu, dl.lam) +
                                dBeta * material::restElasticity<D>(c.mu, c.lamV, Ed) +
                                c.beta * material::restElasticity<D>(dl.mu, dl.lam0, Ed);
    K::subtractStressForce(P.w, F, dT * S + c.t * dS, G, Qn);  // d(t F S)
  }
}

bool Solid::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  const double dRho = props_->density.boundTo(k), dT = props_->thickness.boundTo(k);
  if (!(props_->E.boundTo(k) || props_->nu.boundTo(k) || dRho || dT || props_->alpha.boundTo(k) ||
        props_->beta.boundTo(k)))
    return false;
  switch (shape_) {
    case Simplex::Tri3: parameterDerivativeFixed<2, 3>(s, k, dQ); break;
    case Simplex::Tri6: parameterDerivativeFixed<2, 6>(s, k, dQ); break;
    case Simplex::Tet4: parameterDerivativeFixed<3, 4>(s, k, dQ); break;
    case Simplex::Tet10: parameterDerivativeFixed<3, 10>(s, k, dQ); break;
  }
  const VecX& p = *s.p;
  const double drt = dRho * props_->thickness.value(p) + props_->density.value(p) * dT;
  const int d = dim_;
  dM.setZero(n_ * d, n_ * d);
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j)
      for (int c = 0; c < d; ++c) dM(i * d + c, j * d + c) = drt * massShape_(i, j);
  return true;
}

// U = sum_points w t W(C) - G^T M x [J].
template <int D, int N>
double Solid::potentialFixed(const LocalState& s) const {
  using K = continuum::Kernel<D, D, N>;
  checkState(s);
  const Coefficients c = coefficients(*s.p);
  const Eigen::Map<const typename K::Nodal> X(s.x.data());
  double U = 0.0;
  for (const Point& P : pts_) {
    const typename K::Def F = X * Eigen::Map<const typename K::Grad>(P.G.data());
    checkOrientation(F.determinant());
    U += P.w * c.t * material::pointEnergy<D>(props_->law, F.transpose() * F, c.mu, c.lam);
  }
  if (s.gravity) {  // minus the work of gravity
    const Eigen::Map<const Eigen::Matrix<double, N, N>> M(massShape_.data());
    U -= c.rt * (Eigen::Matrix<double, D, 1>(*s.gravity).transpose() * X * M).sum();
  }
  return U;
}

double Solid::potential(const LocalState& s) const {
  switch (shape_) {
    case Simplex::Tri3: return potentialFixed<2, 3>(s);
    case Simplex::Tri6: return potentialFixed<2, 6>(s);
    case Simplex::Tet4: return potentialFixed<3, 4>(s);
    case Simplex::Tet10: return potentialFixed<3, 10>(s);
  }
  return 0.0;
}

void Solid::force(const LocalState& s, VecX& Q) const {
  switch (shape_) {
    case Simplex::Tri3: return forceFixed<2, 3>(s, Q);
    case Simplex::Tri6: return forceFixed<2, 6>(s, Q);
    case Simplex::Tet4: return forceFixed<3, 4>(s, Q);
    case Simplex::Tet10: return forceFixed<3, 10>(s, Q);
  }
}

void Solid::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  switch (shape_) {
    case Simplex::Tri3: return forceJacobianFixed<2, 3>(s, dQdq, dQdv);
    case Simplex::Tri6: return forceJacobianFixed<2, 6>(s, dQdq, dQdv);
    case Simplex::Tet4: return forceJacobianFixed<3, 4>(s, dQdq, dQdv);
    case Simplex::Tet10: return forceJacobianFixed<3, 10>(s, dQdq, dQdv);
  }
}

}  // namespace flexsens
