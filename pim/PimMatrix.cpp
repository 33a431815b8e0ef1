#include "pim/PimMatrix.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/MemoryBudget.hpp"

namespace flexsens {

namespace {

/// Iterates x <- apply(x) / |.| until the Rayleigh-type estimate |apply(x)| settles (1e-6
/// relative) or 300 iterations; returns the last |apply(x)| and leaves x the converged direction.
template <class Apply>
double powerIterations(VecX& x, const Apply& apply) {
  double estimate = 0.0;
  for (int it = 0; it < 300; ++it) {
    VecX y = apply(x);
    const double next = y.norm();
    if (!(next > 0.0) || !std::isfinite(next)) return next;
    x = y / next;
    if (std::abs(next - estimate) <= 1e-6 * next) return next;
    estimate = next;
  }
  return estimate;
}

/// A start with no special direction: entries 1 + k/n (deterministic), normalized.
VecX startVector(Eigen::Index n) {
  VecX x(n);
  for (Eigen::Index k = 0; k < n; ++k) x[k] = 1.0 + double(k) / double(n);
  return x.normalized();
}

std::string dependentRows(const VecX& u, const std::vector<std::string>& labels) {
  std::ostringstream os;
  const double largest = u.cwiseAbs().maxCoeff();
  for (Eigen::Index r = 0; r < u.size(); ++r)
    if (std::abs(u[r]) > 0.1 * largest) os << " [" << labels[r] << "]";
  return os.str();
}

/// The rank-deficient error when the LU failed: the rows named from the dense SVD when it fits.
[[noreturn]] void throwSingular(const SpMat& A, const std::vector<std::string>& labels, const std::string& what,
                                const std::string& advice, const std::string& luMessage) {
  std::ostringstream os;
  os << what << " is rank-deficient";
  const double n = double(A.rows());
  if (doubles(3.0 * n * n) <= memoryBudget()) {
    const Eigen::BDCSVD<MatX> svd{MatX(A), Eigen::ComputeFullU};
    const VecX sv = svd.singularValues();
    os << " (smallest singular value " << sv[sv.size() - 1] << ", largest " << sv[0] << "); dependent rows:"
       << dependentRows(svd.matrixU().col(sv.size() - 1), labels);
  } else {
    os << " (" << luMessage << "; A is too large for the dense SVD that names the dependent rows)";
  }
  throw NumericalError(os.str() + ". " + advice);
}

}  // namespace

FactoredPimMatrix factorPimMatrix(const SpMat& A, const std::vector<std::string>& labels, const std::string& what,
                                  const std::string& advice) {
  FactoredPimMatrix f;
  f.lu = std::make_unique<SparseLU>();
  try {
    f.lu->factor(A, "PIM matrix A");
  } catch (const NumericalError& e) {
    throwSingular(A, labels, what, advice, e.what());
  }
  VecX x = startVector(A.cols());
  const double largest = std::sqrt(powerIterations(x, [&](const VecX& v) { return VecX(A.transpose() * (A * v)); }));
  VecX v = startVector(A.cols());
  const double inverse = std::sqrt(powerIterations(v, [&](const VecX& y) { return f.lu->solve(f.lu->solveTransposed(y)); }));
  const double smallest = 1.0 / inverse;
  f.condition = largest / smallest;
  if (!(smallest > 1e-12 * largest)) {
    std::ostringstream os;
    os << what << " is rank-deficient (smallest singular value " << smallest << ", largest " << largest
       << "); dependent rows:" << dependentRows(A * v, labels) << ". " << advice;
    throw NumericalError(os.str());
  }
  if (f.condition > 1e10) {
    std::ostringstream os;
    os << what << " is near-singular (condition estimate " << f.condition
       << "); the SDOFs almost depend on each other or on the constraints";
    throw NumericalError(os.str());
  }
  return f;
}

}  // namespace flexsens
