#include "elements/ShellTriangle.hpp"

#include <cmath>

#include "elements/ContinuumKernel.hpp"
#include "elements/KernelElementAD.hpp"
#include "elements/StressDerivative.hpp"
#include "elements/SimplexShape.hpp"  // fmtNumber

namespace flexsens {

namespace {
/// The rest (small-strain) plane-stress elasticity applied to a symmetric A:
/// C0 : A = lambda* tr(A) I + 2 mu A [Pa], lambda* = 2 lambda mu / (lambda + 2 mu).
template <class T> MatT<T> elasticity0(const T& mu, const T& lamStar, const MatT<T>& A) {
  return (lamStar * A.trace()) * MatT<T>::Identity(A.rows(), A.cols()) + (2.0 * mu) * A;
}
/// Consistent mass pattern of a linear triangle per unit rho t A: (1 + delta_ij) / 12.
double massShape(int i, int j) { return (i == j ? 2.0 : 1.0) / 12.0; }
}  // namespace

ShellTriangle::ShellTriangle(std::string name, std::vector<int> nodes, std::shared_ptr<ShellProperties> props,
                             const VecX& restX)
    : KernelElement(std::move(name), std::move(nodes)), props_(std::move(props)) {
  const std::string who = "shell triangle " + this->name();
  if (!props_) throw std::invalid_argument(who + ": no material");
  if (this->nodes().size() != 3 || restX.size() != 9) throw std::invalid_argument(who + ": needs 3 nodes in 3D");
  const Eigen::Vector3d X0 = restX.segment<3>(0), e1 = restX.segment<3>(3) - X0, e2 = restX.segment<3>(6) - X0;
  const Eigen::Vector3d n = e1.cross(e2);
  const double h = std::max({e1.norm(), e2.norm(), (e2 - e1).norm()});
  A_ = 0.5 * n.norm();
  if (!(A_ > 1e-10 * h * h))
    throw std::invalid_argument(who + ": degenerate (rest area " + fmtNumber(A_) + " m^2 for a longest edge of " +
                                fmtNumber(h) + " m; expected a positive area)");
  const Eigen::Vector3d t1 = e1.normalized(), t2 = n.normalized().cross(t1);
  Eigen::Matrix2d Dm;
  Dm << e1.dot(t1), e2.dot(t1), e1.dot(t2), e2.dot(t2);
  const Eigen::Matrix2d Di = Dm.inverse();
  G_.resize(3, 2);
  G_.row(1) = Di.row(0);
  G_.row(2) = Di.row(1);
  G_.row(0) = -(Di.row(0) + Di.row(1));
  basis_.resize(3, 2);
  basis_ << t1, t2;
}

void ShellTriangle::checkDim(const LocalState& s) const {
  if (s.dim != 3 || s.x.size() != 9) throw std::invalid_argument("shell triangle " + name() + ": spatial only (dim must be 3)");
}

template <class T>
void ShellTriangle::membraneStressT(const VecT<T>& x, const T& E0, const T& nu, MatT<T>& E, MatT<T>& S,
                                    MatT<T>& sigma, MatT<T>& dev) const {
  using std::sqrt;
  const T mu = material::mu(E0, nu), lam = material::lambda(E0, nu);
  MatT<T> F = MatT<T>::Zero(3, 2);
  for (int i = 0; i < 3; ++i) F += x.template segment<3>(3 * i) * G_.row(i).template cast<T>();
  const MatT<T> C = F.transpose() * F, I = MatT<T>::Identity(2, 2);
  const MatT<T> E2 = 0.5 * (C - I), S2 = props_->law.stress<T>(E2, mu, lam, "shell triangle " + name());
  const MatT<T> B = basis_.template cast<T>();
  E = B * E2 * B.transpose();
  S = B * S2 * B.transpose();
  const T J = sqrt(C(0, 0) * C(1, 1) - C(0, 1) * C(1, 0));  // area ratio
  sigma = F * S2 * F.transpose() / J;
  dev = sigma - (sigma.trace() / 3.0) * MatT<T>::Identity(3, 3);
}

void ShellTriangle::membraneStress(const LocalState& s, MatX& E, MatX& S, MatX& sigma, double& vonMises) const {
  checkDim(s);
  const VecX& p = *s.p;
  MatX dev;
  membraneStressT<double>(s.x, props_->E.value(p), props_->nu.value(p), E, S, sigma, dev);
  vonMises = std::sqrt(1.5 * (dev.array() * dev.array()).sum());
}

void ShellTriangle::membraneStressDerivative(const LocalState& s, const VecX& dx, int k, MatX& dE, MatX& dS,
                                             MatX& dsigma, double& dVonMises) const {
  checkDim(s);
  const VecX& p = *s.p;
  stressad::directionalDerivative(
      s.x.head(9), dx, props_->E.value(p), props_->E.boundTo(k) ? 1.0 : 0.0, props_->nu.value(p),
      props_->nu.boundTo(k) ? 1.0 : 0.0,
      [this](const auto& x, const auto& E0, const auto& nu, auto& E, auto& S, auto& sigma, auto& dev) {
        membraneStressT<stressad::AD1>(x, E0, nu, E, S, sigma, dev);
      },
      dE, dS, dsigma, dVonMises);
}

// ------------------------------------------------------------------ value templates
// props = (E, nu, density, thickness, alpha, beta).
template <class T>
MatT<T> ShellTriangle::massT(const LocalState&, const VecT<T>& props) const {
  const T m = props[2] * props[3] * A_;  // rho t A [kg]
  MatT<T> M = MatT<T>::Zero(9, 9);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int c = 0; c < 3; ++c) M(3 * i + c, 3 * j + c) = m * massShape(i, j);
  return M;
}

template <class T>
VecT<T> ShellTriangle::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const {
  checkDim(s);
  const T mu = material::mu(props[0], props[1]), lam = material::lambda(props[0], props[1]);
  const T t = props[3], m = props[2] * props[3] * A_, alpha = props[4], beta = props[5];
  const T lamStar = material::planeStressLambda(mu, lam);
  const bool hasV = v.size() == x.size();
  VecT<T> Q = VecT<T>::Zero(9);
  for (int i = 0; i < 3; ++i) {
    if (s.gravity) Q.template segment<3>(3 * i) += (m / 3.0) * s.gravity->template cast<T>();
    if (hasV)
      for (int j = 0; j < 3; ++j) Q.template segment<3>(3 * i) -= (alpha * m * massShape(i, j)) * v.template segment<3>(3 * j);
  }
  if (!membrane_) return Q;
  MatT<T> F = MatT<T>::Zero(3, 2);
  for (int i = 0; i < 3; ++i) F += x.template segment<3>(3 * i) * G_.row(i).template cast<T>();
  const MatT<T> E = 0.5 * (F.transpose() * F - MatT<T>::Identity(2, 2));
  MatT<T> S = props_->law.stress<T>(E, mu, lam, "shell triangle " + name());
  if (hasV) {  // Kelvin-Voigt: beta C0 : dE/dt
    MatT<T> Fd = MatT<T>::Zero(3, 2);
    for (int i = 0; i < 3; ++i) Fd += v.template segment<3>(3 * i) * G_.row(i).template cast<T>();
    const MatT<T> B = F.transpose() * Fd;
    S += beta * elasticity0<T>(mu, lamStar, 0.5 * (B + B.transpose()));
  }
  const MatT<T> P = F * S;
  for (int i = 0; i < 3; ++i) Q.template segment<3>(3 * i) -= (A_ * t) * (P * G_.row(i).transpose().template cast<T>());
  return Q;
}

// ------------------------------------------------------------------ fixed-size kernels
// Stack matrices (elements/ContinuumKernel.hpp with 3 coordinates on the 2D rest plane), the
// law's C^-1 and c once (elements/MaterialPoint.hpp), no heap once the outputs have their size.
namespace {
using Membrane = continuum::Kernel<3, 2, 3>;
[[noreturn]] void throwUndefinedLaw(const std::string& name) {
  throw NumericalError("shell triangle " + name + ": inverted (det F <= 0): the neo-Hookean law is undefined");
}
}  // namespace

ShellTriangle::Coefficients ShellTriangle::coefficients(const VecX& p) const {
  Coefficients c;
  const double E0 = props_->E.value(p), nu = props_->nu.value(p);
  c.mu = material::mu(E0, nu);
  c.lam = material::lambda(E0, nu);
  c.lamStar = material::planeStressLambda(c.mu, c.lam);
  c.t = props_->thickness.value(p);
  c.m = props_->density.value(p) * c.t * A_;
  c.alpha = props_->alpha.value(p);
  c.beta = props_->beta.value(p);
  return c;
}

// Q_i = m/3 g - alpha m sum_j (1 + delta_ij)/12 v_j - A t (F S) G_i (ShellTriangle.hpp).
void ShellTriangle::force(const LocalState& s, VecX& Q) const {
  checkDim(s);
  const Coefficients c = coefficients(*s.p);
  const bool hasV = s.v.size() == s.x.size();
  Q.resize(9);
  Eigen::Map<Membrane::Nodal> Qn(Q.data());
  Qn.setZero();
  if (s.gravity) Qn.colwise() += Eigen::Vector3d((c.m / 3.0) * *s.gravity);
  const Eigen::Map<const Membrane::Nodal> V(s.v.data());  // read only when hasV
  if (hasV && c.alpha != 0.0)  // sum_j (1 + delta_ij)/12 v_j = (v_i + sum_j v_j) / 12
    Qn -= (c.alpha * c.m / 12.0) * (V.colwise() + V.rowwise().sum());
  if (!membrane_) return;
  const Eigen::Map<const Membrane::Grad> G(G_.data());
  const Membrane::Def F = Eigen::Map<const Membrane::Nodal>(s.x.data()) * G;
  material::PointStress<2> ps;
  if (!material::pointStress<2>(props_->law, F.transpose() * F, c.mu, c.lam, false, ps)) throwUndefinedLaw(name());
  if (hasV && c.beta != 0.0)  // Kelvin-Voigt: beta C0 : dE/dt
    ps.S += c.beta * material::restElasticity<2>(c.mu, c.lamStar, Membrane::strainRate(F, V * G));
  Membrane::subtractStressForce(A_ * c.t, F, ps.S, G, Qn);
}

// dQ/dq = -A t (B^T (D B + beta D0 Bd) + (G S G^T) (x) I), dQ/dv = -alpha M - A t beta B^T D0 B.
void ShellTriangle::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  checkDim(s);
  const Coefficients c = coefficients(*s.p);
  const bool hasV = s.v.size() == s.x.size();
  dQdq.resize(9, 9);
  dQdv.resize(9, 9);
  Eigen::Map<Membrane::Tangent> Kq(dQdq.data()), Kv(dQdv.data());
  Kq.setZero();
  Kv.setZero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Kv.block<3, 3>(3 * i, 3 * j).diagonal().setConstant(-c.alpha * c.m * massShape(i, j));
  if (!membrane_) return;
  const Eigen::Map<const Membrane::Grad> G(G_.data());
  const Membrane::Def F = Eigen::Map<const Membrane::Nodal>(s.x.data()) * G;
  const double At = A_ * c.t;
  material::PointStress<2> ps;
  if (!material::pointStress<2>(props_->law, F.transpose() * F, c.mu, c.lam, true, ps)) throwUndefinedLaw(name());
  Membrane::StrainMatrix B, DB, Bd;
  Membrane::strainMatrix(F, G, B);
  DB.noalias() = ps.D * B;
  if (c.beta != 0.0) {
    const material::VoigtMatrix<2> bD0 = material::isotropicTangent<2>(Eigen::Matrix2d::Identity(), 2.0 * c.beta * c.mu,
                                                                       c.beta * c.lamStar);
    const Membrane::StrainMatrix D0B = bD0 * B;
    Membrane::addMaterial(-At, B, D0B, Kv);
    if (hasV) {
      const Membrane::Def Fd = Eigen::Map<const Membrane::Nodal>(s.v.data()) * G;
      ps.S += c.beta * material::restElasticity<2>(c.mu, c.lamStar, Membrane::strainRate(F, Fd));
      Membrane::strainMatrix(Fd, G, Bd);
      DB.noalias() += bD0 * Bd;
    }
  }
  Membrane::addMaterial(-At, B, DB, Kq);
  Membrane::addGeometric(-At, G, ps.S, Kq);
}

// dQ/dp_k at fixed q, v: the chain rule through m = rho t A (gravity, mass damping), alpha, and
// the stress t F S, S = S(mu, lambda) + beta C0(mu, lambda*) : Edot.
bool ShellTriangle::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  const double dRho = props_->density.boundTo(k), dT = props_->thickness.boundTo(k), dAlpha = props_->alpha.boundTo(k),
               dBeta = props_->beta.boundTo(k);
  if (!(props_->E.boundTo(k) || props_->nu.boundTo(k) || dRho || dT || dAlpha || dBeta)) return false;
  checkDim(s);
  const VecX& p = *s.p;
  const Coefficients c = coefficients(p);
  const double rho = props_->density.value(p), dm = (dRho * c.t + rho * dT) * A_;  // d(rho t A) [kg]
  const material::LameDerivative dl =
      material::lameDerivative(props_->E.value(p), props_->nu.value(p), props_->E.boundTo(k), props_->nu.boundTo(k), true);
  const bool hasV = s.v.size() == s.x.size();
  const Eigen::Map<const Membrane::Nodal> V(s.v.data());  // read only when hasV
  dQ.resize(9);
  Eigen::Map<Membrane::Nodal> Qn(dQ.data());
  Qn.setZero();
  if (s.gravity) Qn.colwise() += Eigen::Vector3d((dm / 3.0) * *s.gravity);
  if (hasV)  // sum_j (1 + delta_ij)/12 v_j = (v_i + sum_j v_j) / 12
    Qn -= ((dAlpha * c.m + c.alpha * dm) / 12.0) * (V.colwise() + V.rowwise().sum());
  dM.setZero(9, 9);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) dM.block<3, 3>(3 * i, 3 * j).diagonal().setConstant(dm * massShape(i, j));
  if (!membrane_) return true;
  const Eigen::Map<const Membrane::Grad> G(G_.data());
  const Membrane::Def F = Eigen::Map<const Membrane::Nodal>(s.x.data()) * G;
  const Eigen::Matrix2d C = F.transpose() * F;
  material::PointStress<2> ps;
  if (!material::pointStress<2>(props_->law, C, c.mu, c.lam, false, ps)) throwUndefinedLaw(name());
  const Eigen::Matrix2d Ed = hasV ? Membrane::strainRate(F, V * G) : Eigen::Matrix2d::Zero();
  const Eigen::Matrix2d S = ps.S + c.beta * material::restElasticity<2>(c.mu, c.lamStar, Ed);
  const Eigen::Matrix2d dS = material::stressParameterDerivative<2>(props_->law, C, c.mu, c.lam, dl.mu, dl.lam) +
                             dBeta * material::restElasticity<2>(c.mu, c.lamStar, Ed) +
                             c.beta * material::restElasticity<2>(dl.mu, dl.lam0, Ed);
  Membrane::subtractStressForce(A_, F, dT * S + c.t * dS, G, Qn);  // d(t F S)
  return true;
}

double ShellTriangle::potential(const LocalState& s) const {
  checkDim(s);
  const Coefficients c = coefficients(*s.p);
  const Membrane::Nodal X = Eigen::Map<const Membrane::Nodal>(s.x.data());
  const Membrane::Def F = X * Eigen::Map<const Membrane::Grad>(G_.data());
  double U = membrane_ ? A_ * c.t * material::pointEnergy<2>(props_->law, F.transpose() * F, c.mu, c.lam) : 0.0;
  if (s.gravity) U -= (c.m / 3.0) * (Eigen::Vector3d(*s.gravity).transpose() * X).sum();  // minus gravity's work [J]
  return U;
}

template class KernelElement<ShellTriangle>;

}  // namespace flexsens
