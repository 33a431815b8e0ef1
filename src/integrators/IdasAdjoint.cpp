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
  const Assembler* as = nullptr;
  const VecX* p = nullptr;
  const SpMat* M = nullptr;
  const Source* source = nullptr;
  int n = 0, m = 0, objective = 0, which = -1;
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

/// Keeps IDAS' first error message (the cause; IDASolveB echoes it after) in *ud (a string).
void errorHandler(int, const char* module, const char* function, char* msg, void* ud) {
  auto& text = *static_cast<std::string*>(ud);
  if (text.empty()) text = std::string(module) + "/" + function + ": " + msg;
}

void check(int flag, const char* fn, double t, const Backward* b, const std::string& idasError) {
  if (flag >= 0) return;
  std::unique_ptr<char, decltype(&std::free)> name(IDAGetReturnFlagName(flag), &std::free);
  std::ostringstream os;
  os << "IDAS adjoint: " << fn << " failed at t = " << t << " s with " << (name ? name.get() : "an unknown flag");
  if (b && !b->failure.empty()) os << " (" << b->failure << ")";
  else if (!idasError.empty()) os << " (" << idasError << ")";
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

/// One objective's backward problem on IDAS' memory: yB(T) = 0 (no terminal term), yB_q and
/// yB_v differential, the adjoint multipliers algebraic and out of the error test (as forward).
void IdasAdjoint::addBackwardProblem(int objective, const Source& source, const VecX& y0) {
  void* ida = stepper_->memory();
  const int n = as_.n(), m = as_.m(), N = 2 * (n + m), np = int(p_.size());
  const double T = set_.tEnd;
  SUNContext ctx = stepper_->context();
  backward_.push_back(std::make_unique<Backward>());
  Backward& b = *backward_.back();
  b.as = &as_;
  b.p = &p_;
  b.M = &mass_;
  b.source = &source;
  b.n = n;
  b.m = m;
  b.objective = objective;
  b.zero = SpMat(n, n);
  for (VectorPtr* v : {&b.yB, &b.ypB, &b.idB, &b.atolB}) v->reset(N_VNew_Serial(N, ctx));
  b.qB.reset(N_VNew_Serial(std::max(np, 1), ctx));
  for (VectorPtr* v : {&b.yB, &b.ypB, &b.idB, &b.qB}) view(v->get()).setZero();
  view(b.idB.get()).head(2 * n).setOnes();
  view(b.atolB.get()).setConstant(kUntested);
  view(b.atolB.get()).head(2 * n).setConstant(set_.atol);
  auto ok = [&](int flag, const char* fn) { check(flag, fn, T, &b, idasError_); };
  ok(IDACreateB(ida, &b.which), "IDACreateB");
  ok(IDAInitB(ida, b.which, residualB, T, b.yB.get(), b.ypB.get()), "IDAInitB");
  ok(IDASetUserDataB(ida, b.which, &b), "IDASetUserDataB");
  ok(IDASetErrHandlerFn(IDAGetAdjIDABmem(ida, b.which), errorHandler, &idasError_), "IDASetErrHandlerFn");
  ok(IDASVtolerancesB(ida, b.which, set_.rtol, b.atolB.get()), "IDASVtolerancesB");
  ok(IDASetIdB(ida, b.which, b.idB.get()), "IDASetIdB");
  ok(IDASetSuppressAlgB(ida, b.which, SUNTRUE), "IDASetSuppressAlgB");
  ok(IDASetMaxNumStepsB(ida, b.which, kMaxIdasStepsPerFrame), "IDASetMaxNumStepsB");
  // (backwards in time: a negative first step; the same size as the forward one's)
  ok(IDASetInitStepB(ida, b.which, -std::min(1e-6, 1e-3 * set_.frameInterval)), "IDASetInitStepB");
  if (set_.dt > 0) ok(IDASetMaxStepB(ida, b.which, set_.dt), "IDASetMaxStepB");
  // The matrix's size: the forward pattern at the start (the callback reallocates if it grows).
  const Eigen::Index nnz = gglJacobian(as_, p_, y0, 1.0, b.accJacobian).nonZeros();
  b.J.reset(SUNSparseMatrix(N, N, std::max<Eigen::Index>(1, nnz), CSC_MAT, ctx));
  b.LS.reset(sparseLULinearSolver(ctx, b.lu, b.linearFailure));
  if (!b.J || !b.LS) throw NumericalError("IDAS adjoint: could not create the sparse LU linear solver");
  ok(IDASetLinearSolverB(ida, b.which, b.LS.get(), b.J.get()), "IDASetLinearSolverB");
  ok(IDASetJacFnB(ida, b.which, jacobianB), "IDASetJacFnB");
  ok(IDAQuadInitB(ida, b.which, quadratureB, b.qB.get()), "IDAQuadInitB");
  ok(IDAQuadSStolerancesB(ida, b.which, set_.rtol, set_.atol), "IDAQuadSStolerancesB");
  ok(IDASetQuadErrConB(ida, b.which, SUNTRUE), "IDASetQuadErrConB");
}

/// dG/dp at t0 from the backward problem b: -integral yB^T F_p dt + (F_y'^T yB)(t0) . dy0/dp.
VecX IdasAdjoint::gradientAtStart(Backward& b) {
  void* ida = stepper_->memory();
  const double tStart = start_.x.t;
  const int n = as_.n();
  double tret = tStart;
  check(IDAGetB(ida, b.which, &tret, b.yB.get(), b.ypB.get()), "IDAGetB", tStart, &b, idasError_);
  check(IDAGetQuadB(ida, b.which, &tret, b.qB.get()), "IDAGetQuadB", tStart, &b, idasError_);
  const auto lB = view(b.yB.get());
  VecX g(p_.size());
  for (Eigen::Index k = 0; k < g.size(); ++k) {
    const State& s0 = start_.dp[size_t(k)];
    g[k] = view(b.qB.get())[k] + lB.head(n).dot(s0.q) + lB.segment(n, n).dot(mass_ * s0.v);
  }
  void* mb = IDAGetAdjIDABmem(ida, b.which);
  long steps = 0, setups = 0;
  check(IDAGetNumSteps(mb, &steps), "IDAGetNumSteps", tStart, &b, idasError_);
  check(IDAGetNumLinSolvSetups(mb, &setups), "IDAGetNumLinSolvSetups", tStart, &b, idasError_);
  st_.backwardSteps += steps;
  st_.backwardFactorizations += setups;
  return g;
}

MatX IdasAdjoint::backward(int objectives, const Source& source) {
  const auto t0 = std::chrono::steady_clock::now();
  void* ida = stepper_->memory();
  const double tStart = start_.x.t;
  mass_ = as_.mass(p_);
  idasError_.clear();
  check(IDASetErrHandlerFn(ida, errorHandler, &idasError_), "IDASetErrHandlerFn", set_.tEnd, nullptr, idasError_);
  VecX y0(2 * (as_.n() + as_.m()));
  y0 << start_.x.q, start_.x.v, start_.x.lambda, VecX::Zero(as_.m());
  as_.setTime(tStart);
  for (int i = 0; i < objectives; ++i) addBackwardProblem(i, source, y0);
  if (const int flag = IDASolveB(ida, tStart, IDA_NORMAL); flag < 0) {
    const Backward* failed = backward_.front().get();  // the one whose callback failed, if any
    for (const auto& b : backward_)
      if (!b->failure.empty()) failed = b.get();
    check(flag, "IDASolveB", tStart, failed, idasError_);
  }
  MatX G(p_.size(), objectives);
  for (int i = 0; i < objectives; ++i) G.col(i) = gradientAtStart(*backward_[size_t(i)]);
  st_.backwardSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return G;
}

}  // namespace flexsens
