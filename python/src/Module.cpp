// The Python module `flexsens`: flexsens.load(path) and flexsens.loads(text, base_dir) return a
// Scene; Scene.run, Scene.static and Scene.modes call the library's commands (docs/python.md).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "Errors.hpp"
#include "Result.hpp"
#include "Scene.hpp"
#include "scene/InputFiles.hpp"

namespace flexsens_python {

namespace {

std::string pathText(const py::object& path) { return py::module_::import("os").attr("fspath")(path).cast<std::string>(); }

py::object integratorSettings(const SceneHandle& h) {
  if (!h.dynamic) return py::none();
  return py::dict(py::arg("type") = h.integratorType, py::arg("t_end") = h.tEnd, py::arg("dt") = h.dt,
                  py::arg("rtol") = h.rtol, py::arg("frame_interval") = h.frameInterval);
}

py::dict parameterDict(const SceneHandle& h) {
  py::dict d;
  for (const auto& [name, value] : h.parameters) d[py::str(name)] = value;
  return d;
}

py::object run(const SceneHandle& h, std::optional<std::string> caseName,
               std::optional<std::map<std::string, double>> parameters, std::optional<std::string> integrator,
               std::optional<double> tEnd, std::optional<double> dt, std::optional<double> rtol,
               std::optional<std::string> method, std::optional<std::string> newton, py::object out,
               py::object progress, std::optional<double> rhoInf, std::optional<bool> projections,
               std::optional<double> ndStep, std::optional<std::string> ndScheme) {
  RunArguments a{caseName, parameters, integrator, method, newton, ndScheme, tEnd, dt, rtol, rhoInf, ndStep,
                 projections, out, progress};
  return runScene(h, a);
}

void bindSceneClass(py::module_& m) {
  py::class_<SceneHandle>(m, "Scene", "A scene read from YAML (flexsens.load, flexsens.loads). It does not change: "
                                      "parameter values and options apply to one run.")
      .def_property_readonly("file", [](const SceneHandle& h) { return h.path; })
      .def_property_readonly("text", [](const SceneHandle& h) { return h.text; }, "the YAML as read")
      .def_property_readonly("parameters", parameterDict, "dict design parameter -> nominal value")
      .def_property_readonly("cases", [](const SceneHandle& h) { return h.cases; }, "names of the PIM cases")
      .def_property_readonly("outputs", [](const SceneHandle& h) { return h.outputs; }, "names of the outputs")
      .def_property_readonly("coordinates", [](const SceneHandle& h) { return h.coordinates; }, "labels of q")
      .def_property_readonly("integrator", integratorSettings, "the scene's integrator settings (None: static only)")
      .def_property_readonly("counts", sceneCounts, "sizes as `flexsens check` prints them (n, m, d, per case m_r, d_s, ...)")
      .def("run", run, "Integrates the scene (one PIM case) and returns a Result; see docs/python.md.",
           py::arg("case") = py::none(), py::arg("parameters") = py::none(), py::arg("integrator") = py::none(),
           py::arg("t_end") = py::none(), py::arg("dt") = py::none(), py::arg("rtol") = py::none(),
           py::arg("method") = "dd", py::arg("newton") = py::none(), py::arg("out") = py::none(),
           py::arg("progress") = py::none(), py::kw_only(), py::arg("rho_inf") = py::none(),
           py::arg("projections") = py::none(), py::arg("nd_step") = py::none(), py::arg("nd_scheme") = py::none())
      .def("static", staticScene, "Load-stepped static equilibrium with its sensitivities; returns a Result "
                                  "(t: the load factors).",
           py::arg("load_steps") = py::none(), py::arg("method") = py::none(), py::arg("parameters") = py::none(),
           py::arg("out") = py::none(), py::arg("progress") = py::none())
      .def("modes", sceneModes, "Natural frequencies, shapes and energy shares at the initial state.",
           py::arg("count") = 5)
      .def("__repr__", [](const SceneHandle& h) {
        return "<flexsens.Scene " + h.path + ": " + std::to_string(h.coordinates.size()) + " coordinates, " +
               std::to_string(h.parameters.size()) + " parameters, " + std::to_string(h.cases.size()) + " cases>"; });
}

void bindLoading(py::module_& m) {
  m.def("load", [](const py::object& path) { return loadScene(pathText(path)); },
        "Reads a scene file (YAML); InputError names the file, line and key of a mistake.", py::arg("path"));
  m.def("loads", [](const std::string& text, const py::object& baseDir) { return loadsScene(text, pathText(baseDir)); },
        "Reads a scene from YAML text; the files it names are relative to base_dir.", py::arg("text"),
        py::arg("base_dir") = ".");
  m.def("allow_path", [](const py::object& folder) { flexsens::allowInputDirectory(pathText(folder), "allow_path"); },
        "Lets scenes read files in `folder` and below besides their own folder, as the CLI's --allow-path: for "
        "the whole process (call it before runs start in other threads).", py::arg("folder"));
}

}  // namespace

void defineModule(py::module_& m) {
  m.doc() = "flexsens: flexible multibody dynamics with design sensitivities (docs/python.md)";
  m.attr("__version__") = "0.1.0";
  registerErrors(m);
  bindResult(m);
  bindModes(m);
  bindSceneClass(m);
  bindLoading(m);
}

}  // namespace flexsens_python

PYBIND11_MODULE(flexsens, m) { flexsens_python::defineModule(m); }
