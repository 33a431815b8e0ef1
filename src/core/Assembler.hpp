// The one assembly path: global vectors and sparse blocks of
//   M q'' + Phi_q^T lambda = Q(q, v, p),   Phi(q, p) = 0
// and their derivatives, gathered from the elements' and constraints' local kernels.
// Integrators compose their Newton matrices from these blocks through a SparseAccumulator,
// so each block is written once, at a row/column offset and with a scale chosen by the caller.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/Model.hpp"
#include "core/SparseAccumulator.hpp"

namespace flexsens {

/// Where the assembled derivatives come from: the elements' and constraints' hand-written
/// analytic partials (sensitivity method "dd"), or forward-mode automatic differentiation of
/// their value templates (method "ad"). Values (force, phi, mass, potential) are the same.
enum class Derivatives { Analytic, AutomaticDifferentiation };

class Assembler {
 public:
  using ConstraintList = std::vector<std::unique_ptr<Constraint>>;
  /// Assembles the model's elements and `constraints` (default: the model's own). The PIM
  /// passes its rigidization constraints Lambda here to reuse the same path.
  explicit Assembler(const Model& model, const ConstraintList* constraints = nullptr,
                     Derivatives derivatives = Derivatives::Analytic);
  Assembler(const Model& model, Derivatives derivatives)
      : Assembler(model, nullptr, derivatives) {}
  /// Derivative mode of every derivative entry point below (blocks, products, parameter
  /// derivatives); may be changed between evaluations.
  void setDerivatives(Derivatives d) {
    derivatives_ = d;
    massDerivatives_.clear();  // computed by the other mode's kernels
  }
  Derivatives derivatives() const { return derivatives_; }
  /// Scales the applied loads (gravity and elements with isLoad()) in every force entry point
  /// below: the static solver's load factor in (0, 1]; 1 for dynamics.
  void setLoadFactor(double s) const;
  double loadFactor() const { return loadFactor_; }
  /// The time t [s] every entry point below evaluates at (LocalState::t): loads and drivers
  /// that vary in time read it, the rest ignore it. Integrators set it before each evaluation
  /// (as MFEM's TimeDependentOperator::SetTime), the initial state sets t0.
  void setTime(double t) const { time_ = t; }
  double time() const { return time_; }
  /// True when some constraint is a driver (rheonomic): the time terms below are not zero.
  bool rheonomic() const { return rheonomic_; }
  const Model& model() const { return model_; }
  int n() const { return model_.n; }
  int m() const { return m_; }
  const ConstraintList& constraints() const { return cons_; }
  /// Label of constraint row r, e.g. "bar_A1.length" or "fx[1]".
  std::string rowLabel(int r) const;

  // --- vectors -----------------------------------------------------------------------
  VecX force(const VecX& q, const VecX& v, const VecX& p) const {          ///< Q [N]
    VecX Q;
    elementForces(q, v, p, false, Q);
    return Q;
  }
  /// Q [N] into Q's storage (no allocation once sized: the Newton residual's).
  void force(const VecX& q, const VecX& v, const VecX& p, VecX& Q) const { elementForces(q, v, p, false, Q); }
  VecX phi(const VecX& q, const VecX& p) const;                           ///< Phi
  VecX phiQTimes(const VecX& q, const VecX& p, const VecX& x) const;      ///< Phi_q x
  VecX phiQTransposeTimes(const VecX& q, const VecX& p, const VecX& l) const;  ///< Phi_q^T l
  /// Phi and Phi_q^T l in one pass over the constraints (each gathered once): the Newton
  /// residual needs both at every iteration.
  void constraintTerms(const VecX& q, const VecX& p, const VecX& l, VecX& phi, VecX& phiQTl) const;
  /// Phi_p and Phi_qp^T l for parameter k in one pass (each constraint's derivative computed
  /// once): the fixed-step sensitivity right-hand sides need both.
  void constraintParamTerms(const VecX& q, const VecX& p, int k, const VecX& l, VecX& phiP, VecX& phiQPTl) const;
  VecX hessianQuadratic(const VecX& q, const VecX& p, const VecX& v) const;  ///< (v^T H_i v)_i
  VecX hessianTimes(const VecX& q, const VecX& p, const VecX& w, const VecX& x) const;  ///< (sum w_i H_i) x
  VecX hessianRowsTimes(const VecX& q, const VecX& p, const VecX& v, const VecX& x) const;  ///< (v^T H_i x)_i

  // --- time terms of drivers (zero vectors when no constraint is rheonomic) ------------
  VecX phiT(const VecX& q, const VecX& p) const;                             ///< Phi_t
  VecX phiQTTimes(const VecX& q, const VecX& p, const VecX& x) const;        ///< Phi_qt x
  /// g = Phi_tt + 2 Phi_qt v: d2 Phi/dt2 = Phi_q a + (v^T H_i v)_i + g.
  VecX accelerationTimeTerms(const VecX& q, const VecX& v, const VecX& p) const;
  VecX accelerationTimeTermsQTimes(const VecX& q, const VecX& v, const VecX& p, const VecX& x) const;  ///< g_q x
  VecX phiTParamDerivative(const VecX& q, const VecX& p, int k) const;       ///< Phi_tp
  VecX accelerationTimeTermsParamDerivative(const VecX& q, const VecX& v, const VecX& p, int k) const;  ///< g_p
  /// Phi_qt at (r0, c0): the q-derivative of Phi_t (GGL velocity rows).
  void addPhiQT(SparseAccumulator& acc, const VecX& q, const VecX& p, double s, int64_t r0, int64_t c0) const;

  /// Phi_q (m x n), sparse.
  SpMat phiQSparse(const VecX& q, const VecX& p) const;
  /// The same in acc's storage (its pattern kept from call to call).
  const SpMat& phiQSparse(const VecX& q, const VecX& p, SparseAccumulator& acc) const;
  /// Phi_q as a dense matrix (small systems: PIM, least-norm projections).
  MatX phiQDense(const VecX& q, const VecX& p) const { return MatX(phiQSparse(q, p)); }
  /// Constant mass matrix M(p) (elements' masses do not depend on q).
  SpMat mass(const VecX& p) const;
  double potentialEnergy(const VecX& q, const VecX& p) const;
  /// -grad V [N]: the forces at rest of the elements with a potential (all but the loads
  /// that do external work, externalWork()).
  VecX conservativeForce(const VecX& q, const VecX& p) const {
    VecX Q;
    elementForces(q, VecX::Zero(q.size()), p, true, Q);
    return Q;
  }
  /// Power [W] of the loads that do external work (externalWork()), v . Q, at time().
  double externalPower(const VecX& q, const VecX& v, const VecX& p) const;
  /// The dampers' forces [N]: Q(q, v) - Q(q, 0) of the velocity-dependent elements without
  /// external work. With externalPower and the drivers' lambda^T Phi_t their power
  /// v . dampingForce is dE/dt, E = T + V; the energy audit integrates it.
  VecX dampingForce(const VecX& q, const VecX& v, const VecX& p) const;
  /// Whether an element has a damping force (dampingForce can be nonzero).
  bool damped() const;

  // --- sparse blocks, added as s * block at (r0, c0) ------------------------------------
  void addMass(SparseAccumulator& acc, const VecX& p, double s, int64_t r0, int64_t c0) const;
  /// Adds -sq dQ/dq at (r0, cq) and -sv dQ/dv at (r0, cv).
  void addForceJacobian(SparseAccumulator& acc, const VecX& q, const VecX& v, const VecX& p,
                        double sq, double sv, int64_t r0, int64_t cq, int64_t cv) const;
  /// dQ/dq into kq and dQ/dv into kv (each n x n, begun by the caller), one element
  /// Jacobian per element for both; elements without velocity dependence add nothing to kv.
  void addForceJacobians(SparseAccumulator& kq, SparseAccumulator& kv, const VecX& q,
                         const VecX& v, const VecX& p) const;
  /// sm M - sq dQ/dq - sv dQ/dv at (r0, c0), one block per element: the fixed-step Newton
  /// matrix's top-left block with a third of the scatter of addMass + addForceJacobian.
  void addMassAndForceJacobian(SparseAccumulator& acc, const VecX& q, const VecX& v, const VecX& p,
                               double sm, double sq, double sv, int64_t r0, int64_t c0) const;
  /// Phi_q at (r0, c0), or Phi_q^T when transposed.
  void addPhiQ(SparseAccumulator& acc, const VecX& q, const VecX& p, double s, int64_t r0,
               int64_t c0, bool transposed) const;
  /// sum_i w_i Hess(Phi_i) at (r0, c0): the q-derivative of Phi_q^T w.
  void addHessian(SparseAccumulator& acc, const VecX& q, const VecX& p, const VecX& w, double s,
                  int64_t r0, int64_t c0) const;
  /// Rows (Hess(Phi_i) v)^T at (r0, c0): the q-derivative of Phi_q v.
  void addHessianRows(SparseAccumulator& acc, const VecX& q, const VecX& p, const VecX& v,
                      double s, int64_t r0, int64_t c0) const;

  // --- partial derivatives with respect to design parameter k -------------------------
  VecX forceParamDerivative(const VecX& q, const VecX& v, const VecX& p, int k) const;  ///< Q_p
  VecX massParamDerivativeTimes(const VecX& p, int k, const VecX& a) const;           ///< M_p a
  /// The same two into r's storage (the fixed-step sensitivity right-hand sides, every step
  /// and parameter: their vectors were a tenth of the ten-parameter five-bar's overhead).
  void forceParamDerivative(const VecX& q, const VecX& v, const VecX& p, int k, VecX& r) const;
  void massParamDerivativeTimes(const VecX& p, int k, const VecX& a, VecX& r) const;
  VecX phiParamDerivative(const VecX& q, const VecX& p, int k) const;                  ///< Phi_p
  VecX phiQParamDerivativeTimes(const VecX& q, const VecX& p, int k, const VecX& x) const;  ///< Phi_qp x
  VecX phiQParamDerivativeTransposeTimes(const VecX& q, const VecX& p, int k,
                                         const VecX& l) const;  ///< Phi_qp^T l

  /// Local state of a node list (ground nodes included at their fixed positions; with
  /// `slopes`, each node's slope after its position, a clamped slope at its fixed value).
  LocalState localState(const std::vector<int>& nodes, const VecX& q, const VecX& v,
                        const VecX& p, int gradients = 0) const;
  LocalState localState(const Element& e, const VecX& q, const VecX& v, const VecX& p) const {
    return localState(e.nodes(), q, v, p, e.gradients());
  }
  LocalState localState(const Constraint& c, const VecX& q, const VecX& v, const VecX& p) const {
    return localState(c.nodes(), q, v, p, c.gradients());
  }
  /// The local state of element e / constraint c in a buffer shared by the elements
  /// (constraints) of its local size (no allocation once sized; valid until the next call for
  /// an element / constraint of that size).
  const LocalState& elementState(size_t e, const VecX& q, const VecX& v, const VecX& p) const;
  const LocalState& constraintState(size_t c, const VecX& q, const VecX& v, const VecX& p) const;
  const std::vector<int>& elementDofs(size_t e) const { return elemDofs_[e]; }
  /// The element mass matrices at p (empty: no mass), kept while p stays the same: mass is
  /// configuration independent (the integrators assemble M once per run on that premise), and
  /// each Newton matrix used to evaluate every element's again (flexible five-bar: 3% of a run).
  const std::vector<MatX>& elementMasses(const VecX& p) const;
  const std::vector<int>& constraintDofs(size_t c) const { return consDofs_[c]; }
  int constraintRow(size_t c) const { return consRow_[c]; }

 private:
  std::vector<int> dofMap(const std::vector<int>& nodes, int gradients) const;
  /// An m-vector with each driver's rows pick(c, Phi_t, Phi_qt, g, g_q) at (q, v), zero elsewhere.
  template <class Pick>
  VecX driverRows(const VecX& q, const VecX& v, const VecX& p, Pick pick) const;
  /// Sum of the elements' forces at (q, v); with potentialOnly, of those with a potential.
  void elementForces(const VecX& q, const VecX& v, const VecX& p, bool potentialOnly, VecX& Q) const;
  // The local derivative kernels, analytic or AD by derivatives_ (the loops are shared).
  void elementForceJacobian(const Element& el, const LocalState& s, MatX& dQdq, MatX& dQdv) const;
  bool elementParameterDerivative(const Element& el, const LocalState& s, int k, VecX& dQ,
                                  MatX& dM) const;
  void constraintJacobian(const Constraint& co, const LocalState& s, MatX& J) const;
  void constraintHessian(const Constraint& co, const LocalState& s, int r, MatX& H) const;
  bool constraintParameterDerivative(const Constraint& co, const LocalState& s, int k, VecX& dphi,
                                     MatX& dJ) const;
  const Model& model_;
  const ConstraintList& cons_;
  int m_ = 0;
  std::vector<std::vector<int>> elemDofs_, consDofs_;
  std::vector<int> consRow_;
  std::vector<int> consRowsLocal_;
  /// Gravity at the p of the current evaluation when a component is a design parameter
  /// (elements read gravity through a pointer). Makes an Assembler single-threaded.
  mutable VecX gravityAtP_;
  /// The local state of nodes (gradients per node as in LocalState) at (q, v, p) into s, the
  /// entries' dofs from map (dofMap(nodes, gradients): elemDofs_, consDofs_).
  void gatherLocalState(LocalState& s, const std::vector<int>& nodes, const std::vector<int>& map, const VecX& q,
                        const VecX& v, const VecX& p, int gradients) const;
  void setEvaluationPoint(LocalState& s, const VecX& p) const;  ///< p, t and gravity of s
  /// r[map[j]] += (J^T l)_j for the entries map[j] >= 0.
  static void addTransposeTimes(const MatX& J, const std::vector<int>& map, Eigen::Ref<const VecX> l, VecX& r);
  /// A local state and the kernel outputs (Q or phi; dQ/dq or Phi_q; dQ/dv or a Hessian row)
  /// shared by the elements (constraints) of one local shape: local size (and rows). Each
  /// kernel writes the same sizes at every call, so nothing is resized from one element to the
  /// next (one buffer for all kernels was freed and allocated from kernel to kernel: malloc and
  /// free ~16% of the n = 8 flexible five-bar's run), and the few buffers stay in cache (one
  /// per element was 13 MB on the shell panel at n = 24495, where gathering the local states
  /// took 14% of the run against 5% at n = 1800).
  struct Scratch {
    LocalState state;
    VecX vec;
    MatX a, b;
  };
  mutable std::vector<Scratch> scratch_;
  std::vector<size_t> elemScratch_, consScratch_;  ///< each element's / constraint's scratch_ entry
  void assignScratch();
  std::vector<std::vector<int>> consRows_;  ///< each constraint's global rows (consRow_ on)
  /// Per design parameter k: the elements (constraints) whose Q or M (Phi) depend on it, found
  /// at the first derivative with respect to k by asking each one (a kernel's "false" is
  /// structural: no property or time function of it is bound to k). The parameter loops then
  /// visit only those, not every element once per parameter and step.
  const std::vector<int>& elementsDependingOn(int k, const VecX& q, const VecX& v, const VecX& p) const;
  const std::vector<int>& constraintsDependingOn(int k, const VecX& q, const VecX& p) const;
  mutable std::vector<std::optional<std::vector<int>>> paramElements_, paramConstraints_;  ///< by k
  mutable std::vector<MatX> masses_;
  mutable VecX paramDphi_;  ///< constraintParamTerms' per-constraint storage
  mutable MatX paramDJ_;
  mutable VecX paramDQ_;    ///< forceParamDerivative's and massParamDerivativeTimes' element storage
  mutable MatX paramDM_;
  /// Per constraint with a constant Hessian: its structural nonzeros (column-major local
  /// indices j nl + i), found at the first addHessian.
  mutable std::vector<std::optional<std::vector<int>>> hessianPattern_;
  mutable std::vector<double> hessianValues_;  ///< addHessian's sums over a pattern, kept
  mutable std::optional<VecX> massesAt_;  ///< the p of masses_ and massDerivatives_
  /// dM_e/dp_k of the elements whose mass depends on p_k, kept like masses_ (the sensitivity
  /// right-hand sides asked for them at every step and parameter: 8% of the five-bar's run
  /// with ten parameters).
  const std::vector<std::pair<int, MatX>>& elementMassDerivatives(const VecX& p, int k) const;
  mutable std::vector<std::optional<std::vector<std::pair<int, MatX>>>> massDerivatives_;  ///< by k
  bool gravityBound_ = false;
  mutable double loadFactor_ = 1.0;
  mutable double time_ = 0.0;
  bool rheonomic_ = false;
  Derivatives derivatives_ = Derivatives::Analytic;
};

}  // namespace flexsens
