// flexsens.Result: what a run (or a static run) computed, kept in C++ vectors that the numpy
// arrays look into without a copy (each array's base is the Result object, read-only).
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

namespace flexsens_python {

namespace py = pybind11;

/// Filled by the Collector while the run goes (without the GIL), then owned by its Result.
struct ResultData {
  std::vector<std::string> columns;         ///< series.csv's header
  std::vector<std::vector<double>> series;  ///< per column, one value per frame
  std::vector<double> q, v;                 ///< frames x n, row-major [m, m/s]
  std::vector<double> dq, dv;               ///< frames x n x np, row-major [per unit of the parameter]
  long frames = 0;
  long n = 0, np = 0;
  std::vector<std::string> outputs;      ///< output names, in the scene's order
  std::vector<std::string> parameters;   ///< the run's design parameters
  std::vector<double> parameterValues;   ///< their values in the run
  std::vector<std::string> coordinates;  ///< labels of q's entries, "x(n1)"
  std::string summaryJson;               ///< summary.json's text (however the run ended)
  std::string directory;                 ///< where the files went; empty: none written
};

/// The Python object of a finished (or failed) run.
struct Result {
  std::shared_ptr<ResultData> data;
  py::object summary;  ///< summary.json as a dict, parsed on first use
};

void bindResult(py::module_& m);
py::object makeResult(std::shared_ptr<ResultData> data);

}  // namespace flexsens_python
