#include "constraints/Driver.hpp"

#include <cmath>

namespace flexsens {

void Driver::coefficients(const Term& tm, double f, double a[4]) const {
  const double th = offset_ + f, c = std::cos(th), s = std::sin(th);
  switch (tm.a) {
    case Coefficient::One: a[0] = 1; a[1] = a[2] = a[3] = 0; break;
    case Coefficient::MinusF: a[0] = -th; a[1] = -1; a[2] = a[3] = 0; break;
    case Coefficient::MinusF2: a[0] = -th * th; a[1] = -2 * th; a[2] = -2; a[3] = 0; break;
    case Coefficient::Cos: a[0] = c; a[1] = -s; a[2] = -c; a[3] = s; break;
    case Coefficient::MinusSin: a[0] = -s; a[1] = -c; a[2] = s; a[3] = c; break;
  }
}

void Driver::phi(const LocalState& s, VecX& out) const {
  const double f = f_->at(s.t, *s.p).f;
  double a[4];
  out.setZero(1);
  for (const Term& tm : terms_) {
    coefficients(tm, f, a);
    out[0] += a[0] * value(tm, s.x);
  }
}

void Driver::jacobian(const LocalState& s, MatX& J) const {
  const double f = f_->at(s.t, *s.p).f;
  double a[4];
  J.setZero(1, s.x.size());
  for (const Term& tm : terms_) {
    coefficients(tm, f, a);
    J.row(0) += a[0] * gradient(tm, s.x).transpose();
  }
}

void Driver::hessian(const LocalState& s, int, MatX& H) const {
  const double f = f_->at(s.t, *s.p).f;
  double a[4];
  H.setZero(s.x.size(), s.x.size());
  for (const Term& tm : terms_) {
    coefficients(tm, f, a);
    H += a[0] * tm.H;
  }
}

bool Driver::parameterDerivative(const LocalState& s, int k, VecX& dphi, MatX& dJ) const {
  TimeValue d;
  if (!f_->parameterDerivative(s.t, *s.p, k, d)) return false;
  const double f = f_->at(s.t, *s.p).f;
  double a[4];
  dphi.setZero(1);
  dJ.setZero(1, s.x.size());
  for (const Term& tm : terms_) {
    coefficients(tm, f, a);
    dphi[0] += a[1] * d.f * value(tm, s.x);
    dJ.row(0) += a[1] * d.f * gradient(tm, s.x).transpose();
  }
  return true;
}

void Driver::timeDerivatives(const LocalState& s, VecX& phiT, MatX& phiQT, VecX& g, MatX& dgdq) const {
  const TimeValue f = f_->at(s.t, *s.p);
  const int n = static_cast<int>(s.x.size());
  const VecX v = s.v.size() == n ? s.v : VecX(VecX::Zero(n));
  double a[4];
  phiT.setZero(1);
  phiQT.setZero(1, n);
  g.setZero(1);
  dgdq.setZero(1, n);
  for (const Term& tm : terms_) {
    coefficients(tm, f.f, a);
    const double B = value(tm, s.x);
    const VecX dB = gradient(tm, s.x);
    const double ctt = a[2] * f.df * f.df + a[1] * f.ddf;  // coefficient of B in Phi_tt
    phiT[0] += a[1] * f.df * B;
    phiQT.row(0) += a[1] * f.df * dB.transpose();
    g[0] += ctt * B + 2.0 * a[1] * f.df * dB.dot(v);
    dgdq.row(0) += ctt * dB.transpose() + 2.0 * a[1] * f.df * (tm.H * v).transpose();
  }
}

bool Driver::timeParameterDerivative(const LocalState& s, int k, VecX& phiTp, VecX& gp) const {
  TimeValue d;
  if (!f_->parameterDerivative(s.t, *s.p, k, d)) return false;
  const TimeValue f = f_->at(s.t, *s.p);
  const int n = static_cast<int>(s.x.size());
  const VecX v = s.v.size() == n ? s.v : VecX(VecX::Zero(n));
  double a[4];
  phiTp.setZero(1);
  gp.setZero(1);
  for (const Term& tm : terms_) {
    coefficients(tm, f.f, a);
    const double B = value(tm, s.x), Bv = gradient(tm, s.x).dot(v);
    const double ct = a[2] * d.f * f.df + a[1] * d.df;  // d/dp of a' f'
    phiTp[0] += ct * B;
    gp[0] += (a[3] * d.f * f.df * f.df + 2.0 * a[2] * f.df * d.df + a[2] * d.f * f.ddf + a[1] * d.ddf) * B +
             2.0 * ct * Bv;
  }
  return true;
}

namespace {
/// Selection E (dim x local dofs) of node slot `slot`: x_slot = E x.
MatX select(int slot, int dim, int nodes) {
  MatX E = MatX::Zero(dim, dim * nodes);
  E.block(0, dim * slot, dim, dim).setIdentity();
  return E;
}
}  // namespace

CoordinateDriver::CoordinateDriver(std::string name, int node, int dim, int component, double x0,
                                   std::unique_ptr<TimeFunction> f)
    : Driver(std::move(name), {node}, std::move(f)) {
  offset_ = x0;
  Term x{MatX::Zero(dim, dim), VecX::Unit(dim, component), 0.0, Coefficient::One};
  Term one{MatX::Zero(dim, dim), VecX::Zero(dim), 1.0, Coefficient::MinusF};
  terms_ = {x, one};
}

double CoordinateDriver::reactionScale(const VecX& x, VecX* grad) const {
  if (grad) grad->setZero(x.size());
  return 1.0;
}

DistanceDriver::DistanceDriver(std::string name, int a, int b, int dim, double L0,
                               std::unique_ptr<TimeFunction> f)
    : Driver(std::move(name), {a, b}, std::move(f)) {
  offset_ = L0;
  const MatX D = select(1, dim, 2) - select(0, dim, 2);  // d = x_b - x_a
  Term d2{2.0 * D.transpose() * D, VecX::Zero(2 * dim), 0.0, Coefficient::One};
  Term one{MatX::Zero(2 * dim, 2 * dim), VecX::Zero(2 * dim), 1.0, Coefficient::MinusF2};
  terms_ = {d2, one};
}

double DistanceDriver::reactionScale(const VecX& x, VecX* grad) const {
  const int dim = static_cast<int>(x.size()) / 2;
  const VecX d = x.segment(dim, dim) - x.head(dim);
  const double L = d.norm();
  if (grad) {
    grad->resize(x.size());
    grad->head(dim) = -2.0 * d / L;
    grad->tail(dim) = 2.0 * d / L;
  }
  return 2.0 * L;
}

AngleDriver::AngleDriver(std::string name, std::vector<int> nodes, double theta0,
                         std::unique_ptr<TimeFunction> f)
    : Driver(std::move(name), std::move(nodes), std::move(f)) {
  offset_ = theta0;
  const MatX U = select(1, 2, 4) - select(0, 2, 4), W = select(3, 2, 4) - select(2, 2, 4);
  MatX Jr(2, 2);
  Jr << 0, 1, -1, 0;  // u x w = u^T Jr w
  const MatX Bc = U.transpose() * Jr * W, Bd = U.transpose() * W;
  Term cross{Bc + Bc.transpose(), VecX::Zero(8), 0.0, Coefficient::Cos};
  Term dot{Bd + Bd.transpose(), VecX::Zero(8), 0.0, Coefficient::MinusSin};
  terms_ = {cross, dot};
}

double AngleDriver::reactionScale(const VecX& x, VecX* grad) const {
  const VecX u = x.segment(2, 2) - x.segment(0, 2), w = x.segment(6, 2) - x.segment(4, 2);
  const double lu = u.norm(), lw = w.norm();
  if (grad) {
    grad->resize(8);
    grad->segment(0, 2) = -lw / lu * u;
    grad->segment(2, 2) = lw / lu * u;
    grad->segment(4, 2) = -lu / lw * w;
    grad->segment(6, 2) = lu / lw * w;
  }
  return lu * lw;
}

}  // namespace flexsens
