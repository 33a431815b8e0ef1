// Redundant constraints: rows of Phi_q that depend on the others at a configuration (a planar
// loop of revolute joints built in 3D, a closed loop with one distance too many). Found by a
// rank-revealing QR (column pivoting) of Phi_q^T; the rows the pivoting leaves last are the
// dependent ones. Dense: models with n * m up to kMaxEntries only.
#pragma once

#include <string>
#include <vector>

#include "core/Assembler.hpp"

namespace flexsens {

struct RedundancyReport {
  bool checked = false;  ///< false when the model is too large for the dense check
  int rows = 0;          ///< m
  int rank = 0;          ///< numerical rank of Phi_q
  std::vector<std::string> dependent;  ///< labels of rows that depend on the others
  double tolerance = 0;  ///< rank threshold relative to the largest |R_ii|
};

inline constexpr double kMaxRedundancyEntries = 4e7;  ///< n * m of the dense check (320 MB)

RedundancyReport constraintRedundancy(const Assembler& as, const VecX& q, const VecX& p);

}  // namespace flexsens
