// A fill-reducing ordering for the saddle-point matrices [A  B^T; B  0] flexsens factorizes
// (Newton, iteration and augmented matrices). Unknowns with a nonzero diagonal are primal
// (coordinates, velocities), the others multipliers. AMD orders the primal unknowns on the graph
// of A + B^T B (two that share a constraint are neighbours), and each multiplier follows the
// last of its primal neighbours that is not dense. So when the LU reaches a multiplier, its
// neighbours are eliminated and its pivot is the Schur entry -b A^{-1} b^T, not a structural
// zero: the factorization keeps the diagonal and the fill stays what AMD predicted.
// (bench/linear/results.md: KLU's AMD on the whole matrix pivots off the zero diagonals and
// fills 5-18x nnz(A) on the satellite; this ordering 1.3x.)
#pragma once

#include <vector>

#include "core/Types.hpp"

namespace flexsens {

/// The ordering as a permutation: position k holds the unknown eliminated k-th.
std::vector<int64_t> saddlePointOrdering(const SpMat& A);

}  // namespace flexsens
