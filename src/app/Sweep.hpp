// `flexsens sweep SCENE`: runs the scene over a grid or a Latin hypercube of parameter values
// (and over its PIM cases), each sample by the library's own run (or static) entry point, and
// keeps the chosen outputs and their sensitivities at chosen times in one table:
// <out>/sweep.csv and sweep.json (app/SweepTable.hpp), plotted by scripts/plot_sweep.py
// into sweep.png. Under mpirun the samples spread over the ranks (parallel/TaskFarm.hpp);
// every sample's numbers are the same on 1 rank or P, the table is in sample order. Samples
// that fail, end suspect, run past the time limit or are lost with their rank are kept with
// their status and reason; the sweep goes on. The output folder is written as every run's
// (output/RunDirectory.hpp): locked, staged, committed, refused when it holds user files.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/SweepTable.hpp"

namespace flexsens {

struct SweepRequest {
  std::string scenePath;
  std::string outDir;                    ///< empty: <output.directory>-sweep
  RunOptions options;                    ///< --integrator, --t-end, --dt, --method ... as for run
  std::vector<std::string> parameters;   ///< --parameter specs (app/SweepPlan.hpp)
  int samples = 0;                       ///< --samples: Latin hypercube; 0: a grid
  std::optional<std::uint64_t> seed;     ///< --seed (Latin hypercube), default 1
  std::vector<std::string> cases;        ///< PIM cases; empty: every case of the scene
  bool statics = false;                  ///< each sample is `flexsens static`
  bool perturbedStart = false;           ///< --start perturbed: a run starts as Scene.run(parameters=)
  std::optional<int> loadSteps;          ///< static: --load-steps
  std::vector<double> times;             ///< --at [s]; empty: t_end
  std::vector<std::string> outputs;      ///< --output; empty: every output of the scene
  double sampleTimeLimit = 0.0;          ///< [s] per sample, 0: none
  double rankTimeout = 10.0;             ///< [s] of silence before a rank running a sample is lost
  bool keepSamples = false;              ///< <out>/samples/<index>/ with series.csv, summary.json
  bool plots = true;                     ///< draw sweep.png (scripts/plot_sweep.py)
};

/// Everything the sweep runs, validated (the same on every rank).
struct SweepPlan {
  SweepTable table;   ///< rows still empty
  SweepSetup setup;   ///< scratch still empty
  std::string outDir;
};

/// Reads the scene and every case with the first sample's values, checks the options
/// (InputError naming the option or the scene's key) and lists the samples. Writes nothing.
SweepPlan prepareSweep(const SweepRequest& request);

struct SweepResult {
  bool reporter = false;  ///< this process is rank 0: it wrote the table and reports
  std::string directory;
  SweepTable table;
  SweepRunInfo info;
  int interruptedBy = 0;  ///< the signal that stopped the sweep (the table holds what finished)
  std::string plotNote;   ///< why sweep.png was not drawn, or ""
  /// 0 every sample complete; 5 some sample suspect, failed or lost (the table says which).
  int status() const;
};

SweepResult sweepCommand(const SweepRequest& request);

}  // namespace flexsens
