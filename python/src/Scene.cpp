#include "Scene.hpp"

#include <pybind11/stl.h>

#include <filesystem>
#include <mutex>

#include "Collector.hpp"
#include "Errors.hpp"
#include "app/Commands.hpp"
#include "core/Interrupt.hpp"
#include "output/ResultWriter.hpp"
#include "scene/InputFiles.hpp"

namespace flexsens_python {

namespace {

using flexsens::InputError;

/// Names, values and settings of the scene as read (without a case).
void describe(const flexsens::Scene& sc, SceneHandle& h) {
  const flexsens::Model& m = *sc.model;
  for (const auto& par : m.parameters) h.parameters.emplace_back(par.name, par.nominal);
  h.cases = sc.caseNames;
  for (const auto& o : sc.outputs) h.outputs.push_back(o.name);
  for (int i = 0; i < m.n; ++i) h.coordinates.push_back(m.coordinateLabel(i));
  h.dynamic = sc.hasIntegrator;
  h.integratorType = sc.integrator.type;
  h.tEnd = sc.integrator.tEnd;
  h.dt = sc.integrator.dt;
  h.rtol = sc.integrator.rtol;
  h.frameInterval = sc.integrator.frameInterval;
}

SceneHandle readHandle(std::string path, std::string text) {
  SceneHandle h;
  h.path = std::move(path);
  h.text = std::move(text);
  py::gil_scoped_release nogil;  // a scene with geometry meshes it in a child process: seconds
  describe(flexsens::readSceneText(h.text, h.path), h);
  return h;
}

/// The folder name of `out` (str or os.PathLike).
std::string pathText(const py::object& out) {
  return py::module_::import("os").attr("fspath")(out).cast<std::string>();
}

/// The case a run runs: the one named, the scene's only one, or none for a scene without cases.
std::vector<std::string> chosenCase(const SceneHandle& h, const std::optional<std::string>& name) {
  if (name) return {*name};
  if (h.cases.empty()) return {};
  if (h.cases.size() == 1) return {h.cases.front()};
  std::string names;
  for (const auto& c : h.cases) names += (names.empty() ? "" : ", ") + c;
  throw InputError(h.path + ": key 'cases': the scene has " + std::to_string(h.cases.size()) + " PIM cases (" + names +
                   "); name the one to run: run(case=...)");
}

flexsens::RunOptions runOptions(const RunArguments& a) {
  flexsens::RunOptions o;
  o.integrator = a.integrator;
  o.method = a.method;
  o.newton = a.newton;
  o.ndScheme = a.ndScheme;
  o.tEnd = a.tEnd;
  o.dt = a.dt;
  o.rtol = a.rtol;
  o.rhoInf = a.rhoInf;
  o.ndStep = a.ndStep;
  o.projections = a.projections;
  if (a.parameters) o.parameters.assign(a.parameters->begin(), a.parameters->end());
  if (!a.out.is_none()) o.outDir = pathText(a.out);
  return o;
}

/// Outputs, parameters (with the values the run uses) and coordinate labels of a prepared case.
void describeRun(const flexsens::Scene& sc, ResultData& d) {
  const flexsens::Model& m = *sc.model;
  for (const auto& o : sc.outputs) d.outputs.push_back(o.name);
  for (const auto& par : m.parameters) {
    d.parameters.push_back(par.name);
    d.parameterValues.push_back(par.nominal);
  }
  for (int i = 0; i < m.n; ++i) d.coordinates.push_back(m.coordinateLabel(i));
}

/// Before the first run that writes files (VTK frames), as the command line does at its start;
/// a process that never writes files keeps glibc's defaults.
void keepFreedMemoryOnce() {
  static std::once_flag once;
  std::call_once(once, flexsens::keepFreedMemory);
}

/// After the run, with the GIL: what Ctrl-C or the callback raised first, then the run's own
/// failure (a NumericalError carries the frames up to it), else the Result.
py::object finish(Collector& collector, std::exception_ptr failure, const std::shared_ptr<ResultData>& data) {
  collector.raisePending();
  if (!failure) return makeResult(data);
  try {
    std::rethrow_exception(failure);
  } catch (const flexsens::NumericalError& e) {
    raiseNumericalError(e.what(), data->summaryJson.empty() ? py::object(py::none()) : makeResult(data));
  }
  return py::none();  // not reached: the other errors propagate to the translation (Errors.cpp)
}

}  // namespace

SceneHandle loadScene(const std::string& path) {
  std::string text;
  try {
    text = flexsens::readBoundedFile(path, flexsens::inputPolicy().maxSceneBytes, path);
  } catch (const std::runtime_error& e) {
    throw InputError(path + ": cannot read the scene file: " + e.what());
  }
  return readHandle(path, std::move(text));
}

SceneHandle loadsScene(const std::string& text, const std::string& baseDir) {
  return readHandle((std::filesystem::path(baseDir) / "<string>").string(), text);
}

py::object runScene(const SceneHandle& h, const RunArguments& a) {
  flexsens::RunRequest request;
  request.scenePath = h.path;
  request.sceneText = h.text;
  request.cases = chosenCase(h, a.caseName);
  request.options = runOptions(a);
  auto data = std::make_shared<ResultData>();
  Collector collector(*data, a.progress);
  const flexsens::RunHooks hooks{&collector, !a.out.is_none(), false};
  if (hooks.writeFiles) keepFreedMemoryOnce();
  std::exception_ptr failure;
  {
    py::gil_scoped_release nogil;
    try {
      const std::vector<flexsens::RunCase> cases = flexsens::prepareRun(request);
      describeRun(cases.front().scene, *data);
      if (hooks.writeFiles) data->directory = cases.front().directory;
      flexsens::runCases(cases, {}, hooks);
    } catch (...) {
      failure = std::current_exception();
    }
  }
  return finish(collector, failure, data);
}

py::object staticScene(const SceneHandle& h, std::optional<int> loadSteps, std::optional<std::string> method,
                       std::optional<std::map<std::string, double>> parameters, py::object out, py::object progress) {
  flexsens::StaticRequest request;
  request.scenePath = h.path;
  request.sceneText = h.text;
  request.loadSteps = loadSteps;
  if (method) request.method = *method;
  if (parameters) request.parameters.assign(parameters->begin(), parameters->end());
  if (!out.is_none()) request.outDir = pathText(out);
  auto data = std::make_shared<ResultData>();
  for (const auto& name : h.outputs) data->outputs.push_back(name);
  for (const auto& [name, value] : h.parameters) {
    data->parameters.push_back(name);
    data->parameterValues.push_back(parameters && parameters->count(name) ? parameters->at(name) : value);
  }
  data->coordinates = h.coordinates;
  data->directory = request.outDir;
  Collector collector(*data, progress);
  const flexsens::RunHooks hooks{&collector, !out.is_none(), false};
  if (hooks.writeFiles) keepFreedMemoryOnce();
  std::exception_ptr failure;
  {
    py::gil_scoped_release nogil;
    try {
      const flexsens::StaticCommandResult r = flexsens::staticCommand(request, hooks);
      if (r.interruptedBy) throw flexsens::Interrupted(r.interruptedBy, r.interruptedAt);
    } catch (...) {
      failure = std::current_exception();
    }
  }
  return finish(collector, failure, data);
}

}  // namespace flexsens_python
