// The parts of the scene reader beside the per-kind table: PIM cases (CaseReader.cpp) and run
// settings (SettingsReader.cpp). SceneReader.cpp calls them in the order a scene is built.
#pragma once

#include <optional>
#include <set>
#include <utility>

#include "scene/Scene.hpp"
#include "scene/SceneContext.hpp"

namespace flexsens {

/// The PIM case a model is built for (none when `name` is empty), and its parameter list.
struct CaseSelection {
  std::string name;        ///< requested case name ("" = plain model)
  std::string path;        ///< key path of the selected case, e.g. "cases[2]"
  std::string paramsPath;  ///< its "parameters" key path
  std::set<std::string> params;
  std::vector<std::pair<std::string, YAML::Node>> paramNodes;  ///< name -> YAML node (errors)
};

/// Validates every case's keys and names (into sc.caseNames); returns the selected one.
std::optional<YAML::Node> selectCase(SceneContext& ctx, const YAML::Node& list, Scene& sc, CaseSelection& sel);
/// F-R twins: the case's rigid_model bodies become rigid through the rigidization generator.
void applyRigidModels(SceneContext& ctx, const YAML::Node& c, const CaseSelection& sel);
/// The case's rigidized bodies (Lambda rows), SDOFs and parameters.
std::unique_ptr<PimCase> readPimCase(SceneContext& ctx, const YAML::Node& c, const CaseSelection& sel);

/// Axis index of a component name ("x", ...) in the scene's axes, or -1.
int axisIndex(const Model& m, const std::string& a);
/// A component name read at `n`; fails listing the scene's axes.
int component(const SceneContext& ctx, const YAML::Node& n, const std::string& path);
/// A node's component: an axis, or `x'`... (the slope's component) for a node with a slope;
/// returned as in Model::dof (dim + c for a slope component).
int nodeComponent(const SceneContext& ctx, int nd, const YAML::Node& n, const std::string& path);

void readStaticSettings(const YamlReader& r, const YAML::Node& in, StaticSceneSettings& s);
void readIntegrator(const YamlReader& r, const YAML::Node& in, IntegratorSettings& s);
void readOutputs(SceneContext& ctx, const YAML::Node& list, Scene& sc);
/// `objectives:` (scene/Objective.hpp), after the outputs and the integrator.
void readObjectives(SceneContext& ctx, const YAML::Node& list, Scene& sc);
/// `optimize:` (scene/OptimizeSpec.hpp), after the parameters and the objectives.
void readOptimize(SceneContext& ctx, const YAML::Node& in, Scene& sc);
void readOutputSettings(const YamlReader& r, const YAML::Node& o, Scene& sc);

}  // namespace flexsens
