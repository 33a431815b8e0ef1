// The Perturbed Initial Model (paper sections 2-4): for a case, the rigidization constraints
// Lambda(q) of its initially undeformed flexible bodies and its SDOFs z(q) complete the
// constraints to a square system
//   A = [Phi_q; Lambda_q; z_q],   A q_p0 = [-Phi_p; -Lambda_p; z_p0]            (eq. 8)
//   A q'_p0 = [-(Phi_q q_p)_q q' - Phi_qp q'; same for Lambda; z'_p0 - (z_q q_p)_q q']  (eq. 9)
// The remaining initial sensitivities (a_p0, lambda_p0) follow from the dynamics. Lambda_q
// holds only the rigidization rows independent of Phi_q and of earlier rows (m_r of them);
// the rows left out must hold for the solution too (checked).
//
// Massless coordinates (parts with `inertia: none`, integrators/InitialState.hpp) are fixed
// neither by rigidization nor by SDOFs but by their equilibrium F_m = (Phi_q^T lambda - Q)_m = 0,
// which holds at the nominal start (equilibrateMassless). Its parameter derivative
//   K_m. q_p + Phi_Cm^T lambda_C,p = (Q_p - Phi_qp^T lambda)_m,   K = -Q_q + H(lambda),
// with the multipliers lambda_C of the constraint rows C touching them as extra unknowns, is
// taken in its eliminated form: multiplied by N^T, N an orthonormal basis of the null space of
// Phi_Cm (the directions the massless coordinates can take with the others held and Phi_C
// kept), it needs no multipliers (those of a Phi_Cm with dependent rows are not determined by the
// equilibrium anyway: the acceleration solve picks them). So A gains e = a - rank(Phi_Cm) rows
// N^T K_m. / kappa (kappa = max |K_mm| [N/m], making them O(1) like the other rows), and the
// required SDOF count becomes d_s = d - m_r - e. Velocities: the quasi-static rate at fixed K,
// N^T K_m. q'_p0 = 0, as masslessSensitivity (exact when the nominal v = 0, as at a deployment
// from rest; otherwise the terms (K_q q_p + K_p) v are left out). A massless body cannot be
// rigidized (its nodes move to equilibrium at t = 0; the reader refuses it).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/Assembler.hpp"
#include "integrators/State.hpp"
#include "pim/Sdof.hpp"

namespace flexsens {

struct PimCase {
  std::string name;
  std::string file;                          ///< scene file, for messages
  std::vector<std::string> rigidized;        ///< bodies rigidized in the PIM
  std::vector<std::string> rigidModel;       ///< bodies modelled rigid in this case (F-R twins)
  std::vector<std::string> parameters;       ///< parameter names of the case
  Assembler::ConstraintList lambda;          ///< Lambda(q, p)
  std::vector<std::unique_ptr<Sdof>> sdofs;  ///< z(q)
};

struct PimReport {
  /// mr: independent rigidization equations kept in A; lambdaGenerated: all the generator
  /// produced; lambdaDropped = lambdaGenerated - mr (rows implied by Phi and earlier rows).
  int n = 0, m = 0, d = 0, mr = 0, ds = 0, lambdaGenerated = 0, lambdaDropped = 0;
  /// Massless coordinates a and their equilibrium rows e = a - rank(Phi_Cm) in A (d_s = d - m_r - e).
  int massless = 0, me = 0;
  double condition = 0.0;  ///< 2-norm condition number of A
  MatX qp, vp;             ///< n x (number of parameters)
};

/// Rows of Lambda_q kept in the PIM matrix: independent of Phi_q's rows and of each other, at
/// (q, p), chosen greedily: Phi's rows first, then the rigidization rows in order, a row kept
/// when it adds a direction to those before it. A rigidized body's equations can be implied by
/// the model's constraints (e.g. the out-of-plane components of a planar cloud whose nodes the
/// model keeps on a plane); keeping them would make A singular. Rows that own a coordinate no
/// other row touches are kept without dense work (RigidizationRows.cpp).
struct LambdaSelection {
  std::vector<int> kept, dropped;  ///< row indices of Lambda, ascending
};
LambdaSelection selectRigidizationRows(const Assembler& as, const Assembler& lambda, const VecX& q,
                                       const VecX& p);

/// n, m, d, m_r (independent rigidization rows), e (massless equilibrium rows),
/// d_s = d - m_r - e (required SDOFs), and the
/// generated/dropped rigidization rows at (q, p), without solving (for `flexsens check`).
/// report.ds is the required count here, not the number of SDOFs the case gives.
PimReport pimCounts(const Assembler& as, const PimCase& c, const VecX& q, const VecX& p);

/// Solves eqs. (8) and (9) at the consistent nominal state s (positions, velocities) and
/// returns the full initial state with sensitivities. Throws InputError for a wrong SDOF
/// count or a body that is not undeformed, NumericalError for a singular or near-singular A or
/// massless coordinates not in equilibrium at s (s.lambda must be the multipliers of s: the
/// equilibrium's K holds H(lambda)).
/// Dependent rigidization rows are left out of A (see selectRigidizationRows); afterwards
/// q_p0 and q'_p0 must satisfy them too, or InputError (the rigidized bodies over-constrain
/// the mechanism for that parameter).
StateWithSens pimInitialState(const Assembler& as, const PimCase& c, const State& s,
                              const VecX& p, PimReport& report);

/// The nonlinear PIM assembly at parameters p: q with Phi(q, p) = 0, Lambda(q, p) = 0,
/// z(q) = z(q0) + z_p0 (p_k - p0_k) and, with massless coordinates, their equilibrium
/// (Phi_q^T lambda - Q)_m = 0 (unknowns q and the multipliers of the rows touching them; Q at
/// v = 0, which massless rows do not depend on) by Newton from q0 (q0 must be the equilibrated
/// nominal start for q(p0) = q0), p differing from p0 in parameter k only. For
/// finite-difference validation (app/FiniteDifferences) and runs at other parameter values
/// (app/ParameterValues).
VecX perturbedConfiguration(const Assembler& as, const PimCase& c, const VecX& q0,
                            const VecX& p0, const VecX& p, int k);
/// The same for p differing from p0 in any parameters: the SDOF targets move by
/// z_p0 sum_k (p_k - p0_k) (eq. 8 prescribes the same z_p0 for every parameter).
VecX perturbedConfiguration(const Assembler& as, const PimCase& c, const VecX& q0,
                            const VecX& p0, const VecX& p);

}  // namespace flexsens
