// `flexsens sweep`'s options and report (the command itself: app/Sweep.hpp).
#pragma once

#include <CLI/CLI.hpp>

#include "app/Sweep.hpp"

namespace flexsens {

struct SweepArgs {
  CLI::App* command = nullptr;
  SweepRequest request;
  std::string integrator, newtonMode, projections, method;
  double tEnd = 0, dt = 0, rhoInf = 0, rtol = 0;
  int loadSteps = 0;
  std::uint64_t seed = 1;
  bool noPlots = false;
  std::string start = "scene";
};

void addSweep(CLI::App& app, SweepArgs& a);
/// Runs the sweep; rank 0 prints where the table went and which samples did not complete.
/// Exit code: 0 every sample complete, 5 some not (suspect, failed, lost), 128 + signal.
int executeSweep(SweepArgs& a);

}  // namespace flexsens
