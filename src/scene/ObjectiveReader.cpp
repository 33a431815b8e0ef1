// `objectives:` of a scene (scene/Objective.hpp): terminal, integral, tracking, max (a KS
// aggregate) and weighted sums of these, each checked against the outputs and the run's times.
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "elements/SimplexShape.hpp"  // fmtNumber
#include "scene/InputFiles.hpp"
#include "scene/SceneParts.hpp"
#include "scene/TimeFunctionReader.hpp"

namespace flexsens {

double ObjectiveSpec::targetAt(double t) const {
  if (target) return target->at(t, VecX()).f;
  const std::vector<double>& ts = targetTimes;
  if (t <= ts.front()) return targetValues.front();
  if (t >= ts.back()) return targetValues.back();
  const size_t i = size_t(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin());  // ts[i-1] <= t < ts[i]
  const double s = (t - ts[i - 1]) / (ts[i] - ts[i - 1]);
  return (1.0 - s) * targetValues[i - 1] + s * targetValues[i];
}

namespace {

constexpr const char* kKinds = "terminal, integral, tracking, max, mass or sum";

/// Reads an objective's output name into spec.output; fails listing the scene's outputs.
void readOutputName(const SceneContext& ctx, const YAML::Node& in, const std::string& path, const Scene& sc,
                    ObjectiveSpec& spec) {
  const YamlReader& r = ctx.r;
  const std::string name = r.text(r.require(in, "output", path), path + ".output");
  for (size_t k = 0; k < sc.outputs.size(); ++k)
    if (sc.outputs[k].name == name) spec.output = int(k);
  if (spec.output >= 0) return;
  std::string names;
  for (const auto& o : sc.outputs) names += (names.empty() ? "" : ", ") + o.name;
  r.fail(in["output"], path + ".output",
         "no output named '" + name + "'; expected one of the scene's outputs" +
             (names.empty() ? " (it defines none: add it under outputs)" : ": " + names));
}

/// The window `from`, `to` [s] within [0, t_end].
void readWindow(const YamlReader& r, const YAML::Node& in, const std::string& path, double tEnd, ObjectiveSpec& spec) {
  if (in["from"]) spec.from = r.nonNegative(in["from"], path + ".from");
  if (in["to"]) spec.to = r.positive(in["to"], path + ".to");
  const double to = spec.to < 0 ? tEnd : spec.to;
  if (in["to"] && tEnd > 0 && spec.to > tEnd * (1.0 + 1e-12))
    r.fail(in["to"], path + ".to", "expected a time within the run, at most t_end = " + fmtNumber(tEnd) + " s");
  if (!(spec.from < to))
    r.fail(in["from"] ? in["from"] : in, path + ".from",
           "expected from < to (the window's start before its end, " + fmtNumber(to) + " s)");
}

/// tracking's `csv: file` (rows t, value): times increasing and covering the window.
void readTargetCsv(const SceneContext& ctx, const YAML::Node& in, const std::string& path, double tEnd,
                   ObjectiveSpec& spec) {
  const YamlReader& r = ctx.r;
  const std::string key = path + ".csv";
  const std::string name = r.text(in["csv"], key);
  const std::uintmax_t limit = inputPolicy().maxTableBytes;
  const std::string full = sceneDataFile(r, in["csv"], key, name, limit);
  try {
    parseTimeTable(readBoundedFile(full, limit, name), name, spec.targetTimes, spec.targetValues);
  } catch (const std::runtime_error& e) {
    r.fail(in["csv"], key, e.what());
  }
  const double to = spec.to < 0 ? tEnd : spec.to;
  if (spec.targetTimes.front() > spec.from || spec.targetTimes.back() < to)
    r.fail(in["csv"], key,
           "the target's times " + fmtNumber(spec.targetTimes.front()) + " ... " + fmtNumber(spec.targetTimes.back()) +
               " s do not cover the window " + fmtNumber(spec.from) + " ... " + fmtNumber(to) +
               " s; give rows from the window's start to its end");
}

/// mass: {of: BODY}: the elements named BODY or BODY.<part> (a meshed body's cells) with mass.
void readMassBody(SceneContext& ctx, const YAML::Node& in, const std::string& path, ObjectiveSpec& spec) {
  const YamlReader& r = ctx.r;
  r.allowKeys(in, path, {"of"});
  const std::string body = r.text(r.require(in, "of", path), path + ".of");
  std::string names;
  std::set<std::string> bodies;
  for (size_t e = 0; e < ctx.m.elements.size(); ++e) {
    const std::string& name = ctx.m.elements[e]->name();
    if (name == body || name.rfind(body + ".", 0) == 0) spec.elements.push_back(int(e));
    const std::string owner = name.substr(0, name.find('.'));
    if (bodies.insert(owner).second && names.size() < 400) names += (names.empty() ? "" : ", ") + owner;
  }
  if (spec.elements.empty())
    r.fail(in["of"], path + ".of", "no element or meshed body named '" + body + "'; expected one of: " + names);
}

void readKind(SceneContext& ctx, const YAML::Node& in, const std::string& path, const Scene& sc, double tEnd,
              ObjectiveSpec& spec) {
  const YamlReader& r = ctx.r;
  r.requireMap(in, path);
  if (spec.kind == "mass") {
    readMassBody(ctx, in, path, spec);
    return;
  }
  if (spec.kind == "terminal") {
    r.allowKeys(in, path, {"output", "at"});
    readOutputName(ctx, in, path, sc, spec);
    if (in["at"]) {
      if (tEnd <= 0) r.fail(in["at"], path + ".at", "a static scene's terminal objective is at its last load step: remove at");
      spec.at = r.nonNegative(in["at"], path + ".at");
      if (spec.at > tEnd * (1.0 + 1e-12))
        r.fail(in["at"], path + ".at", "expected a time within the run, at most t_end = " + fmtNumber(tEnd) + " s");
    }
    return;
  }
  if (tEnd <= 0)
    r.fail(in, path, "a static scene (no integrator) takes terminal objectives only, at its last load step");
  if (spec.kind == "integral") {
    r.allowKeys(in, path, {"output", "power", "from", "to"});
    readOutputName(ctx, in, path, sc, spec);
    if (in["power"]) {
      spec.power = r.integer(in["power"], path + ".power");
      if (spec.power < 1 || spec.power > 16) r.fail(in["power"], path + ".power", "expected a whole power from 1 to 16");
    }
    readWindow(r, in, path, tEnd, spec);
  } else if (spec.kind == "tracking") {
    r.allowKeys(in, path, {"output", "target", "csv", "from", "to"});
    readOutputName(ctx, in, path, sc, spec);
    readWindow(r, in, path, tEnd, spec);
    if (bool(in["target"]) == bool(in["csv"]))
      r.fail(in, path, "expected either target (a time function) or csv (a file of rows t, value), one of them");
    if (in["target"]) spec.target = readTimeFunction(ctx, in["target"], path + ".target", spec.name + ".target");
    else readTargetCsv(ctx, in, path, tEnd, spec);
  } else if (spec.kind == "max") {
    r.allowKeys(in, path, {"output", "rho", "from", "to"});
    readOutputName(ctx, in, path, sc, spec);
    spec.rho = r.positive(r.require(in, "rho", path), path + ".rho");
    readWindow(r, in, path, tEnd, spec);
  }
}

/// sum: [{objective, weight}]: the other objectives, read first (any order in the list).
void readSum(const SceneContext& ctx, const YAML::Node& in, const std::string& path, const Scene& sc,
             ObjectiveSpec& spec) {
  const YamlReader& r = ctx.r;
  r.requireList(in, path);
  if (in.size() == 0) r.fail(in, path, "expected at least one term {objective, weight}");
  for (size_t i = 0; i < in.size(); ++i) {
    const std::string tp = at(path, i);
    r.requireMap(in[i], tp);
    r.allowKeys(in[i], tp, {"objective", "weight"});
    const std::string name = r.text(r.require(in[i], "objective", tp), tp + ".objective");
    int found = -1;
    std::string names;
    for (size_t k = 0; k < sc.objectives.size(); ++k)
      if (sc.objectives[k].kind != "sum") {
        if (sc.objectives[k].name == name) found = int(k);
        names += (names.empty() ? "" : ", ") + sc.objectives[k].name;
      }
    if (found < 0)
      r.fail(in[i]["objective"], tp + ".objective",
             "no objective named '" + name + "' to sum; expected one of the scene's objectives other than sums" +
                 (names.empty() ? std::string(" (there are none)") : ": " + names));
    spec.terms.emplace_back(found, in[i]["weight"] ? r.number(in[i]["weight"], tp + ".weight") : 1.0);
  }
}

/// The entry's kind: exactly one of the kind keys.
std::string kindOf(const YamlReader& r, const YAML::Node& o, const std::string& path) {
  std::string kind;
  for (const char* k : {"terminal", "integral", "tracking", "max", "mass", "sum"})
    if (o[k]) {
      if (!kind.empty()) r.fail(o[k], path + "." + k, "an objective has one kind; got " + kind + " and " + k);
      kind = k;
    }
  if (kind.empty()) r.fail(o, path, std::string("expected one of the keys ") + kKinds);
  return kind;
}

}  // namespace

void readObjectives(SceneContext& ctx, const YAML::Node& list, Scene& sc) {
  const YamlReader& r = ctx.r;
  r.requireList(list, "objectives");
  const double tEnd = sc.hasIntegrator ? sc.integrator.tEnd : 0.0;
  std::vector<std::pair<YAML::Node, std::string>> sums;  // read after every other objective
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node o = list[i];
    const std::string path = at("objectives", i);
    r.requireMap(o, path);
    r.allowKeys(o, path, {"name", "terminal", "integral", "tracking", "max", "mass", "sum"});
    ObjectiveSpec spec;
    spec.name = r.text(r.require(o, "name", path), path + ".name");
    for (const auto& other : sc.objectives)
      if (other.name == spec.name) r.fail(o["name"], path + ".name", "duplicate objective name '" + spec.name + "'");
    spec.kind = kindOf(r, o, path);
    spec.where = ctx.where(o, path);
    if (spec.kind != "sum") readKind(ctx, o[spec.kind], path + "." + spec.kind, sc, tEnd, spec);
    else sums.emplace_back(o, path);
    sc.objectives.push_back(std::move(spec));
  }
  for (size_t s = 0, k = 0; k < sc.objectives.size(); ++k)
    if (sc.objectives[k].kind == "sum") {
      readSum(ctx, sums[s].first["sum"], sums[s].second + ".sum", sc, sc.objectives[k]);
      ++s;
    }
}

}  // namespace flexsens
