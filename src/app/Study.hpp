// The speed-versus-accuracy study (`flexsens study`): one run on this machine measures CPU
// time and error of every sensitivity method and integrator on the rigid and flexible
// five-bar and on the seed paper's (000) 3D four-bar and double pendulum, and writes a
// markdown report with CSV data (PNG plots by scripts/plot_study.py).
#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace flexsens {

class RunDirectory;

struct StudyOptions {
  std::string outDir = "bench/study";
  std::string sourceDir = ".";  ///< where examples/ lives
  bool quick = false;           ///< shorter sweeps (smoke test)
};

/// Runs the study into opt.outDir (output/RunDirectory.hpp: locked, refused when it holds
/// files flexsens did not write, staged); returns the path of the report.
std::string runStudy(const StudyOptions& opt);

/// One section of the report, computed alone (the study spread over MPI ranks).
struct StudyPart {
  std::string report;                                      ///< its markdown
  std::vector<std::pair<std::string, std::string>> files;  ///< name, text (CSV)
  double cpuSeconds = 0.0;                                 ///< [s] CPU it took
};
/// The report's sections after its header, and section `index` of them alone.
int studySectionCount();
StudyPart runStudySection(const StudyOptions& opt, int index);
/// The header, the parts in order and the end (plots; the wall time since `started`, the CPU
/// time with the parts'), written as runStudy writes them.
std::string writeStudyParts(RunDirectory& dir, const StudyOptions& opt, const std::vector<StudyPart>& parts,
                            std::chrono::steady_clock::time_point started);
/// The study's last step: writes `files` (name, text) into dir's staging folder, every write
/// checked, lists `plots` as files scripts/plot_study.py draws there, and moves the folder
/// into place. Throws OutputError naming the file (a full disk: "No space left on device");
/// then nothing is moved into place. Returns the report's path (<final>/study.md).
std::string writeStudyOutput(RunDirectory& dir, const std::vector<std::pair<std::string, std::string>>& files,
                             const std::vector<std::string>& plots);

}  // namespace flexsens
