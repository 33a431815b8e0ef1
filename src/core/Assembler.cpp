#include "core/Assembler.hpp"

#include <map>
#include <optional>

namespace flexsens {

namespace {
std::vector<int> iota(int start, int count) {
  std::vector<int> r(count);
  for (int i = 0; i < count; ++i) r[i] = start + i;
  return r;
}

/// The indices i < count with depends(i), found at the first request for parameter k and kept
/// in cache[k].
template <class Depends>
const std::vector<int>& dependentsOf(std::vector<std::optional<std::vector<int>>>& cache, int k, size_t count,
                                     Depends depends) {
  if (size_t(k) >= cache.size()) cache.resize(size_t(k) + 1);
  auto& slot = cache[size_t(k)];
  if (!slot) {
    slot.emplace();
    for (size_t i = 0; i < count; ++i)
      if (depends(i)) slot->push_back(int(i));
  }
  return *slot;
}
}  // namespace

Assembler::Assembler(const Model& model, const ConstraintList* constraints, Derivatives derivatives)
    : model_(model), cons_(constraints ? *constraints : model.constraints), derivatives_(derivatives) {
  for (int g : model_.gravityParam) gravityBound_ = gravityBound_ || g >= 0;
  for (const auto& e : model_.elements) elemDofs_.push_back(dofMap(e->nodes(), e->gradients()));
  for (const auto& c : cons_) {
    consDofs_.push_back(dofMap(c->nodes(), c->gradients()));
    consRow_.push_back(m_);
    consRows_.push_back(iota(m_, c->rows()));
    m_ += c->rows();
    rheonomic_ = rheonomic_ || c->rheonomic();
  }
  assignScratch();
}

void Assembler::assignScratch() {
  std::map<std::pair<size_t, int>, size_t> shapes;  // (local size, rows; -1: an element) -> entry
  auto entry = [&](size_t local, int rows) {
    const auto it = shapes.emplace(std::make_pair(local, rows), shapes.size()).first;
    return it->second;
  };
  for (const auto& map : elemDofs_) elemScratch_.push_back(entry(map.size(), -1));
  for (size_t c = 0; c < cons_.size(); ++c) consScratch_.push_back(entry(consDofs_[c].size(), cons_[c]->rows()));
  scratch_.resize(shapes.size());
}

void Assembler::setLoadFactor(double s) const { loadFactor_ = s; }

std::string Assembler::rowLabel(int r) const {
  for (size_t c = 0; c < cons_.size(); ++c)
    if (r >= consRow_[c] && r < consRow_[c] + cons_[c]->rows())
      return cons_[c]->rows() == 1 ? cons_[c]->name()
                                   : cons_[c]->name() + "[" + std::to_string(r - consRow_[c]) + "]";
  return "row " + std::to_string(r);
}

std::vector<int> Assembler::dofMap(const std::vector<int>& nodes, int gradients) const {
  std::vector<int> map;
  const int perNode = (1 + gradients) * model_.dim;
  for (int nd : nodes) {
    const Node& N = model_.nodes[nd];
    if (gradients && N.gradients(model_.dim) != gradients)
      throw std::invalid_argument("node " + N.name + " carries " + std::to_string(N.gradients(model_.dim)) +
                                  " position gradient(s); its element needs " + std::to_string(gradients));
    for (int c = 0; c < perNode; ++c) map.push_back(model_.dof(nd, c));
  }
  return map;
}

LocalState Assembler::localState(const std::vector<int>& nodes, const VecX& q, const VecX& v,
                                 const VecX& p, int gradients) const {
  LocalState s;
  gatherLocalState(s, nodes, dofMap(nodes, gradients), q, v, p, gradients);
  return s;
}

const LocalState& Assembler::elementState(size_t e, const VecX& q, const VecX& v, const VecX& p) const {
  const Element& el = *model_.elements[e];
  LocalState& s = scratch_[elemScratch_[e]].state;
  gatherLocalState(s, el.nodes(), elemDofs_[e], q, v, p, el.gradients());
  return s;
}

const LocalState& Assembler::constraintState(size_t c, const VecX& q, const VecX& v, const VecX& p) const {
  const Constraint& co = *cons_[c];
  LocalState& s = scratch_[consScratch_[c]].state;
  gatherLocalState(s, co.nodes(), consDofs_[c], q, v, p, co.gradients());
  return s;
}

void Assembler::gatherLocalState(LocalState& s, const std::vector<int>& nodes, const std::vector<int>& map,
                                 const VecX& q, const VecX& v, const VecX& p, int gradients) const {
  // Through the dof map (dofMap: node after node, positions then gradients), one indexed copy
  // per entry: the residual gathers every element and constraint at every iteration, and the
  // per-node segment copies this replaced were 7% of the satellite's run.
  const int d = model_.dim;
  s.dim = d;
  s.gradients = gradients;
  const int w = s.nodeSize();
  const size_t len = map.size();
  s.x.resize(len);
  s.v.resize(len);
  const bool withV = v.size() > 0;
  for (size_t i = 0; i < len; ++i) {
    const int g = map[i];
    if (g >= 0) {
      s.x[i] = q[g];
      s.v[i] = withV ? v[g] : 0.0;
    } else {  // a ground node's position or a clamped gradient: fixed, at rest
      const Node& nd = model_.nodes[nodes[i / w]];
      const int c = int(i % w);
      s.x[i] = c < d ? nd.position[c] : nd.slope[c - d];
      s.v[i] = 0.0;
    }
  }
  setEvaluationPoint(s, p);
}

void Assembler::setEvaluationPoint(LocalState& s, const VecX& p) const {
  s.p = &p;
  s.t = time_;
  if (gravityBound_ || loadFactor_ != 1.0) {
    gravityAtP_ = loadFactor_ * model_.gravityAt(p);
    s.gravity = &gravityAtP_;
  } else {
    s.gravity = &model_.gravity;
  }
}

// ------------------------------------------------------------------ local derivative kernels
void Assembler::elementForceJacobian(const Element& el, const LocalState& s, MatX& dQdq,
                                     MatX& dQdv) const {
  if (derivatives_ == Derivatives::AutomaticDifferentiation)
    el.forceJacobianAD(s, dQdq, dQdv);
  else
    el.forceJacobian(s, dQdq, dQdv);
}

bool Assembler::elementParameterDerivative(const Element& el, const LocalState& s, int k, VecX& dQ,
                                           MatX& dM) const {
  return derivatives_ == Derivatives::AutomaticDifferentiation ? el.parameterDerivativeAD(s, k, dQ, dM)
                                                               : el.parameterDerivative(s, k, dQ, dM);
}

void Assembler::constraintJacobian(const Constraint& co, const LocalState& s, MatX& J) const {
  if (derivatives_ == Derivatives::AutomaticDifferentiation)
    co.jacobianAD(s, J);
  else
    co.jacobian(s, J);
}

void Assembler::constraintHessian(const Constraint& co, const LocalState& s, int r, MatX& H) const {
  if (derivatives_ == Derivatives::AutomaticDifferentiation)
    co.hessianAD(s, r, H);
  else
    co.hessian(s, r, H);
}

bool Assembler::constraintParameterDerivative(const Constraint& co, const LocalState& s, int k,
                                              VecX& dphi, MatX& dJ) const {
  return derivatives_ == Derivatives::AutomaticDifferentiation
             ? co.parameterDerivativeAD(s, k, dphi, dJ)
             : co.parameterDerivative(s, k, dphi, dJ);
}

const std::vector<int>& Assembler::elementsDependingOn(int k, const VecX& q, const VecX& v, const VecX& p) const {
  VecX dQ;
  MatX dM;
  return dependentsOf(paramElements_, k, model_.elements.size(), [&](size_t e) {
    return elementParameterDerivative(*model_.elements[e], elementState(e, q, v, p), k, dQ, dM);
  });
}

const std::vector<int>& Assembler::constraintsDependingOn(int k, const VecX& q, const VecX& p) const {
  VecX dphi;
  MatX dJ;
  return dependentsOf(paramConstraints_, k, cons_.size(), [&](size_t c) {
    return constraintParameterDerivative(*cons_[c], constraintState(c, q, VecX(), p), k, dphi, dJ);
  });
}

// ----------------------------------------------------------------------------- vectors
void Assembler::elementForces(const VecX& q, const VecX& v, const VecX& p, bool potentialOnly, VecX& Q) const {
  Q.setZero(n());
  for (size_t e = 0; e < model_.elements.size(); ++e) {
    const auto& el = *model_.elements[e];
    if (potentialOnly && el.externalWork()) continue;  // no potential: all its force is work
    VecX& Ql = scratch_[elemScratch_[e]].vec;
    el.force(elementState(e, q, v, p), Ql);
    if (el.isLoad()) Ql *= loadFactor_;
    const auto& map = elemDofs_[e];
    for (size_t i = 0; i < map.size(); ++i)
      if (map[i] >= 0) Q[map[i]] += Ql[i];
  }
}

// Element by element, and only the elements that do external work or whose force at v
// differs from the one at rest: the others' terms cancel exactly, and the energy audit
// evaluated this at every step as two whole force vectors (9% of the flexible five-bar's run).
double Assembler::externalPower(const VecX& q, const VecX& v, const VecX& p) const {
  double P = 0.0;
  VecX Qv;
  for (size_t e = 0; e < model_.elements.size(); ++e) {
    const auto& el = *model_.elements[e];
    if (!el.externalWork()) continue;
    el.force(elementState(e, q, v, p), Qv);
    if (el.isLoad()) Qv *= loadFactor_;
    const auto& map = elemDofs_[e];
    for (size_t i = 0; i < map.size(); ++i)
      if (map[i] >= 0) P += v[map[i]] * Qv[i];
  }
  return P;
}

bool Assembler::damped() const {
  for (const auto& el : model_.elements)
    if (!el->externalWork() && el->velocityDependent()) return true;
  return false;
}

VecX Assembler::dampingForce(const VecX& q, const VecX& v, const VecX& p) const {
  VecX F = VecX::Zero(q.size()), Qv, Q0;
  for (size_t e = 0; e < model_.elements.size(); ++e) {
    const auto& el = *model_.elements[e];
    if (el.externalWork() || !el.velocityDependent()) continue;
    el.force(elementState(e, q, v, p), Qv);
    el.force(elementState(e, q, VecX(), p), Q0);
    Qv -= Q0;
    if (el.isLoad()) Qv *= loadFactor_;
    const auto& map = elemDofs_[e];
    for (size_t i = 0; i < map.size(); ++i)
      if (map[i] >= 0) F[map[i]] += Qv[i];
  }
  return F;
}

VecX Assembler::phi(const VecX& q, const VecX& p) const {
  VecX r(m());
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    VecX& pl = scratch_[consScratch_[c]].vec;
    co.phi(constraintState(c, q, VecX(), p), pl);
    r.segment(consRow_[c], co.rows()) = pl;
  }
  return r;
}

VecX Assembler::phiQTimes(const VecX& q, const VecX& p, const VecX& x) const {
  VecX r = VecX::Zero(m());
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    MatX& J = scratch_[consScratch_[c]].a;
    constraintJacobian(co, constraintState(c, q, VecX(), p), J);
    const auto& map = consDofs_[c];
    for (size_t j = 0; j < map.size(); ++j)
      if (map[j] >= 0) r.segment(consRow_[c], co.rows()) += J.col(j) * x[map[j]];
  }
  return r;
}

VecX Assembler::phiQTransposeTimes(const VecX& q, const VecX& p, const VecX& l) const {
  VecX r = VecX::Zero(n());
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    MatX& J = scratch_[consScratch_[c]].a;
    constraintJacobian(co, constraintState(c, q, VecX(), p), J);
    addTransposeTimes(J, consDofs_[c], l.segment(consRow_[c], co.rows()), r);
  }
  return r;
}

void Assembler::constraintTerms(const VecX& q, const VecX& p, const VecX& l, VecX& phi, VecX& phiQTl) const {
  phi.resize(m());
  phiQTl.setZero(n());
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    VecX& pl = scratch_[consScratch_[c]].vec;
    MatX& J = scratch_[consScratch_[c]].a;
    const LocalState& s = constraintState(c, q, VecX(), p);
    co.phi(s, pl);
    phi.segment(consRow_[c], co.rows()) = pl;
    constraintJacobian(co, s, J);
    addTransposeTimes(J, consDofs_[c], l.segment(consRow_[c], co.rows()), phiQTl);
  }
}

void Assembler::addTransposeTimes(const MatX& J, const std::vector<int>& map, Eigen::Ref<const VecX> l, VecX& r) {
  for (size_t j = 0; j < map.size(); ++j)
    if (map[j] >= 0) r[map[j]] += J.col(Eigen::Index(j)).dot(l);
}

namespace {
VecX gather(const std::vector<int>& map, const VecX& x) {
  VecX r = VecX::Zero(map.size());
  for (size_t i = 0; i < map.size(); ++i)
    if (map[i] >= 0) r[i] = x[map[i]];
  return r;
}
}  // namespace

VecX Assembler::hessianQuadratic(const VecX& q, const VecX& p, const VecX& v) const {
  return hessianRowsTimes(q, p, v, v);
}

VecX Assembler::hessianRowsTimes(const VecX& q, const VecX& p, const VecX& v, const VecX& x) const {
  VecX r = VecX::Zero(m());
  MatX H;
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    const LocalState& s = constraintState(c, q, VecX(), p);
    const VecX vl = gather(consDofs_[c], v), xl = gather(consDofs_[c], x);
    for (int i = 0; i < co.rows(); ++i) {
      constraintHessian(co, s, i, H);
      r[consRow_[c] + i] = vl.dot(H * xl);
    }
  }
  return r;
}

VecX Assembler::hessianTimes(const VecX& q, const VecX& p, const VecX& w, const VecX& x) const {
  VecX r = VecX::Zero(n());
  MatX H;
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    const LocalState& s = constraintState(c, q, VecX(), p);
    const auto& map = consDofs_[c];
    const VecX xl = gather(map, x);
    for (int i = 0; i < co.rows(); ++i) {
      constraintHessian(co, s, i, H);
      const VecX g = w[consRow_[c] + i] * (H * xl);
      for (size_t j = 0; j < map.size(); ++j)
        if (map[j] >= 0) r[map[j]] += g[j];
    }
  }
  return r;
}

// ------------------------------------------------------------------ time terms (drivers)
template <class Pick>
VecX Assembler::driverRows(const VecX& q, const VecX& v, const VecX& p, Pick pick) const {
  VecX r = VecX::Zero(m());
  if (!rheonomic_) return r;
  VecX pt, g;
  MatX pqt, dg;
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    if (!co.rheonomic()) continue;
    co.timeDerivatives(constraintState(c, q, v, p), pt, pqt, g, dg);
    r.segment(consRow_[c], co.rows()) = pick(c, pt, pqt, g, dg);
  }
  return r;
}

VecX Assembler::phiT(const VecX& q, const VecX& p) const {
  return driverRows(q, VecX(), p, [](size_t, const VecX& pt, const MatX&, const VecX&, const MatX&) { return pt; });
}

VecX Assembler::phiQTTimes(const VecX& q, const VecX& p, const VecX& x) const {
  return driverRows(q, VecX(), p, [&](size_t c, const VecX&, const MatX& pqt, const VecX&, const MatX&) {
    return VecX(pqt * gather(consDofs_[c], x));
  });
}

VecX Assembler::accelerationTimeTerms(const VecX& q, const VecX& v, const VecX& p) const {
  return driverRows(q, v, p, [](size_t, const VecX&, const MatX&, const VecX& g, const MatX&) { return g; });
}

VecX Assembler::accelerationTimeTermsQTimes(const VecX& q, const VecX& v, const VecX& p,
                                            const VecX& x) const {
  return driverRows(q, v, p, [&](size_t c, const VecX&, const MatX&, const VecX&, const MatX& dg) {
    return VecX(dg * gather(consDofs_[c], x));
  });
}

VecX Assembler::phiTParamDerivative(const VecX& q, const VecX& p, int k) const {
  VecX r = VecX::Zero(m());
  if (!rheonomic_) return r;
  VecX ptp, gp;
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    if (co.rheonomic() && co.timeParameterDerivative(constraintState(c, q, VecX(), p), k, ptp, gp))
      r.segment(consRow_[c], co.rows()) = ptp;
  }
  return r;
}

VecX Assembler::accelerationTimeTermsParamDerivative(const VecX& q, const VecX& v, const VecX& p,
                                                     int k) const {
  VecX r = VecX::Zero(m());
  if (!rheonomic_) return r;
  VecX ptp, gp;
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    if (co.rheonomic() && co.timeParameterDerivative(constraintState(c, q, v, p), k, ptp, gp))
      r.segment(consRow_[c], co.rows()) = gp;
  }
  return r;
}

void Assembler::addPhiQT(SparseAccumulator& acc, const VecX& q, const VecX& p, double s,
                         int64_t r0, int64_t c0) const {
  if (!rheonomic_) return;
  VecX pt, g;
  MatX pqt, dg;
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    if (!co.rheonomic()) continue;
    co.timeDerivatives(constraintState(c, q, VecX(), p), pt, pqt, g, dg);
    acc.addBlock(consRows_[c], consDofs_[c], pqt, s, r0, c0);
  }
}

SpMat Assembler::phiQSparse(const VecX& q, const VecX& p) const {
  SparseAccumulator acc;
  return phiQSparse(q, p, acc);
}

const SpMat& Assembler::phiQSparse(const VecX& q, const VecX& p, SparseAccumulator& acc) const {
  acc.begin(m(), n());
  addPhiQ(acc, q, p, 1.0, 0, 0, false);
  return acc.finish();
}

SpMat Assembler::mass(const VecX& p) const {
  SparseAccumulator acc;
  acc.begin(n(), n());
  addMass(acc, p, 1.0, 0, 0);
  return acc.finish();
}

double Assembler::potentialEnergy(const VecX& q, const VecX& p) const {
  double U = 0.0;  // (each element's state in its scratch: no allocation per element and step)
  for (size_t e = 0; e < model_.elements.size(); ++e) U += model_.elements[e]->potential(elementState(e, q, VecX(), p));
  return U;
}

// ----------------------------------------------------------------------------- blocks
const std::vector<MatX>& Assembler::elementMasses(const VecX& p) const {
  if (massesAt_ && massesAt_->size() == p.size() && *massesAt_ == p) return masses_;
  const VecX none;
  const VecX q0 = model_.initialPositions();  // mass is configuration independent
  masses_.assign(model_.elements.size(), MatX());
  for (size_t e = 0; e < model_.elements.size(); ++e)
    if (!model_.elements[e]->mass(elementState(e, q0, none, p), masses_[e])) masses_[e].resize(0, 0);
  massDerivatives_.clear();  // of the previous p
  massesAt_ = p;
  return masses_;
}

const std::vector<std::pair<int, MatX>>& Assembler::elementMassDerivatives(const VecX& p, int k) const {
  elementMasses(p);  // keyed to the same p
  if (massDerivatives_.size() <= size_t(k)) massDerivatives_.resize(size_t(k) + 1);
  auto& slot = massDerivatives_[size_t(k)];
  if (slot) return *slot;
  slot.emplace();
  VecX dQ;
  MatX dM;
  const VecX q0 = model_.initialPositions();
  for (int e : elementsDependingOn(k, q0, VecX(), p)) {
    const auto& el = *model_.elements[size_t(e)];
    if (elementParameterDerivative(el, elementState(size_t(e), q0, VecX(), p), k, dQ, dM) && dM.size() &&
        !dM.isZero(0.0))
      slot->emplace_back(e, dM);
  }
  return *slot;
}

void Assembler::addMass(SparseAccumulator& acc, const VecX& p, double s, int64_t r0,
                        int64_t c0) const {
  const std::vector<MatX>& masses = elementMasses(p);
  for (size_t e = 0; e < model_.elements.size(); ++e)
    if (masses[e].size()) acc.addBlock(elemDofs_[e], elemDofs_[e], masses[e], s, r0, c0);
}

void Assembler::addForceJacobian(SparseAccumulator& acc, const VecX& q, const VecX& v,
                                 const VecX& p, double sq, double sv, int64_t r0, int64_t cq,
                                 int64_t cv) const {
  MatX Kq, Kv;
  for (size_t e = 0; e < model_.elements.size(); ++e) {
    const auto& el = *model_.elements[e];
    if (sq == 0.0 && !el.velocityDependent()) continue;  // dQ/dv alone, and it is 0 here
    elementForceJacobian(el, elementState(e, q, v, p), Kq, Kv);
    const double lf = el.isLoad() ? loadFactor_ : 1.0;
    if (sq != 0.0) acc.addBlock(elemDofs_[e], elemDofs_[e], Kq, -sq * lf, r0, cq);
    if (sv != 0.0) acc.addBlock(elemDofs_[e], elemDofs_[e], Kv, -sv * lf, r0, cv);
  }
}

void Assembler::addForceJacobians(SparseAccumulator& kq, SparseAccumulator& kv,
                                          const VecX& q, const VecX& v, const VecX& p) const {
  MatX Kq, Kv;
  for (size_t e = 0; e < model_.elements.size(); ++e) {
    const auto& el = *model_.elements[e];
    elementForceJacobian(el, elementState(e, q, v, p), Kq, Kv);
    const double lf = el.isLoad() ? loadFactor_ : 1.0;
    kq.addBlock(elemDofs_[e], elemDofs_[e], Kq, lf, 0, 0);
    if (!Kv.isZero(0.0)) kv.addBlock(elemDofs_[e], elemDofs_[e], Kv, lf, 0, 0);
  }
}

void Assembler::addMassAndForceJacobian(SparseAccumulator& acc, const VecX& q, const VecX& v,
                                        const VecX& p, double sm, double sq, double sv, int64_t r0,
                                        int64_t c0) const {
  const std::vector<MatX>* masses = sm != 0.0 ? &elementMasses(p) : nullptr;
  for (size_t e = 0; e < model_.elements.size(); ++e) {
    const auto& el = *model_.elements[e];
    MatX& Kq = scratch_[elemScratch_[e]].a;
    MatX& Kv = scratch_[elemScratch_[e]].b;
    elementForceJacobian(el, elementState(e, q, v, p), Kq, Kv);
    const double lf = el.isLoad() ? loadFactor_ : 1.0;
    Kq *= -sq * lf;
    if (sv != 0.0) Kq -= (sv * lf) * Kv;
    if (masses && (*masses)[e].size()) Kq += sm * (*masses)[e];
    acc.addBlock(elemDofs_[e], elemDofs_[e], Kq, 1.0, r0, c0);
  }
}

void Assembler::addPhiQ(SparseAccumulator& acc, const VecX& q, const VecX& p, double s,
                        int64_t r0, int64_t c0, bool transposed) const {
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    MatX& J = scratch_[consScratch_[c]].a;
    constraintJacobian(co, constraintState(c, q, VecX(), p), J);
    const std::vector<int>& rows = consRows_[c];
    if (transposed)
      acc.addBlock(consDofs_[c], rows, J.transpose(), s, r0, c0);
    else
      acc.addBlock(rows, consDofs_[c], J, s, r0, c0);
  }
}

void Assembler::addHessian(SparseAccumulator& acc, const VecX& q, const VecX& p, const VecX& w,
                           double s, int64_t r0, int64_t c0) const {
  MatX sum;
  std::vector<double>& vals = hessianValues_;
  if (hessianPattern_.size() != cons_.size()) hessianPattern_.assign(cons_.size(), {});
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    MatX& H = scratch_[consScratch_[c]].b;
    const LocalState& ls = constraintState(c, q, VecX(), p);
    const int nl = static_cast<int>(consDofs_[c].size());
    const auto& map = consDofs_[c];
    if (!co.constantHessian()) {
      sum.setZero(nl, nl);
      for (int i = 0; i < co.rows(); ++i) {
        constraintHessian(co, ls, i, H);
        sum += w[consRow_[c] + i] * H;
      }
      acc.addBlock(map, map, sum, s, r0, c0);
      continue;
    }
    // Only the structural nonzeros (the same at every call, found at the first): a point on a
    // body's plane has 72 of 225 (satellite: 40.6k additions per Newton matrix, 28k of them
    // zeros, before; with the pattern's search repeated at every call, 3% of its run).
    auto& pattern = hessianPattern_[c];
    if (!pattern) {
      MatX mask = MatX::Zero(nl, nl);
      for (int i = 0; i < co.rows(); ++i) {
        constraintHessian(co, ls, i, H);
        mask += H.cwiseAbs();
      }
      pattern.emplace();
      for (int j = 0; j < nl; ++j)
        for (int i = 0; i < nl; ++i)
          if (map[i] >= 0 && map[j] >= 0 && mask(i, j) != 0.0) pattern->push_back(int(j) * nl + i);
    }
    vals.assign(pattern->size(), 0.0);
    for (int i = 0; i < co.rows(); ++i) {
      constraintHessian(co, ls, i, H);
      const double wi = w[consRow_[c] + i];
      for (size_t k = 0; k < pattern->size(); ++k) vals[k] += wi * H.data()[(*pattern)[k]];
    }
    for (size_t k = 0; k < pattern->size(); ++k) {
      const int e = (*pattern)[k];
      acc.add(r0 + map[size_t(e % nl)], c0 + map[size_t(e / nl)], s * vals[k]);
    }
  }
}

void Assembler::addHessianRows(SparseAccumulator& acc, const VecX& q, const VecX& p,
                               const VecX& v, double s, int64_t r0, int64_t c0) const {
  MatX H;
  for (size_t c = 0; c < cons_.size(); ++c) {
    const auto& co = *cons_[c];
    const LocalState& ls = constraintState(c, q, VecX(), p);
    const VecX vl = gather(consDofs_[c], v);
    MatX rowsBlock(co.rows(), consDofs_[c].size());
    for (int i = 0; i < co.rows(); ++i) {
      constraintHessian(co, ls, i, H);
      rowsBlock.row(i) = (H * vl).transpose();
    }
    acc.addBlock(consRows_[c], consDofs_[c], rowsBlock, s, r0, c0);
  }
}

// ------------------------------------------------------------------ parameter derivatives
VecX Assembler::forceParamDerivative(const VecX& q, const VecX& v, const VecX& p, int k) const {
  VecX r;
  forceParamDerivative(q, v, p, k, r);
  return r;
}

void Assembler::forceParamDerivative(const VecX& q, const VecX& v, const VecX& p, int k, VecX& r) const {
  r.setZero(n());
  VecX& dQ = paramDQ_;  // kept: the sensitivity right-hand sides ask at every step and parameter
  MatX& dM = paramDM_;
  // Gravity loads are M times the uniform acceleration (rigid bars and consistent beam
  // masses alike), so d Q / d g_c = M_e e_c element by element.
  for (size_t c = 0; c < model_.gravityParam.size(); ++c) {
    if (model_.gravityParam[c] != k) continue;
    for (size_t e = 0; e < model_.elements.size(); ++e) {
      const auto& el = *model_.elements[e];
      if (!el.mass(elementState(e, q, v, p), dM)) continue;
      // A uniform translation e_c: 1 on every node's position component c, 0 on gradients.
      const int w = (1 + el.gradients()) * model_.dim;
      VecX unit = VecX::Zero(dM.cols());
      for (int a = 0; a < unit.size() / w; ++a) unit[a * w + c] = 1.0;
      const VecX g = loadFactor_ * (dM * unit);
      const auto& map = elemDofs_[e];
      for (size_t i = 0; i < map.size(); ++i)
        if (map[i] >= 0) r[map[i]] += g[i];
    }
  }
  for (int e : elementsDependingOn(k, q, v, p)) {
    const auto& el = *model_.elements[size_t(e)];
    if (!elementParameterDerivative(el, elementState(size_t(e), q, v, p), k, dQ, dM)) continue;
    if (el.isLoad()) dQ *= loadFactor_;
    const auto& map = elemDofs_[e];
    for (size_t i = 0; i < map.size(); ++i)
      if (map[i] >= 0) r[map[i]] += dQ[i];
  }
}

VecX Assembler::massParamDerivativeTimes(const VecX& p, int k, const VecX& a) const {
  VecX r;
  massParamDerivativeTimes(p, k, a, r);
  return r;
}

void Assembler::massParamDerivativeTimes(const VecX& p, int k, const VecX& a, VecX& r) const {
  r.setZero(n());
  VecX& al = paramDQ_;
  for (const auto& [e, dM] : elementMassDerivatives(p, k)) {
    const auto& map = elemDofs_[size_t(e)];
    al.resize(Eigen::Index(map.size()));
    for (size_t i = 0; i < map.size(); ++i) al[Eigen::Index(i)] = map[i] >= 0 ? a[map[i]] : 0.0;
    for (size_t i = 0; i < map.size(); ++i)
      if (map[i] >= 0) r[map[i]] += dM.row(Eigen::Index(i)).dot(al);
  }
}

VecX Assembler::phiParamDerivative(const VecX& q, const VecX& p, int k) const {
  VecX r = VecX::Zero(m());
  VecX dphi;
  MatX dJ;
  for (int ci : constraintsDependingOn(k, q, p)) {
    const size_t c = size_t(ci);
    const auto& co = *cons_[c];
    if (constraintParameterDerivative(co, constraintState(c, q, VecX(), p), k, dphi, dJ))
      r.segment(consRow_[c], co.rows()) = dphi;
  }
  return r;
}

VecX Assembler::phiQParamDerivativeTimes(const VecX& q, const VecX& p, int k, const VecX& x) const {
  VecX r = VecX::Zero(m());
  VecX dphi;
  MatX dJ;
  for (int ci : constraintsDependingOn(k, q, p)) {
    const size_t c = size_t(ci);
    const auto& co = *cons_[c];
    if (constraintParameterDerivative(co, constraintState(c, q, VecX(), p), k, dphi, dJ) && dJ.size())
      r.segment(consRow_[c], co.rows()) = dJ * gather(consDofs_[c], x);
  }
  return r;
}

VecX Assembler::phiQParamDerivativeTransposeTimes(const VecX& q, const VecX& p, int k,
                                                  const VecX& l) const {
  VecX phiP, r;
  constraintParamTerms(q, p, k, l, phiP, r);
  return r;
}

void Assembler::constraintParamTerms(const VecX& q, const VecX& p, int k, const VecX& l, VecX& phiP,
                                     VecX& phiQPTl) const {
  phiP.setZero(m());
  phiQPTl.setZero(n());
  for (int ci : constraintsDependingOn(k, q, p)) {
    const size_t c = size_t(ci);
    const auto& co = *cons_[c];
    if (!constraintParameterDerivative(co, constraintState(c, q, VecX(), p), k, paramDphi_, paramDJ_)) continue;
    phiP.segment(consRow_[c], co.rows()) = paramDphi_;
    if (paramDJ_.size()) addTransposeTimes(paramDJ_, consDofs_[c], l.segment(consRow_[c], co.rows()), phiQPTl);
  }
}

}  // namespace flexsens
