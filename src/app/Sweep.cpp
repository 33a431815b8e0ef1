#include "app/Sweep.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "app/PlotScript.hpp"
#include "output/Manifest.hpp"
#include "output/RunDirectory.hpp"
#include "parallel/TaskFarm.hpp"

namespace flexsens {

namespace fs = std::filesystem;

namespace {

/// This process's private folder for its samples' runs (under $TMPDIR or /tmp), removed at
/// the end. Each rank has its own: ranks on other machines need no shared file system.
class Scratch {
 public:
  Scratch() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/flexsens-sweep-XXXXXX";
    if (!::mkdtemp(pattern.data())) throw OutputError("cannot create a scratch folder " + pattern + " for the samples");
    path_ = pattern;
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

std::string describeSample(const SweepTable& t, int index) {
  std::ostringstream os;
  const Sample& s = t.samples[index];
  os << "sample " << index << "/" << t.samples.size() << " [";
  bool first = true;
  for (const ParameterRange& r : t.design.ranges)
    if (r.swept()) {
      os << (first ? "" : ", ") << r.name << " = " << exactNumber(s.values.at(r.name));
      first = false;
    }
  if (!s.caseName.empty()) os << ", case " << s.caseName;
  return os.str() + "]";
}

/// A sample's row from how its task ended (on rank 0), with a line on stderr.
SampleRow rowOf(const SweepTable& t, const TaskOutcome& o, double timeLimit) {
  SampleRow row;
  if (o.done) {
    row = unpackSampleRow(o.payload);
  } else {
    row.index = o.index;
    row.status = o.interrupted ? "interrupted" : "lost";
    row.reason = o.lost;
    if (!o.interrupted && timeLimit > 0 && o.lost.rfind("exceeded the time limit", 0) == 0)
      row.reason += " (--sample-time-limit)";
    row.cells.assign(t.columns.size(), "");
  }
  row.rank = o.rank;
  row.seconds = o.seconds;
  std::ostringstream os;
  os << "flexsens sweep: " << describeSample(t, o.index) << " " << row.status;
  if (!row.reason.empty()) os << ": " << row.reason.substr(0, 300);
  os << " (" << std::setprecision(3) << row.seconds << " s, rank " << row.rank << ")\n";
  std::cerr << os.str();
  return row;
}

/// <staging>/samples/<index>/ with the samples' series.csv and summary.json, each folder
/// with its manifest (output/Manifest.hpp) so that a rerun replaces them.
void writeSampleFolders(RunDirectory& dir, const SweepTable& t) {
  const std::string samples = dir.staging() + "/samples", shown = dir.final() + "/samples";
  fs::create_directories(samples);
  for (const SampleRow& r : t.rows) {
    if (r.files.empty()) continue;
    const std::string name = std::to_string(r.index);
    fs::create_directories(samples + "/" + name);
    for (const auto& [file, text] : r.files)
      writeFileChecked(samples + "/" + name + "/" + file, shown + "/" + name + "/" + file, text);
    writeManifestOfContents(samples + "/" + name, shown + "/" + name, "sample", {});
  }
  writeManifestOfContents(samples, shown, "samples", {});
}

/// OpenMPI's mpirun ends the whole job when a rank dies unless --enable-recovery is given
/// (it then sets OMPI_MCA_orte_enable_recovery=1 for the ranks): say so once, on rank 0.
void noteRecovery(const RankSession& session) {
  const char* recovery = std::getenv("OMPI_MCA_orte_enable_recovery");
  if (session.rank() != 0 || !session.spread() || !std::getenv("OMPI_COMM_WORLD_SIZE")) return;
  if (recovery && std::string(recovery) == "1") return;
  std::cerr << "flexsens: note: without mpirun --enable-recovery, OpenMPI ends the whole job when a rank dies "
               "(the sweep then keeps the samples that finished); with it the other ranks finish (docs/sweeps.md)\n";
}

SweepRunInfo runInfo(const FarmSummary& f, double wall, double timeLimit) {
  SweepRunInfo info;
  info.ranks = f.ranks;
  info.wallSeconds = wall;
  info.overheadPerSample = f.overheadPerTask;
  info.sampleTimeLimit = timeLimit;
  info.lostRanks = f.lostRanks;
  if (f.interruptedBy) {
    info.status = "interrupted";
    info.interruptedBy = f.interruptedBy == SIGINT ? "SIGINT" : f.interruptedBy == SIGTERM ? "SIGTERM" : "signal";
  }
  return info;
}

}  // namespace

int SweepResult::status() const {
  for (const SampleRow& r : table.rows)
    if (r.status != "complete") return 5;
  return 0;
}

SweepResult sweepCommand(const SweepRequest& request) {
  const auto t0 = std::chrono::steady_clock::now();
  RankSession session("sweep");
  std::unique_ptr<RunDirectory> dir;
  SweepPlan plan;
  try {
    plan = prepareSweep(request);  // every rank: the same samples, the same errors
    if (session.rank() == 0) dir = std::make_unique<RunDirectory>(plan.outDir, "sweep");
  } catch (...) {
    stopFarmWorkers(session);  // they wait for their first task
    throw;
  }
  noteRecovery(session);
  const Scratch scratch;
  plan.setup.scratch = scratch.path();
  SweepResult res;
  SweepTable& t = res.table = plan.table;
  t.rows.resize(t.samples.size());
  for (size_t i = 0; i < t.rows.size(); ++i) {  // not_run until a rank reports it
    t.rows[i].index = static_cast<int>(i);
    t.rows[i].cells.resize(t.columns.size());
  }
  FarmOptions farm;
  farm.timeLimit = request.sampleTimeLimit;
  farm.rankTimeout = request.rankTimeout;
  farm.quiet = true;  // a sample's notes and progress would bury the sweep's lines
  const FarmSummary f = runTaskFarm(
      session, static_cast<int>(t.samples.size()),
      [&plan](int i) { return packSampleRow(runSample(plan.setup, plan.table.samples[i])); },
      [&t, &request](const TaskOutcome& o) { t.rows[o.index] = rowOf(t, o, request.sampleTimeLimit); }, farm);
  if (session.rank() != 0) return res;
  res.reporter = true;
  res.interruptedBy = f.interruptedBy;
  res.info = runInfo(f, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                     request.sampleTimeLimit);
  writeFileChecked(dir->staging() + "/sweep.csv", dir->final() + "/sweep.csv", sweepCsv(t));
  writeFileChecked(dir->staging() + "/sweep.json", dir->final() + "/sweep.json", sweepJson(t, res.info));
  if (request.keepSamples) writeSampleFolders(*dir, t);
  dir->keep("sweep.png");  // drawn by scripts/plot_sweep.py after the commit
  dir->commit();
  res.directory = dir->final();
  if (request.plots && !res.interruptedBy) res.plotNote = drawPlotScript("plot_sweep.py", res.directory);
  return res;
}

}  // namespace flexsens
