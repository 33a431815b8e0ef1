#include "elements/Solid.hpp"

#include <cmath>

#include "elements/KernelElementAD.hpp"
#include "elements/StressDerivative.hpp"

namespace flexsens {

std::vector<std::pair<std::string, Quantity*>> SolidProperties::properties() {
  std::vector<std::pair<std::string, Quantity*>> p{{"E", &E}, {"nu", &nu}, {"density", &density}};
  if (dim == 2) p.push_back({"thickness", &thickness});
  p.push_back({"alpha", &alpha});
  p.push_back({"beta", &beta});
  return p;
}

namespace {
/// The reference Jacobian dX/dxi (dim x dim) at a point with shape gradients dN (nodes x dim).
MatX restJacobian(const MatX& restX, const MatX& dN) { return restX * dN; }
}  // namespace

Solid::Solid(std::string name, std::vector<int> nodes, std::shared_ptr<SolidProperties> props, Simplex shape,
             const MatX& restX)
    : KernelElement(std::move(name), std::move(nodes)), props_(std::move(props)), shape_(shape) {
  const std::string who = "solid element " + this->name();
  dim_ = simplexDim(shape);
  n_ = simplexNodes(shape);
  if (!props_) throw std::invalid_argument(who + ": no material");
  if (static_cast<int>(this->nodes().size()) != n_ || restX.rows() != dim_ || restX.cols() != n_)
    throw std::invalid_argument(who + ": a " + simplexName(shape) + " needs " + std::to_string(n_) + " nodes of dimension " +
                                std::to_string(dim_));
  // Scale of the element for the degeneracy test: det J0 against (longest corner edge)^dim.
  double h = 0.0;
  for (int a = 0; a <= dim_; ++a)
    for (int b = a + 1; b <= dim_; ++b) h = std::max(h, (restX.col(a) - restX.col(b)).norm());
  const double tol = 1e-10 * std::pow(h, dim_);
  VecX N;
  MatX dN;
  auto check = [&](const VecX& xi, double detJ) {
    if (!(detJ > tol)) {
      const VecX X = restX * N;
      throw std::invalid_argument(who + ": " + (detJ < -tol ? "inverted" : "degenerate") +
                                  " (det dX/dxi = " + fmtNumber(detJ) + " at rest point (" +
                                  fmtNumber(X[0]) + ", " + fmtNumber(X[1]) +
                                  (dim_ == 3 ? ", " + fmtNumber(X[2]) : std::string()) +
                                  "); expected a positive " + (dim_ == 2 ? "area" : "volume") + ")");
    }
    (void)xi;
  };
  const SimplexRule ks = stiffnessRule(shape);
  for (size_t g = 0; g < ks.x.size(); ++g) {
    simplexShape(shape, ks.x[g], N, dN);
    const MatX J = restJacobian(restX, dN);
    const double detJ = J.determinant();
    check(ks.x[g], detJ);
    pts_.push_back({dN * J.inverse(), ks.w[g] * detJ});
  }
  {
    const VecX xi = VecX::Constant(dim_, 1.0 / (dim_ + 1));
    simplexShape(shape, xi, N, dN);
    const MatX J = restJacobian(restX, dN);
    check(xi, J.determinant());
    centroidG_ = dN * J.inverse();
  }
  const SimplexRule ms = massRule(shape);
  massShape_.setZero(n_, n_);
  for (size_t g = 0; g < ms.x.size(); ++g) {
    simplexShape(shape, ms.x[g], N, dN);
    const double detJ = restJacobian(restX, dN).determinant();
    check(ms.x[g], detJ);
    massShape_ += (ms.w[g] * detJ) * N * N.transpose();
  }
}

void Solid::checkOrientation(double detF) const {
  if (props_->law.law == Law::NeoHookean && !(detF > 0.0))
    throw NumericalError("solid element " + name() + ": inverted (det F = " + fmtNumber(detF) +
                         " <= 0, the element turned inside out): the neo-Hookean energy is undefined");
}

double Solid::lambdaRest(double mu, double lam) const {
  return props_->law.planeStress() ? material::planeStressLambda(mu, lam) : lam;
}

// ------------------------------------------------------------------ value templates
// props = (E, nu, density, thickness, alpha, beta).
template <class T>
MatT<T> Solid::massT(const LocalState&, const VecT<T>& props) const {
  const int d = dim_;
  const T rt = props[2] * props[3];  // [kg/m^3] or [kg/m^2]
  MatT<T> M = MatT<T>::Zero(n_ * d, n_ * d);
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j)
      for (int c = 0; c < d; ++c) M(i * d + c, j * d + c) = rt * massShape_(i, j);
  return M;
}

template <class T>
VecT<T> Solid::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const {
  const int d = dim_;
  if (s.dim != d) throw std::invalid_argument("solid element " + name() + ": needs positions of dimension " + std::to_string(d));
  const T mu = material::mu(props[0], props[1]), lam = material::lambda(props[0], props[1]);
  const T lamV = props_->law.planeStress() ? material::planeStressLambda(mu, lam) : lam;
  const T rt = props[2] * props[3], t = props[3], alpha = props[4], beta = props[5];
  const bool hasV = v.size() == x.size();
  const VecX g = s.gravity ? VecX(*s.gravity) : VecX(VecX::Zero(d));
  VecT<T> Q = VecT<T>::Zero(n_ * d);
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j) {
      VecT<T> a = (g * massShape_(i, j)).template cast<T>();
      if (hasV) a -= (alpha * massShape_(i, j)) * v.segment(j * d, d);
      Q.segment(i * d, d) += rt * a;
    }
  const MatT<T> I = MatT<T>::Identity(d, d);
  const std::string who = "solid element " + name();
  for (const Point& P : pts_) {
    MatT<T> F = MatT<T>::Zero(d, d), Fd = MatT<T>::Zero(d, d);
    for (int i = 0; i < n_; ++i) {
      F += x.segment(i * d, d) * P.G.row(i).template cast<T>();
      if (hasV) Fd += v.segment(i * d, d) * P.G.row(i).template cast<T>();
    }
    checkOrientation(material::plain(material::det(F)));
    const MatT<T> E = 0.5 * (F.transpose() * F - I);
    MatT<T> S = props_->law.stress(E, mu, lam, who);
    if (hasV) {
      const MatT<T> A = F.transpose() * Fd, Ed = 0.5 * (A + A.transpose());
      S += beta * (lamV * Ed.trace() * I + 2.0 * mu * Ed);
    }
    const MatT<T> PK1 = F * S;
    for (int i = 0; i < n_; ++i) Q.segment(i * d, d) -= (P.w * t) * (PK1 * P.G.row(i).transpose().template cast<T>());
  }
  return Q;
}

// ------------------------------------------------------------------ analytic derivatives
// force(), forceJacobian(), parameterDerivative() and potential(): SolidKernel.cpp.
template <class T>
void Solid::centroidStressT(const VecT<T>& x, const T& E0, const T& nu, MatT<T>& E, MatT<T>& S, MatT<T>& sigma,
                            MatT<T>& dev) const {
  using std::log;
  const int d = dim_;
  const T mu = material::mu(E0, nu), lam = material::lambda(E0, nu);
  const MatX& G = centroidG_;
  MatT<T> F = MatT<T>::Zero(d, d);
  for (int i = 0; i < n_; ++i)
    for (int r = 0; r < d; ++r)
      for (int c = 0; c < d; ++c) F(r, c) += x[i * d + r] * G(i, c);
  E = 0.5 * (F.transpose() * F - MatT<T>::Identity(d, d));
  S = props_->law.stress<T>(E, mu, lam, "solid element " + name());
  const T J = material::det<T>(F);
  sigma = F * S * F.transpose() / J;
  T s33 = T(0.0);  // out-of-plane Cauchy stress: plane strain (F33 = 1)
  if (props_->law.planar == PlanarState::PlaneStrain)
    s33 = (props_->law.law == Law::SaintVenantKirchhoff ? T(lam * E.trace()) : T(lam * log(J))) / J;
  MatT<T> full = MatT<T>::Zero(3, 3);
  full.topLeftCorner(d, d) = sigma;
  if (d == 2) full(2, 2) = s33;
  dev = full - (full.trace() / 3.0) * MatT<T>::Identity(3, 3);
}

void Solid::centroidStress(const LocalState& s, MatX& E, MatX& S, MatX& sigma, double& vonMises) const {
  const VecX& p = *s.p;
  MatX dev;
  centroidStressT<double>(s.x.head(dim_ * n_), props_->E.value(p), props_->nu.value(p), E, S, sigma, dev);
  vonMises = std::sqrt(1.5 * (dev.array() * dev.array()).sum());
}

void Solid::centroidStressDerivative(const LocalState& s, const VecX& dx, int k, MatX& dE, MatX& dS, MatX& dsigma,
                                     double& dVonMises) const {
  const VecX& p = *s.p;
  stressad::directionalDerivative(
      s.x.head(dim_ * n_), dx, props_->E.value(p), props_->E.boundTo(k) ? 1.0 : 0.0, props_->nu.value(p),
      props_->nu.boundTo(k) ? 1.0 : 0.0,
      [this](const auto& x, const auto& E0, const auto& nu, auto& E, auto& S, auto& sigma, auto& dev) {
        centroidStressT<stressad::AD1>(x, E0, nu, E, S, sigma, dev);
      },
      dE, dS, dsigma, dVonMises);
}

template class KernelElement<Solid>;

}  // namespace flexsens
