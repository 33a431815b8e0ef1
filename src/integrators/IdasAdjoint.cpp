#include "integrators/IdasAdjoint.hpp"

#include <idas/idas.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "core/MemoryBudget.hpp"
#include "core/SparseLU.hpp"
#include "integrators/GglSystem.hpp"
#include "integrators/IdasLinearSolver.hpp"
#include "integrators/IdasStepper.hpp"
#include "integrators/InitialState.hpp"

namespace flexsens {

namespace {

Eigen::Map<VecX> view(N_Vector v) { return {N_VGetArrayPointer(v), N_VGetLength(v)}; }

struct VectorDeleter { void operator()(_generic_N_Vector* v) const { N_VDestroy(v); } };
struct MatrixDeleter { void operator()(_generic_SUNMatrix* A) const { SUNMatDestroy(A); } };
struct SolverDeleter { void operator()(_generic_SUNLinearSolver* S) const { SUNLinSolFree(S); } };
using VectorPtr = std::unique_ptr<_generic_N_Vector, VectorDeleter>;

/// Absolute tolerance of the adjoint multipliers: out of the corrector's test (IdasStepper's
/// kUntestedTolerance, the same reason: their corrections are O(1/h) times the others').
constexpr double kUntested = 1e30;

}  // namespace

/// One objective's backward problem: its callbacks' data and SUNDIALS objects.
struct IdasAdjoint::Backward {
  const Assembler* as;
  const VecX* p;
  const SpMat* M;
  const Source* source;
  int n, m, objective, which = -1;
  SparseAccumulator accResidual, accJacobian;
  SpMat zero;  ///< n x n: the sensitivity residual's Q_q, Q_v at zero sensitivity
  SparseLU lu;
  std::string failure, linearFailure;
  VectorPtr yB, ypB, qB, idB, atolB;
  std::unique_ptr<_generic_SUNMatrix, MatrixDeleter> J;
  std::unique_ptr<_generic_SUNLinearSolver, SolverDeleter> LS;

  State state(double t, N_Vector yy, N_Vector yp) const {
    const auto Y = view(yy), D = view(yp);
    State x;
    x.t = t;
    x.q = Y.segment(0, n);
    x.v = Y.segment(n, n);
    x.lambda = Y.segment(2 * n, m);
    x.a = D.segment(n, n);
    return x;
  }
};

namespace {

using Backward = IdasAdjoint::Backward;

/// F_y'^T yB' - F_y^T yB + g_y^T.
int residualB(double t, N_Vector yy, N_Vector yp, N_Vector yyB, N_Vector ypB, N_Vector rrB, void* ud) {
  auto& b = *static_cast<Backward*>(ud);
  try {
    b.as->setTime(t);
    const SpMat& Fy = gglJacobian(*b.as, *b.p, view(yy), 0.0, b.accResidual);
    auto r = view(rrB);
    const auto lB = view(yyB), dB = view(ypB);
    r = -(Fy.transpose() * lB);
    r.head(b.n) += dB.head(b.n);
    r.segment(b.n, b.n) += *b.M * dB.segment(b.n, b.n);
    (*b.source)(t, b.state(t, yy, yp), b.objective, r.head(b.n), r.segment(b.n, b.n));
    return r.allFinite() ? 0 : 1;
  } catch (const std::exception& e) {
    b.failure = e.what();
    return -1;
  }
}

/// dFB/dyB + cjB dFB/dyB' = -(F_y - cjB F_y')^T: the forward iteration matrix at -cjB, transposed.
int jacobianB(double t, double cjB, N_Vector yy, N_Vector, N_Vector, N_Vector, N_Vector, SUNMatrix JB, void* ud,
              N_Vector, N_Vector, N_Vector) {
  auto& b = *static_cast<Backward*>(ud);
  try {
    b.as->setTime(t);
    SpMat A = -SpMat(gglJacobian(*b.as, *b.p, view(yy), -cjB, b.accJacobian).transpose());
    A.makeCompressed();
    if (SUNSparseMatrix_NNZ(JB) < A.nonZeros()) SUNSparseMatrix_Reallocate(JB, A.nonZeros());
    std::memcpy(SUNSparseMatrix_IndexPointers(JB), A.outerIndexPtr(), sizeof(int64_t) * (A.cols() + 1));
    std::memcpy(SUNSparseMatrix_IndexValues(JB), A.innerIndexPtr(), sizeof(int64_t) * A.nonZeros());
    std::memcpy(SUNSparseMatrix_Data(JB), A.valuePtr(), sizeof(double) * A.nonZeros());
    return 0;
  } catch (const std::exception& e) {
    b.failure = e.what();
    return -1;
  }
}

/// yB . F_p per parameter; IDAS integrates it from T back to t0, so qB(t0) = -integral yB^T F_p dt.
int quadratureB(double t, N_Vector yy, N_Vector yp, N_Vector yyB, N_Vector, N_Vector rhsQB, void* ud) {
  auto& b = *static_cast<Backward*>(ud);
  try {
    b.as->setTime(t);
    const VecX y = view(yy), ydot = view(yp), zeros = VecX::Zero(y.size());
    const auto lB = view(yyB);
    auto out = view(rhsQB);
    for (Eigen::Index k = 0; k < out.size(); ++k)
      out[k] = lB.dot(gglSensitivityResidual(*b.as, *b.p, *b.M, y, ydot, int(k), zeros, zeros, b.zero, b.zero));
    return out.allFinite() ? 0 : 1;
  } catch (const std::exception& e) {
    b.failure = e.what();
    return -1;
  }
}

/// IDAS' last error message in the backward pass.
std::string lastIdasError;

void errorHandler(int, const char* module, const char* function, char* msg, void*) {
  if (lastIdasError.empty()) lastIdasError = std::string(module) + "/" + function + ": " + msg;  // the cause, not the echo
}

void check(int flag, const char* fn, double t, const Backward* b) {
  if (flag >= 0) return;
  std::unique_ptr<char, decltype(&std::free)> name(IDAGetReturnFlagName(flag), &std::free);
  std::ostringstream os;
  os << "IDAS adjoint: " << fn << " failed at t = " << t << " s with " << (name ? name.get() : "an unknown flag");
  if (b && !b->failure.empty()) os << " (" << b->failure << ")";
  else if (!lastIdasError.empty()) os << " (" << lastIdasError << ")";
  if (b && !b->linearFailure.empty()) os << "; the last failed factorization: " << b->linearFailure;
  os << "; try a tighter or looser rtol/atol, a smaller maximum step (dt), or --method forward";
  throw NumericalError(os.str());
}

}  // namespace

long idasCheckpointSteps(int stateSize, long requested) {
  if (requested > 0) return requested;
  const double perStep = doubles(2.0 * std::max(stateSize, 1));
  return std::clamp(long(0.25 * memoryBudget() / perStep), 10L, 5000L);
}

IdasAdjoint::IdasAdjoint(const Assembler& as, const VecX& p, const StateWithSens& start, const IntegratorSettings& set,
                         long stepsPerCheckpoint)
    : as_(as), p_(p), start_(start), set_(set) {
  if (!masslessCoordinates(as, p).empty())
    throw InputError("option --method adjoint: integrator idas: the continuous adjoint does not handle massless "
                     "coordinates (inertia: none); use --method forward, or a fixed-step integrator (" +
                     std::string(kAdjointIntegrators) + ") whose discrete adjoint does");
  StateWithSens plain;
  plain.x = start.x;
  stepper_ = std::make_unique<IdasStepper>(as, p, plain, set);
  st_.checkpointEvery = idasCheckpointSteps(2 * (as.n() + as.m()), stepsPerCheckpoint);
  stepper_->enableAdjoint(st_.checkpointEvery);
}

IdasAdjoint::~IdasAdjoint() { stepper_.reset(); }

IntegratorStats IdasAdjoint::forward(Observer& obs, const IdasStepHook& afterStep) {
  const auto t0 = std::chrono::steady_clock::now();
  StateWithSens plain;
  plain.x = start_.x;
  const IntegratorStats stats = integrateIdas(*stepper_, plain, set_, obs, afterStep);
  st_.checkpoints = stepper_->checkpoints() + 1;  // IDAS' count leaves out the one at the start
  st_.forwardSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

MatX IdasAdjoint::backward(int objectives, const Source& source) {
  const auto t0 = std::chrono::steady_clock::now();
  void* ida = stepper_->memory();
  const int n = as_.n(), m = as_.m(), N = 2 * (n + m), np = int(p_.size());
  const double T = set_.tEnd, tStart = start_.x.t;
  const SpMat M = as_.mass(p_);
  lastIdasError.clear();
  check(IDASetErrHandlerFn(ida, errorHandler, nullptr), "IDASetErrHandlerFn", T, nullptr);
  VecX y0 = VecX::Zero(N);  // the start, to size the matrices' pattern
  y0 << start_.x.q, start_.x.v, start_.x.lambda, VecX::Zero(m);
  as_.setTime(tStart);
  for (int i = 0; i < objectives; ++i) {
    backward_.push_back(std::make_unique<Backward>());
    Backward& b = *backward_.back();
    b.as = &as_;
    b.p = &p_;
    b.M = &M;
    b.source = &source;
    b.n = n;
    b.m = m;
    b.objective = i;
    b.zero = SpMat(n, n);
    SUNContext ctx = stepper_->context();
    b.yB.reset(N_VNew_Serial(N, ctx));
    b.ypB.reset(N_VNew_Serial(N, ctx));
    b.qB.reset(N_VNew_Serial(std::max(np, 1), ctx));
    b.idB.reset(N_VNew_Serial(N, ctx));
    b.atolB.reset(N_VNew_Serial(N, ctx));
    view(b.yB.get()).setZero();  // F_y'^T yB(T) = 0: no terminal term
    view(b.ypB.get()).setZero();
    view(b.qB.get()).setZero();
    view(b.idB.get()).setZero();
    view(b.idB.get()).head(2 * n).setOnes();  // yB_q, yB_v differential, the rest algebraic
    view(b.atolB.get()).setConstant(kUntested);
    view(b.atolB.get()).head(2 * n).setConstant(set_.atol);
    check(IDACreateB(ida, &b.which), "IDACreateB", T, &b);
    check(IDAInitB(ida, b.which, residualB, T, b.yB.get(), b.ypB.get()), "IDAInitB", T, &b);
    check(IDASetUserDataB(ida, b.which, &b), "IDASetUserDataB", T, &b);
    check(IDASetErrHandlerFn(IDAGetAdjIDABmem(ida, b.which), errorHandler, nullptr), "IDASetErrHandlerFn", T, &b);
    check(IDASVtolerancesB(ida, b.which, set_.rtol, b.atolB.get()), "IDASVtolerancesB", T, &b);
    check(IDASetIdB(ida, b.which, b.idB.get()), "IDASetIdB", T, &b);
    check(IDASetSuppressAlgB(ida, b.which, SUNTRUE), "IDASetSuppressAlgB", T, &b);
    check(IDASetMaxNumStepsB(ida, b.which, kMaxIdasStepsPerFrame), "IDASetMaxNumStepsB", T, &b);
    check(IDASetInitStepB(ida, b.which, -std::min(1e-6, 1e-3 * set_.frameInterval)), "IDASetInitStepB", T, &b);
    if (set_.dt > 0) check(IDASetMaxStepB(ida, b.which, set_.dt), "IDASetMaxStepB", T, &b);
    // The matrix's pattern: the forward one transposed (assembled once to size it).
    b.J.reset(SUNSparseMatrix(N, N, std::max<Eigen::Index>(1, gglJacobian(as_, p_, y0, 1.0, b.accJacobian).nonZeros()),
                              CSC_MAT, ctx));
    b.LS.reset(sparseLULinearSolver(ctx, b.lu, b.linearFailure));
    check(IDASetLinearSolverB(ida, b.which, b.LS.get(), b.J.get()), "IDASetLinearSolverB", T, &b);
    check(IDASetJacFnB(ida, b.which, jacobianB), "IDASetJacFnB", T, &b);
    check(IDAQuadInitB(ida, b.which, quadratureB, b.qB.get()), "IDAQuadInitB", T, &b);
    check(IDAQuadSStolerancesB(ida, b.which, set_.rtol, set_.atol), "IDAQuadSStolerancesB", T, &b);
    check(IDASetQuadErrConB(ida, b.which, SUNTRUE), "IDASetQuadErrConB", T, &b);
  }
  check(IDASolveB(ida, tStart, IDA_NORMAL), "IDASolveB", tStart, backward_.empty() ? nullptr : backward_.front().get());
  MatX G(np, objectives);
  for (int i = 0; i < objectives; ++i) {
    Backward& b = *backward_[size_t(i)];
    double tret = tStart;
    check(IDAGetB(ida, b.which, &tret, b.yB.get(), b.ypB.get()), "IDAGetB", tStart, &b);
    check(IDAGetQuadB(ida, b.which, &tret, b.qB.get()), "IDAGetQuadB", tStart, &b);
    const auto lB = view(b.yB.get());
    for (int k = 0; k < np; ++k) {
      const State& s0 = start_.dp[size_t(k)];  // (F_y'^T yB)(t0) . dy0/dp_k
      G(k, i) = view(b.qB.get())[k] + lB.head(n).dot(s0.q) + lB.segment(n, n).dot(M * s0.v);
    }
    void* mb = IDAGetAdjIDABmem(ida, b.which);
    long steps = 0, setups = 0;
    IDAGetNumSteps(mb, &steps);
    IDAGetNumLinSolvSetups(mb, &setups);
    st_.backwardSteps += steps;
    st_.backwardFactorizations += setups;
  }
  st_.backwardSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return G;
}

}  // namespace flexsens
