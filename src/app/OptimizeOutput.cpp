#include "app/OptimizeOutput.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "output/GradientVtu.hpp"
#include "output/Manifest.hpp"
#include "output/ResultWriter.hpp"

namespace flexsens {

namespace {

/// Full precision: the optimum read back is the optimum written.
std::string exact(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string historyCsv(const OptimizeResult& r, bool withVariables) {
  std::ostringstream out;
  out << "evaluation,status,objective";
  for (const std::string& c : r.constraints) out << "," << c;
  if (withVariables)
    for (const std::string& v : r.variables) out << "," << v;
  out << ",seconds\n";
  for (const OptimizeEvaluation& e : r.history) {
    out << e.index << "," << e.status << "," << (e.ok ? exact(e.objective) : "");
    for (size_t c = 0; c < r.constraints.size(); ++c) out << "," << (e.ok ? exact(e.constraints[c]) : "");
    if (withVariables)
      for (Eigen::Index i = 0; i < e.x.size(); ++i) out << "," << exact(e.x[i]);
    out << "," << e.seconds << "\n";
  }
  return out.str();
}

std::string variablesCsv(const OptimizeResult& r) {
  std::ostringstream out;
  out << "evaluation";
  for (const std::string& v : r.variables) out << "," << v;
  out << "\n";
  for (const OptimizeEvaluation& e : r.history) {
    out << e.index;
    for (Eigen::Index i = 0; i < e.x.size(); ++i) out << "," << exact(e.x[i]);
    out << "\n";
  }
  return out.str();
}

/// optimum.csv: parameter, start, optimum, lower, upper (the best evaluation's values).
std::string optimumCsv(const OptimizeResult& r) {
  std::ostringstream out;
  out << "parameter,start,optimum,lower,upper\n";
  if (r.history.empty()) return out.str();
  const VecX& x0 = r.history.front().x;
  const VecX& xb = r.best >= 0 ? r.history[size_t(r.best)].x : x0;
  for (size_t i = 0; i < r.variables.size(); ++i) {
    const Eigen::Index k = Eigen::Index(i);
    out << r.variables[i] << "," << exact(x0[k]) << "," << exact(xb[k]) << "," << exact(r.lower[k]) << ","
        << exact(r.upper[k]) << "\n";
  }
  return out.str();
}

std::string evaluationJson(const OptimizeResult& r, const OptimizeEvaluation& e) {
  std::ostringstream js;
  js << "{\"evaluation\": " << e.index << ", \"status\": " << jsonString(e.status);
  if (e.ok) {
    js << ", \"objective\": " << jsonNumber(e.objective) << ", \"constraints\": {";
    for (size_t c = 0; c < r.constraints.size(); ++c)
      js << (c ? ", " : "") << jsonString(r.constraints[c]) << ": " << jsonNumber(e.constraints[c]);
    js << "}";
  }
  if (!e.message.empty()) js << ", \"message\": " << jsonString(e.message);
  js << ", \"variables\": {";
  for (size_t i = 0; i < r.variables.size(); ++i)
    js << (i ? ", " : "") << jsonString(r.variables[i]) << ": " << jsonNumber(e.x[Eigen::Index(i)]);
  js << "}}";
  return js.str();
}

std::string optimizeJson(const OptimizeResult& r) {
  std::ostringstream js;
  js << "{\n  \"status\": " << jsonString(r.status) << ",\n  \"nlopt_result\": " << jsonString(r.nloptResult)
     << ",\n  \"nlopt_code\": " << r.nloptCode << ",\n  \"algorithm\": " << jsonString(r.algorithm)
     << ",\n  \"gradient\": " << jsonString(r.gradient) << ",\n  \"objective\": " << jsonString(r.objective)
     << ",\n  \"constraints\": [";
  for (size_t c = 0; c < r.constraints.size(); ++c)
    js << (c ? ", " : "") << "{\"objective\": " << jsonString(r.constraints[c]) << ", \""
       << (r.upperBounds[c] ? "max" : "min") << "\": " << jsonNumber(r.bounds[c]) << "}";
  js << "],\n  \"evaluations\": " << r.history.size() << ",\n  \"wall_time_s\": " << jsonNumber(r.wallSeconds)
     << ",\n  \"kkt_residual\": " << jsonNumber(r.kktResidual);
  if (!r.history.empty()) js << ",\n  \"start\": " << evaluationJson(r, r.history.front());
  if (r.best >= 0) js << ",\n  \"optimum\": " << evaluationJson(r, r.history[size_t(r.best)]);
  if (r.failed >= 0) js << ",\n  \"failure\": " << evaluationJson(r, r.history[size_t(r.failed)]);
  if (r.interruptedBy) js << ",\n  \"interrupted_by\": " << r.interruptedBy;
  if (!r.sceneNote.empty()) js << ",\n  \"optimized_scene\": " << jsonString(r.sceneNote);
  js << "\n}\n";
  return js.str();
}

/// The scalar node of `property` in an item: the key itself, else the first one below it.
YAML::Node findKey(const YAML::Node& item, const std::string& property) {
  if (item.IsMap()) {
    if (item[property] && item[property].IsScalar()) return item[property];
    for (const auto& kv : item)
      if (const YAML::Node found = findKey(kv.second, property); found) return found;
  } else if (item.IsSequence()) {
    for (const auto& child : item)
      if (const YAML::Node found = findKey(child, property); found) return found;
  }
  return YAML::Node(YAML::NodeType::Undefined);
}

/// Where parameter k's value stands in the scene: the property's scalar node, or undefined.
YAML::Node valueNode(const YAML::Node& root, const Model& m, const Parameter& par) {
  const size_t dot = par.boundTo.rfind('.');
  const std::string of = par.boundTo.substr(0, dot), property = par.boundTo.substr(dot + 1);
  if (of == "gravity") {
    for (int c = 0; c < m.dim; ++c)
      if (property == std::string(1, m.axisName(c)) && root["gravity"] && root["gravity"].IsSequence())
        return root["gravity"][size_t(c)];
    return YAML::Node(YAML::NodeType::Undefined);
  }
  int axis = -1;  // a point force's or torque's component by its axis name
  for (int c = 0; c < m.dim; ++c)
    if (property == std::string(1, m.axisName(c))) axis = c;
  for (const char* list : {"elements", "constraints"})
    if (root[list] && root[list].IsSequence())
      for (const auto& item : root[list])
        if (item.IsMap() && item["name"] && item["name"].IsScalar() && item["name"].Scalar() == of) {
          for (const char* vector : {"force", "torque"})
            if (axis >= 0 && item[vector] && item[vector].IsSequence() && item[vector].size() == size_t(m.dim))
              return item[vector][size_t(axis)];
          return findKey(item, property);
        }
  return YAML::Node(YAML::NodeType::Undefined);
}

/// The length of the scalar's text at pos: a quoted scalar to its closing quote, a plain one
/// to the next , ] } # or line end (trailing blanks dropped).
size_t scalarLength(const std::string& text, size_t pos) {
  if (text[pos] == '"' || text[pos] == '\'') {
    const size_t close = text.find(text[pos], pos + 1);
    return close == std::string::npos ? 1 : close - pos + 1;
  }
  size_t end = pos;
  while (end < text.size() && std::string(",]}#\n\r").find(text[end]) == std::string::npos) ++end;
  while (end > pos && (text[end - 1] == ' ' || text[end - 1] == '\t')) --end;
  return end - pos;
}

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// optimized.yaml: the scene with the best whole-body values; a header says what it holds.
std::string optimizedScene(const Scene& sc, const OptimizeResult& r, std::string& note) {
  std::vector<std::pair<int, double>> values;
  size_t families = 0, i = 0;
  const VecX& xb = r.history[size_t(r.best)].x;
  for (const OptimizeVariable& v : sc.optimize.variables)
    for (int k : v.parameters) {
      if (sc.model->parameters[size_t(k)].family.empty()) values.emplace_back(k, xb[Eigen::Index(i)]);
      else ++families;
      ++i;
    }
  std::vector<std::string> missed;
  const std::string text = optimizedSceneText(readText(sc.file), sc, values, missed);
  std::ostringstream head;
  head << "# flexsens optimize: " << sc.file << " at evaluation " << r.history[size_t(r.best)].index << " (status "
       << r.status << "), objective " << r.objective << " = " << exact(r.history[size_t(r.best)].objective) << "\n";
  if (families) {
    note = std::to_string(families) + " per-element values are in optimum.csv only (a scene gives one value per body)";
    head << "# " << note << "\n";
  }
  for (const std::string& name : missed) {
    head << "# " << name << " is not written in the scene (a default): its optimum is in optimum.csv\n";
    note += (note.empty() ? "" : "; ") + name + " not in the scene's text (optimum.csv)";
  }
  return head.str() + text;
}

}  // namespace

std::string optimizedSceneText(const std::string& text, const Scene& sc, const std::vector<std::pair<int, double>>& values,
                               std::vector<std::string>& missed) {
  const YAML::Node root = YAML::Load(text);
  std::vector<std::pair<size_t, std::pair<size_t, std::string>>> edits;  // pos, (length, new text)
  for (const auto& [k, value] : values) {
    const Parameter& par = sc.model->parameters[size_t(k)];
    const YAML::Node node = valueNode(root, *sc.model, par);
    if (!node || !node.IsScalar() || node.Mark().pos < 0 || size_t(node.Mark().pos) >= text.size()) {
      missed.push_back(par.name);
      continue;
    }
    const size_t pos = size_t(node.Mark().pos);
    edits.push_back({pos, {scalarLength(text, pos), exact(value)}});
  }
  std::sort(edits.begin(), edits.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string out = text;
  for (const auto& [pos, edit] : edits) out.replace(pos, edit.first, edit.second);
  return out;
}

void writeOptimizeOutputs(RunDirectory& dir, const Scene& sc, OptimizeResult& r) {
  auto write = [&](const std::string& name, const std::string& text) {
    writeFileChecked(dir.staging() + "/" + name, dir.final() + "/" + name, text);
  };
  const bool wide = r.variables.size() > kHistoryVariableColumns;
  write("history.csv", historyCsv(r, !wide));
  if (wide) write("history_variables.csv", variablesCsv(r));
  write("optimum.csv", optimumCsv(r));
  if (r.best >= 0) write("optimized.yaml", optimizedScene(sc, r, r.sceneNote));
  if (r.best >= 0 && hasPerElementParameters(*sc.model)) {  // the optimized design, for ParaView
    VecX p = sc.model->nominalParameters();
    size_t i = 0;
    for (const OptimizeVariable& v : sc.optimize.variables)
      for (int k : v.parameters) p[k] = r.history[size_t(r.best)].x[Eigen::Index(i++)];
    writeParameterVtu(dir.staging() + "/optimum.vtu", dir.final() + "/optimum.vtu", *sc.model, p);
  }
  write("optimize.json", optimizeJson(r));
}

}  // namespace flexsens
