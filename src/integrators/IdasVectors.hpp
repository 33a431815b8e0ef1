// SUNDIALS vectors, matrices and solvers as IdasStepper and IdasAdjoint hold them: RAII owners,
// an Eigen view of a serial N_Vector, and the GGL state y = (q, v, lambda, mu),
// y' = (v, a, ...) (integrators/GglSystem.hpp) as a State.
#pragma once

#include <nvector/nvector_serial.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include <memory>

#include "integrators/State.hpp"

namespace flexsens {

struct VectorDeleter {
  void operator()(_generic_N_Vector* v) const { N_VDestroy(v); }
};
struct MatrixDeleter {
  void operator()(_generic_SUNMatrix* A) const { SUNMatDestroy(A); }
};
struct SolverDeleter {
  void operator()(_generic_SUNLinearSolver* S) const { SUNLinSolFree(S); }
};
using VectorPtr = std::unique_ptr<_generic_N_Vector, VectorDeleter>;

inline Eigen::Map<VecX> view(N_Vector v) { return {N_VGetArrayPointer(v), N_VGetLength(v)}; }

/// The state (t, q, v, lambda, a) held in y, y' of a model of n coordinates and m constraints.
inline State gglState(double t, N_Vector y, N_Vector yp, int n, int m) {
  const auto Y = view(y), D = view(yp);
  State s;
  s.t = t;
  s.q = Y.segment(0, n);
  s.v = Y.segment(n, n);
  s.lambda = Y.segment(2 * n, m);
  s.a = D.segment(n, n);
  return s;
}

}  // namespace flexsens
