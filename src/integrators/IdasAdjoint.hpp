// The continuous-time adjoint of an IDAS run (SUNDIALS IDAS' adjoint module) for objectives
// G_i = integral over [t0, T] of g_i(t, y) dt on the GGL form F(t, y, y', p) = 0
// (integrators/GglSystem.hpp). The forward pass is the IDAS run without sensitivities, with
// IDAS' checkpoints (IDAAdjInit, Hermite interpolation between the stored steps); the backward
// problem of each objective is the adjoint DAE
//   F_y'^T yB' - F_y^T yB + g_y^T = 0
// (F_y' = diag(I, M, 0, 0) is constant), solved from T back to t0 by IDASolveB with the
// transposed iteration matrix -(F_y - cjB F_y')^T in the same sparse LU, and
//   dG/dp = -integral of yB^T F_p dt + (F_y'^T yB)(t0) . dy0/dp + c_p
// (IDAQuadB for the integral; dy0/dp the initial sensitivities, PIM case or least-norm rule).
// Without a terminal part yB_q(T) = yB_v(T) = 0 and c_p = 0. A terminal part phi(q(T), v(T))
// (at t_end only) sets them so that phi_y s = (F_y'^T yB)(T) . s for every s(T) the
// constraints' sensitivities allow (yB_q, yB_v in the null space of Phi_q: projections,
// M-weighted for the velocities; terminalCondition), the rest being c_p = -w . (Phi_q v +
// Phi_t)_p - z . Phi_p with w, z those projections' multipliers. The adjoint multipliers and
// yB'(T) are then made consistent (consistentStart).
// This differentiates the exact solution, not the discrete one: it agrees with IDAS' forward
// sensitivities to the integration tolerance, not to round-off.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/Assembler.hpp"
#include "integrators/Adjoint.hpp"
#include "integrators/Idas.hpp"
#include "integrators/Settings.hpp"
#include "integrators/State.hpp"

namespace flexsens {

class IdasStepper;

/// IDAS steps between two checkpoints: `requested` when positive, else as many as a quarter
/// of the memory budget holds (two vectors of `stateSize` doubles per step, Hermite), at most
/// 5000 and at least 10.
long idasCheckpointSteps(int stateSize, long requested);

class IdasAdjoint {
 public:
  /// Adds dg_i/dq and dg_i/dv at time t [s] and state x into gq, gv (i = objective).
  using Source = std::function<void(double t, const State& x, int objective, Eigen::Ref<VecX> gq, Eigen::Ref<VecX> gv)>;

  /// InputError for a model with massless coordinates (their algebraic adjoint is not set up).
  IdasAdjoint(const Assembler& as, const VecX& p, const StateWithSens& start, const IntegratorSettings& set,
              long stepsPerCheckpoint);
  ~IdasAdjoint();
  IdasAdjoint(const IdasAdjoint&) = delete;
  IdasAdjoint& operator=(const IdasAdjoint&) = delete;

  /// The forward pass (IDASolveF), `obs` and `afterStep` seeing it as in integrateIdas.
  IntegratorStats forward(Observer& obs, const IdasStepHook& afterStep);
  /// Adds dphi_i/dq and dphi_i/dv of objective i's terminal part phi_i(q(T), v(T)) at the
  /// final state x into phiQ, phiV (zero: none).
  using Terminal = std::function<void(const State& x, int objective, Eigen::Ref<VecX> phiQ, Eigen::Ref<VecX> phiV)>;

  /// The backward problems, one per objective: dG_i/dp (parameters x objectives).
  MatX backward(int objectives, const Source& source, const Terminal& terminal = {});
  const AdjointStatistics& statistics() const { return st_; }

  struct Backward;

 private:
  void addBackwardProblem(int objective, const Source& source, const VecX& y0, const VecX& yBT, const VecX& ypBT);
  VecX saddleSolve(bool massMetric, const VecX& q, const VecX& rhs) const;
  VecX velocityConstraintGradientTimes(const State& xT, const VecX& w) const;
  VecX terminalCondition(const State& xT, const VecX& phiQ, const VecX& phiV, VecX& yBT) const;
  void consistentStart(const State& xT, const VecX& yT, int objective, const Source& source, VecX& yBT, VecX& ypBT);
  VecX gradientAtStart(Backward& b);

  const Assembler& as_;
  const VecX p_;
  const StateWithSens& start_;
  const IntegratorSettings set_;
  SpMat mass_;                ///< M(p), constant: F_y' = diag(I, M, 0, 0)
  std::string idasError_;     ///< IDAS' first error message of the backward pass
  std::vector<std::unique_ptr<Backward>> backward_;
  std::unique_ptr<IdasStepper> stepper_;  ///< destroyed first (~IdasAdjoint): IDAS' memory before the B objects
  AdjointStatistics st_;
};

}  // namespace flexsens
