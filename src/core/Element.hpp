// The one element interface. An element couples a few nodes; it sees only its local
// coordinates (dim values per node, then the node's position gradients when the element has
// gradients(): the ANCF cable's slope, the ANCF beam's r_x, r_y, r_z; fixed values included with zero velocity) and the design-parameter vector p. It never sees the integrator or the scene file.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "core/Types.hpp"

namespace flexsens {

/// Dense vectors and matrices of any scalar type T: double for values, Eigen's
/// AutoDiffScalar for the automatic-differentiation ("ad") kernels (elements/AutoDiff.hpp).
/// Each element and constraint writes its value (Q(x, v, props), M(props), Phi(x, props))
/// once as a template on T and evaluates it with both.
template <class T> using VecT = Eigen::Matrix<T, Eigen::Dynamic, 1>;
template <class T> using MatT = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

/// Local view of the state of the nodes an element or constraint touches.
struct LocalState {
  int dim = 2;                 ///< position coordinates per node (2 planar, 3 spatial)
  /// Position-gradient vectors each node carries after its position (dim entries each): 0,
  /// 1 (the ANCF cable's slope r_s) or 3 (the full ANCF beam's r_x, r_y, r_z).
  int gradients = 0;
  VecX x;                      ///< positions (then gradients [-]), node after node [m]
  VecX v;                      ///< velocities [m/s]
  const VecX* p = nullptr;     ///< design parameters (values of all parameters)
  const VecX* gravity = nullptr; ///< gravity vector, dim entries [m/s^2]
  double t = 0.0;              ///< time [s]: read by loads and drivers that vary in time
  double value(const Quantity& s) const { return s.value(*p); }
  int nodeSize() const { return (1 + gradients) * dim; }  ///< local coordinates per node
};

class Element {
 public:
  Element(std::string name, std::vector<int> nodes) : name_(std::move(name)), nodes_(std::move(nodes)) {}
  virtual ~Element() = default;

  const std::string& name() const { return name_; }
  const std::vector<int>& nodes() const { return nodes_; }
  virtual std::string kind() const = 0;
  /// Position-gradient vectors per node in the local coordinates (LocalState::gradients): 0
  /// positions only (gradients, if any, are not seen), 1 the ANCF cable's slope, 3 the full
  /// ANCF beam's r_x, r_y, r_z; every node must then carry exactly that many.
  virtual int gradients() const { return 0; }
  bool usesSlopes() const { return gradients() > 0; }

  /// Constant (configuration-independent) local mass matrix [kg]; false if massless.
  virtual bool mass(const LocalState& s, MatX& M) const { (void)s; (void)M; return false; }
  /// Generalized force Q (right-hand side of M q'' + Phi_q^T lambda = Q) [N].
  virtual void force(const LocalState& s, VecX& Q) const = 0;
  /// dQ/dq [N/m] and dQ/dv [N s/m], analytic.
  virtual void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const = 0;
  /// False when Q never depends on v (dQ/dv = 0 at every state, checked against AD in
  /// test_autodiff): passes that need dQ/dv alone skip the element. Default: may depend.
  virtual bool velocityDependent() const { return true; }
  /// Partial derivatives of Q and M with respect to design parameter k at fixed q, v.
  /// Returns false when the element does not depend on parameter k (outputs untouched).
  virtual bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const = 0;

  // --- the same derivatives by forward-mode automatic differentiation ("ad") of the
  // element's value templates (force, mass); a property Quantity q is bound to parameter k
  // when q.param == k. Defaults throw std::logic_error("no AD kernel").
  /// dQ/dq and dQ/dv by AD of the force template.
  virtual void forceJacobianAD(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
    (void)s; (void)dQdq; (void)dQdv;
    throw std::logic_error("no AD kernel");
  }
  /// Same contract as parameterDerivative (false, outputs untouched, when no property the
  /// kernels read is bound to k); dQ by AD of the force template, dM by AD of the mass
  /// template (an empty 0x0 dM for massless elements).
  virtual bool parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
    (void)s; (void)k; (void)dQ; (void)dM;
    throw std::logic_error("no AD kernel");
  }

  /// An applied load (point force, torque): the static solver scales its force by the load
  /// factor, like gravity. Internal forces (elastic, damping) are not loads.
  virtual bool isLoad() const { return false; }
  /// True for a load that does work the potential does not hold (varying in time, follower):
  /// its potential() is 0 and the energy audit integrates its whole power v . Q as work.
  virtual bool externalWork() const { return false; }
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
  /// As Element::gradients: local coordinates are positions and gradients node after node.
  virtual int gradients() const { return 0; }
  bool usesSlopes() const { return gradients() > 0; }

  virtual void phi(const LocalState& s, VecX& out) const = 0;
  /// Phi_q: rows() x local dofs.
  virtual void jacobian(const LocalState& s, MatX& J) const = 0;
  /// Second derivative of row r, local dofs x local dofs. flexsens constraints are at most
  /// quadratic in q (paper, remark 4.1), so the Hessian is constant in q.
  virtual void hessian(const LocalState& s, int r, MatX& H) const = 0;
  /// True when every row's Hessian is the same at every state, q and t alike (checked against
  /// AD at a second state in test_autodiff): the assembly then leaves the Hessian's zero
  /// entries out of the Newton matrix's pattern (fewer entries to add and to factor). Default
  /// false: an angle driver's Hessian is constant in q but moves with f(t).
  virtual bool constantHessian() const { return false; }
  /// Phi_p and Phi_qp for parameter k; false if the constraint does not depend on k.
  virtual bool parameterDerivative(const LocalState& s, int k, VecX& dphi, MatX& dJ) const = 0;

  // --- the same derivatives by forward-mode automatic differentiation ("ad") of the
  // constraint's Phi template. Defaults throw std::logic_error("no AD kernel").
  /// Phi_q by first-order AD.
  virtual void jacobianAD(const LocalState& s, MatX& J) const {
    (void)s; (void)J;
    throw std::logic_error("no AD kernel");
  }
  /// Hessian of row r by nested (second-order) AD.
  virtual void hessianAD(const LocalState& s, int r, MatX& H) const {
    (void)s; (void)r; (void)H;
    throw std::logic_error("no AD kernel");
  }
  /// Same contract as parameterDerivative: Phi_p by AD, Phi_qp (rows() x local dofs) by
  /// nested AD; false, outputs untouched, when no property is bound to k.
  virtual bool parameterDerivativeAD(const LocalState& s, int k, VecX& dphi, MatX& dJ) const {
    (void)s; (void)k; (void)dphi; (void)dJ;
    throw std::logic_error("no AD kernel");
  }
  virtual std::vector<std::pair<std::string, Quantity*>> properties() = 0;

  // --- rheonomic constraints (drivers): Phi(q, t) depends on the time s.t. The defaults are
  // those of the scleronomic constraints: every time derivative is zero.
  virtual bool rheonomic() const { return false; }
  /// At s.t: Phi_t (rows), Phi_qt (rows x local dofs), the time terms of the acceleration
  /// constraint g = Phi_tt + 2 Phi_qt v (v = s.v; rows) and dg/dq (rows x local dofs), so
  /// that d2 Phi/dt2 = Phi_q a + (v^T H_i v)_i + g.
  virtual void timeDerivatives(const LocalState& s, VecX& phiT, MatX& phiQT, VecX& g, MatX& dgdq) const {
    (void)s; (void)phiT; (void)phiQT; (void)g; (void)dgdq;
  }
  /// Phi_tp and g_p for design parameter k at fixed q, v, t; false when independent of k.
  virtual bool timeParameterDerivative(const LocalState& s, int k, VecX& phiTp, VecX& gp) const {
    (void)s; (void)k; (void)phiTp; (void)gp;
    return false;
  }

 private:
  std::string name_;
  std::vector<int> nodes_;
};

}  // namespace flexsens
