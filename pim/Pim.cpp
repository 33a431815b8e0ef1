#include "pim/Pim.hpp"

#include <sstream>

#include "integrators/InitialState.hpp"

namespace flexsens {

namespace {

/// A = [Phi_q; Lambda_q; z_q] and the labels of its rows.
MatX pimMatrix(const Assembler& as, const Assembler& lam, const PimCase& c, const VecX& q,
               const VecX& p, std::vector<std::string>* labels) {
  const Model& m = as.model();
  MatX A(m.n, m.n);
  A.topRows(as.m()) = as.phiQDense(q, p);
  A.middleRows(as.m(), lam.m()) = lam.phiQDense(q, p);
  for (size_t i = 0; i < c.sdofs.size(); ++i)
    A.row(as.m() + lam.m() + i) = c.sdofs[i]->gradient(m, q).transpose();
  if (labels) {
    for (int r = 0; r < as.m(); ++r) labels->push_back("Phi: " + as.rowLabel(r));
    for (int r = 0; r < lam.m(); ++r) labels->push_back("Lambda: " + lam.rowLabel(r));
    for (const auto& z : c.sdofs) labels->push_back("SDOF: " + z->name);
  }
  return A;
}

void checkCount(const Assembler& as, const Assembler& lam, const PimCase& c) {
  const int d = as.n() - as.m(), mr = lam.m();
  const int ds = d - mr;
  if (static_cast<int>(c.sdofs.size()) != ds) {
    std::ostringstream os;
    os << c.file << ": case '" << c.name << "': " << c.sdofs.size() << " SDOF(s) given, but d - m_r = "
       << d << " - " << mr << " = " << ds << " are required (n = " << as.n() << ", m = " << as.m()
       << ", m_r = " << mr << " rigidization equations)";
    if (ds < 0) os << "; the rigidized bodies over-constrain the mechanism: rigidize fewer bodies";
    throw InputError(os.str());
  }
}

}  // namespace

StateWithSens pimInitialState(const Assembler& as, const PimCase& c, const State& s,
                              const VecX& p, PimReport& rep) {
  const Model& m = as.model();
  const Assembler lam(m, &c.lambda, as.derivatives());
  checkCount(as, lam, c);
  rep.n = m.n;
  rep.m = as.m();
  rep.d = m.n - as.m();
  rep.mr = lam.m();
  rep.ds = static_cast<int>(c.sdofs.size());
  if (lam.m()) {
    const VecX L = lam.phi(s.q, p);
    int worst;
    const double err = L.cwiseAbs().maxCoeff(&worst);
    if (err > 1e-8) {
      std::ostringstream os;
      os << c.file << ": case '" << c.name << "': a rigidized body is not undeformed at t = 0 ("
         << lam.rowLabel(worst) << " = " << err << "); the PIM rigidizes only initially "
         << "undeformed bodies: remove it from 'rigidize' or start it undeformed";
      throw InputError(os.str());
    }
  }
  std::vector<std::string> labels;
  const MatX A = pimMatrix(as, lam, c, s.q, p, &labels);
  const Eigen::JacobiSVD<MatX> svd(A, Eigen::ComputeFullU);
  const VecX sv = svd.singularValues();
  rep.condition = sv[0] / sv[sv.size() - 1];
  if (!(sv[sv.size() - 1] > 1e-12 * sv[0])) {
    // Rows taking part in the dependency: large entries of the left null vector.
    const VecX u = svd.matrixU().col(sv.size() - 1);
    std::ostringstream os;
    os << "case '" << c.name << "': the PIM matrix A = [Phi_q; Lambda_q; z_q] is rank-deficient "
       << "(smallest singular value " << sv[sv.size() - 1] << ", largest " << sv[0]
       << "); dependent rows:";
    for (int r = 0; r < u.size(); ++r)
      if (std::abs(u[r]) > 0.1 * u.cwiseAbs().maxCoeff()) os << " [" << labels[r] << "]";
    os << ". Choose SDOFs that are independent of each other and of the constraints";
    throw NumericalError(os.str());
  }
  if (rep.condition > 1e10) {
    std::ostringstream os;
    os << "case '" << c.name << "': the PIM matrix A is near-singular (condition estimate "
       << rep.condition << "); the SDOFs almost depend on each other or on the constraints";
    throw NumericalError(os.str());
  }
  const Eigen::PartialPivLU<MatX> lu(A);
  const int np = static_cast<int>(p.size());
  StateWithSens out;
  out.x = s;
  rep.qp.resize(m.n, np);
  rep.vp.resize(m.n, np);
  for (int k = 0; k < np; ++k) {
    VecX b(m.n);
    b.head(as.m()) = -as.phiParamDerivative(s.q, p, k);
    b.segment(as.m(), lam.m()) = -lam.phiParamDerivative(s.q, p, k);
    for (size_t i = 0; i < c.sdofs.size(); ++i) b[as.m() + lam.m() + i] = c.sdofs[i]->dp;
    State d;
    d.q = lu.solve(b);
    b.head(as.m()) = -(as.hessianRowsTimes(s.q, p, s.v, d.q) + as.phiQParamDerivativeTimes(s.q, p, k, s.v));
    b.segment(as.m(), lam.m()) =
        -(lam.hessianRowsTimes(s.q, p, s.v, d.q) + lam.phiQParamDerivativeTimes(s.q, p, k, s.v));
    for (size_t i = 0; i < c.sdofs.size(); ++i)
      b[as.m() + lam.m() + i] = c.sdofs[i]->dv - d.q.dot(c.sdofs[i]->hessian(m, s.q) * s.v);
    d.v = lu.solve(b);
    solveAccelerationSensitivity(as, s, p, k, d);
    rep.qp.col(k) = d.q;
    rep.vp.col(k) = d.v;
    out.dp.push_back(d);
  }
  return out;
}

VecX perturbedConfiguration(const Assembler& as, const PimCase& c, const VecX& q0,
                            const VecX& p0, const VecX& p, int k) {
  const Model& m = as.model();
  const Assembler lam(m, &c.lambda, as.derivatives());
  checkCount(as, lam, c);
  VecX target(c.sdofs.size());
  for (size_t i = 0; i < c.sdofs.size(); ++i)
    target[i] = c.sdofs[i]->value(m, q0) + c.sdofs[i]->dp * (p[k] - p0[k]);
  VecX q = q0;
  for (int it = 0; it < 50; ++it) {
    VecX F(m.n);
    F.head(as.m()) = as.phi(q, p);
    F.segment(as.m(), lam.m()) = lam.phi(q, p);
    for (size_t i = 0; i < c.sdofs.size(); ++i) F[as.m() + lam.m() + i] = c.sdofs[i]->value(m, q) - target[i];
    if (F.lpNorm<Eigen::Infinity>() < 1e-14) return q;
    q -= pimMatrix(as, lam, c, q, p, nullptr).partialPivLu().solve(F);
  }
  throw NumericalError("case '" + c.name + "': the perturbed initial configuration did not converge");
}

}  // namespace flexsens
