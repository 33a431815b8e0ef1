// The files of `flexsens sweep`: sweep.csv (one row per sample in sample order: index,
// parameter values, case, status, reason, then the outputs and sensitivities at each time)
// and sweep.json (the design, the columns, the counts per status, the ranks and timing).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "app/SweepSample.hpp"

namespace flexsens {

/// What the sweep ran and how each sample ended (rows[i] is sample i).
struct SweepTable {
  std::string scenePath;
  SweepDesign design;
  bool statics = false;
  std::vector<double> times;          ///< [s] (dynamic sweeps)
  std::vector<std::string> outputs;
  std::vector<OutputColumn> columns;
  std::vector<Sample> samples;
  std::vector<SampleRow> rows;
  bool hasCases() const { return !(design.cases.size() == 1 && design.cases.front().empty()); }
};

/// How the sweep went as a whole (sweep.json).
struct SweepRunInfo {
  std::string status = "complete";  ///< complete (every sample ran to an outcome) | interrupted
  std::string interruptedBy;        ///< SIGINT | SIGTERM
  int ranks = 1;
  double wallSeconds = 0.0;
  double overheadPerSample = 0.0;   ///< [s] scheduling cost per sample (parallel/TaskFarm.hpp)
  double sampleTimeLimit = 0.0;     ///< [s] 0: none
  std::vector<std::string> lostRanks;
};

/// The statuses in the order reports list them.
const std::vector<std::string>& sampleStatuses();
/// Number of rows per status (every status present, 0 included).
std::map<std::string, int> countStatuses(const std::vector<SampleRow>& rows);
/// A number as the shortest text that reads back to the same double.
std::string exactNumber(double v);

std::string sweepCsv(const SweepTable& t);
std::string sweepJson(const SweepTable& t, const SweepRunInfo& info);

}  // namespace flexsens
