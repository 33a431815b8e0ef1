#include "constraints/SelectedRows.hpp"

#include <algorithm>

namespace flexsens {

SelectedRows::SelectedRows(std::unique_ptr<Constraint> inner, std::vector<int> keep)
    : Constraint(inner->name(), inner->nodes()), inner_(std::move(inner)), keep_(std::move(keep)) {}

VecX SelectedRows::pick(const VecX& x) const {
  VecX r(keep_.size());
  for (size_t i = 0; i < keep_.size(); ++i) r[i] = x[keep_[i]];
  return r;
}

MatX SelectedRows::pickRows(const MatX& A) const {
  MatX r(keep_.size(), A.cols());
  for (size_t i = 0; i < keep_.size(); ++i) r.row(i) = A.row(keep_[i]);
  return r;
}

void SelectedRows::phi(const LocalState& s, VecX& out) const {
  VecX all;
  inner_->phi(s, all);
  out = pick(all);
}

void SelectedRows::jacobian(const LocalState& s, MatX& J) const {
  MatX all;
  inner_->jacobian(s, all);
  J = pickRows(all);
}

void SelectedRows::jacobianAD(const LocalState& s, MatX& J) const {
  MatX all;
  inner_->jacobianAD(s, all);
  J = pickRows(all);
}

bool SelectedRows::parameterDerivative(const LocalState& s, int k, VecX& dphi, MatX& dJ) const {
  VecX a;
  MatX b;
  if (!inner_->parameterDerivative(s, k, a, b)) return false;
  dphi = pick(a);
  dJ = pickRows(b);
  return true;
}

bool SelectedRows::parameterDerivativeAD(const LocalState& s, int k, VecX& dphi, MatX& dJ) const {
  VecX a;
  MatX b;
  if (!inner_->parameterDerivativeAD(s, k, a, b)) return false;
  dphi = pick(a);
  dJ = pickRows(b);
  return true;
}

void SelectedRows::timeDerivatives(const LocalState& s, VecX& phiT, MatX& phiQT, VecX& g, MatX& dgdq) const {
  VecX a, c;
  MatX b, d;
  inner_->timeDerivatives(s, a, b, c, d);
  if (a.size()) phiT = pick(a);
  if (b.rows()) phiQT = pickRows(b);
  if (c.size()) g = pick(c);
  if (d.rows()) dgdq = pickRows(d);
}

bool SelectedRows::timeParameterDerivative(const LocalState& s, int k, VecX& phiTp, VecX& gp) const {
  VecX a, b;
  if (!inner_->timeParameterDerivative(s, k, a, b)) return false;
  if (a.size()) phiTp = pick(a);
  if (b.size()) gp = pick(b);
  return true;
}

double SelectedRows::leftOutViolation(const LocalState& s) const {
  VecX all;
  inner_->phi(s, all);
  double worst = 0.0;
  for (int i = 0; i < all.size(); ++i)
    if (!std::binary_search(keep_.begin(), keep_.end(), i)) worst = std::max(worst, std::abs(all[i]));
  return worst;
}

}  // namespace flexsens
