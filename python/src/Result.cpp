#include "Result.hpp"

#include <pybind11/stl.h>

#include <algorithm>

#include "Arrays.hpp"

namespace flexsens_python {

namespace {

py::array view(const py::object& owner, const std::vector<double>& data, std::vector<py::ssize_t> shape) {
  return readOnlyView(owner, data, std::move(shape));
}

const ResultData& dataOf(const py::object& self) { return *self.cast<const Result&>().data; }

/// The series column `name`, or None when the run has none of that name.
py::object column(const py::object& self, const std::string& name) {
  const ResultData& d = dataOf(self);
  const auto it = std::find(d.columns.begin(), d.columns.end(), name);
  if (it == d.columns.end()) return py::none();
  return view(self, d.series[static_cast<size_t>(it - d.columns.begin())], {d.frames});
}

py::dict summaryOf(const py::object& self) {
  Result& r = self.cast<Result&>();
  if (!r.summary) r.summary = py::module_::import("json").attr("loads")(r.data->summaryJson);
  return r.summary;
}

py::dict outputs(const py::object& self) {
  py::dict out;
  for (const auto& name : dataOf(self).outputs) out[py::str(name)] = column(self, name);
  return out;
}

py::dict sensitivities(const py::object& self) {
  py::dict out;
  const ResultData& d = dataOf(self);
  for (const auto& o : d.outputs)
    for (const auto& p : d.parameters) out[py::make_tuple(o, p)] = column(self, "d" + o + "/d" + p);
  return out;
}

py::dict series(const py::object& self) {
  py::dict out;
  for (const auto& name : dataOf(self).columns) out[py::str(name)] = column(self, name);
  return out;
}

py::object energy(const py::object& self) {
  py::object kinetic = column(self, "kinetic_J");
  if (kinetic.is_none()) return py::none();  // static runs have no energy columns
  py::dict out;
  out["kinetic"] = kinetic;
  out["potential"] = column(self, "potential_J");
  out["total"] = column(self, "energy_J");
  return out;
}

py::dict parameterValues(const py::object& self) {
  py::dict out;
  const ResultData& d = dataOf(self);
  for (size_t k = 0; k < d.parameters.size(); ++k) out[py::str(d.parameters[k])] = d.parameterValues[k];
  return out;
}

std::string repr(const py::object& self) {
  const ResultData& d = dataOf(self);
  return "<flexsens.Result " + summaryOf(self)["status"].cast<std::string>() + ": " + std::to_string(d.frames) +
         " frames, n = " + std::to_string(d.n) + ", " + std::to_string(d.np) + " parameters>";
}

}  // namespace

py::object makeResult(std::shared_ptr<ResultData> data) { return py::cast(Result{std::move(data), py::object()}); }

void bindResult(py::module_& m) {
  py::class_<Result>(m, "Result", "What a run computed: frames of the outputs, their sensitivities, the state "
                                  "and its sensitivities, and summary.json. Arrays are read-only views.")
      .def_property_readonly("t", [](py::object s) {
        const ResultData& d = dataOf(s);
        return d.series.empty() ? view(s, {}, {0}) : view(s, d.series.front(), {d.frames}); },
                             "frame times [s] (static runs: load factors)")
      .def_property_readonly("outputs", outputs, "dict output name -> values per frame")
      .def_property_readonly("sensitivities", sensitivities, "dict (output, parameter) -> d output / d parameter per frame")
      .def_property_readonly("series", series, "dict column -> values per frame: every column of series.csv")
      .def_property_readonly("q", [](py::object s) { return view(s, dataOf(s).q, {dataOf(s).frames, dataOf(s).n}); },
                             "positions, frames x n [m]")
      .def_property_readonly("v", [](py::object s) { return view(s, dataOf(s).v, {dataOf(s).frames, dataOf(s).n}); },
                             "velocities, frames x n [m/s]")
      .def_property_readonly("dq", [](py::object s) {
        const ResultData& d = dataOf(s);
        return view(s, d.dq, {d.frames, d.n, d.np}); }, "dq/dp, frames x n x parameters")
      .def_property_readonly("dv", [](py::object s) {
        const ResultData& d = dataOf(s);
        return view(s, d.dv, {d.frames, d.n, d.np}); }, "dv/dp, frames x n x parameters")
      .def_property_readonly("energy", energy, "dict kinetic, potential, total -> [J] per frame (None for a static run)")
      .def_property_readonly("summary", summaryOf, "summary.json as a dict")
      .def_property_readonly("status", [](py::object s) { return summaryOf(s)["status"]; },
                             "complete, suspect, failed or interrupted")
      .def_property_readonly("reason", [](py::object s) -> py::object {
        py::dict js = summaryOf(s);
        return js.contains("error") ? js["error"] : py::str(""); }, "why the run is suspect or failed; '' otherwise")
      .def_property_readonly("parameters", parameterValues, "dict parameter -> the value the run used")
      .def_property_readonly("coordinates", [](py::object s) { return dataOf(s).coordinates; },
                             "labels of q's entries, e.g. 'x(n1)'")
      .def_property_readonly("directory", [](py::object s) -> py::object {
        const std::string& dir = dataOf(s).directory;
        return dir.empty() ? py::object(py::none()) : py::object(py::str(dir)); }, "where the files went; None")
      .def("__len__", [](py::object s) { return dataOf(s).frames; })
      .def("__repr__", repr);
}

}  // namespace flexsens_python
