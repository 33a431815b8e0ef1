// One fixed step's nonlinear equations in the unknowns x = (q_{n+1}, l = sigma lambda_{n+1}):
//   r(x) = [ sigma (M a(q) - Q(qf, vf)) + Phi_q(q)^T l ;  Phi(q) ] = 0,   sigma = 1 / ca,
// with a(q), v(q) from the scheme (integrators/Scheme.hpp) and the forces at the scheme's point
// (qf, vf) (q_{n+1}, v_{n+1} but for the midpoint rule), and their Newton matrix dr/dx. The
// equations of a step are set up by begin(); the Newton solver (integrators/NewtonSolver) and
// the sensitivity solver (integrators/StepSensitivity) evaluate them; an adjoint replays them.
#pragma once

#include "core/Assembler.hpp"
#include "core/SparseAccumulator.hpp"
#include "integrators/Scheme.hpp"
#include "integrators/State.hpp"

namespace flexsens {

/// The Newton matrix at q_{n+1} = q (time t), with the forces and the reaction at their
/// scheme point (qf, vf) at sc.forceTime(t) (dqf/dq = fw). Leaves the assembler at time t.
SpMat newtonMatrix(const Assembler& as, SparseAccumulator& acc, const VecX& q, const VecX& qf, const VecX& vf,
                   const VecX& lt, const VecX& p, const Scheme& sc, double t);
/// The residual's constraint parts: phi = Phi(q_{n+1}, t_{n+1}), and the reaction
/// phiQTl = Phi_q^T l at the force point (qf, tf) (q_{n+1}, t_{n+1} but for the midpoint rule).
/// Leaves the assembler at time t.
void constraintResidual(const Assembler& as, const Scheme& sc, const VecX& q, const VecX& qf, double t,
                        const VecX& p, const VecX& l, VecX& phi, VecX& phiQTl, VecX& scratch);

class StepEquations {
 public:
  /// residualEvaluations counts every residual evaluated.
  StepEquations(const Assembler& as, const VecX& p, const Scheme& sc, long& residualEvaluations);

  /// The equations of step `step` from `old` (kept by reference until the next begin) to time
  /// t: the history terms, and the assembler at t (index 3: equilibrium, loads and the drivers'
  /// Phi(q, t) all at t_{n+1}).
  void begin(const State& old, double t, long step);
  /// r(q, l), a new vector (the kept parts: no heap traffic but for it).
  VecX residual(const VecX& q, const VecX& l);
  /// The Newton matrix dr/dx at (q, l), assembled into acc (a copy: what the LU factorizes).
  SpMat matrix(SparseAccumulator& acc, const VecX& q, const VecX& l);
  /// The step's end state at the solution (q, l): a, v by the scheme, lambda = l / sigma.
  State solution(const VecX& q, const VecX& l) const;
  /// The force point of the solution: qf = sc.forcePoint(q), vf = sc.forcePoint(v) (views of
  /// kept buffers or of q, v themselves; valid until the next residual or matrix).
  const VecX& forcePositions(const VecX& q);
  const VecX& forceVelocities(const VecX& v);

  const Assembler& assembler() const { return as_; }
  const VecX& parameters() const { return p_; }
  const Scheme& scheme() const { return sc_; }
  const SpMat& mass() const { return M_; }
  double sigma() const { return sigma_; }
  const State& old() const { return *old_; }
  double time() const { return t_; }
  long step() const { return step_; }
  const VecX& abar() const { return abar_; }
  const VecX& vbar() const { return vbar_; }

 private:
  const Assembler& as_;
  const VecX& p_;
  const Scheme& sc_;
  const int n_, m_;
  const SpMat M_;
  const double sigma_;
  long& residualEvaluations_;
  const State* old_ = nullptr;
  double t_ = 0.0;
  long step_ = 0;
  // The step's history terms and the residual's parts, kept across steps and iterations (no
  // heap traffic: with the kernels' temporaries, malloc and free were ~16% of the n = 8
  // flexible five-bar's run).
  VecX abar_, vbar_, aBuf_, vBuf_, forceBuf_;
  VecX phiBuf_, phiQTlBuf_;  // the residual's constraint terms
  VecX phiMidBuf_;           // midpoint: Phi at the force point (unused)
  VecX qfBuf_, vfBuf_;       // the midpoint's force state
};

}  // namespace flexsens
