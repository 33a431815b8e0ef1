// The library's entry points, one per command: run, static, modes, check, study. Each takes a
// request (what the command line's options say), returns a result object, and writes files
// only through the output layer (output/RunDirectory, output/ResultWriter). The command line
// (src/cli/main.cpp) parses options into requests and prints the results; a Python binding or
// an MPI sweep calls the same functions. Notes that a user should see while a command works
// (projected initial velocities, left-out constraint rows, the case starting) go to stderr.
//
// Interrupts: the caller installs the signal handlers (core/Interrupt.hpp); a run stops at the
// end of the step the signal arrived in, writes what it reached and throws Interrupted.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/Modes.hpp"
#include "app/Run.hpp"
#include "app/StaticRun.hpp"
#include "app/Study.hpp"
#include "core/RedundantRows.hpp"
#include "pim/Pim.hpp"

namespace flexsens {

/// The scene a request names: the file at `path`, or `text` when it is not empty (a scene
/// given as text; `path` names it in messages, and its folder is the scene's folder).
Scene readRequestedScene(const std::string& path, const std::string& text, const std::string& caseName = "",
                         const ParameterValues& values = {});

/// What a caller takes from a command besides, or instead of, its files (the Python binding).
struct RunHooks {
  RunListener* listener = nullptr;  ///< sees every frame, the progress and the summary of each case
  bool writeFiles = true;           ///< false: nothing written, no output folder touched
  bool announce = true;             ///< "flexsens: running ..." on stderr for each case
};

// ------------------------------------------------------------------ run
struct RunRequest {
  std::string scenePath;
  RunOptions options;
  std::vector<std::string> cases;  ///< PIM cases to run; empty: every case of the scene
  ParameterValues parameterValues;  ///< parameters set to these values (a sweep's sample)
  std::string sceneText;           ///< non-empty: the scene itself (readRequestedScene)
};

/// One case of a run, read and validated, with the directory its results go to.
struct RunCase {
  std::string scenePath;  ///< as requested
  std::string name;       ///< "" for a scene without cases
  Scene scene;
  std::string directory;
};

struct RunCommandResult {
  std::vector<RunResult> cases;  ///< in the order run
  int status = 0;                ///< 0, or 5 when a case's result is suspect
  /// A signal that arrived after the last step of cases.back(): later cases were not run.
  int interruptedBy = 0;
};

/// Reads every requested case and applies the options: all validated before anything is
/// written (InputError naming the file, line and key, or the option).
std::vector<RunCase> prepareRun(const RunRequest& request);
/// Runs the prepared cases in order; `caseDone` (when given) sees each result as it comes.
RunCommandResult runCases(const std::vector<RunCase>& cases,
                          const std::function<void(const RunCase&, const RunResult&)>& caseDone = {},
                          const RunHooks& hooks = {});
/// prepareRun then runCases; under mpirun with several ranks and cases, the cases spread
/// over the ranks and rank 0 writes (app/CaseRanks.hpp); other ranks return an empty result.
RunCommandResult runCommand(const RunRequest& request,
                            const std::function<void(const RunCase&, const RunResult&)>& caseDone = {});

// ------------------------------------------------------------------ static
struct StaticRequest {
  std::string scenePath;
  std::string outDir;             ///< empty: <output.directory>-static
  std::optional<int> loadSteps;   ///< empty: the scene's static.load_steps
  std::string method;             ///< dd | ad; empty: the scene's
  ParameterValues parameterValues;  ///< parameters set to these values (a sweep's sample)
  bool frames = true;               ///< false: no VTK frames whatever the scene says
  std::string sceneText;          ///< non-empty: the scene itself (readRequestedScene)
  /// Design parameter values (name, value) instead of the nominal ones; the equilibrium is
  /// found from the scene's positions as for the nominal values.
  std::vector<std::pair<std::string, double>> parameters;
};

struct StaticCommandResult {
  StaticResult result;
  std::string directory;
  bool vtk = false;         ///< the scene writes VTK frames
  int interruptedBy = 0;    ///< signal that stopped it (the converged load steps are written)
  double interruptedAt = 0.0;  ///< load factor reached then
};

/// With hooks.writeFiles false nothing is written (the listener sees the load steps).
StaticCommandResult staticCommand(const StaticRequest& request, const RunHooks& hooks = {});

// ------------------------------------------------------------------ modes
struct ModesRequest {
  std::string scenePath;
  int count = 5;  ///< modes at each end of the spectrum
  std::string sceneText;  ///< non-empty: the scene itself (readRequestedScene)
};

struct ModesCommandResult {
  std::vector<std::string> leftOutRows;  ///< constraint rows the reader left out as dependent
  ModalAnalysis analysis;
};

/// The modes at the consistent initial state. NumericalError (exit 2) when Phi_q is rank
/// deficient at the initial positions: like `run`, the defect is one of the configuration.
ModesCommandResult modesCommand(const ModesRequest& request);

// ------------------------------------------------------------------ check
struct CaseCheck {
  std::string name;
  int n = 0, m = 0;
  PimReport pim;
};

struct CheckResult {
  std::string scenePath;
  int dim = 0, n = 0, m = 0;
  size_t elements = 0, constraints = 0, parameters = 0, outputs = 0;
  std::vector<std::string> redundantRows;  ///< left out by the reader
  /// Meshed body -> its Physical Points and node groups (name, node count).
  std::map<std::string, std::vector<std::pair<std::string, int>>> meshGroups;
  DependentRows stillDependent;            ///< after the elimination (empty unless a defect)
  std::vector<CaseCheck> cases;
};

/// Reads the scene and each PIM case (the PIM's own counts); throws what reading throws.
/// A non-empty sceneText is the scene itself (readRequestedScene).
CheckResult checkCommand(const std::string& scenePath, const std::string& sceneText = "");
/// `flexsens check`'s text.
std::string checkReport(const CheckResult& r);

// ------------------------------------------------------------------ study
/// Runs the study (app/Study.hpp); returns the path of its report. Under mpirun the sections
/// spread over the ranks (app/StudyRanks.hpp); other ranks than 0 return "".
std::string studyCommand(const StudyOptions& options);

}  // namespace flexsens
