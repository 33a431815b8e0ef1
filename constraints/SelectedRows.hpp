// A constraint with some of its rows left out: what stays of a joint whose other rows are
// redundant (they depend on the rest of the model's constraints, e.g. the out-of-plane rows
// of a planar loop built in 3D, or Bricard's sixth joint). The full constraint is kept so a
// run can check that the left-out rows stay satisfied (the redundancy persists).
#pragma once

#include <memory>

#include "core/Element.hpp"

namespace flexsens {

class SelectedRows : public Constraint {
 public:
  /// keep: the inner constraint's row indices that stay, ascending, not empty.
  SelectedRows(std::unique_ptr<Constraint> inner, std::vector<int> keep);

  std::string kind() const override { return inner_->kind(); }
  int rows() const override { return static_cast<int>(keep_.size()); }
  int gradients() const override { return inner_->gradients(); }
  void phi(const LocalState& s, VecX& out) const override;
  void jacobian(const LocalState& s, MatX& J) const override;
  void hessian(const LocalState& s, int r, MatX& H) const override { inner_->hessian(s, keep_[r], H); }
  bool constantHessian() const override { return inner_->constantHessian(); }
  bool parameterDerivative(const LocalState& s, int k, VecX& dphi, MatX& dJ) const override;
  void jacobianAD(const LocalState& s, MatX& J) const override;
  void hessianAD(const LocalState& s, int r, MatX& H) const override { inner_->hessianAD(s, keep_[r], H); }
  bool parameterDerivativeAD(const LocalState& s, int k, VecX& dphi, MatX& dJ) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return inner_->properties(); }
  bool rheonomic() const override { return inner_->rheonomic(); }
  void timeDerivatives(const LocalState& s, VecX& phiT, MatX& phiQT, VecX& g, MatX& dgdq) const override;
  bool timeParameterDerivative(const LocalState& s, int k, VecX& phiTp, VecX& gp) const override;

  const Constraint& full() const { return *inner_; }
  const std::vector<int>& kept() const { return keep_; }
  /// Largest |Phi_i| of the left-out rows at s.
  double leftOutViolation(const LocalState& s) const;

 private:
  VecX pick(const VecX& x) const;
  MatX pickRows(const MatX& A) const;
  std::unique_ptr<Constraint> inner_;
  std::vector<int> keep_;
};

}  // namespace flexsens
