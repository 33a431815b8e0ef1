// Redundant constraints handled by elimination: rows of Phi_q that depend on the others at the
// initial positions (rank-revealing QR with column pivoting of Phi_q^T; the rows the pivoting
// leaves last) are left out of the model, so the Newton, IDAS and PIM matrices are regular.
// This is exact while the redundancy persists along the motion (Bricard, a parallelogram with
// a third crank, a planar loop of revolute joints built in 3D: structural redundancy); a run
// checks that the left-out rows stay satisfied (RedundancyMonitor) and is `suspect` otherwise.
// Their reactions are reported as zero: redundant reactions are not unique (the rows kept
// carry the load).
#pragma once

#include <string>
#include <vector>

#include "core/Model.hpp"

namespace flexsens {

/// Pivot threshold relative to the largest: far above the round-off of O(1) entries (1e-16)
/// and far below any physical independence (a 1e-10 rad offset).
inline constexpr double kRedundancyThreshold = 1e-10;
/// n * m^2 up to which the dense QR with column pivoting decides (~0.1 s); larger models use
/// a sparse QR (Eigen::SparseQR, COLAMD order) that flags a column dependent when what is left
/// of it after the earlier ones is below the threshold: the same rank for structural
/// redundancy, but the rows it keeps follow the fill-reducing order, not the largest pivots.
/// (The dense QR cost 40% of a 1-step run of the satellite refined 10x, n = 4815, m = 905.)
inline constexpr double kDenseRedundancyWork = 1e8;

struct DependentRows {
  bool checked = false;         ///< false for a model without constraints (nothing to check)
  int rank = 0;                 ///< numerical rank of Phi_q
  std::vector<int> rows;        ///< global row indices that depend on the others, ascending
  std::vector<std::string> labels;  ///< "constraint" or "constraint[i]" for each
};

/// The dependent rows of Phi_q(q0, p) over `m.constraints` (finalized model).
DependentRows dependentRows(const Model& m, const VecX& q0, const VecX& p);

/// Leaves the dependent rows of m's constraints out (constraints/SelectedRows; a constraint
/// whose rows are all dependent goes), renumbers, and returns what was left out. Call after
/// the parameters are bound.
DependentRows leaveOutRedundantRows(Model& m);

}  // namespace flexsens

namespace flexsens {
class Assembler;
/// Largest |Phi_i| of the left-out rows at (q, p); 0 when nothing was left out.
double leftOutViolation(const Model& m, const Assembler& as, const VecX& q, const VecX& p);
}  // namespace flexsens
