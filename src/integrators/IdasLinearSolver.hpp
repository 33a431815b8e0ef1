// IDAS' linear solver: the same sparse LU as the fixed-step integrators (core/SparseLU: KLU in
// the saddle-point ordering), wrapped as a SUNDIALS matrix-based SUNLinearSolver. SUNDIALS'
// own KLU module orders with AMD on the whole matrix and pivots off the zero diagonals of the
// multiplier rows, which fills the GGL iteration matrix like the Newton matrix
// (bench/linear/results.md).
#pragma once

#include <sundials/sundials_linearsolver.h>

#include <string>

#include "core/SparseLU.hpp"

namespace flexsens {

/// A SUNLinearSolver that factorizes the CSC SUNSparseMatrix IDAS hands to setup() with `lu`
/// and solves with it. A failed factorization returns a recoverable failure (IDAS retries with
/// a smaller step) and leaves its message in *failure. Free with SUNLinSolFree.
SUNLinearSolver sparseLULinearSolver(SUNContext ctx, SparseLU& lu, std::string& failure);

}  // namespace flexsens
