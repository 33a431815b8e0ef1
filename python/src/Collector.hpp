// The run's listener on the Python side: keeps every frame (the series row the writer computed,
// q, v and their sensitivities) in a ResultData, and while the run goes (without the GIL) looks
// at Python every kPythonInterval: takes the GIL for a moment, runs the signal handlers (Ctrl-C
// raises KeyboardInterrupt there) and the progress callback. An exception from either stops
// the run of this thread at the end of its step (core/Interrupt.hpp, requestThreadInterrupt)
// and is raised when the run has ended.
#pragma once

#include <pybind11/pybind11.h>

#include <chrono>
#include <optional>

#include "Result.hpp"
#include "app/Run.hpp"

namespace flexsens_python {

/// [s] between two looks at Python: Ctrl-C stops a run within about this plus one step, and a
/// progress bar moves 20 times a second; taking the GIL costs microseconds, a step far more.
constexpr double kPythonInterval = 0.05;

class Collector : public flexsens::RunListener {
 public:
  /// Construct and destroy with the GIL held; `progress` is None or callable(t, t_end).
  Collector(ResultData& data, py::object progress);
  ~Collector() override;
  void started(const std::vector<std::string>& columns) override;
  void frame(const flexsens::StateWithSens& s, const std::vector<double>& row) override;
  void progress(double t, double tEnd) override;
  void finished(const std::string& summaryJson) override { data_.summaryJson = summaryJson; }
  /// With the GIL, after the run: the last progress call (t reached, t_end), then raises
  /// what Ctrl-C or the callback raised during the run, if anything.
  void raisePending();
  bool hasPending() const { return pending_.has_value(); }

 private:
  void lookAtPython(double t, double tEnd);  ///< with the GIL
  ResultData& data_;
  py::object callback_;
  std::chrono::steady_clock::time_point nextLook_;
  std::optional<py::error_already_set> pending_;
  double tReached_ = 0.0, tEnd_ = 0.0;  ///< [s]
  bool sawProgress_ = false;
};

}  // namespace flexsens_python
