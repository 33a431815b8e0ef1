// Scene.counts: the numbers `flexsens check` prints (app/Commands.hpp, checkCommand).
#include "Scene.hpp"

#include <pybind11/stl.h>

#include "app/Commands.hpp"

namespace flexsens_python {

namespace {

py::dict caseCounts(const flexsens::CaseCheck& c) {
  const flexsens::PimReport& r = c.pim;
  py::dict d;
  d["n"] = c.n;
  d["m"] = c.m;
  d["d"] = c.n - c.m;
  d["m_r"] = r.mr;
  d["lambda_generated"] = r.lambdaGenerated;
  d["lambda_dropped"] = r.lambdaDropped;
  d["massless"] = r.massless;
  d["e"] = r.me;
  d["d_s"] = r.ds;
  d["condition_A"] = r.condition;
  return d;
}

py::dict toDict(const flexsens::CheckResult& r) {
  py::dict d;
  d["dimension"] = r.dim;
  d["n"] = r.n;
  d["m"] = r.m;
  d["d"] = r.n - r.m;
  d["elements"] = r.elements;
  d["constraints"] = r.constraints;
  d["parameters"] = r.parameters;
  d["outputs"] = r.outputs;
  d["redundant_rows"] = r.redundantRows;
  d["independent"] = r.stillDependent.rows.empty();
  py::dict cases;
  for (const auto& c : r.cases) cases[py::str(c.name)] = caseCounts(c);
  d["cases"] = cases;
  return d;
}

}  // namespace

py::dict sceneCounts(SceneHandle& h) {
  if (!h.counts) {
    flexsens::CheckResult r;
    {
      py::gil_scoped_release nogil;  // one PIM per case
      r = flexsens::checkCommand(h.path, h.text);
    }
    h.counts = toDict(r);
  }
  return h.counts;
}

}  // namespace flexsens_python
