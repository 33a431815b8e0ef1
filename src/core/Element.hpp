// The one element interface. An element couples a few nodes; it sees only its local
// coordinates (dim values per node, ground nodes included with zero velocity) and the
// design-parameter vector p. It never sees the integrator or the scene file.
#pragma once

#include <string>
#include <vector>

#include "core/Types.hpp"

namespace flexsens {

/// Local view of the state of the nodes an element or constraint touches.
struct LocalState {
  int dim = 2;                 ///< coordinates per node (2 planar, 3 spatial)
  VecX x;                      ///< positions, node after node [m]
  VecX v;                      ///< velocities [m/s]
  const VecX* p = nullptr;     ///< design parameters (values of all parameters)
  const VecX* gravity = nullptr; ///< gravity vector, dim entries [m/s^2]
  double value(const Quantity& s) const { return s.value(*p); }
};

class Element {
 public:
  Element(std::string name, std::vector<int> nodes) : name_(std::move(name)), nodes_(std::move(nodes)) {}
  virtual ~Element() = default;

  const std::string& name() const { return name_; }
  const std::vector<int>& nodes() const { return nodes_; }
  virtual std::string kind() const = 0;

  /// Constant (configuration-independent) local mass matrix [kg]; false if massless.
  virtual bool mass(const LocalState& s, MatX& M) const { (void)s; (void)M; return false; }
  /// Generalized force Q (right-hand side of M q'' + Phi_q^T lambda = Q) [N].
  virtual void force(const LocalState& s, VecX& Q) const = 0;
  /// dQ/dq [N/m] and dQ/dv [N s/m], analytic.
  virtual void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const = 0;
  /// Partial derivatives of Q and M with respect to design parameter k at fixed q, v.
  /// Returns false when the element does not depend on parameter k (outputs untouched).
  virtual bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const = 0;
  /// Potential energy (gravity, elastic) [J]; its negative gradient is the conservative part of Q.
  virtual double potential(const LocalState& s) const = 0;
  /// The scalar quantities this element reads, by property name (for parameter binding).
  virtual std::vector<std::pair<std::string, Quantity*>> properties() = 0;

 private:
  std::string name_;
  std::vector<int> nodes_;
};

/// The one constraint interface: Phi(q, p) = 0, rows() scalar equations on the local nodes.
class Constraint {
 public:
  Constraint(std::string name, std::vector<int> nodes) : name_(std::move(name)), nodes_(std::move(nodes)) {}
  virtual ~Constraint() = default;

  const std::string& name() const { return name_; }
  const std::vector<int>& nodes() const { return nodes_; }
  virtual std::string kind() const = 0;
  virtual int rows() const = 0;

  virtual void phi(const LocalState& s, VecX& out) const = 0;
  /// Phi_q: rows() x local dofs.
  virtual void jacobian(const LocalState& s, MatX& J) const = 0;
  /// Second derivative of row r, local dofs x local dofs. flexsens constraints are at most
  /// quadratic in q (paper, remark 4.1), so the Hessian is constant in q.
  virtual void hessian(const LocalState& s, int r, MatX& H) const = 0;
  /// Phi_p and Phi_qp for parameter k; false if the constraint does not depend on k.
  virtual bool parameterDerivative(const LocalState& s, int k, VecX& dphi, MatX& dJ) const = 0;
  virtual std::vector<std::pair<std::string, Quantity*>> properties() = 0;

 private:
  std::string name_;
  std::vector<int> nodes_;
};

}  // namespace flexsens
