// Drivers: rheonomic constraints Phi(q, t) = 0 that prescribe a coordinate, a distance or a
// planar joint angle as its initial value s0 plus a function of time f(t)
// (core/TimeFunction.hpp; f(0) = 0 keeps the initial configuration). Each is one equation
//   Phi(x, t) = sum_j a_j(f(t)) B_j(x),   B_j(x) = x^T H_j x / 2 + g_j . x + c_j
// with constant H_j, g_j, c_j (at most quadratic in q, like every flexsens constraint) and
// scalar coefficients a_j of f, so that every time and parameter derivative follows by the
// chain rule through f, f', f'' and their derivatives with respect to the function's constants:
//   Phi_t  = sum a_j' f' B_j,             Phi_qt = sum a_j' f' grad B_j
//   Phi_tt = sum (a_j'' f'^2 + a_j' f'') B_j
// The reaction of a driver is the generalized force it applies in its own coordinate,
// -lambda dPhi/ds (s the prescribed coordinate, distance [m] or angle [rad]): a force [N] or a
// torque [N m].
//
// AD mode ("ad" sensitivities): drivers use their analytic derivatives (no value template).
#pragma once

#include <memory>

#include "core/Element.hpp"
#include "core/TimeFunction.hpp"

namespace flexsens {

class Driver : public Constraint {
 public:
  /// How a term's coefficient depends on f (s0 = offset_): 1, -(s0 + f), -(s0 + f)^2,
  /// cos(s0 + f), -sin(s0 + f).
  enum class Coefficient { One, MinusF, MinusF2, Cos, MinusSin };
  struct Term {
    MatX H;  ///< constant Hessian of B_j (local dofs x local dofs)
    VecX g;  ///< linear part
    double c = 0.0;
    Coefficient a = Coefficient::One;
  };

  Driver(std::string name, std::vector<int> nodes, std::unique_ptr<TimeFunction> f)
      : Constraint(std::move(name), std::move(nodes)), f_(std::move(f)) {}
  bool rheonomic() const override { return true; }
  int rows() const override { return 1; }
  void phi(const LocalState& s, VecX& out) const override;
  void jacobian(const LocalState& s, MatX& J) const override;
  void hessian(const LocalState& s, int r, MatX& H) const override;
  bool parameterDerivative(const LocalState& s, int k, VecX& dphi, MatX& dJ) const override;
  void timeDerivatives(const LocalState& s, VecX& phiT, MatX& phiQT, VecX& g, MatX& dgdq) const override;
  bool timeParameterDerivative(const LocalState& s, int k, VecX& phiTp, VecX& gp) const override;
  void jacobianAD(const LocalState& s, MatX& J) const override { jacobian(s, J); }
  void hessianAD(const LocalState& s, int r, MatX& H) const override { hessian(s, r, H); }
  bool parameterDerivativeAD(const LocalState& s, int k, VecX& dphi, MatX& dJ) const override {
    return parameterDerivative(s, k, dphi, dJ);
  }
  std::vector<std::pair<std::string, Quantity*>> properties() override { return f_->properties(); }
  const TimeFunction& function() const { return *f_; }

  /// dPhi/ds at the local positions x: the reaction is -lambda times this; and its gradient
  /// with respect to x (for the reaction's sensitivity).
  virtual double reactionScale(const VecX& x, VecX* grad) const = 0;
  /// "N" or "N m".
  virtual const char* reactionUnit() const = 0;

 protected:
  /// Set by the derived constructor.
  std::vector<Term> terms_;
  double offset_ = 0.0;  ///< s0: initial coordinate [m], distance [m] or angle [rad]

 private:
  /// a, a', a'', a''' of term j at f.
  void coefficients(const Term& tm, double f, double a[4]) const;
  static double value(const Term& tm, const VecX& x) { return 0.5 * x.dot(tm.H * x) + tm.g.dot(x) + tm.c; }
  static VecX gradient(const Term& tm, const VecX& x) { return tm.H * x + tm.g; }
  std::unique_ptr<TimeFunction> f_;
};

/// Phi = x_c - (x_c0 + f(t)): coordinate c (0, 1, 2 = the scene's axes) of a node [m].
class CoordinateDriver : public Driver {
 public:
  CoordinateDriver(std::string name, int node, int dim, int component, double x0, std::unique_ptr<TimeFunction> f);
  std::string kind() const override { return "prescribed_coordinate"; }
  double reactionScale(const VecX& x, VecX* grad) const override;
  const char* reactionUnit() const override { return "N"; }
};

/// Phi = |x_b - x_a|^2 - (L0 + f(t))^2: the distance of two nodes [m] (L0 + f > 0).
class DistanceDriver : public Driver {
 public:
  DistanceDriver(std::string name, int a, int b, int dim, double L0, std::unique_ptr<TimeFunction> f);
  std::string kind() const override { return "prescribed_distance"; }
  double reactionScale(const VecX& x, VecX* grad) const override;  ///< 2 |x_b - x_a|
  const char* reactionUnit() const override { return "N"; }
};

/// Planar motor: the angle from u = x_1 - x_0 to w = x_3 - x_2 (counter-clockwise) equals
/// theta0 + f(t), theta0 its initial value:
///   Phi = (u x w) cos(theta0 + f) - (u . w) sin(theta0 + f) = |u||w| sin(theta - theta0 - f).
/// Nodes 0, 1 may be ground nodes (the angle of a body relative to ground). Phi also vanishes
/// at theta - theta0 - f = pi: the motor holds its branch only as long as the integrator does.
class AngleDriver : public Driver {
 public:
  AngleDriver(std::string name, std::vector<int> nodes, double theta0, std::unique_ptr<TimeFunction> f);
  std::string kind() const override { return "motor"; }
  double reactionScale(const VecX& x, VecX* grad) const override;  ///< |u| |w|
  const char* reactionUnit() const override { return "N m"; }
};

}  // namespace flexsens
