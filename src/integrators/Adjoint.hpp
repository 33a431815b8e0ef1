// The discrete adjoint of a fixed-step run (the trapezoidal rule, BDF-1, generalized-alpha,
// the implicit midpoint rule): the exact gradient dJ/dp of an objective J = sum_n j_n(q_n, v_n)
// of the discrete solution, with one backward sweep whatever the number of parameters.
//
// A step maps the carried state y_n = (q_n, v_n, a_n, w_n) (w: generalized-alpha's
// pseudo-acceleration) to y_{n+1} through the solution x = (q_{n+1}, sigma lambda_{n+1}) of
// r(x; y_n, p) = 0 (integrators/StepEquations.hpp), and the forward sensitivities are
//   A dx = -(R_y dy_n + R_p),   dy_{n+1} = G_x dx + G_y dy_n
// (integrators/StepSensitivity.hpp). The adjoint runs this backwards with the transposes:
//   A^T W = G_x^T mu_{n+1},  dJ/dp += -W^T R_p,  mu_n = G_y^T mu_{n+1} - R_y^T W + dj_n/dy_n,
// with A the same Newton matrix at the converged point, and ends with
// dJ/dp += mu_0 . dy_0/dp, the initial sensitivities (PIM case or least-norm rule).
//
// Memory: the forward pass keeps every k-th state (checkpoints) and the states since the last
// one; the sweep recomputes each earlier segment of k steps from its checkpoint, so about
// N/k + k states are held at once instead of N (N steps).
#pragma once

#include <functional>
#include <vector>

#include "core/Assembler.hpp"
#include "integrators/Settings.hpp"
#include "integrators/State.hpp"

namespace flexsens {

struct AdjointStatistics {
  long checkpointEvery = 0;     ///< k
  long checkpoints = 0;         ///< states kept by the forward pass at multiples of k
  long recomputedSteps = 0;     ///< steps taken again from the checkpoints
  long peakStates = 0;          ///< states held at once (checkpoints + one segment)
  double peakStateBytes = 0.0;  ///< their memory [bytes]
  long backwardSteps = 0, backwardFactorizations = 0;
  double forwardSeconds = 0.0, backwardSeconds = 0.0;  ///< wall time of the two passes [s]
};

/// The methods that have a discrete adjoint, for messages.
inline constexpr const char* kAdjointIntegrators = "trapezoidal, bdf1, generalized_alpha and midpoint";
bool hasAdjoint(const std::string& integrator);

/// The checkpoint interval k for a run of `steps` steps whose states take `stateBytes` each:
/// `requested` when positive; else every state (k = steps) when all fit in a quarter of the
/// memory budget (core/MemoryBudget.hpp), else ceil(sqrt(steps + 1)); InputError when even
/// that exceeds the budget.
long checkpointInterval(long steps, double stateBytes, long requested);

/// The adjoints of the start state (q_0, v_0, a_0), one column per objective: dJ/dp gets
/// dq_0/dp^T q + dv_0/dp^T v + da_0/dp^T a from the initial sensitivities.
struct StartAdjoints {
  MatX q, v, a;
  /// A parameter's row of those terms (one entry per objective), d its initial sensitivity.
  Eigen::RowVectorXd termsOf(const State& d) const {
    return d.q.transpose() * q + d.v.transpose() * v + d.a.transpose() * a;
  }
};

class DiscreteAdjoint {
 public:
  /// Adds column i of gq (n x objectives) += dJ_i/dq_n and of gv += dJ_i/dv_n at step n, state x.
  using Source = std::function<void(long n, const State& x, MatX& gq, MatX& gv)>;

  /// InputError for a scheme without an adjoint (IDAS, maggi_rk4) or with projections.
  DiscreteAdjoint(const Assembler& as, const VecX& p, const StateWithSens& start, const IntegratorSettings& set,
                  long checkpointEvery);
  /// The forward pass: integrates without sensitivities, `obs` seeing each step as in a run
  /// (stepped at every step: the objective's samples, the energy audit), keeping checkpoints.
  IntegratorStats forward(Observer& obs);
  /// The backward sweep: dJ_i/dp, one column per objective (parameters x objectives), with the
  /// initial sensitivities' terms when the start carries them (start.dp); without them (a
  /// start of no dp) the caller adds those terms from startAdjoints().
  MatX backward(int objectives, const Source& source);
  const StartAdjoints& startAdjoints() const { return startAdjoints_; }
  const AdjointStatistics& statistics() const { return st_; }

 private:
  /// The states of steps c ... c + len, recomputed from the checkpoint at step c.
  std::vector<State> recompute(long c, long len);
  void addPeak(size_t held);

  const Assembler& as_;
  const VecX p_;
  const StateWithSens& start_;
  const IntegratorSettings set_;
  long steps_ = 0;
  double stateBytes_ = 0.0;
  std::vector<State> checkpoints_;  ///< at steps 0, k, 2k, ...
  std::vector<State> tail_;         ///< the last segment, from the last checkpoint to the end
  AdjointStatistics st_;
  StartAdjoints startAdjoints_;
};

}  // namespace flexsens
