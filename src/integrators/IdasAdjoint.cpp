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
#include "integrators/IdasVectors.hpp"
#include "integrators/InitialState.hpp"

namespace flexsens {

namespace {

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

  State state(double t, N_Vector yy, N_Vector yp) const { return gglState(t, yy, yp, n, m); }
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

/// One objective's backward problem on IDAS' memory from yB(T) = yBT, yB'(T) = ypBT; yB_q and
/// yB_v differential, the adjoint multipliers algebraic and out of the error test (as forward).
void IdasAdjoint::addBackwardProblem(int objective, const Source& source, const VecX& y0, const VecX& yBT,
                                     const VecX& ypBT) {
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
  view(b.yB.get()) = yBT;
  view(b.ypB.get()) = ypBT;
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

/// x = (u, l) with B u + Phi_q^T l = rhs_u, Phi_q u = rhs_l at q, B = M (massMetric) or I.
VecX IdasAdjoint::saddleSolve(bool massMetric, const VecX& q, const VecX& rhs) const {
  const int n = as_.n(), m = as_.m();
  SparseAccumulator acc;
  acc.begin(n + m, n + m);
  if (massMetric) as_.addMass(acc, p_, 1.0, 0, 0);
  else for (int i = 0; i < n; ++i) acc.add(i, i, 1.0);
  if (m) {
    as_.addPhiQ(acc, q, p_, 1.0, 0, n, true);
    as_.addPhiQ(acc, q, p_, 1.0, n, 0, false);
  }
  SparseLU lu;
  lu.factor(acc.finish(), [&]() { return "IDAS adjoint: the projection onto the constraints at t = " + std::to_string(set_.tEnd) + " s"; });
  return lu.solve(rhs);
}

/// (Phi_q v + Phi_t)_q^T w = H(w) v + Phi_qt^T w at the final state.
VecX IdasAdjoint::velocityConstraintGradientTimes(const State& xT, const VecX& w) const {
  if (as_.m() == 0) return VecX::Zero(as_.n());
  SparseAccumulator qt;
  qt.begin(as_.m(), as_.n());
  as_.addPhiQT(qt, xT.q, p_, 1.0, 0, 0);
  return as_.hessianTimes(xT.q, p_, w, xT.v) + qt.finish().transpose() * w;
}

/// The terminal values yB(T) = (a_q, a_v, 0, 0) for phi(q(T), v(T)) and the explicit term c_p:
///   M a_v + Phi_q^T w = phi_v,  Phi_q a_v = 0;   a_q + Phi_q^T z = phi_q - (Phi_q v + Phi_t)_q^T w,  Phi_q a_q = 0
/// (then phi_y s - a_q . s_q - a_v . M s_v = -w . (Phi_q v + Phi_t)_p - z . Phi_p for every s(T)
/// with Phi_q s_q + Phi_p = 0 and Phi_q s_v + (Phi_q v + Phi_t)_q s_q + (Phi_q v + Phi_t)_p = 0).
VecX IdasAdjoint::terminalCondition(const State& xT, const VecX& phiQ, const VecX& phiV, VecX& yBT) const {
  const int n = as_.n(), m = as_.m();
  const VecX& q = xT.q;
  VecX rhs = VecX::Zero(n + m);
  rhs.head(n) = phiV;
  const VecX xv = saddleSolve(true, q, rhs);
  const VecX w = xv.tail(m);
  rhs.head(n) = phiQ - velocityConstraintGradientTimes(xT, w);
  const VecX xq = saddleSolve(false, q, rhs);
  const VecX z = xq.tail(m);
  yBT.head(n) = xq.head(n);
  yBT.segment(n, n) = xv.head(n);
  VecX c = VecX::Zero(p_.size());
  for (Eigen::Index k = 0; m && k < c.size(); ++k)
    c[k] = -w.dot(as_.phiQParamDerivativeTimes(q, p_, int(k), xT.v) + as_.phiTParamDerivative(q, p_, int(k))) -
           z.dot(as_.phiParamDerivative(q, p_, int(k)));
  return c;
}

/// Given yB_q = a_q, yB_v = a_v at T (in the null space of Phi_q), the adjoint multipliers
/// a_phi, a_psi and the derivatives a_q', a_v' that satisfy the backward DAE and the derivatives
/// of its constraints Phi_q a = 0 (q' = v):
///   M a_v' - Phi_q^T a_psi = r_v,  Phi_q a_v' = -(d/dt Phi_q) a_v
///   a_q' - Phi_q^T a_phi = r_q + (Phi_q v + Phi_t)_q^T a_psi,  Phi_q a_q' = -(d/dt Phi_q) a_q
/// with r = F_y^T (a_q, a_v, 0, 0) - g_y. Zeros there made IDAS' first backward step fail its
/// error test down to h ~ 1e-12 s (ANCF pendulum, terminal y_tip).
void IdasAdjoint::consistentStart(const State& xT, const VecX& yT, int objective, const Source& source, VecX& yBT,
                                  VecX& ypBT) {
  const int n = as_.n(), m = as_.m();
  const VecX& q = xT.q;
  as_.setTime(set_.tEnd);
  SparseAccumulator acc;
  VecX r = gglJacobian(as_, p_, yT, 0.0, acc).transpose() * yBT;
  VecX g = VecX::Zero(2 * n);
  source(set_.tEnd, xT, objective, g.head(n), g.segment(n, n));
  r.head(2 * n) -= g;
  auto rate = [&](const VecX& a) {  // (d/dt Phi_q) a
    return VecX(as_.hessianRowsTimes(q, p_, xT.v, a) + as_.phiQTTimes(q, p_, a));
  };
  VecX rhs(n + m);
  rhs << r.segment(n, n), -rate(yBT.segment(n, n));
  const VecX xv = saddleSolve(true, q, rhs);  // (a_v', -a_psi)
  const VecX aPsi = -xv.tail(m);
  rhs << r.head(n) + velocityConstraintGradientTimes(xT, aPsi), -rate(yBT.head(n));
  const VecX xq = saddleSolve(false, q, rhs);  // (a_q', -a_phi)
  ypBT = VecX::Zero(yBT.size());
  ypBT.head(n) = xq.head(n);
  ypBT.segment(n, n) = xv.head(n);
  yBT.segment(2 * n, m) = -xq.tail(m);
  yBT.segment(2 * n + m, m) = aPsi;
}

MatX IdasAdjoint::backward(int objectives, const Source& source, const Terminal& terminal) {
  const auto t0 = std::chrono::steady_clock::now();
  void* ida = stepper_->memory();
  const double tStart = start_.x.t;
  mass_ = as_.mass(p_);
  idasError_.clear();
  check(IDASetErrHandlerFn(ida, errorHandler, &idasError_), "IDASetErrHandlerFn", set_.tEnd, nullptr, idasError_);
  VecX y0(2 * (as_.n() + as_.m()));
  y0 << start_.x.q, start_.x.v, start_.x.lambda, VecX::Zero(as_.m());
  as_.setTime(tStart);
  // The terminal parts at T (IDAS' last step covers T: the forward pass ended there or beyond).
  const State xT = stepper_->stateAt(set_.tEnd).x;
  VecX yT(y0.size());
  yT << xT.q, xT.v, xT.lambda, VecX::Zero(as_.m());  // (mu = 0 on the exact solution)
  MatX terminalTerms = MatX::Zero(p_.size(), objectives);
  for (int i = 0; i < objectives; ++i) {
    VecX phiQ = VecX::Zero(as_.n()), phiV = VecX::Zero(as_.n()), yBT = VecX::Zero(y0.size()), ypBT;
    if (terminal) terminal(xT, i, phiQ, phiV);
    if (!phiQ.isZero(0.0) || !phiV.isZero(0.0)) terminalTerms.col(i) = terminalCondition(xT, phiQ, phiV, yBT);
    consistentStart(xT, yT, i, source, yBT, ypBT);
    addBackwardProblem(i, source, y0, yBT, ypBT);
  }
  if (const int flag = IDASolveB(ida, tStart, IDA_NORMAL); flag < 0) {
    const Backward* failed = backward_.front().get();  // the one whose callback failed, if any
    for (const auto& b : backward_)
      if (!b->failure.empty()) failed = b.get();
    check(flag, "IDASolveB", tStart, failed, idasError_);
  }
  MatX G(p_.size(), objectives);
  for (int i = 0; i < objectives; ++i) G.col(i) = gradientAtStart(*backward_[size_t(i)]) + terminalTerms.col(i);
  st_.backwardSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return G;
}

}  // namespace flexsens
