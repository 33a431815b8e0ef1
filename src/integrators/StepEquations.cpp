#include "integrators/StepEquations.hpp"

namespace flexsens {

SpMat newtonMatrix(const Assembler& as, SparseAccumulator& acc, const VecX& q, const VecX& qf, const VecX& vf,
                   const VecX& lt, const VecX& p, const Scheme& sc, double t) {
  const int n = as.n(), m = as.m();
  const double sigma = 1.0 / sc.ca;
  acc.begin(n + m, n + m);
  as.setTime(sc.forceTime(t));
  as.addMassAndForceJacobian(acc, qf, vf, p, 1.0, sigma * sc.fw, sigma * sc.fw * sc.cv, 0, 0);
  as.addHessian(acc, qf, p, lt, sc.fw, 0, 0);
  as.addPhiQ(acc, qf, p, 1.0, 0, n, true);
  as.setTime(t);
  as.addPhiQ(acc, q, p, 1.0, n, 0, false);
  return acc.finish();
}

void constraintResidual(const Assembler& as, const Scheme& sc, const VecX& q, const VecX& qf, double t,
                        const VecX& p, const VecX& l, VecX& phi, VecX& phiQTl, VecX& scratch) {
  as.setTime(t);
  if (sc.fw == 1.0) {
    as.constraintTerms(q, p, l, phi, phiQTl);
    return;
  }
  as.setTime(sc.forceTime(t));
  as.constraintTerms(qf, p, l, scratch, phiQTl);
  as.setTime(t);
  phi = as.phi(q, p);
}

StepEquations::StepEquations(const Assembler& as, const VecX& p, const Scheme& sc, long& residualEvaluations)
    : as_(as), p_(p), sc_(sc), n_(as.n()), m_(as.m()), M_(as.mass(p)), sigma_(1.0 / sc.ca),
      residualEvaluations_(residualEvaluations) {}

void StepEquations::begin(const State& old, double t, long step) {
  old_ = &old;
  t_ = t;
  step_ = step;
  as_.setTime(t);
  sc_.history(old, abar_, vbar_);
}

VecX StepEquations::residual(const VecX& qq, const VecX& ll) {
  const State& old = *old_;
  aBuf_ = sc_.ca * (qq - old.q) + abar_;
  vBuf_ = sc_.cv * (qq - old.q) + vbar_;
  const VecX& qf = sc_.forcePoint(qq, old.q, qfBuf_);
  as_.setTime(sc_.forceTime(t_));
  as_.force(qf, sc_.forcePoint(vBuf_, old.v, vfBuf_), p_, forceBuf_);
  constraintResidual(as_, sc_, qq, qf, t_, p_, ll, phiBuf_, phiQTlBuf_, phiMidBuf_);
  VecX r(n_ + m_);
  r.head(n_).noalias() = M_ * aBuf_;
  r.head(n_) = sigma_ * (r.head(n_) - forceBuf_) + phiQTlBuf_;
  r.tail(m_) = phiBuf_;
  residualEvaluations_++;
  return r;
}

SpMat StepEquations::matrix(SparseAccumulator& acc, const VecX& qq, const VecX& ll) {
  const State& old = *old_;
  vBuf_ = sc_.cv * (qq - old.q) + vbar_;
  return newtonMatrix(as_, acc, qq, sc_.forcePoint(qq, old.q, qfBuf_), sc_.forcePoint(vBuf_, old.v, vfBuf_), ll, p_,
                      sc_, t_);
}

State StepEquations::solution(const VecX& q, const VecX& lt) const {
  State next;
  next.t = t_;
  next.q = q;
  next.a = sc_.ca * (q - old_->q) + abar_;
  next.v = sc_.cv * (q - old_->q) + vbar_;
  next.lambda = lt / sigma_;
  return next;
}

const VecX& StepEquations::forcePositions(const VecX& q) { return sc_.forcePoint(q, old_->q, qfBuf_); }
const VecX& StepEquations::forceVelocities(const VecX& v) { return sc_.forcePoint(v, old_->v, vfBuf_); }

}  // namespace flexsens
