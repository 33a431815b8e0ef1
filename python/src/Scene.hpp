// flexsens.Scene: a scene read once (flexsens.load / flexsens.loads) and its commands. Each
// command goes through the library's entry points (app/Commands.hpp: prepareRun and runCases,
// staticCommand, modesCommand, checkCommand) with the scene's text, so a run here is the CLI's
// run; the object itself never changes (parameter values apply to one run).
#pragma once

#include <pybind11/pybind11.h>

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace flexsens_python {

namespace py = pybind11;

struct SceneHandle {
  std::string path;  ///< as given (loads: <base_dir>/<string>): messages, the scene's folder
  std::string text;  ///< the YAML as read
  std::vector<std::pair<std::string, double>> parameters;  ///< name, nominal value
  std::vector<std::string> cases, outputs, coordinates;
  bool dynamic = true;  ///< the scene has an integrator (a static-only scene has none)
  std::string integratorType;
  double tEnd = 0, dt = 0, rtol = 0, frameInterval = 0;  ///< [s], [s], [-], [s]
  py::object counts;  ///< `check`'s numbers as a dict, computed on first use
};

/// The keyword arguments of Scene.run (None: the scene's setting).
struct RunArguments {
  std::optional<std::string> caseName;
  std::optional<std::map<std::string, double>> parameters;
  std::optional<std::string> integrator, method, newton, ndScheme;
  std::optional<double> tEnd, dt, rtol, rhoInf, ndStep;
  std::optional<bool> projections;
  py::object out, progress;
};

SceneHandle loadScene(const std::string& path);
SceneHandle loadsScene(const std::string& text, const std::string& baseDir);
py::object runScene(const SceneHandle& scene, const RunArguments& args);
py::object staticScene(const SceneHandle& scene, std::optional<int> loadSteps, std::optional<std::string> method,
                       std::optional<std::map<std::string, double>> parameters, py::object out, py::object progress);
py::dict sceneCounts(SceneHandle& scene);
/// Modes object of `flexsens modes` (Modes.cpp).
py::object sceneModes(const SceneHandle& scene, int count);
void bindModes(py::module_& m);

void bindScene(py::module_& m);

}  // namespace flexsens_python
