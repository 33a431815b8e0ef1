// `optimize:` of a scene (scene/OptimizeSpec.hpp): the objective, the variables with their
// bounds (checked against the parameters' scene values), the constraints, the algorithm.
#include <set>

#include "elements/SimplexShape.hpp"  // fmtNumber
#include "scene/SceneParts.hpp"

namespace flexsens {

namespace {

/// The index of the objective named at `node`; fails listing the scene's objectives.
int objectiveIndex(const YamlReader& r, const Scene& sc, const YAML::Node& node, const std::string& path) {
  const std::string name = r.text(node, path);
  std::string names;
  for (size_t k = 0; k < sc.objectives.size(); ++k) {
    if (sc.objectives[k].name == name) return int(k);
    names += (names.empty() ? "" : ", ") + sc.objectives[k].name;
  }
  r.fail(node, path, "no objective named '" + name + "'; expected one of the scene's objectives" +
                         (names.empty() ? std::string(" (it defines none: add it under objectives)") : ": " + names));
}

/// The model parameters a variable binds: the parameter of that name, or every member of the
/// per-element family of that name. Empty when a PIM case left it out of the model.
std::vector<int> variableParameters(const YamlReader& r, const Scene& sc, const YAML::Node& node,
                                    const std::string& path) {
  const std::string name = r.text(node, path);
  std::vector<int> found;
  std::string names;
  std::set<std::string> families;
  for (size_t k = 0; k < sc.model->parameters.size(); ++k) {
    const Parameter& par = sc.model->parameters[k];
    if (par.name == name || par.family == name) found.push_back(int(k));
    if (par.family.empty()) names += (names.empty() ? "" : ", ") + par.name;
    else if (families.insert(par.family).second) names += (names.empty() ? "" : ", ") + par.family;
  }
  if (found.empty() && !sc.pimCase)
    r.fail(node, path, "no parameter named '" + name + "'; expected one of the scene's parameters" +
                           (names.empty() ? std::string(" (it defines none: add it under parameters)") : ": " + names));
  return found;
}

void readVariable(const SceneContext& ctx, const YAML::Node& in, const std::string& path, Scene& sc) {
  const YamlReader& r = ctx.r;
  r.requireMap(in, path);
  r.allowKeys(in, path, {"parameter", "lower", "upper"});
  OptimizeVariable var;
  var.name = r.text(r.require(in, "parameter", path), path + ".parameter");
  for (const auto& other : sc.optimize.variables)
    if (other.name == var.name) r.fail(in["parameter"], path + ".parameter", "the parameter '" + var.name + "' is a variable already");
  var.parameters = variableParameters(r, sc, in["parameter"], path + ".parameter");
  var.lower = r.number(r.require(in, "lower", path), path + ".lower");
  var.upper = r.number(r.require(in, "upper", path), path + ".upper");
  if (!(var.lower < var.upper))
    r.fail(in["lower"], path + ".lower", "expected lower < upper, got lower " + fmtNumber(var.lower) + " and upper " +
                                             fmtNumber(var.upper));
  for (int k : var.parameters) {  // the optimizer starts at the scene's values
    const Parameter& par = sc.model->parameters[size_t(k)];
    const bool below = par.nominal < var.lower;
    if (below || par.nominal > var.upper)
      r.fail(below ? in["lower"] : in["upper"], path + (below ? ".lower" : ".upper"),
             "the bounds [" + fmtNumber(var.lower) + ", " + fmtNumber(var.upper) + "] exclude the start: " + par.name +
                 " is " + fmtNumber(par.nominal) + " in the scene (" + par.boundTo +
                 "); widen the bounds or change the scene's value");
  }
  if (!var.parameters.empty()) sc.optimize.variables.push_back(var);
}

void readConstraint(const YamlReader& r, const YAML::Node& in, const std::string& path, Scene& sc) {
  r.requireMap(in, path);
  r.allowKeys(in, path, {"objective", "max", "min"});
  OptimizeConstraint c;
  c.objective = objectiveIndex(r, sc, r.require(in, "objective", path), path + ".objective");
  if (c.objective == sc.optimize.objective)
    r.fail(in["objective"], path + ".objective", "the objective minimized cannot also be a constraint");
  if (bool(in["max"]) == bool(in["min"])) r.fail(in, path, "expected one of max (J <= max) and min (J >= min)");
  c.upper = bool(in["max"]);
  c.bound = r.number(c.upper ? in["max"] : in["min"], path + (c.upper ? ".max" : ".min"));
  sc.optimize.constraints.push_back(c);
}

void readAlgorithm(const YamlReader& r, const YAML::Node& in, OptimizeSpec& spec) {
  if (in["algorithm"]) spec.algorithm = r.text(in["algorithm"], "optimize.algorithm");
  if (spec.algorithm != "mma" && spec.algorithm != "slsqp" && spec.algorithm != "lbfgs")
    r.fail(in["algorithm"], "optimize.algorithm", "expected mma, slsqp or lbfgs, got '" + spec.algorithm + "'");
  if (in["gradient"]) spec.gradient = r.text(in["gradient"], "optimize.gradient");
  if (spec.gradient != "adjoint" && spec.gradient != "forward")
    r.fail(in["gradient"], "optimize.gradient", "expected adjoint or forward, got '" + spec.gradient + "'");
  if (in["max_evaluations"]) {
    spec.maxEvaluations = r.integer(in["max_evaluations"], "optimize.max_evaluations");
    if (spec.maxEvaluations < 1 || spec.maxEvaluations > 1000000)
      r.fail(in["max_evaluations"], "optimize.max_evaluations", "expected a whole number from 1 to 1000000");
  }
  if (in["tolerance"]) {
    spec.tolerance = r.positive(in["tolerance"], "optimize.tolerance");
    if (spec.tolerance >= 1.0) r.fail(in["tolerance"], "optimize.tolerance", "expected a relative tolerance below 1");
  }
}

}  // namespace

void readOptimize(SceneContext& ctx, const YAML::Node& in, Scene& sc) {
  const YamlReader& r = ctx.r;
  r.requireMap(in, "optimize");
  r.allowKeys(in, "optimize", {"objective", "algorithm", "variables", "constraints", "max_evaluations", "tolerance",
                               "gradient"});
  OptimizeSpec& spec = sc.optimize;
  spec.given = true;
  spec.where = ctx.where(in, "optimize");
  spec.objective = objectiveIndex(r, sc, r.require(in, "objective", "optimize"), "optimize.objective");
  readAlgorithm(r, in, spec);
  const YAML::Node vars = r.require(in, "variables", "optimize");
  r.requireList(vars, "optimize.variables");
  if (vars.size() == 0) r.fail(vars, "optimize.variables", "expected at least one variable {parameter, lower, upper}");
  for (size_t i = 0; i < vars.size(); ++i) readVariable(ctx, vars[i], at("optimize.variables", i), sc);
  if (!in["constraints"]) return;
  r.requireList(in["constraints"], "optimize.constraints");
  for (size_t i = 0; i < in["constraints"].size(); ++i)
    readConstraint(r, in["constraints"][i], at("optimize.constraints", i), sc);
  if (spec.algorithm == "lbfgs" && !spec.constraints.empty())
    r.fail(in["constraints"], "optimize.constraints",
           "algorithm lbfgs takes bounds only, no constraints; use mma or slsqp, or remove the constraints");
}

}  // namespace flexsens
