// Natural frequencies of the constrained model linearized at a state (`flexsens modes`).
//
// What is linearized: the equations of motion M q'' + Phi_q^T lambda = Q(q, v, p) about the
// state (q, lambda) with the multipliers held at their values there (for the command: the
// consistent initial state, lambda from the initial accelerations). A perturbation dq obeys
//   M dq'' + K dq = 0,   K = -dQ/dq + sum_i lambda_i Phi_i,qq   [N/m],
// restricted to the tangent space Phi_q dq = 0. Velocity terms (dQ/dv damping, gyroscopic
// effects) are left out, and K is replaced by its symmetric part (its asymmetry is reported).
// With an orthonormal basis N of the null space of Phi_q (QR of Phi_q^T, dense):
//   (N^T K N) y = omega^2 (N^T M N) y.
// Massless directions (N^T M N singular: massless parts, see `inertia: none`) are condensed
// statically (their rows are equilibrium equations); a massless direction without stiffness
// is an error naming the coordinates involved. Dense: for models up to a few thousand
// coordinates (the satellite: n = 495, tangent space 390, under a second of CPU).
#pragma once

#include <string>
#include <vector>

#include "core/Assembler.hpp"
#include "integrators/State.hpp"

namespace flexsens {

/// Modal energy of one part (an element's name up to its first '.', e.g. "spring1" for
/// "spring1.segment3"; "constraints" for the term lambda Phi_qq) as a share of the mode's
/// total (strain + kinetic; each is half of it for an eigenmode).
struct EnergyShare {
  std::string part;
  double strain = 0.0;   ///< share of 1/2 x^T K_e x
  double kinetic = 0.0;  ///< share of 1/2 omega^2 x^T M_e x
  double total() const { return strain + kinetic; }
};

struct Mode {
  double omega2 = 0.0;  ///< eigenvalue omega^2 [rad^2/s^2]; negative: unstable direction
  double omega() const;  ///< sqrt(omega2) [rad/s]; -sqrt(-omega2) when negative
  bool rigid = false;    ///< |omega2| below the round-off level of the eigenproblem
  std::vector<EnergyShare> parts;  ///< largest total share first
  /// The shape in the coordinates q (x^T M x = 1), for the modes with energy shares; else empty.
  VecX shape;
};

struct ModalAnalysis {
  int n = 0, m = 0;          ///< coordinates, constraint equations
  int tangent = 0;           ///< dimension of the null space of Phi_q
  int massless = 0;          ///< condensed (massless) directions of the tangent space
  double asymmetry = 0.0;    ///< |K - K^T|_F / |K|_F
  std::vector<Mode> modes;   ///< ascending omega2; energies filled for the ones asked for
  std::string noModes;       ///< why there are none (d = 0, or every direction massless); else empty
};

/// K = -dQ/dq + sum_i lambda_i Phi_i,qq at s.q, s.v, s.lambda (dense, not symmetrized) [N/m].
MatX tangentStiffness(const Assembler& as, const State& s, const VecX& p);

/// Modes of the model at state s (q, lambda). Energy shares are computed for the `count`
/// lowest elastic and `count` highest modes. Throws NumericalError when Phi_q is rank
/// deficient (naming the dependent constraint rows) or a massless direction has no stiffness.
ModalAnalysis analyzeModes(const Assembler& as, const State& s, const VecX& p, int count = 5);

/// InputError (core/MemoryBudget.hpp) when the dense eigenproblem of n coordinates would
/// exceed the memory budget; analyzeModes calls it first, `flexsens modes` before anything.
void requireModesMemory(int n);

/// Rank check of Phi_q at q: throws NumericalError naming the redundant constraint rows.
void requireIndependentConstraints(const Assembler& as, const VecX& q, const VecX& p);

/// Explicit RK4 stability limit on the imaginary axis: |omega dt| <= 2 sqrt(2) = 2.8284; the
/// classical value quoted for RK4 on oscillators is 2.785 (the real-axis limit), used here as the
/// conservative bound dt < 2.785 / omega_max [s].
constexpr double kRk4StabilityLimit = 2.785;
/// A fixed-step implicit scheme resolves a mode when omega dt <= 0.1 (about 63 steps per
/// period: trapezoidal period error (omega dt)^2/12 < 1e-3, BDF-1 amplitude loss ~30% per period).
constexpr double kResolveLimit = 0.1;

/// Indices into a.modes of the modes a report lists: the `count` lowest elastic ones (after the
/// rigid ones) and the `count` highest.
void listedModes(const ModalAnalysis& a, int count, std::vector<int>& low, std::vector<int>& high);

/// Human-readable report (`flexsens modes`) and the same as JSON (`--json`).
std::string modesReport(const ModalAnalysis& a, int count);
std::string modesJson(const ModalAnalysis& a, int count);

}  // namespace flexsens
