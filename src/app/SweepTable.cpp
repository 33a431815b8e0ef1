#include "app/SweepTable.hpp"

#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "output/ResultWriter.hpp"

namespace flexsens {

namespace {

/// A CSV field, quoted when it holds a comma, a quote or a line break (RFC 4180).
std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string jsonList(const std::vector<std::string>& items) {
  std::string r = "[";
  for (size_t i = 0; i < items.size(); ++i) r += (i ? ", " : "") + items[i];
  return r + "]";
}

std::string parametersJson(const SweepDesign& d) {
  std::vector<std::string> items;
  for (const ParameterRange& r : d.ranges) {
    std::string item = "{\"name\": " + jsonString(r.name);
    if (r.fixed()) item += ", \"value\": " + exactNumber(r.low);
    else item += ", \"low\": " + exactNumber(r.low) + ", \"high\": " + exactNumber(r.high);
    if (r.grid()) item += ", \"count\": " + std::to_string(r.count);
    items.push_back(item + "}");
  }
  return jsonList(items);
}

std::string columnsJson(const SweepTable& t) {
  std::vector<std::string> items;
  for (const OutputColumn& c : t.columns) {
    std::string item = "{\"header\": " + jsonString(c.header) + ", \"output\": " + jsonString(c.output) +
                       ", \"parameter\": " + (c.parameter.empty() ? "null" : jsonString(c.parameter));
    if (!t.statics) item += ", \"time\": " + exactNumber(c.time);
    items.push_back(item + "}");
  }
  return jsonList(items);
}

/// Per status, the sample indices that ended so (the counts, and where to look).
std::string statusesJson(const std::vector<SampleRow>& rows) {
  std::ostringstream os;
  os << "{";
  bool first = true;
  for (const std::string& st : sampleStatuses()) {
    std::vector<std::string> idx;
    for (const SampleRow& r : rows)
      if (r.status == st) idx.push_back(std::to_string(r.index));
    os << (first ? "" : ", ") << jsonString(st) << ": " << jsonList(idx);
    first = false;
  }
  return os.str() + "}";
}

std::string rowsJson(const SweepTable& t) {
  std::vector<std::string> items;
  for (const SampleRow& r : t.rows) {
    std::ostringstream os;
    os << "{\"index\": " << r.index << ", \"case\": " << jsonString(t.samples[r.index].caseName)
       << ", \"status\": " << jsonString(r.status) << ", \"reason\": " << jsonString(r.reason)
       << ", \"rank\": " << r.rank << ", \"seconds\": " << jsonNumber(r.seconds) << "}";
    items.push_back(os.str());
  }
  std::string s = "[";
  for (size_t i = 0; i < items.size(); ++i) s += (i ? ",\n    " : "\n    ") + items[i];
  return s + (items.empty() ? "]" : "\n  ]");
}

}  // namespace

const std::vector<std::string>& sampleStatuses() {
  static const std::vector<std::string> s = {"complete", "suspect", "failed", "lost", "interrupted", "not_run"};
  return s;
}

std::map<std::string, int> countStatuses(const std::vector<SampleRow>& rows) {
  std::map<std::string, int> n;
  for (const std::string& s : sampleStatuses()) n[s] = 0;
  for (const SampleRow& r : rows) ++n[r.status];
  return n;
}

std::string exactNumber(double v) {
  char buf[40];
  for (int prec = 15; prec <= 17; ++prec) {
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string sweepCsv(const SweepTable& t) {
  std::ostringstream os;
  os << "index";
  for (const ParameterRange& r : t.design.ranges) os << "," << csvField(r.name);
  if (t.hasCases()) os << ",case";
  os << ",status,reason";
  for (const OutputColumn& c : t.columns) os << "," << csvField(c.header);
  os << "\n";
  for (const SampleRow& r : t.rows) {
    const Sample& s = t.samples[r.index];
    os << r.index;
    for (const ParameterRange& p : t.design.ranges) os << "," << exactNumber(s.values.at(p.name));
    if (t.hasCases()) os << "," << csvField(s.caseName);
    os << "," << r.status << "," << csvField(r.reason);
    for (const std::string& cell : r.cells) os << "," << cell;
    os << "\n";
  }
  return os.str();
}

std::string sweepJson(const SweepTable& t, const SweepRunInfo& info) {
  std::vector<std::string> cases, times, outputs;
  for (const auto& c : t.design.cases) cases.push_back(jsonString(c));
  for (double x : t.times) times.push_back(exactNumber(x));
  for (const auto& o : t.outputs) outputs.push_back(jsonString(o));
  std::vector<std::string> lostRanks;
  for (const auto& l : info.lostRanks) lostRanks.push_back(jsonString(l));
  std::ostringstream os;
  os << "{\n  \"status\": " << jsonString(info.status) << ",\n";
  if (!info.interruptedBy.empty()) os << "  \"interrupted_by\": " << jsonString(info.interruptedBy) << ",\n";
  os << "  \"scene\": " << jsonString(t.scenePath) << ",\n"
     << "  \"design\": " << jsonString(t.design.samples > 0 ? "latin_hypercube" : "grid") << ",\n";
  if (t.design.samples > 0) os << "  \"seed\": " << t.design.seed << ",\n";
  os << "  \"samples\": " << t.rows.size() << ",\n"
     << "  \"parameters\": " << parametersJson(t.design) << ",\n"
     << "  \"cases\": " << jsonList(cases) << ",\n"
     << "  \"static\": " << (t.statics ? "true" : "false") << ",\n"
     << "  \"times\": " << jsonList(times) << ",\n"
     << "  \"outputs\": " << jsonList(outputs) << ",\n"
     << "  \"columns\": " << columnsJson(t) << ",\n"
     << "  \"statuses\": " << statusesJson(t.rows) << ",\n"
     << "  \"ranks\": " << info.ranks << ",\n"
     << "  \"lost_ranks\": " << jsonList(lostRanks) << ",\n"
     << "  \"sample_time_limit_s\": " << jsonNumber(info.sampleTimeLimit) << ",\n"
     << "  \"wall_time_s\": " << jsonNumber(info.wallSeconds) << ",\n"
     << "  \"scheduling_overhead_per_sample_s\": " << jsonNumber(info.overheadPerSample) << ",\n"
     << "  \"rows\": " << rowsJson(t) << "\n}\n";
  return os.str();
}

}  // namespace flexsens
