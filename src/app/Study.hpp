// The speed-versus-accuracy study (`flexsens study`): one run on this machine measures CPU
// time and error of every sensitivity method and integrator on the rigid and flexible
// five-bar and on the seed paper's (000) 3D four-bar and double pendulum, and writes a
// markdown report with CSV data (PNG plots by scripts/plot_study.py).
#pragma once

#include <string>

namespace flexsens {

struct StudyOptions {
  std::string outDir = "bench/study";
  std::string sourceDir = ".";  ///< where examples/ lives
  bool quick = false;           ///< shorter sweeps (smoke test)
};

/// Runs the study; returns the path of the report.
std::string runStudy(const StudyOptions& opt);

}  // namespace flexsens
