#include "app/BodyMass.hpp"

#include <set>

#include "core/Assembler.hpp"

namespace flexsens {

namespace {

/// U^T A U with U the unit translation along the first axis in the element's local coordinates.
double translationEnergy(const MatX& A, int nodes, int nodeSize) {
  double sum = 0.0;
  for (int a = 0; a < nodes; ++a)
    for (int b = 0; b < nodes; ++b) sum += A(a * nodeSize, b * nodeSize);
  return sum;
}

}  // namespace

ExplicitObjective bodyMass(const Model& m, const std::vector<int>& elements, const VecX& p) {
  ExplicitObjective out;
  out.gradient = VecX::Zero(p.size());
  const Assembler as(m);
  const VecX q = m.initialPositions(), v = VecX::Zero(m.n);  // the mass matrix is constant
  for (int e : elements) {
    const Element& el = *m.elements[size_t(e)];
    const LocalState s = as.localState(el, q, v, p);
    const int nodes = int(el.nodes().size()), size = s.nodeSize();
    MatX M;
    if (!el.mass(s, M)) continue;
    out.value += translationEnergy(M, nodes, size);
    std::set<int> bound;  // only the parameters this element reads (hundreds of per-element ones)
    for (const auto& [name, quantity] : m.elements[size_t(e)]->properties())
      if (quantity->param >= 0) bound.insert(quantity->param);
    for (int k : bound) {
      VecX dQ;
      MatX dM;
      if (el.parameterDerivative(s, k, dQ, dM) && dM.rows() == M.rows() && dM.cols() == M.cols())
        out.gradient[k] += translationEnergy(dM, nodes, size);
    }
  }
  return out;
}

ExplicitObjective explicitObjective(const Model& m, const std::vector<ObjectiveSpec>& objectives, size_t i,
                                    const VecX& p) {
  const ObjectiveSpec& o = objectives[i];
  if (o.kind == "mass") return bodyMass(m, o.elements, p);
  ExplicitObjective out;
  out.gradient = VecX::Zero(p.size());
  if (o.kind != "sum") return out;
  for (const auto& [k, w] : o.terms)
    if (objectives[size_t(k)].kind == "mass") {
      const ExplicitObjective term = bodyMass(m, objectives[size_t(k)].elements, p);
      out.value += w * term.value;
      out.gradient += w * term.gradient;
    }
  return out;
}

}  // namespace flexsens
