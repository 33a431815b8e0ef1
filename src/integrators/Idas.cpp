#include "integrators/Idas.hpp"
#include "integrators/InitialState.hpp"

#include <idas/idas.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <sstream>

#include "integrators/IdasLinearSolver.hpp"
#include "integrators/StepEnd.hpp"
#include "integrators/TimeGrid.hpp"

namespace flexsens {

// ------------------------------------------------------------------ the GGL system
std::vector<int> gglPinnedRows(const Assembler& as, const std::vector<int>& massless) {
  if (massless.empty() || as.m() == 0) return {};
  std::vector<char> isMassless(as.n(), 0);
  for (int i : massless) isMassless[i] = 1;
  std::vector<int> rows;
  for (size_t c = 0; c < as.constraints().size(); ++c) {
    bool touches = false;
    for (int i : as.constraintDofs(c)) touches = touches || (i >= 0 && isMassless[i]);
    if (!touches) continue;
    for (int r = 0; r < as.constraints()[c]->rows(); ++r) rows.push_back(as.constraintRow(c) + r);
  }
  std::sort(rows.begin(), rows.end());
  return rows;
}

VecX gglResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y, const VecX& yp,
                 const std::vector<int>& pinned) {
  const int n = as.n(), m = as.m();
  const VecX q = y.segment(0, n), v = y.segment(n, n);
  const VecX lam = y.segment(2 * n, m), mu = y.segment(2 * n + m, m);
  VecX r(2 * (n + m));
  r.segment(0, n) = yp.segment(0, n) - v + as.phiQTransposeTimes(q, p, mu);
  r.segment(n, n) = M * yp.segment(n, n) + as.phiQTransposeTimes(q, p, lam) - as.force(q, v, p);
  if (m) {
    r.segment(2 * n, m) = as.phi(q, p);
    r.segment(2 * n + m, m) = as.phiQTimes(q, p, v) + as.phiT(q, p);  // d Phi/dt = 0 (drivers: Phi_t)
    for (int row : pinned) r[2 * n + m + row] = mu[row];
  }
  return r;
}

const SpMat& gglJacobian(const Assembler& as, const VecX& p, const VecX& y, double cj,
                         SparseAccumulator& acc, const std::vector<int>& pinned) {
  const int n = as.n(), m = as.m();
  const VecX q = y.segment(0, n), v = y.segment(n, n);
  const VecX lam = y.segment(2 * n, m), mu = y.segment(2 * n + m, m);
  acc.begin(2 * (n + m), 2 * (n + m));
  for (int i = 0; i < n; ++i) {  // q rows: cj I + H(mu), -I, Phi_q^T (mu)
    acc.add(i, i, cj);
    acc.add(i, n + i, -1.0);
  }
  as.addHessian(acc, q, p, mu, 1.0, 0, 0);
  as.addPhiQ(acc, q, p, 1.0, 0, 2 * n + m, true);
  // v rows: H(lambda) - Q_q, cj M - Q_v, Phi_q^T (lambda)
  as.addHessian(acc, q, p, lam, 1.0, n, 0);
  as.addForceJacobian(acc, q, v, p, 1.0, 1.0, n, 0, n);
  as.addMass(acc, p, cj, n, n);
  as.addPhiQ(acc, q, p, 1.0, n, 2 * n, true);
  // Phi rows: Phi_q; Phi_q v rows: d(Phi_q v)/dq, Phi_q
  as.addPhiQ(acc, q, p, 1.0, 2 * n, 0, false);
  as.addHessianRows(acc, q, p, v, 1.0, 2 * n + m, 0);
  as.addPhiQT(acc, q, p, 1.0, 2 * n + m, 0);
  as.addPhiQ(acc, q, p, 1.0, 2 * n + m, n, false);
  std::vector<int> pinnedRows;
  for (int row : pinned) {
    acc.add(2 * n + m + row, 2 * n + m + row, 0.0);
    pinnedRows.push_back(2 * n + m + row);
  }
  acc.finish();
  acc.setRowsToIdentity(pinnedRows);
  return acc.matrix();
}

void gglForceJacobians(const Assembler& as, const VecX& p, const VecX& y, SparseAccumulator& kq,
                       SparseAccumulator& kv) {
  const int n = as.n();
  const VecX q = y.segment(0, n), v = y.segment(n, n);
  kq.begin(n, n);
  kv.begin(n, n);
  as.addForceJacobians(kq, kv, q, v, p);
  kq.finish();
  kv.finish();
}

VecX gglSensitivityResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y,
                            const VecX& yp, int k, const VecX& s, const VecX& sd,
                            const std::vector<int>& pinned) {
  SparseAccumulator kq, kv;
  gglForceJacobians(as, p, y, kq, kv);
  return gglSensitivityResidual(as, p, M, y, yp, k, s, sd, kq.matrix(), kv.matrix(), pinned);
}

VecX gglSensitivityResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y,
                            const VecX& yp, int k, const VecX& s, const VecX& sd, const SpMat& Qq,
                            const SpMat& Qv, const std::vector<int>& pinned) {
  const int n = as.n(), m = as.m();
  const VecX q = y.segment(0, n), v = y.segment(n, n);
  const VecX lam = y.segment(2 * n, m), mu = y.segment(2 * n + m, m);
  const VecX sq = s.segment(0, n), sv = s.segment(n, n);
  const VecX sl = s.segment(2 * n, m), sm = s.segment(2 * n + m, m);
  VecX r(2 * (n + m));
  r.segment(0, n) = sd.segment(0, n) - sv + as.phiQTransposeTimes(q, p, sm) +
                    as.hessianTimes(q, p, mu, sq) + as.phiQParamDerivativeTransposeTimes(q, p, k, mu);
  r.segment(n, n) = M * sd.segment(n, n) + as.massParamDerivativeTimes(p, k, yp.segment(n, n)) +
                    as.phiQTransposeTimes(q, p, sl) + as.hessianTimes(q, p, lam, sq) +
                    as.phiQParamDerivativeTransposeTimes(q, p, k, lam) - Qq * sq -
                    Qv * sv - as.forceParamDerivative(q, v, p, k);
  if (m) {
    r.segment(2 * n, m) = as.phiQTimes(q, p, sq) + as.phiParamDerivative(q, p, k);
    r.segment(2 * n + m, m) = as.phiQTimes(q, p, sv) + as.hessianRowsTimes(q, p, v, sq) +
                              as.phiQParamDerivativeTimes(q, p, k, v) + as.phiQTTimes(q, p, sq) +
                              as.phiTParamDerivative(q, p, k);
    for (int row : pinned) r[2 * n + m + row] = sm[row];
  }
  return r;
}

namespace {

// ------------------------------------------------------------ RAII for SUNDIALS objects
struct ContextDeleter { void operator()(SUNContext c) const { SUNContext_Free(&c); } };
struct VectorDeleter { void operator()(_generic_N_Vector* v) const { N_VDestroy(v); } };
struct MatrixDeleter { void operator()(_generic_SUNMatrix* A) const { SUNMatDestroy(A); } };
struct SolverDeleter { void operator()(_generic_SUNLinearSolver* S) const { SUNLinSolFree(S); } };
struct IdaDeleter { void operator()(void* mem) const { IDAFree(&mem); } };
using VectorPtr = std::unique_ptr<_generic_N_Vector, VectorDeleter>;

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

Eigen::Map<VecX> view(N_Vector v) { return {N_VGetArrayPointer(v), N_VGetLength(v)}; }

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

// Callbacks: thin wrappers over the GGL functions above (exceptions become return codes).
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

State unpack(double t, N_Vector y, N_Vector yp, int n, int m) {
  const auto Y = view(y), D = view(yp);
  State s;
  s.t = t;
  s.q = Y.segment(0, n);
  s.v = Y.segment(n, n);
  s.lambda = Y.segment(2 * n, m);
  s.a = D.segment(n, n);
  return s;
}

}  // namespace

/// Corrector iterations the staggered sensitivity solve may take per step (IDAS' default 4).
constexpr int kIdasSensitivityIterations = 10;
/// The absolute tolerance of a variable the corrector's convergence test leaves out (multipliers,
/// undamped massless velocities): its weight 1e-30 makes any correction pass.
constexpr double kUntestedTolerance = 1e30;
/// Steps IDAS may take between two frames before the run stops as too much work.
constexpr long kMaxIdasStepsPerFrame = 1000000;

IntegratorStats integrateIdas(const Assembler& as, const VecX& p, const StateWithSens& start,
                              const IntegratorSettings& set, Observer& obs) {
  const int n = as.n(), m = as.m();
  const int N = 2 * (n + m);
  const int Ns = static_cast<int>(start.dp.size());
  VecX pWork = p;  // IDAS' difference quotients perturb the parameters in place
  Problem pb{&as, &pWork, n, m, {}, {}, {}, {}, 0.0, {}, {}, {}, {}, {}, {}, {}};
  double t = start.x.t;

  SUNContext rawCtx = nullptr;
  if (SUNContext_Create(nullptr, &rawCtx) != 0) throw NumericalError("IDAS: SUNContext_Create failed");
  std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextDeleter> ctx(rawCtx);
  VectorPtr y(N_VNew_Serial(N, ctx.get())), yp(N_VNew_Serial(N, ctx.get()));
  VectorPtr id(N_VNew_Serial(N, ctx.get()));
  pack(start.x, n, m, y.get(), yp.get());
  view(id.get()).setZero();
  view(id.get()).head(2 * n).setOnes();  // q, v differential; lambda, mu algebraic
  const std::vector<int> massless = masslessCoordinates(as, p);  // equilibrium rows: algebraic
  if (n > 0 && static_cast<int>(massless.size()) == n)
    throw InputError("integrator idas: every coordinate is massless (inertia: none), the model is "
                     "static; use bdf1 or trapezoidal (each step an equilibrium) or the static solver");
  for (int i : massless) view(id.get())[i] = view(id.get())[n + i] = 0.0;
  pb.pinned = gglPinnedRows(as, massless);

  std::unique_ptr<void, IdaDeleter> mem(IDACreate(ctx.get()));
  if (!mem) throw NumericalError("IDAS: IDACreate failed");
  void* ida = mem.get();
  check(IDASetErrHandlerFn(ida, errorHandler, &pb), "IDASetErrHandlerFn", pb, t);
  check(IDAInit(ida, residual, t, y.get(), yp.get()), "IDAInit", pb, t);
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
  VectorPtr atolv(N_VNew_Serial(N, ctx.get()));
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
  check(IDASVtolerances(ida, set.rtol, atolv.get()), "IDASVtolerances", pb, t);
  check(IDASetUserData(ida, &pb), "IDASetUserData", pb, t);
  check(IDASetId(ida, id.get()), "IDASetId", pb, t);
  check(IDASetSuppressAlg(ida, SUNTRUE), "IDASetSuppressAlg", pb, t);
  check(IDASetMaxNumSteps(ida, kMaxIdasStepsPerFrame), "IDASetMaxNumSteps", pb, t);
  if (set.dt > 0) check(IDASetMaxStep(ida, set.dt), "IDASetMaxStep", pb, t);
  // IDAS' own first-step estimate makes |h y'| small in the error weights; starting from
  // rest with tight atol that gives h ~ 1e-11 s, where the index-2 iteration matrix
  // (condition ~ 1/h^2) is too ill-conditioned for the corrector. Start at a step that
  // the error test will cut if needed, but not so small.
  check(IDASetInitStep(ida, std::min(1e-6, 1e-3 * set.frameInterval)), "IDASetInitStep", pb, t);

  // Pattern: assemble once at the initial state to size the sparse matrix.
  {
    VectorPtr tmp(N_VNew_Serial(N, ctx.get()));  // (the Jacobian callback sets the time t)
    std::unique_ptr<_generic_SUNMatrix, MatrixDeleter> probe(SUNSparseMatrix(N, N, 1, CSC_MAT, ctx.get()));
    if (jacobian(t, 1.0, y.get(), yp.get(), tmp.get(), probe.get(), &pb, nullptr, nullptr, nullptr) != 0)
      throw NumericalError("IDAS: Jacobian assembly failed at t = " + std::to_string(t) + ": " + pb.failure);
  }
  std::unique_ptr<_generic_SUNMatrix, MatrixDeleter> J(
      SUNSparseMatrix(N, N, pb.acc.matrix().nonZeros(), CSC_MAT, ctx.get()));
  SparseLU lu;
  std::unique_ptr<_generic_SUNLinearSolver, SolverDeleter> LS(sparseLULinearSolver(ctx.get(), lu, pb.linearFailure));
  if (!J || !LS) throw NumericalError("IDAS: could not create the sparse LU linear solver");
  check(IDASetLinearSolver(ida, LS.get(), J.get()), "IDASetLinearSolver", pb, t);
  check(IDASetJacFn(ida, jacobian), "IDASetJacFn", pb, t);

  std::vector<N_Vector> yS, ypS;
  const int corrector = set.sensitivityCorrector == "simultaneous" ? IDA_SIMULTANEOUS : IDA_STAGGERED;
  VecX pbar;  // parameter scales for the difference quotients (alive while IDAS runs)
  auto freeSens = [&]() {
    for (auto v : yS) N_VDestroy(v);
    for (auto v : ypS) N_VDestroy(v);
  };
  struct Guard { std::function<void()> f; ~Guard() { f(); } } guard{freeSens};
  if (Ns > 0) {
    for (int k = 0; k < Ns; ++k) {
      yS.push_back(N_VNew_Serial(N, ctx.get()));
      ypS.push_back(N_VNew_Serial(N, ctx.get()));
      pack(start.dp[k], n, m, yS.back(), ypS.back());
    }
    if (set.sensitivityMethod == "dq") {
      // IDAS' internal difference quotients (centered) instead of the analytic residual.
      pbar = p.cwiseAbs();
      for (int k = 0; k < Ns; ++k)
        if (pbar[k] == 0.0) pbar[k] = 1.0;
      check(IDASensInit(ida, Ns, corrector, nullptr, yS.data(), ypS.data()), "IDASensInit", pb, t);
      check(IDASetSensParams(ida, pWork.data(), pbar.data(), nullptr), "IDASetSensParams", pb, t);
      check(IDASetSensDQMethod(ida, IDA_CENTERED, 0.0), "IDASetSensDQMethod", pb, t);
    } else {
      check(IDASensInit(ida, Ns, corrector, sensResidual, yS.data(), ypS.data()), "IDASensInit", pb, t);
    }
    check(IDASensEEtolerances(ida), "IDASensEEtolerances", pb, t);
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
      check(IDASetSensMaxNonlinIters(ida, kIdasSensitivityIterations), "IDASetSensMaxNonlinIters", pb, t);
    else  // the simultaneous corrector: the same 10 iterations for state and sensitivities
      check(IDASetMaxNonlinIters(ida, kIdasSensitivityIterations), "IDASetMaxNonlinIters", pb, t);
    check(IDASetSensErrCon(ida, set.sensitivityErrorControl ? SUNTRUE : SUNFALSE), "IDASetSensErrCon", pb, t);
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
  const bool normwise = Ns > 0 && set.sensitivityTolerance == "normwise";
  std::vector<VectorPtr> atolS, ySNow;  // the absolute tolerances set, the sensitivities reached
  std::vector<N_Vector> atolSRaw, ySNowRaw;
  for (int k = 0; normwise && k < Ns; ++k) {
    atolS.emplace_back(N_VNew_Serial(N, ctx.get()));
    atolSRaw.push_back(atolS.back().get());
    ySNow.emplace_back(N_VNew_Serial(N, ctx.get()));
    ySNowRaw.push_back(ySNow.back().get());
  }
  auto updateSensitivityTolerances = [&](double tNow) {
    if (!normwise) return;
    double tS = tNow;
    if (tNow == start.x.t)
      for (int k = 0; k < Ns; ++k) N_VScale(1.0, yS[size_t(k)], ySNowRaw[size_t(k)]);
    else
      check(IDAGetSens(ida, &tS, ySNowRaw.data()), "IDAGetSens", pb, tNow);
    const auto atolY = view(atolv.get());
    for (int k = 0; k < Ns; ++k) {
      const double floor = set.rtol * view(ySNowRaw[size_t(k)]).head(2 * n).lpNorm<Eigen::Infinity>();
      auto a = view(atolSRaw[size_t(k)]);
      for (int i = 0; i < N; ++i) a[i] = atolY[i] >= kUntestedTolerance ? atolY[i] : std::max(atolY[i], floor);
    }
    check(IDASensSVtolerances(ida, set.rtol, atolSRaw.data()), "IDASensSVtolerances", pb, tNow);
  };
  updateSensitivityTolerances(t);

  IntegratorStats st;
  auto counter = [&](int (*get)(void*, long*), const char* fn) {
    long v = 0;
    check(get(ida, &v), fn, pb, t);
    return v;
  };
  auto readCounters = [&] {
    st.steps = counter(IDAGetNumSteps, "IDAGetNumSteps");
    st.newtonIterations = counter(IDAGetNumNonlinSolvIters, "IDAGetNumNonlinSolvIters");
    st.factorizations = counter(IDAGetNumLinSolvSetups, "IDAGetNumLinSolvSetups");
    st.luFill = lu.maxFill();
    st.factorizationSeconds = lu.factorSeconds();
    st.residualEvaluations = counter(IDAGetNumResEvals, "IDAGetNumResEvals");
    st.jacobianEvaluations = counter(IDAGetNumJacEvals, "IDAGetNumJacEvals");
    st.errorTestFailures = counter(IDAGetNumErrTestFails, "IDAGetNumErrTestFails");
    st.convergenceFailures = counter(IDAGetNumNonlinSolvConvFails, "IDAGetNumNonlinSolvConvFails");
  };
  // The state (and sensitivities) at tq, from IDAS' interpolating polynomial of the last step
  // (exact at its end point tq = t; valid back to its start).
  VectorPtr yOut(N_VNew_Serial(N, ctx.get())), ypOut(N_VNew_Serial(N, ctx.get()));
  std::vector<VectorPtr> ySOut, ypSOut;
  std::vector<N_Vector> ySOutRaw, ypSOutRaw;
  for (int k = 0; k < Ns; ++k) {
    ySOut.emplace_back(N_VNew_Serial(N, ctx.get()));
    ypSOut.emplace_back(N_VNew_Serial(N, ctx.get()));
    ySOutRaw.push_back(ySOut.back().get());
    ypSOutRaw.push_back(ypSOut.back().get());
  }
  auto stateAt = [&](double tq) {
    check(IDAGetDky(ida, tq, 0, yOut.get()), "IDAGetDky", pb, tq);
    check(IDAGetDky(ida, tq, 1, ypOut.get()), "IDAGetDky", pb, tq);
    StateWithSens out;
    out.x = unpack(tq, yOut.get(), ypOut.get(), n, m);
    if (!out.x.q.allFinite()) check(IDA_CONV_FAIL, "IDASolve (non-finite state)", pb, tq);
    if (Ns > 0) {
      check(IDAGetSensDky(ida, tq, 0, ySOutRaw.data()), "IDAGetSensDky", pb, tq);
      check(IDAGetSensDky(ida, tq, 1, ypSOutRaw.data()), "IDAGetSensDky", pb, tq);
      for (int k = 0; k < Ns; ++k) out.dp.push_back(unpack(tq, ySOutRaw[k], ypSOutRaw[k], n, m));
    }
    as.setTime(tq);
    if (m) st.maxConstraintViolation =
        std::max(st.maxConstraintViolation, as.phi(out.x.q, p).lpNorm<Eigen::Infinity>());
    return out;
  };
  beginRun(obs, start);
  as.setTime(t);
  st.maxConstraintViolation = m ? as.phi(start.x.q, p).lpNorm<Eigen::Infinity>() : 0.0;
  const long nframes = outputCount(set.tEnd - t, set.frameInterval);
  // (IDAS 6.4 cannot clear a stop time; one beyond the run's end stops nothing)
  const double farStop = set.tEnd + std::max(1.0, std::abs(set.tEnd - t));
  double stopSet = std::nan("");
  for (long f = 1; f <= nframes; ++f) {
    const double tout = (f == nframes) ? set.tEnd : start.x.t + f * set.frameInterval;
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
    // One step per call, so that a signal is seen after the step it arrived in. IDAS' own
    // step limit (IDASetMaxNumSteps) counts per call, so one step per call needs our own.
    for (long stepsThisFrame = 0; t < tout; ++stepsThisFrame) {
      if (stepsThisFrame >= kMaxIdasStepsPerFrame) {
        readCounters();
        obs.reached(st);
        check(IDA_TOO_MUCH_WORK, "IDASolve", pb, t);
      }
      double hNext = 0.0;
      check(IDAGetCurrentStep(ida, &hNext), "IDAGetCurrentStep", pb, t);
      const double left = tout - t;
      const double stop = (left < 0.5 * hNext || left >= 2.0 * hNext) ? farStop  // step past / not yet
                          : (left <= hNext) ? tout                                // land
                                            : t + 0.5 * left;  // two steps of left/2 >= hNext/2
      if (stop != stopSet) {
        check(IDASetStopTime(ida, stop), "IDASetStopTime", pb, t);
        stopSet = stop;
      }
      if (stepsThisFrame > 0 || f > 1) updateSensitivityTolerances(t);
      double tret = t;
      const int flag = IDASolve(ida, set.tEnd, &tret, y.get(), yp.get(), IDA_ONE_STEP);
      if (flag < 0) {  // the failed run's summary reports the work done up to here
        readCounters();
        obs.reached(st);
      }
      check(flag, "IDASolve", pb, t);
      t = tret;
      if (t < tout && interruptSignal()) {
        readCounters();
        StateWithSens out = stateAt(t);
        endStep(obs, out, st, false);  // writes the state reached and throws Interrupted
      }
      obs.stepped(unpack(t, y.get(), yp.get(), n, m));
      obs.progress(std::min(t, set.tEnd));
    }
    StateWithSens out = stateAt(tout);
    readCounters();
    endStep(obs, out, st, true);
  }
  readCounters();
  return st;
}

}  // namespace flexsens
