#include "app/Commands.hpp"

#include <iostream>
#include <optional>
#include <sstream>

#include "app/CaseRanks.hpp"
#include "app/StudyRanks.hpp"
#include "app/ParameterValues.hpp"
#include "core/Interrupt.hpp"
#include "core/MemoryBudget.hpp"
#include "integrators/InitialState.hpp"
#include "output/RunDirectory.hpp"

namespace flexsens {

Scene readRequestedScene(const std::string& path, const std::string& text, const std::string& caseName,
                         const ParameterValues& values) {
  return text.empty() ? readScene(path, caseName, values) : readSceneText(text, path, caseName, values);
}

// ------------------------------------------------------------------ run
std::vector<RunCase> prepareRun(const RunRequest& request) {
  Scene base = readRequestedScene(request.scenePath, request.sceneText, "", request.parameterValues);
  base.requireDynamics();
  std::vector<std::string> names = request.cases;
  if (names.empty()) names = base.caseNames;
  if (names.empty()) names.push_back("");
  if (!base.hasIntegrator)
    throw InputError(request.scenePath + ":1:1: key 'integrator': the scene has no integrator (a static scene: "
                     "use `flexsens static`, or add an integrator to run it)");
  std::vector<RunCase> cases;
  for (const auto& name : names) {
    Scene sc = name.empty() ? std::move(base)
                            : readRequestedScene(request.scenePath, request.sceneText, name, request.parameterValues);
    cases.push_back({request.scenePath, name, std::move(sc), ""});
    applyOptions(cases.back().scene, request.options);
    cases.back().directory = cases.back().scene.output.directory + (name.empty() ? "" : "/" + name);
  }
  return cases;
}

RunCommandResult runCases(const std::vector<RunCase>& cases,
                          const std::function<void(const RunCase&, const RunResult&)>& caseDone,
                          const RunHooks& hooks) {
  RunCommandResult result;
  if (cases.empty()) return result;
  // The output folder locked once for all the cases (each into <folder>/<case>/).
  std::optional<RunDirectory> out;
  if (hooks.writeFiles) out.emplace(cases.front().scene.output.directory, cases.front().name.empty() ? "run" : "cases");
  for (const RunCase& c : cases) {
    std::ostringstream line;  // one write: runs in other threads do not cut into it
    line << "flexsens: running " << c.scenePath << (c.name.empty() ? "" : " case " + c.name) << " with "
         << c.scene.integrator.type << " to t = " << c.scene.integrator.tEnd << " s\n";
    if (hooks.announce) std::cerr << line.str();
    result.cases.push_back(runScene(c.scene, out ? &*out : nullptr, c.name, hooks.listener));
    if (!result.cases.back().suspect.empty()) result.status = 5;
    if (caseDone) caseDone(c, result.cases.back());
    if (const int sig = interruptSignal()) {  // arrived after the last step: later cases do not start
      result.interruptedBy = sig;
      break;
    }
  }
  return result;
}

RunCommandResult runCommand(const RunRequest& request,
                            const std::function<void(const RunCase&, const RunResult&)>& caseDone) {
  RankSession ranks("run");  // one rank unless mpirun or srun started this process
  std::vector<RunCase> cases = prepareRun(request);
  if (ranks.spread() && cases.size() > 1) return runCasesOnRanks(ranks, cases, caseDone);
  if (ranks.rank() != 0) return {};  // one case: rank 0 runs it
  return runCases(cases, caseDone);
}

// ------------------------------------------------------------------ static
StaticCommandResult staticCommand(const StaticRequest& request, const RunHooks& hooks) {
  Scene sc = readRequestedScene(request.scenePath, request.sceneText, "", request.parameterValues);
  setParameterValues(sc, request.parameters);
  if (request.loadSteps) {
    if (*request.loadSteps < 1 || *request.loadSteps > 100000)
      throw InputError("option --load-steps: expected 1 to 100000");
    sc.statics.loadSteps = *request.loadSteps;
  }
  if (!request.method.empty()) {
    if (request.method != "dd" && request.method != "ad")
      throw InputError("option --method: static sensitivities are dd or ad, got '" + request.method + "'");
    sc.sensitivity.method = request.method;
  }
  if (!request.frames) sc.output.vtk = false;
  StaticCommandResult out;
  // Beside the run's directory, not inside it: a rerun replaces its directory whole.
  out.directory = request.outDir.empty() ? sc.output.directory + "-static" : request.outDir;
  out.vtk = sc.output.vtk;
  try {
    out.result = runStaticScene(sc, hooks.writeFiles ? out.directory : "", sc.statics.loadSteps, hooks.listener);
  } catch (const Interrupted& e) {
    out.interruptedBy = e.signal;
    out.interruptedAt = e.t;
  }
  return out;
}

// ------------------------------------------------------------------ modes
ModesCommandResult modesCommand(const ModesRequest& request) {
  Scene sc = readRequestedScene(request.scenePath, request.sceneText);
  sc.requireDynamics();
  requireModesMemory(sc.model->n);
  Assembler as(*sc.model);
  const VecX p = sc.model->nominalParameters();
  ModesCommandResult out;
  out.leftOutRows = sc.model->redundantRows;
  if (!out.leftOutRows.empty()) {  // left out by the reader; the modes are those of the rest
    std::ostringstream note;  // one write: runs in other threads do not cut into it
    note << "flexsens: note: constraint rows dependent on the others at the initial positions, left out:";
    for (const auto& l : out.leftOutRows) note << " " << l;
    std::cerr << note.str() << "\n";
  }
  requireIndependentConstraints(as, projectPositions(as, sc.model->initialPositions(), p), p);
  out.analysis = analyzeModes(as, consistentState(as, p), p, request.count);
  return out;
}

// ------------------------------------------------------------------ check
CheckResult checkCommand(const std::string& scenePath, const std::string& sceneText) {
  Scene sc = readRequestedScene(scenePath, sceneText);
  sc.requireDynamics();
  const Model& m = *sc.model;
  CheckResult r;
  r.scenePath = scenePath;
  r.dim = m.dim;
  r.n = m.n;
  r.m = m.m;
  r.elements = m.elements.size();
  r.constraints = m.constraints.size();
  r.parameters = m.parameters.size();
  r.outputs = sc.outputs.size();
  r.redundantRows = m.redundantRows;
  r.meshGroups = sc.meshGroups;
  // The reader left dependent rows out already (core/RedundantRows.hpp); confirm the rest.
  r.stillDependent = dependentRows(m, m.initialPositions(), m.nominalParameters());
  for (const auto& name : sc.caseNames) {
    // The PIM's own count: m_r = independent rigidization equations (rank-revealing).
    Scene cs = readRequestedScene(scenePath, sceneText, name);
    const Model& cm = *cs.model;
    Assembler as(cm);
    CaseCheck c{name, cm.n, cm.m, {}};
    initialState(as, cm.nominalParameters(), cs.pimCase.get(), &c.pim);
    r.cases.push_back(c);
  }
  return r;
}

std::string checkReport(const CheckResult& r) {
  std::ostringstream os;
  os << r.scenePath << ": valid\n"
     << "  dimension " << r.dim << ", n = " << r.n << " coordinates, m = " << r.m << " constraint equations, d = "
     << r.n - r.m << " degrees of freedom\n"
     << "  " << r.elements << " elements, " << r.constraints << " constraints, " << r.parameters << " parameters, "
     << r.outputs << " outputs\n";
  if (!r.stillDependent.rows.empty())  // cannot happen after leaveOutRedundantRows; say so if it does
    os << "  constraints still dependent after the elimination: rank " << r.stillDependent.rank << " of " << r.m << "\n";
  else if (r.redundantRows.empty())
    os << "  constraints independent at the initial positions (rank Phi_q = " << r.m << ")\n";
  else {
    os << "  REDUNDANT constraints: rank Phi_q = " << r.m << " of " << r.m + r.redundantRows.size()
       << " rows, so the mechanism has " << r.n - r.m << " degrees of freedom. Dependent rows, left out "
          "of the dynamics (run checks that they stay satisfied; remove them from the scene, or "
          "replace joints by ones that constrain less, e.g. a spherical for a revolute in a planar loop):";
    for (const auto& l : r.redundantRows) os << " " << l;
    os << "\n";
  }
  for (const auto& [body, groups] : r.meshGroups) {
    os << "  node groups of " << body << " (Physical Points name single nodes; outputs and joints may name them):";
    for (const auto& [g, count] : groups) os << " " << g << " (" << count << (count == 1 ? " node)" : " nodes)");
    os << "\n";
  }
  for (const CaseCheck& c : r.cases) {
    const PimReport& rep = c.pim;
    os << "  case " << c.name << ": n = " << c.n << ", m = " << c.m << ", d = " << c.n - c.m << ", m_r = " << rep.mr
       << " (" << rep.lambdaGenerated << " generated, " << rep.lambdaDropped << " implied by the constraints), ";
    if (rep.massless) os << "e = " << rep.me << " equilibrium rows of " << rep.massless << " massless coordinates, ";
    os << "d_s = " << rep.ds << " SDOFs, cond(A) = " << rep.condition << "\n";
  }
  return os.str();
}

// ------------------------------------------------------------------ study
std::string studyCommand(const StudyOptions& options) {
  RankSession ranks("study");  // one rank unless mpirun or srun started this process
  return ranks.spread() ? runStudyOnRanks(ranks, options) : runStudy(options);
}

}  // namespace flexsens
