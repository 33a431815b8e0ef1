// The PIM matrix A (square, n x n, sparse) factorized once per case, with its 2-norm condition
// number estimated from the factors (Pim.cpp builds A; the initial sensitivities solve with it).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/SparseLU.hpp"
#include "core/Types.hpp"

namespace flexsens {

struct FactoredPimMatrix {
  std::unique_ptr<SparseLU> lu;  ///< of A
  double condition = 0.0;        ///< sigma_max / sigma_min (estimated: pimCondition)
};

/// Factorizes A and estimates its condition: sigma_max by power iterations on A^T A, sigma_min
/// by inverse iterations (solves with A and A^T from its one LU), each to 1e-6 relative or 300
/// iterations. A rank-deficient A (the LU fails, or sigma_min <= 1e-12 sigma_max) is a NumericalError naming
/// the rows that take part in the dependency (the large entries of the left singular vector of
/// sigma_min: from the dense SVD when the LU failed and A fits the memory budget); a
/// near-singular one (condition above 1e10) one with the estimate. `what` opens the messages
/// ("case 'F1': the PIM matrix A = [...]"); `advice` ends the rank-deficient one.
FactoredPimMatrix factorPimMatrix(const SpMat& A, const std::vector<std::string>& labels, const std::string& what,
                                  const std::string& advice);

}  // namespace flexsens
