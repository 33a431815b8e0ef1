#include "app/ParameterValues.hpp"

#include <cmath>

#include "app/Run.hpp"
#include "integrators/InitialState.hpp"

namespace flexsens {

namespace {

std::string parameterNames(const Model& m) {
  std::string names;
  for (const auto& par : m.parameters) names += (names.empty() ? "" : ", ") + par.name;
  return names.empty() ? "none" : names;
}

/// Node positions, gradients and their rates from q and v (Model::initialPositions inverted).
void setInitialState(Model& m, const VecX& q, const VecX& v) {
  for (auto& nd : m.nodes) {
    if (!nd.ground) {
      nd.position = q.segment(nd.firstDof, m.dim);
      nd.velocity = v.segment(nd.firstDof, m.dim);
    }
    if (nd.slopeDof >= 0) {
      nd.slope = q.segment(nd.slopeDof, nd.slope.size());
      nd.slopeRate = v.segment(nd.slopeDof, nd.slope.size());
    }
  }
}

/// The nominal values with the named ones in place; InputError for an unknown name or a value
/// that is not finite.
VecX parameterVector(const Scene& sc, const ParameterChanges& values) {
  const Model& m = *sc.model;
  VecX p = m.nominalParameters();
  for (const auto& [name, value] : values) {
    size_t k = 0;
    while (k < m.parameters.size() && m.parameters[k].name != name) ++k;
    if (k == m.parameters.size())
      throw InputError(sc.file + ": key 'parameters': no parameter named '" + name + "'" +
                       (sc.pimCase ? " in case " + sc.pimCase->name + " (a case's start depends on its own parameters only)"
                                   : "") + "; parameters: " + parameterNames(m));
    if (!std::isfinite(value))
      throw InputError(sc.file + ": key 'parameters': the value of '" + name + "' must be a finite number");
    p[static_cast<Eigen::Index>(k)] = value;
  }
  return p;
}

void setNominal(Model& m, const VecX& p) {
  for (size_t k = 0; k < m.parameters.size(); ++k) m.parameters[k].nominal = p[static_cast<Eigen::Index>(k)];
}

}  // namespace

void setParameterValues(Scene& sc, const ParameterChanges& values) { setNominal(*sc.model, parameterVector(sc, values)); }

void applyParameterValues(Scene& sc, const ParameterChanges& values) {
  Model& m = *sc.model;
  const VecX p0 = m.nominalParameters(), p = parameterVector(sc, values);
  if (p == p0) return;
  sc.requireDynamics();  // the nominal start needs a model the integrators can run
  const Assembler as(m);
  const StateWithSens start = initialState(as, p0, sc.pimCase.get());  // at the nominal values
  VecX v = start.x.v;
  for (Eigen::Index k = 0; k < p.size(); ++k) v += start.dp[k].v * (p[k] - p0[k]);
  as.setTime(start.x.t);
  const VecX q = sc.pimCase ? perturbedConfiguration(as, *sc.pimCase, start.x.q, p0, p)
                            : projectPositions(as, start.x.q, p);
  setInitialState(m, q, projectVelocities(as, q, v, p));
  setNominal(m, p);
}

}  // namespace flexsens
