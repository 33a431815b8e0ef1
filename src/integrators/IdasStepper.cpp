#include "integrators/IdasStepper.hpp"

#include <idas/idas.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>

#include "integrators/GglSystem.hpp"
#include "integrators/IdasLinearSolver.hpp"
#include "integrators/IdasVectors.hpp"
#include "integrators/InitialState.hpp"

namespace flexsens {

namespace {

// ------------------------------------------------------------ RAII for SUNDIALS objects
struct ContextDeleter { void operator()(SUNContext c) const { SUNContext_Free(&c); } };
struct IdaDeleter { void operator()(void* mem) const { IDAFree(&mem); } };

struct Problem {
  const Assembler* as;
  VecX* p;  ///< IDAS perturbs it in place with the difference-quotient method (dq)
  int n, m;
  SparseAccumulator acc;
  std::vector<int> pinned;   ///< gglPinnedRows
  SparseAccumulator kq, kv;  ///< dQ/dq, dQ/dv for the sensitivity residuals
  double tOfK = 0.0;         ///< time and state kq, kv were assembled at: in the staggered
  VecX yOfK;                 ///< corrector IDAS calls the sensitivity residual at one (t, y)
                             ///< once per iteration; the Jacobians are assembled once for all
  SpMat M;
  VecX pOfM;  ///< parameters M was computed at
  /// The mass matrix at the current p (recomputed only when IDAS has perturbed p).
  const SpMat& mass() {
    // (M.rows() != n: not computed yet, which the parameter test alone misses when there are
    // no parameters: an empty p equals the empty pOfM.)
    if (M.rows() != n || pOfM.size() != p->size() || pOfM != *p) {
      M = as->mass(*p);
      pOfM = *p;
    }
    return M;
  }
  std::string lastError;  ///< last message from IDAS' error handler
  std::string failure;    ///< exception text caught inside a callback
  std::string linearFailure;  ///< the last factorization that failed (IDAS may have recovered)
  std::string sensitivityHint;  ///< appended to step failures: what to try with sensitivities
};


void check(int flag, const char* fn, const Problem& pb, double t) {
  if (flag >= 0) return;
  std::ostringstream os;
  // IDAGetReturnFlagName returns malloc'ed text: the caller frees it.
  std::unique_ptr<char, decltype(&std::free)> name(IDAGetReturnFlagName(flag), &std::free);
  os << "IDAS: " << fn << " failed at t = " << t << " s with " << (name ? name.get() : "an unknown flag");
  if (!pb.failure.empty()) os << " (" << pb.failure << ")";
  else if (!pb.lastError.empty()) os << " (" << pb.lastError << ")";
  if (!pb.linearFailure.empty()) os << "; the last failed factorization: " << pb.linearFailure;
  if (flag == IDA_CONV_FAIL || flag == IDA_ERR_FAIL || flag == IDA_TOO_MUCH_WORK)
    os << "; try a looser rtol/atol, a smaller maximum step (dt), or check the model's "
          "stiffness and initial state"
       << pb.sensitivityHint;
  throw NumericalError(os.str());
}

// ------------------------------------------------------------ callbacks
// Thin wrappers over the GGL functions (integrators/GglSystem; exceptions become return codes).
int residual(double t, N_Vector yy, N_Vector yp, N_Vector rr, void* ud) {
  auto& pb = *static_cast<Problem*>(ud);
  try {
    pb.as->setTime(t);
    auto r = view(rr);
    r = gglResidual(*pb.as, *pb.p, pb.mass(), view(yy), view(yp), pb.pinned);
    return r.allFinite() ? 0 : 1;  // recoverable: IDAS retries with a smaller step
  } catch (const std::exception& e) {
    pb.failure = e.what();
    return -1;
  }
}

int jacobian(double t, double cj, N_Vector yy, N_Vector, N_Vector, SUNMatrix J, void* ud, N_Vector,
             N_Vector, N_Vector) {
  auto& pb = *static_cast<Problem*>(ud);
  try {
    pb.as->setTime(t);
    const SpMat& A = gglJacobian(*pb.as, *pb.p, view(yy), cj, pb.acc, pb.pinned);
    if (SUNSparseMatrix_NNZ(J) < A.nonZeros()) SUNSparseMatrix_Reallocate(J, A.nonZeros());
    std::memcpy(SUNSparseMatrix_IndexPointers(J), A.outerIndexPtr(), sizeof(int64_t) * (A.cols() + 1));
    std::memcpy(SUNSparseMatrix_IndexValues(J), A.innerIndexPtr(), sizeof(int64_t) * A.nonZeros());
    std::memcpy(SUNSparseMatrix_Data(J), A.valuePtr(), sizeof(double) * A.nonZeros());
    return 0;
  } catch (const std::exception& e) {
    pb.failure = e.what();
    return -1;
  }
}

int sensResidual(int Ns, double t, N_Vector yy, N_Vector yp, N_Vector, N_Vector* yS, N_Vector* ypS,
                 N_Vector* rS, void* ud, N_Vector, N_Vector, N_Vector) {
  auto& pb = *static_cast<Problem*>(ud);
  try {
    pb.as->setTime(t);
    const auto y = view(yy);
    // (a perturbed p (dq) never reaches here: dq has no sensitivity residual function)
    if (pb.yOfK.size() != y.size() || t != pb.tOfK || pb.yOfK != y) {
      gglForceJacobians(*pb.as, *pb.p, y, pb.kq, pb.kv);
      pb.yOfK = y;
      pb.tOfK = t;
    }
    for (int k = 0; k < Ns; ++k) {
      auto r = view(rS[k]);
      r = gglSensitivityResidual(*pb.as, *pb.p, pb.mass(), view(yy), view(yp), k, view(yS[k]), view(ypS[k]),
                                 pb.kq.matrix(), pb.kv.matrix(), pb.pinned);
    }
    return 0;
  } catch (const std::exception& e) {
    pb.failure = e.what();
    return -1;
  }
}

void errorHandler(int, const char* module, const char* function, char* msg, void* ud) {
  auto& pb = *static_cast<Problem*>(ud);
  pb.lastError = std::string(module) + "/" + function + ": " + msg;
}

void pack(const State& s, int n, int m, N_Vector y, N_Vector yp) {
  auto Y = view(y), D = view(yp);
  Y.setZero();
  D.setZero();
  Y.segment(0, n) = s.q;
  Y.segment(n, n) = s.v;
  Y.segment(2 * n, m) = s.lambda;
  D.segment(0, n) = s.v;
  D.segment(n, n) = s.a;
}


}  // namespace

static_assert(kIdasTooMuchWork == IDA_TOO_MUCH_WORK, "IdasStepper.hpp's copy of IDAS' flag");

/// Corrector iterations the staggered sensitivity solve may take per step (IDAS' default 4).
constexpr int kIdasSensitivityIterations = 10;
/// The absolute tolerance of a variable the corrector's convergence test leaves out (multipliers,
/// undamped massless velocities): its weight 1e-30 makes any correction pass.
constexpr double kUntestedTolerance = 1e30;

struct IdasStepper::Impl {
  Impl(const Assembler& as, const VecX& p, const StateWithSens& start, const IntegratorSettings& set);
  // ---- setup, in the order IDAS needs it
  void createVectors(const StateWithSens& start);
  void createIda();
  void setTolerances();
  void setOptions();
  void attachLinearSolver();
  // ---- sensitivity configuration
  void configureSensitivities(const StateWithSens& start);
  void prepareNormwiseTolerances();
  void updateSensitivityTolerances(double tNow);
  // ---- the loop's pieces
  int step(double tout, bool updateTolerances);
  StateWithSens stateAt(double tq);
  void readCounters();
  N_Vector newVector() { return N_VNew_Serial(N, ctx.get()); }
  void check(int flag, const char* fn, double tAt) const { flexsens::check(flag, fn, pb, tAt); }

  const Assembler& as;
  const VecX p;  ///< the run's parameters (pWork: IDAS' copy, perturbed in place by dq)
  const IntegratorSettings set;
  const int n, m, N, Ns;
  const double tStart;
  VecX pWork;
  Problem pb;
  double t;
  std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextDeleter> ctx;
  VectorPtr y, yp, id;
  std::vector<int> massless;
  std::unique_ptr<void, IdaDeleter> mem;
  void* ida = nullptr;
  VectorPtr atolv;
  std::unique_ptr<_generic_SUNMatrix, MatrixDeleter> J;
  SparseLU lu;
  std::unique_ptr<_generic_SUNLinearSolver, SolverDeleter> LS;
  std::vector<VectorPtr> yS, ypS;  ///< the initial sensitivities IDAS starts from
  std::vector<N_Vector> ySRaw, ypSRaw;
  VecX pbar;  ///< parameter scales for the difference quotients (alive while IDAS runs)
  bool normwise = false;
  std::vector<VectorPtr> atolS, ySNow;  ///< the absolute tolerances set, the sensitivities reached
  std::vector<N_Vector> atolSRaw, ySNowRaw;
  double stopSet = std::nan("");
  VectorPtr yOut, ypOut;  ///< stateAt's interpolated state and sensitivities
  std::vector<VectorPtr> ySOut, ypSOut;
  std::vector<N_Vector> ySOutRaw, ypSOutRaw;
  IntegratorStats st;
  bool adjoint = false;  ///< IDASolveF (enableAdjoint)
  int checkpoints = 0;   ///< IDASolveF's count
};

IdasStepper::Impl::Impl(const Assembler& as_, const VecX& p_, const StateWithSens& start,
                        const IntegratorSettings& set_)
    : as(as_), p(p_), set(set_), n(as_.n()), m(as_.m()), N(2 * (n + m)), Ns(static_cast<int>(start.dp.size())),
      tStart(start.x.t), pWork(p_), pb{&as_, &pWork, n, m, {}, {}, {}, {}, 0.0, {}, {}, {}, {}, {}, {}, {}},
      t(start.x.t) {
  createVectors(start);
  createIda();
  setTolerances();
  setOptions();
  attachLinearSolver();
  configureSensitivities(start);
  prepareNormwiseTolerances();
  updateSensitivityTolerances(t);
  yOut.reset(newVector());
  ypOut.reset(newVector());
  for (int k = 0; k < Ns; ++k) {
    ySOut.emplace_back(newVector());
    ypSOut.emplace_back(newVector());
    ySOutRaw.push_back(ySOut.back().get());
    ypSOutRaw.push_back(ypSOut.back().get());
  }
}

void IdasStepper::Impl::createVectors(const StateWithSens& start) {
  SUNContext rawCtx = nullptr;
  if (SUNContext_Create(nullptr, &rawCtx) != 0) throw NumericalError("IDAS: SUNContext_Create failed");
  ctx.reset(rawCtx);
  y.reset(newVector());
  yp.reset(newVector());
  id.reset(newVector());
  pack(start.x, n, m, y.get(), yp.get());
  view(id.get()).setZero();
  view(id.get()).head(2 * n).setOnes();  // q, v differential; lambda, mu algebraic
  massless = masslessCoordinates(as, p);  // equilibrium rows: algebraic
  if (n > 0 && static_cast<int>(massless.size()) == n)
    throw InputError("integrator idas: every coordinate is massless (inertia: none), the model is "
                     "static; use bdf1 or trapezoidal (each step an equilibrium) or the static solver");
  for (int i : massless) view(id.get())[i] = view(id.get())[n + i] = 0.0;
  pb.pinned = gglPinnedRows(as, massless);
}

void IdasStepper::Impl::createIda() {
  mem.reset(IDACreate(ctx.get()));
  if (!mem) throw NumericalError("IDAS: IDACreate failed");
  ida = mem.get();
  check(IDASetErrHandlerFn(ida, errorHandler, &pb), "IDASetErrHandlerFn", t);
  check(IDAInit(ida, residual, t, y.get(), yp.get()), "IDAInit", t);
}

void IdasStepper::Impl::setTolerances() {
  // Vector tolerances. The multipliers lambda, mu (index 2 in the GGL form: fixed by q, v) are
  // out of the error test (IDASetId 0, suppressed) and out of the corrector's convergence test:
  // their corrections are O(1/h) times those of q, v. With atol max(atol, sqrt(rtol)) = 1e-4 the
  // corrector's test was ruled by a two-step sawtooth of lambda (bar lengths, the cube's
  // attached point A4; 0.1 N) near the satellite's near-singular configuration; one failure
  // cut h, which made the multipliers' corrections larger, down to h ~ 1e-13 s: the massless
  // satellite SAT2 stopped at t = 1.839 s (rtol 1e-8). With multiplier atol 0.1 and 100 it ran
  // on, the two runs within 1e-7 (x_B2) and 2e-5 (dx_B2/dL) of the largest values up to 2 s.
  // Positions and velocities keep rtol/atol and carry the accuracy: a multiplier off by its
  // correction moves v in the next iteration, which is tested.
  atolv.reset(newVector());
  view(atolv.get()).head(2 * n).setConstant(set.atol);
  view(atolv.get()).tail(2 * m).setConstant(kUntestedTolerance);
  // The velocities of massless coordinates: v_m = q_m' (their q-row) is the BDF derivative of
  // an algebraic q_m, so its Newton correction is cj = O(1/h) times q_m's. With atol 1e-10 the
  // corrector could not converge v_m below ~1e-8 s steps (massless satellite, first step), and
  // wherever a step failed to converge, the cut h made v_m's weighted correction larger, and
  // the next attempt failed too, down to h ~ 1e-11 s, with a well-conditioned iteration matrix:
  // the massless satellite stopped at t = 0.1377 s (rtol 1e-6; now it runs on) and SAT1 at
  // 2.32 s (rtol 1e-8; with this change alone 3.08 s, the later stops are the sensitivity
  // corrector's, below). Unless a velocity-dependent force (damping) acts on q_m, v_m feeds
  // no other equation (the velocity rows of its constraints are pinned), so it leaves the
  // convergence test (a tolerance no correction reaches; it is out of the error test already,
  // IDASetId 0). A
  // damped v_m is part of the equilibrium and keeps max(atol, sqrt(rtol)). q_m keeps rtol/atol.
  if (!massless.empty()) {
    // dQ/dv at the start and at velocities 1 m/s larger (a damper nonlinear in v may have
    // dQ/dv = 0 at rest)
    std::vector<char> damped(n, 0);
    VecX yProbe = view(y.get());
    for (int probe = 0; probe < 2; ++probe, yProbe.segment(n, n).array() += 1.0) {
      SparseAccumulator kq, kv;
      gglForceJacobians(as, p, yProbe, kq, kv);
      for (int c = 0; c < kv.matrix().outerSize(); ++c)
        for (SpMat::InnerIterator it(kv.matrix(), c); it; ++it)
          if (it.value() != 0.0) damped[c] = 1;
    }
    for (int i : massless)
      view(atolv.get())[n + i] = damped[i] ? std::max(set.atol, std::sqrt(set.rtol)) : kUntestedTolerance;
  }
  check(IDASVtolerances(ida, set.rtol, atolv.get()), "IDASVtolerances", t);
}

void IdasStepper::Impl::setOptions() {
  check(IDASetUserData(ida, &pb), "IDASetUserData", t);
  check(IDASetId(ida, id.get()), "IDASetId", t);
  check(IDASetSuppressAlg(ida, SUNTRUE), "IDASetSuppressAlg", t);
  check(IDASetMaxNumSteps(ida, kMaxIdasStepsPerFrame), "IDASetMaxNumSteps", t);
  if (set.dt > 0) check(IDASetMaxStep(ida, set.dt), "IDASetMaxStep", t);
  // IDAS' own first-step estimate makes |h y'| small in the error weights; starting from
  // rest with tight atol that gives h ~ 1e-11 s, where the index-2 iteration matrix
  // (condition ~ 1/h^2) is too ill-conditioned for the corrector. Start at a step that
  // the error test will cut if needed, but not so small.
  check(IDASetInitStep(ida, std::min(1e-6, 1e-3 * set.frameInterval)), "IDASetInitStep", t);
}

void IdasStepper::Impl::attachLinearSolver() {
  // Pattern: assemble once at the initial state to size the sparse matrix.
  {
    VectorPtr tmp(newVector());  // (the Jacobian callback sets the time t)
    std::unique_ptr<_generic_SUNMatrix, MatrixDeleter> probe(SUNSparseMatrix(N, N, 1, CSC_MAT, ctx.get()));
    if (jacobian(t, 1.0, y.get(), yp.get(), tmp.get(), probe.get(), &pb, nullptr, nullptr, nullptr) != 0)
      throw NumericalError("IDAS: Jacobian assembly failed at t = " + std::to_string(t) + ": " + pb.failure);
  }
  J.reset(SUNSparseMatrix(N, N, pb.acc.matrix().nonZeros(), CSC_MAT, ctx.get()));
  LS.reset(sparseLULinearSolver(ctx.get(), lu, pb.linearFailure));
  if (!J || !LS) throw NumericalError("IDAS: could not create the sparse LU linear solver");
  check(IDASetLinearSolver(ida, LS.get(), J.get()), "IDASetLinearSolver", t);
  check(IDASetJacFn(ida, jacobian), "IDASetJacFn", t);
}

void IdasStepper::Impl::configureSensitivities(const StateWithSens& start) {
  if (Ns == 0) return;
  const int corrector = set.sensitivityCorrector == "simultaneous" ? IDA_SIMULTANEOUS : IDA_STAGGERED;
  for (int k = 0; k < Ns; ++k) {
    yS.emplace_back(newVector());
    ypS.emplace_back(newVector());
    ySRaw.push_back(yS.back().get());
    ypSRaw.push_back(ypS.back().get());
    pack(start.dp[k], n, m, yS.back().get(), ypS.back().get());
  }
  if (set.sensitivityMethod == "dq") {
    // IDAS' internal difference quotients (centered) instead of the analytic residual.
    pbar = p.cwiseAbs();
    for (int k = 0; k < Ns; ++k)
      if (pbar[k] == 0.0) pbar[k] = 1.0;
    check(IDASensInit(ida, Ns, corrector, nullptr, ySRaw.data(), ypSRaw.data()), "IDASensInit", t);
    check(IDASetSensParams(ida, pWork.data(), pbar.data(), nullptr), "IDASetSensParams", t);
    check(IDASetSensDQMethod(ida, IDA_CENTERED, 0.0), "IDASetSensDQMethod", t);
  } else {
    check(IDASensInit(ida, Ns, corrector, sensResidual, ySRaw.data(), ypSRaw.data()), "IDASensInit", t);
  }
  check(IDASensEEtolerances(ida), "IDASensEEtolerances", t);
  if (set.sensitivityTolerance == "state")
    pb.sensitivityHint = "; if the sensitivities grow far beyond the state's size (|dq/dp| |p| / L in the "
                         "run health), integrator.sensitivity_tolerance: normwise holds each to rtol "
                         "of its own size";
  // The staggered sensitivity corrector iterates with the state's (possibly older) iteration
  // matrix; IDAS allows it 4 iterations, after which the step fails and h is cut. At rtol
  // 1e-10 the rigid five-bar (case R3) then failed for good at t = 1.436 s, and the massless
  // satellite at rtol 1e-8 at t = 1.69 s; with 10 both run through (the equations are
  // linear: more iterations of a contracting iteration cost no accuracy). The simultaneous
  // corrector's iteration leaves out the coupling of the sensitivities to the state's
  // correction (second derivatives times dq/dp), so it too contracts only linearly where the
  // sensitivities are large: with IDAS' 4 iterations the massless satellite SAT2 (rtol 1e-8)
  // failed for good at t = 4.394 s, with 10 it ran through 5 s.
  if (corrector == IDA_STAGGERED)
    check(IDASetSensMaxNonlinIters(ida, kIdasSensitivityIterations), "IDASetSensMaxNonlinIters", t);
  else  // the simultaneous corrector: the same 10 iterations for state and sensitivities
    check(IDASetMaxNonlinIters(ida, kIdasSensitivityIterations), "IDASetMaxNonlinIters", t);
  check(IDASetSensErrCon(ida, set.sensitivityErrorControl ? SUNTRUE : SUNFALSE), "IDASetSensErrCon", t);
}

// Normwise sensitivity tolerances. IDAS' estimated ones (IDASensEEtolerances) weigh each
// sensitivity component with the state's weight rtol |y_i| + atol_i: an absolute accuracy
// of the state's size. A sensitivity that grows (an unstable motion: the massless
// satellite's dx_B2/dL grows as exp(3.8 t/s), to 1e8 by 6 s) is then asked for ~16 digits:
// its round-off alone fails the corrector's test and the error test whatever h, IDAS cuts h
// to ~1e-11 s and stops (SAT1 at t = 5.93 s, SAT2 at 6.06 s, rtol 1e-8). Normwise, each
// sensitivity vector is held to rtol of its own size: rtol |s_i| + max(atol_i, rtol
// |s_k|_inf), the norm over all of dq/dp and dv/dp (the multipliers stay out of the test).
// That norm is ruled by the largest velocity sensitivities, so the positions' sensitivities
// are held more loosely than rtol of their own size (SAT1, rtol 1e-8: dx_B2/dL 3e-4 off the
// 1e-10 reference by 0.7 s). Tried: the norm taken apart over dq/dp and dv/dp and over the
// tested components only (7.6e-6 off at 0.7 s), but then SAT1 stopped again, at 6.12 s.
// Updated before every step from the sensitivities reached (one pass over them).
void IdasStepper::Impl::prepareNormwiseTolerances() {
  normwise = Ns > 0 && set.sensitivityTolerance == "normwise";
  for (int k = 0; normwise && k < Ns; ++k) {
    atolS.emplace_back(newVector());
    atolSRaw.push_back(atolS.back().get());
    ySNow.emplace_back(newVector());
    ySNowRaw.push_back(ySNow.back().get());
  }
}

void IdasStepper::Impl::updateSensitivityTolerances(double tNow) {
  if (!normwise) return;
  double tS = tNow;
  if (tNow == tStart)
    for (int k = 0; k < Ns; ++k) N_VScale(1.0, ySRaw[size_t(k)], ySNowRaw[size_t(k)]);
  else
    check(IDAGetSens(ida, &tS, ySNowRaw.data()), "IDAGetSens", tNow);
  const auto atolY = view(atolv.get());
  for (int k = 0; k < Ns; ++k) {
    const double floor = set.rtol * view(ySNowRaw[size_t(k)]).head(2 * n).lpNorm<Eigen::Infinity>();
    auto a = view(atolSRaw[size_t(k)]);
    for (int i = 0; i < N; ++i) a[i] = atolY[i] >= kUntestedTolerance ? atolY[i] : std::max(atolY[i], floor);
  }
  check(IDASensSVtolerances(ida, set.rtol, atolSRaw.data()), "IDASensSVtolerances", tNow);
}


// Frames: IDAS lands on a frame time (a stop time) when that cuts its next step by at most
// half; otherwise it steps past it and the frame is interpolated (IDAGetDky, the method's
// own polynomial, as IDA_NORMAL does). A stop time at every frame made IDAS cut the step
// that reaches it to whatever was left, down to 1e-7 of the step before; at such a step the
// iteration matrix of the index-2 GGL form with massless parts is singular to round-off
// and the corrector failed for good (massless satellite, rtol 1e-8: t = 0.0199998 s, frame
// at 0.02 s). A stop time is set only for a step that will reach it: while one is set,
// IDAS shortens its next step to whatever is left after each step, so a step that ended a
// hair short of a frame set far ahead (5e-12 s: the seed-000 four-bar at 0.12 s with its
// 1e-3 s step limit) made the next step 5e-12 s, where the iteration matrix is singular,
// and the run failed. Where one step would overshoot by little (h < left < 2 h), a stop
// half-way splits what is left into two steps of at least h/2, so that frames stay step
// ends: an interpolated frame carries the polynomial's error in the algebraic variables
// (massless coordinates, multipliers), which are out of the error test.
int IdasStepper::Impl::step(double tout, bool updateTolerances) {
  // (IDAS 6.4 cannot clear a stop time; one beyond the run's end stops nothing)
  const double farStop = set.tEnd + std::max(1.0, std::abs(set.tEnd - tStart));
  double hNext = 0.0;
  check(IDAGetCurrentStep(ida, &hNext), "IDAGetCurrentStep", t);
  const double left = tout - t;
  // With the adjoint's checkpoints no frame stops a step: IDASolveB recomputes each interval
  // between checkpoints from its checkpoint without them, and an interval recomputed with more
  // steps than IDAS stored for it overruns IDAS' step array (a segfault in IDASolveB: the
  // ANCF pendulum with a checkpoint every 50 steps).
  const double stop = (adjoint || left < 0.5 * hNext || left >= 2.0 * hNext) ? farStop  // step past / not yet
                      : (left <= hNext) ? tout                                // land
                                        : t + 0.5 * left;  // two steps of left/2 >= hNext/2
  if (stop != stopSet) {
    check(IDASetStopTime(ida, stop), "IDASetStopTime", t);
    stopSet = stop;
  }
  if (updateTolerances) updateSensitivityTolerances(t);
  double tret = t;
  const int flag = adjoint ? IDASolveF(ida, set.tEnd, &tret, y.get(), yp.get(), IDA_ONE_STEP, &checkpoints)
                           : IDASolve(ida, set.tEnd, &tret, y.get(), yp.get(), IDA_ONE_STEP);
  if (flag >= 0) t = tret;
  return flag;
}

StateWithSens IdasStepper::Impl::stateAt(double tq) {
  check(IDAGetDky(ida, tq, 0, yOut.get()), "IDAGetDky", tq);
  check(IDAGetDky(ida, tq, 1, ypOut.get()), "IDAGetDky", tq);
  StateWithSens out;
  out.x = gglState(tq, yOut.get(), ypOut.get(), n, m);
  if (!out.x.q.allFinite()) check(IDA_CONV_FAIL, "IDASolve (non-finite state)", tq);
  if (Ns > 0) {
    check(IDAGetSensDky(ida, tq, 0, ySOutRaw.data()), "IDAGetSensDky", tq);
    check(IDAGetSensDky(ida, tq, 1, ypSOutRaw.data()), "IDAGetSensDky", tq);
    for (int k = 0; k < Ns; ++k) out.dp.push_back(gglState(tq, ySOutRaw[k], ypSOutRaw[k], n, m));
  }
  as.setTime(tq);
  if (m) st.maxConstraintViolation = std::max(st.maxConstraintViolation, as.phi(out.x.q, p).lpNorm<Eigen::Infinity>());
  return out;
}

void IdasStepper::Impl::readCounters() {
  auto counter = [&](int (*get)(void*, long*), const char* fn) {
    long v = 0;
    check(get(ida, &v), fn, t);
    return v;
  };
  st.steps = counter(IDAGetNumSteps, "IDAGetNumSteps");
  st.newtonIterations = counter(IDAGetNumNonlinSolvIters, "IDAGetNumNonlinSolvIters");
  st.factorizations = counter(IDAGetNumLinSolvSetups, "IDAGetNumLinSolvSetups");
  st.luFill = lu.maxFill();
  st.choleskyFactorizations = lu.choleskyFactorizations();
  st.ldltFactorizations = lu.ldltFactorizations();
  st.factorizationSeconds = lu.factorSeconds();
  st.residualEvaluations = counter(IDAGetNumResEvals, "IDAGetNumResEvals");
  st.jacobianEvaluations = counter(IDAGetNumJacEvals, "IDAGetNumJacEvals");
  st.errorTestFailures = counter(IDAGetNumErrTestFails, "IDAGetNumErrTestFails");
  st.convergenceFailures = counter(IDAGetNumNonlinSolvConvFails, "IDAGetNumNonlinSolvConvFails");
}

// ------------------------------------------------------------ the public face
IdasStepper::IdasStepper(const Assembler& as, const VecX& p, const StateWithSens& start,
                         const IntegratorSettings& set)
    : impl_(std::make_unique<Impl>(as, p, start, set)) {
  as.setTime(start.x.t);
  impl_->st.maxConstraintViolation = impl_->m ? as.phi(start.x.q, p).lpNorm<Eigen::Infinity>() : 0.0;
}
IdasStepper::~IdasStepper() = default;

double IdasStepper::time() const { return impl_->t; }
int IdasStepper::step(double tout, bool updateTolerances) { return impl_->step(tout, updateTolerances); }
void IdasStepper::throwIfFailed(int flag, const char* function) const { impl_->check(flag, function, impl_->t); }
State IdasStepper::current() const {
  return gglState(impl_->t, impl_->y.get(), impl_->yp.get(), impl_->n, impl_->m);
}
StateWithSens IdasStepper::stateAt(double tq) { return impl_->stateAt(tq); }
void IdasStepper::enableAdjoint(long stepsPerCheckpoint) {
  impl_->check(IDAAdjInit(impl_->ida, stepsPerCheckpoint, IDA_HERMITE), "IDAAdjInit", impl_->t);
  impl_->adjoint = true;
}
long IdasStepper::checkpoints() const { return impl_->checkpoints; }
void* IdasStepper::memory() const { return impl_->ida; }
SUNContext IdasStepper::context() const { return impl_->ctx.get(); }
const IntegratorStats& IdasStepper::statistics() {
  impl_->readCounters();
  return impl_->st;
}

}  // namespace flexsens
