// Writes a run's results: series.csv (t, named outputs and their parameter derivatives),
// one VTK .vtu per frame plus frames.pvd for ParaView, and summary.json at the end.
// VTK objects are created only when VTK output is enabled.
#pragma once

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "integrators/State.hpp"
#include "output/Energy.hpp"
#include "scene/Scene.hpp"

namespace flexsens {

class ResultWriter : public Observer {
 public:
  /// dir must exist; an empty dir writes no file (the rows are computed all the same, for a
  /// caller that keeps them in memory). stem prefixes the file names (e.g. "" or "R1_"). Error messages name
  /// the files under shownDir (the final directory when dir is its staging copy).
  /// timeColumn names series.csv's first column ("load_factor" for static runs).
  /// Each driver adds its reaction (<name>.reaction_N or _Nm: -lambda dPhi/ds) after the outputs'
  /// derivatives, then its derivatives. With `energy`, series.csv ends with the columns
  /// kinetic_J, potential_J, energy_J.
  ResultWriter(const Scene& scene, std::string dir, std::string stem, std::string shownDir = "",
               const std::string& timeColumn = "t", const EnergyMeter* energy = nullptr);
  void frame(const StateWithSens& s) override;
  void progress(double t) override;
  void reached(const IntegratorStats& st) override { stats_ = st; }
  /// Writes the .pvd index and closes the CSV; call when the run ended (complete or not).
  /// Every write is checked: OutputError names the file and the OS reason.
  void close();
  /// Time the integration reached [s] and the counters reported with it.
  double timeReached() const { return tReached_; }
  const IntegratorStats& statistics() const { return stats_; }
  const std::vector<double>& frameTimes() const { return times_; }
  const std::vector<std::string>& files() const { return files_; }
  /// Values of the named outputs (and derivatives) at the last frame, for reports.
  const std::vector<double>& lastRow() const { return lastRow_; }
  const std::vector<std::string>& columns() const { return columns_; }
  long frames() const { return static_cast<long>(times_.size()); }
  /// Leaves out the progress line on stderr (a caller that shows progress itself).
  void hideProgress() { showProgress_ = false; }

 private:
  void writeVtu(const StateWithSens& s, const std::string& name) const;
  /// Local positions (and their parameter derivatives) of a node list, ground nodes fixed.
  VecX gatherNodes(const std::vector<int>& nodes, const VecX& q, bool derivative) const;
  /// Drivers (constraint index, first multiplier row): their reactions are columns.
  std::vector<std::pair<size_t, int>> drivers_;
  [[noreturn]] void fail(const std::string& name, int err) const;
  /// NumericalError naming the column, the time and a remedy if lastRow_ holds a NaN or inf:
  /// no non-finite number reaches series.csv (and through it summary.json) of any run.
  void requireFiniteRow() const;
  const Scene& scene_;
  const EnergyMeter* energy_;
  std::string dir_, stem_, shownDir_;
  IntegratorStats stats_;
  double tReached_ = 0.0;
  std::ofstream csv_;
  std::vector<std::string> columns_;
  std::vector<double> lastRow_;
  std::vector<double> times_;
  std::vector<std::string> vtuFiles_, files_;
  double tEnd_;
  double startWall_;
  double lastPrint_ = 0.0;
  bool printed_ = false;
  bool showProgress_ = true;
  bool writes_ = true;  ///< false: no dir, no file
};

/// VTK's XML writer allocates and frees large buffers for every frame; glibc would return them
/// to the kernel each time (brk shrink + TLB flush), which cost 80% of a 500-frame run of a
/// small model. Keeps freed memory in the process instead (mallopt, for the whole process: the
/// command line sets it at its start, the Python module before its first run that writes files).
void keepFreedMemory();

/// Minimal JSON text building for summary.json (values are numbers, strings, lists).
std::string jsonString(const std::string& s);
std::string jsonNumber(double v);  ///< non-finite numbers become null

}  // namespace flexsens
