#include "integrators/IdasLinearSolver.hpp"

#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_sparse.h>

namespace flexsens {

namespace {

struct Content {
  SparseLU* lu;
  std::string* failure;
  SpMat A;  ///< the matrix of the last setup, as Eigen's CSC
  MatX rhs;  ///< solve()'s workspace (one column)
  long lastFlag = 0;
};

Content& content(SUNLinearSolver S) { return *static_cast<Content*>(S->content); }

SUNLinearSolver_Type type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int initialize(SUNLinearSolver) { return SUNLS_SUCCESS; }

int setup(SUNLinearSolver S, SUNMatrix J) {
  Content& c = content(S);
  const int64_t N = SUNSparseMatrix_Columns(J);
  const int64_t* outer = SUNSparseMatrix_IndexPointers(J);
  c.A = Eigen::Map<const SpMat>(N, N, outer[N], outer, SUNSparseMatrix_IndexValues(J), SUNSparseMatrix_Data(J));
  try {
    c.lu->factor(c.A, "IDAS iteration matrix");
    c.lastFlag = SUNLS_SUCCESS;
  } catch (const std::exception& e) {
    *c.failure = e.what();
    c.lastFlag = SUNLS_PACKAGE_FAIL_REC;
  }
  return int(c.lastFlag);
}

int solve(SUNLinearSolver S, SUNMatrix, N_Vector x, N_Vector b, realtype) {
  Content& c = content(S);
  const int64_t N = N_VGetLength(b);
  c.rhs = Eigen::Map<const VecX>(N_VGetArrayPointer(b), N);
  c.lu->solve(c.rhs);
  Eigen::Map<VecX>(N_VGetArrayPointer(x), N) = c.rhs.col(0);
  c.lastFlag = c.rhs.allFinite() ? SUNLS_SUCCESS : SUNLS_PACKAGE_FAIL_REC;
  return int(c.lastFlag);
}

sunindextype lastFlag(SUNLinearSolver S) { return content(S).lastFlag; }

int destroy(SUNLinearSolver S) {
  if (!S) return SUNLS_SUCCESS;
  delete static_cast<Content*>(S->content);
  S->content = nullptr;
  SUNLinSolFreeEmpty(S);
  return SUNLS_SUCCESS;
}

}  // namespace

SUNLinearSolver sparseLULinearSolver(SUNContext ctx, SparseLU& lu, std::string& failure) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (!S) return nullptr;
  S->ops->gettype = type;
  S->ops->getid = id;
  S->ops->initialize = initialize;
  S->ops->setup = setup;
  S->ops->solve = solve;
  S->ops->lastflag = lastFlag;
  S->ops->free = destroy;
  S->content = new Content{&lu, &failure, SpMat(), MatX(), 0};
  return S;
}

}  // namespace flexsens
