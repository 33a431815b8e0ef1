// Basic numeric types shared by every layer.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace flexsens {

using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
/// Vector and matrix of a node's dimension (2 or 3) with inline storage: element kernels that
/// run for every element at every Newton iteration use them instead of heap-allocated VecX.
using VecUpTo3 = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, 3, 1>;
using MatUpTo3 = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 3, 3>;
/// Compressed-column sparse matrix with 64-bit indices, the layout SUNDIALS' KLU wants.
using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int64_t>;

/// A scalar model quantity (length, stiffness, mass, ...), either a constant or bound to a
/// design parameter p[param]. Elements read it through value(p) so that the model itself
/// stays immutable while parameters are perturbed.
struct Quantity {
  double constant = 0.0;
  int param = -1;  ///< index into p, or -1
  double value(const VecX& p) const { return param >= 0 ? p[param] : constant; }
  bool boundTo(int k) const { return param == k; }
};

/// Error in user input (scene file, command line): message already names file:line and key.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Numerical failure (Newton, singular matrix, integrator): message names time, step, quantity.
struct NumericalError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A result file or directory could not be written: message names the path and the OS reason.
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Another run holds the output directory's lock.
struct DirectoryBusy : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace flexsens
