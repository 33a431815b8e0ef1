// Scene.modes: natural frequencies, shapes and the parts that carry them (`flexsens modes`,
// app/Commands.hpp modesCommand, app/Modes.hpp).
#include <pybind11/stl.h>

#include <cmath>

#include "Arrays.hpp"
#include "Scene.hpp"
#include "app/Commands.hpp"

namespace flexsens_python {

namespace {

struct ModesObject {
  flexsens::ModalAnalysis analysis;
  int count = 5;
  std::vector<int> listed;     ///< indices into analysis.modes: lowest elastic, then highest
  std::vector<double> shapes;  ///< listed x n, row-major
  std::vector<std::string> coordinates;
  py::object summary;
};

const ModesObject& modesOf(const py::object& self) { return self.cast<const ModesObject&>(); }

std::vector<double> listedOmega(const ModesObject& m, double scale) {
  std::vector<double> w;
  for (int j : m.listed) w.push_back(m.analysis.modes[j].omega() * scale);
  return w;
}

py::list parts(const ModesObject& m) {
  py::list all;
  for (int j : m.listed) {
    py::list mode;
    for (const auto& sh : m.analysis.modes[j].parts)
      mode.append(py::dict(py::arg("part") = sh.part, py::arg("strain") = sh.strain, py::arg("kinetic") = sh.kinetic));
    all.append(mode);
  }
  return all;
}

}  // namespace

py::object sceneModes(const SceneHandle& h, int count) {
  flexsens::ModesRequest request;
  request.scenePath = h.path;
  request.sceneText = h.text;
  request.count = count;
  ModesObject m;
  m.count = count;
  m.coordinates = h.coordinates;
  {
    py::gil_scoped_release nogil;
    m.analysis = flexsens::modesCommand(request).analysis;
  }
  std::vector<int> low, high;
  flexsens::listedModes(m.analysis, count, low, high);
  m.listed = low;
  m.listed.insert(m.listed.end(), high.begin(), high.end());
  for (int j : m.listed) {
    const flexsens::VecX& x = m.analysis.modes[j].shape;
    m.shapes.insert(m.shapes.end(), x.data(), x.data() + x.size());
  }
  return py::cast(std::move(m));
}

void bindModes(py::module_& mod) {
  py::class_<ModesObject>(mod, "Modes", "Modes of the model linearized at its consistent initial state: the `count` "
                                        "lowest elastic ones and the `count` highest, as `flexsens modes` lists them.")
      .def_property_readonly("frequencies", [](py::object s) {
        return py::array(py::cast(listedOmega(modesOf(s), 1.0 / (2 * M_PI)))); }, "f [Hz] of the listed modes")
      .def_property_readonly("omega", [](py::object s) { return py::array(py::cast(listedOmega(modesOf(s), 1.0))); },
                             "omega [rad/s] of the listed modes (negative: unstable, omega^2 < 0)")
      .def_property_readonly("indices", [](py::object s) {
        std::vector<int> one;
        for (int j : modesOf(s).listed) one.push_back(j + 1);
        return one; }, "each listed mode's number in the ascending list of all modes (1 = lowest)")
      .def_property_readonly("shapes", [](py::object s) {
        const ModesObject& m = modesOf(s);
        return readOnlyView(s, m.shapes, {static_cast<py::ssize_t>(m.listed.size()), m.analysis.n}); },
        "listed modes x n: each shape in the coordinates q, x^T M x = 1")
      .def_property_readonly("parts", [](py::object s) { return parts(modesOf(s)); },
                             "per listed mode, the parts' shares of its energy (largest first)")
      .def_property_readonly("all_omega", [](py::object s) {
        std::vector<double> w;
        for (const auto& md : modesOf(s).analysis.modes) w.push_back(md.omega());
        return py::array(py::cast(w)); }, "omega [rad/s] of every mode, rigid-body ones included, ascending")
      .def_property_readonly("coordinates", [](py::object s) { return modesOf(s).coordinates; })
      .def_property_readonly("summary", [](py::object s) {
        ModesObject& m = s.cast<ModesObject&>();
        if (!m.summary) m.summary = py::module_::import("json").attr("loads")(flexsens::modesJson(m.analysis, m.count));
        return m.summary; }, "`flexsens modes --json` as a dict")
      .def_property_readonly("report", [](py::object s) { return flexsens::modesReport(modesOf(s).analysis, modesOf(s).count); },
                             "`flexsens modes`' text")
      .def("__len__", [](py::object s) { return modesOf(s).listed.size(); });
}

}  // namespace flexsens_python
