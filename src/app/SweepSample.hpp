// One sample of `flexsens sweep`, run in a child process (parallel/TaskFarm.hpp): the scene
// with the sample's parameter values and PIM case, through the library's entry points
// (prepareRun and runCases, or staticCommand) into a private scratch folder, without VTK
// frames. Kept: the chosen outputs and their sensitivities at the chosen times, read from the
// run's series.csv as written there (a sample's row equals its own `flexsens run`).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/Run.hpp"
#include "app/SweepPlan.hpp"

namespace flexsens {

/// One value column of sweep.csv: an output or one of its sensitivities, at one time.
struct OutputColumn {
  std::string output;     ///< the scene's output name
  std::string parameter;  ///< "": the output's value; else d(output)/d(parameter)
  double time = 0.0;      ///< [s]; static sweeps: the equilibrium at load factor 1
  std::string header;     ///< sweep.csv's name: "z2@1.5", "dz2/dL_A1@1.5" (static: "z2")
  /// The column of series.csv it is read from.
  std::string source() const { return parameter.empty() ? output : "d" + output + "/d" + parameter; }
};

/// What every sample of a sweep shares.
struct SweepSetup {
  std::string scenePath;
  RunOptions options;            ///< run options given on the command line
  bool statics = false;          ///< `flexsens static` per sample
  /// The run starts from the case's perturbed start at the sample's values (app/ParameterValues.hpp)
  /// instead of the scene with the values written in.
  bool perturbedStart = false;
  std::optional<int> loadSteps;  ///< static: --load-steps
  std::vector<OutputColumn> columns;
  double timeTolerance = 1e-9;   ///< [s] a series.csv row is at time T within this (frame spacing / 1000)
  std::string scratch;           ///< this process's private folder for the samples' runs
  bool keepFiles = false;        ///< return the run's series.csv and summary.json (--keep-samples)
};

/// A sample's row of sweep.csv.
struct SampleRow {
  int index = 0;
  std::string status = "not_run";  ///< complete | suspect | failed | lost | interrupted | not_run
  std::string reason;              ///< suspect, failed: the run's; lost: what happened
  std::vector<std::string> cells;  ///< one per column, as series.csv holds it ("" when absent)
  std::vector<std::pair<std::string, std::string>> files;  ///< name, text (keepFiles)
  int rank = -1;                   ///< where it ran (rank 0 fills it in)
  double seconds = 0.0;            ///< [s] wall time of the sample's process
};

/// Runs the sample (any failure of the run becomes the row's status and reason) and removes
/// its scratch folder.
SampleRow runSample(const SweepSetup& setup, const Sample& sample);

std::string packSampleRow(const SampleRow& row);
SampleRow unpackSampleRow(const std::string& bytes);

}  // namespace flexsens
