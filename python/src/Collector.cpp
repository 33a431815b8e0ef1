#include "Collector.hpp"

#include <csignal>

#include "core/Interrupt.hpp"

namespace flexsens_python {

Collector::Collector(ResultData& data, py::object progress)
    : data_(data), callback_(std::move(progress)), nextLook_(std::chrono::steady_clock::now()) {
  flexsens::clearThreadInterrupt();  // a request belongs to one run of this thread
}

Collector::~Collector() { flexsens::clearThreadInterrupt(); }

void Collector::started(const std::vector<std::string>& columns) {
  data_.columns = columns;
  data_.series.assign(columns.size(), {});
}

void Collector::frame(const flexsens::StateWithSens& s, const std::vector<double>& row) {
  if (data_.frames == 0) {
    data_.n = s.x.q.size();
    data_.np = static_cast<long>(s.dp.size());
  }
  for (size_t c = 0; c < row.size() && c < data_.series.size(); ++c) data_.series[c].push_back(row[c]);
  data_.q.insert(data_.q.end(), s.x.q.data(), s.x.q.data() + s.x.q.size());
  data_.v.insert(data_.v.end(), s.x.v.data(), s.x.v.data() + s.x.v.size());
  for (long i = 0; i < data_.n; ++i)  // frames x n x np: the parameters of one coordinate together
    for (long k = 0; k < data_.np; ++k) {
      data_.dq.push_back(s.dp[k].q[i]);
      data_.dv.push_back(s.dp[k].v.size() ? s.dp[k].v[i] : 0.0);
    }
  ++data_.frames;
}

void Collector::progress(double t, double tEnd) {
  tReached_ = t;
  tEnd_ = tEnd;
  sawProgress_ = true;
  const auto now = std::chrono::steady_clock::now();
  if (now < nextLook_ || pending_) return;
  nextLook_ = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                        std::chrono::duration<double>(kPythonInterval));
  py::gil_scoped_acquire gil;
  lookAtPython(t, tEnd);
}

void Collector::lookAtPython(double t, double tEnd) {
  try {
    // Signal handlers run in the main thread only: elsewhere this returns 0 at once.
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!callback_.is_none()) callback_(t, tEnd);
  } catch (py::error_already_set& e) {
    pending_.emplace(e);
    flexsens::requestThreadInterrupt(SIGINT);  // this run stops at the end of its step
  }
}

void Collector::raisePending() {
  if (!pending_ && sawProgress_) lookAtPython(tReached_, tEnd_);  // a bar ends where the run did
  if (pending_) throw *pending_;
}

}  // namespace flexsens_python
