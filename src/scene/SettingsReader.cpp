// What to run and what to write: the `integrator`, `outputs` and `output` keys of a scene.
#include <filesystem>

#include "integrators/TimeGrid.hpp"
#include "scene/SceneParts.hpp"

namespace flexsens {

void readStaticSettings(const YamlReader& r, const YAML::Node& in, StaticSceneSettings& s) {
  s.given = true;
  if (in.IsNull()) return;
  r.allowKeys(in, "static", {"load_steps", "linear"});
  if (in["linear"]) s.linear = r.boolean(in["linear"], "static.linear");
  if (s.linear && in["load_steps"])
    r.fail(in["load_steps"], "static.load_steps", "a linear analysis (linear: true) takes no load steps: remove load_steps");
  if (in["load_steps"]) {
    s.loadSteps = r.integer(in["load_steps"], "static.load_steps");
    if (s.loadSteps < 1 || s.loadSteps > 100000)
      r.fail(in["load_steps"], "static.load_steps", "expected a number of load steps from 1 to 100000");
  }
}

void readIntegrator(const YamlReader& r, const YAML::Node& in, IntegratorSettings& s) {
  r.allowKeys(in, "integrator", {"type", "t_end", "dt", "rtol", "atol", "newton_tol",
                                 "max_newton_iterations", "frame_interval", "sensitivity_error_control",
                                 "sensitivity_corrector", "sensitivity_tolerance", "rho_inf", "energy_tolerance", "energy_loss_tolerance", "newton", "projections"});
  s.type = r.text(r.require(in, "type", "integrator"), "integrator.type");
  if (!isIntegratorType(s.type))
    r.fail(in["type"], "integrator.type", std::string("expected ") + kIntegratorTypes + ", got '" + s.type + "'");
  s.tEnd = r.positive(r.require(in, "t_end", "integrator"), "integrator.t_end");
  if (in["dt"]) s.dt = r.positive(in["dt"], "integrator.dt");
  else if (s.type != "idas") r.require(in, "dt", "integrator");
  else s.dt = 0.0;
  if (in["rtol"]) s.rtol = r.positive(in["rtol"], "integrator.rtol");
  if (in["atol"]) s.atol = r.positive(in["atol"], "integrator.atol");
  if (in["newton_tol"]) s.newtonTol = r.positive(in["newton_tol"], "integrator.newton_tol");
  if (in["max_newton_iterations"]) {
    s.maxNewtonIterations = r.integer(in["max_newton_iterations"], "integrator.max_newton_iterations");
    if (s.maxNewtonIterations < 1 || s.maxNewtonIterations > 1000)  // beyond 1000 it only hides a divergence
      r.fail(in["max_newton_iterations"], "integrator.max_newton_iterations", "expected 1 ... 1000");
  }
  s.frameInterval = in["frame_interval"] ? r.positive(in["frame_interval"], "integrator.frame_interval")
                                         : std::max(s.dt, s.tEnd / 200.0);
  if (in["rho_inf"]) {
    s.rhoInf = r.number(in["rho_inf"], "integrator.rho_inf");
    if (!(s.rhoInf >= 0.0 && s.rhoInf <= 1.0)) r.fail(in["rho_inf"], "integrator.rho_inf", "expected a number in [0, 1]");
  }
  if (in["newton"]) {
    s.newton = r.text(in["newton"], "integrator.newton");
    if (!isNewtonMode(s.newton))
      r.fail(in["newton"], "integrator.newton", "expected full or modified, got '" + s.newton + "'");
  }
  if (in["projections"]) {
    s.projections = r.boolean(in["projections"], "integrator.projections");
    if (s.projections && !takesProjections(s.type))
      r.fail(in["projections"], "integrator.projections",
             "projections apply to the trapezoidal rule and generalized_alpha, not to " + s.type);
  }
  if (in["energy_tolerance"]) s.energyTolerance = r.nonNegative(in["energy_tolerance"], "integrator.energy_tolerance");
  if (in["energy_loss_tolerance"])
    s.energyLossTolerance = r.nonNegative(in["energy_loss_tolerance"], "integrator.energy_loss_tolerance");
  if (in["sensitivity_error_control"])
    s.sensitivityErrorControl = r.boolean(in["sensitivity_error_control"], "integrator.sensitivity_error_control");
  if (in["sensitivity_corrector"]) {
    s.sensitivityCorrector = r.text(in["sensitivity_corrector"], "integrator.sensitivity_corrector");
    if (!isSensitivityCorrector(s.sensitivityCorrector))
      r.fail(in["sensitivity_corrector"], "integrator.sensitivity_corrector",
             "expected staggered or simultaneous, got '" + s.sensitivityCorrector + "'");
  }
  if (in["sensitivity_tolerance"]) {
    s.sensitivityTolerance = r.text(in["sensitivity_tolerance"], "integrator.sensitivity_tolerance");
    if (!isSensitivityTolerance(s.sensitivityTolerance))
      r.fail(in["sensitivity_tolerance"], "integrator.sensitivity_tolerance",
             "expected state or normwise, got '" + s.sensitivityTolerance + "'");
  }
  if (const auto pr = checkTimes(s))  // t_end, dt, frame_interval against each other
    r.fail(in[pr->key] ? in[pr->key] : in, "integrator." + pr->key, pr->message);
}

void readOutputs(SceneContext& ctx, const YAML::Node& list, Scene& sc) {
  const YamlReader& r = ctx.r;
  const Model& m = ctx.m;
  r.requireList(list, "outputs");
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node o = list[i];
    const std::string path = at("outputs", i);
    r.allowKeys(o, path, {"name", "node", "component", "angle", "quantity"});
    OutputSpec spec;
    spec.name = r.text(r.require(o, "name", path), path + ".name");
    if (o["quantity"]) {  // position (default), velocity (its time derivative) or displacement
      const std::string qn = r.text(o["quantity"], path + ".quantity");
      if (qn != "position" && qn != "velocity" && qn != "displacement")
        r.fail(o["quantity"], path + ".quantity", "expected position, velocity or displacement, got '" + qn + "'");
      spec.rate = qn == "velocity";
      spec.displacement = qn == "displacement";
      if (spec.displacement && o["angle"])
        r.fail(o["quantity"], path + ".quantity", "a displacement is of a node's coordinate: give node and component, not angle");
    }
    for (const auto& other : sc.outputs)
      if (other.name == spec.name) r.fail(o["name"], path + ".name", "duplicate output name '" + spec.name + "'");
    if (o["angle"]) {  // signed angle [rad] from-vector -> to-vector about the axis
      if (o["node"] || o["component"]) r.fail(o, path, "give either angle or node and component, not both");
      if (m.dim != 3) r.fail(o["angle"], path + ".angle", "angle outputs need a spatial scene (dimension 3)");
      r.allowKeys(o["angle"], path + ".angle", {"axis", "from", "to"});
      const AngleNodes an = ctx.angleNodes(o["angle"], path + ".angle");
      ctx.initialAngle(an, o["angle"], path + ".angle");
      spec.angle = an.list();
      sc.outputs.push_back(spec);
      continue;
    }
    spec.node = ctx.node(r.require(o, "node", path), path + ".node");
    spec.component = nodeComponent(ctx, spec.node, r.require(o, "component", path), path + ".component");
    if (spec.displacement && spec.component >= m.dim)
      r.fail(o["component"], path + ".component", "a displacement is of a position: expected an axis, not a slope component");
    sc.outputs.push_back(spec);
  }
}

void readOutputSettings(const YamlReader& r, const YAML::Node& o, Scene& sc) {
  sc.output.directory = "results/" + std::filesystem::path(sc.file).stem().string();
  if (!o) return;
  r.allowKeys(o, "output", {"directory", "vtk", "plots"});
  if (o["directory"]) sc.output.directory = r.text(o["directory"], "output.directory");
  if (o["vtk"]) sc.output.vtk = r.boolean(o["vtk"], "output.vtk");
  if (o["plots"]) sc.output.plots = r.boolean(o["plots"], "output.plots");
}

}  // namespace flexsens
