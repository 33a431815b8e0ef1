// Sensitivity degrees of freedom z(q) of a PIM case (paper eq. 7): scalar functions of the
// coordinates whose parameter derivatives z_p0, z'_p0 the user prescribes.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/Model.hpp"

namespace flexsens {

class Sdof {
 public:
  virtual ~Sdof() = default;
  std::string name;
  double dp = 0.0;  ///< prescribed dz/dp at t = 0
  double dv = 0.0;  ///< prescribed dz'/dp at t = 0
  virtual double value(const Model& m, const VecX& q) const = 0;
  virtual VecX gradient(const Model& m, const VecX& q) const = 0;   ///< z_q (n)
  virtual MatX hessian(const Model& m, const VecX& q) const = 0;    ///< z_qq (n x n)
};

/// A linear combination sum_j coef_j q[dof_j] (a single node coordinate is the simplest).
class LinearSdof : public Sdof {
 public:
  struct Term { int node, component; double coef; };
  std::vector<Term> terms;
  double value(const Model& m, const VecX& q) const override;
  VecX gradient(const Model& m, const VecX& q) const override;
  MatX hessian(const Model& m, const VecX& q) const override;
};

/// Planar angle of the segment a -> b to the first axis: atan2(r_b2 - r_a2, r_b1 - r_a1) [rad].
class AngleSdof : public Sdof {
 public:
  int a = -1, b = -1;
  double value(const Model& m, const VecX& q) const override;
  VecX gradient(const Model& m, const VecX& q) const override;
  MatX hessian(const Model& m, const VecX& q) const override;
};

}  // namespace flexsens
