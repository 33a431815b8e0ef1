// One run of a scene: consistent initial state (and sensitivities), integration, output.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/Assembler.hpp"
#include "integrators/State.hpp"
#include "scene/Scene.hpp"

namespace flexsens {

class RunDirectory;

/// Command-line overrides of the scene's settings.
struct RunOptions {
  std::optional<std::string> outDir;
  std::optional<std::string> integrator;
  std::optional<double> tEnd, dt;
  std::optional<double> rhoInf, rtol;  ///< generalized_alpha rho_inf; IDAS relative tolerance
  std::optional<std::string> newton;  ///< fixed-step Newton: full | modified
  std::optional<bool> projections;    ///< trapezoidal / generalized-alpha: project v and a
  std::optional<std::string> method;  ///< dd | dq | nd
  std::optional<double> ndStep;
  std::optional<std::string> ndScheme;
  /// Design parameter values the run starts from (name, value), the others nominal: see
  /// applyParameterValues (app/ParameterValues.hpp).
  std::vector<std::pair<std::string, double>> parameters;
};

/// What a caller keeps of a run besides, or instead of, its files (the Python binding): the
/// series.csv columns, every frame with its row, progress, and summary.json's text, which
/// `finished` receives however the run ends (complete, suspect, failed, interrupted).
class RunListener {
 public:
  virtual ~RunListener() = default;
  virtual void started(const std::vector<std::string>& columns) { (void)columns; }
  virtual void frame(const StateWithSens& s, const std::vector<double>& row) = 0;
  /// Once per step: time reached and the end time [s].
  virtual void progress(double t, double tEnd) { (void)t, (void)tEnd; }
  virtual void finished(const std::string& summaryJson) { (void)summaryJson; }
};

struct RunResult {
  std::string directory;
  IntegratorStats stats;
  double wallSeconds = 0.0;
  std::string suspect;  ///< the energy audit's reason when the run is suspect, else empty
};

/// Applies the overrides to the scene settings; throws InputError naming the option.
void applyOptions(Scene& scene, const RunOptions& opt);
/// Consistent initial state at t = 0 for parameters p (no sensitivities).
State consistentState(const Assembler& as, const VecX& p);
/// With its sensitivities: from the scene's PIM case when there is one (report filled),
/// otherwise by the least-norm rule (Phi_q q_p = -Phi_p with the smallest |q_p|).
StateWithSens initialState(const Assembler& as, const VecX& p, const PimCase* pim = nullptr,
                           PimReport* report = nullptr);
/// The least-norm initial sensitivities of parameters first ... first + count - 1 at the
/// consistent state x (what initialState gives without a PIM case), one per parameter.
std::vector<State> leastNormSensitivities(const Assembler& as, const State& x, const VecX& p, int first, int count);
/// Integrates from `start` with the scene's integrator, sending frames to `obs`.
IntegratorStats integrate(const Assembler& as, const VecX& p, const StateWithSens& start,
                          const IntegratorSettings& set, Observer& obs);
/// Runs the scene, writes results into outDir (output/RunDirectory.hpp: locked, staged,
/// refused when it holds files flexsens did not write); on failure marks summary.json as
/// failed and rethrows.
RunResult runScene(const Scene& scene, const std::string& outDir);
/// The same into `part` of an output folder the caller holds ("" the whole folder, else a
/// PIM case's subfolder), committed when the run ends.
RunResult runScene(const Scene& scene, RunDirectory& dir, const std::string& part);
/// The same with a listener; without a folder (dir null) nothing is written and the results
/// reach only the listener.
RunResult runScene(const Scene& scene, RunDirectory* dir, const std::string& part, RunListener* listener);

}  // namespace flexsens
