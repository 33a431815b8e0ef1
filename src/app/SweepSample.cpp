#include "app/SweepSample.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/Commands.hpp"
#include "core/Interrupt.hpp"
#include "parallel/Packer.hpp"

namespace flexsens {

namespace fs = std::filesystem;

namespace {

/// series.csv as text cells: the header, then the rows (flexsens writes no quoted fields).
struct Series {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

std::vector<std::string> splitCsvLine(const std::string& line) {
  std::vector<std::string> cells(1);
  for (char c : line) {
    if (c == ',') cells.emplace_back();
    else if (c != '\r') cells.back() += c;
  }
  return cells;
}

Series readSeries(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw OutputError("cannot read " + path);
  Series s;
  std::string line;
  if (std::getline(in, line)) s.header = splitCsvLine(line);
  while (std::getline(in, line))
    if (!line.empty()) s.rows.push_back(splitCsvLine(line));
  return s;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The row of `s` at time `t` (the first column), or nullptr.
const std::vector<std::string>* rowAt(const Series& s, double t, double tolerance) {
  for (const auto& r : s.rows)
    if (!r.empty() && std::abs(std::strtod(r[0].c_str(), nullptr) - t) <= tolerance) return &r;
  return nullptr;
}

/// The sample's cells from its series.csv; a time without a row is a failure (it names it).
void readCells(const SweepSetup& setup, const std::string& seriesPath, SampleRow& row) {
  const Series s = readSeries(seriesPath);
  for (size_t c = 0; c < setup.columns.size(); ++c) {
    const OutputColumn& col = setup.columns[c];
    const std::vector<std::string>* r =
        setup.statics ? (s.rows.empty() ? nullptr : &s.rows.back()) : rowAt(s, col.time, setup.timeTolerance);
    if (!r) {
      std::ostringstream os;
      os << "series.csv has no row at t = " << col.time << " s";
      throw NumericalError(os.str());
    }
    for (size_t k = 0; k < s.header.size() && k < r->size(); ++k)
      if (s.header[k] == col.source()) row.cells[c] = (*r)[k];
  }
}

/// Runs the sample into `dir`; returns the folder holding its series.csv and summary.json.
std::string runInto(const SweepSetup& setup, const Sample& sample, const std::string& dir, SampleRow& row) {
  if (setup.statics) {
    StaticRequest req;
    req.scenePath = setup.scenePath;
    req.outDir = dir;
    req.loadSteps = setup.loadSteps;
    req.method = setup.options.method.value_or("");
    req.parameterValues = sample.values;
    req.frames = false;
    const StaticCommandResult r = staticCommand(req);
    if (r.interruptedBy) throw InterruptedBeforeRun(r.interruptedBy, "during the static solution");
    row.status = "complete";
    return r.directory;
  }
  RunRequest req;
  req.scenePath = setup.scenePath;
  req.options = setup.options;
  req.options.outDir = dir;
  if (!sample.caseName.empty()) req.cases = {sample.caseName};
  if (setup.perturbedStart) {
    // The nominal scene, moved to the values as a PIM case says its start moves (Python's
    // Scene.run(parameters=)): a rigidized body stays undeformed.
    for (const auto& [name, value] : sample.values) req.options.parameters.emplace_back(name, value);
  } else {
    req.parameterValues = sample.values;
  }
  std::vector<RunCase> cases = prepareRun(req);
  for (RunCase& c : cases) c.scene.output.vtk = false;  // a sweep keeps numbers, not frames
  const RunCommandResult r = runCases(cases);
  const std::string& suspect = r.cases.front().suspect;
  row.status = suspect.empty() ? "complete" : "suspect";
  row.reason = suspect;
  return r.cases.front().directory;
}

void keepFiles(const std::string& folder, SampleRow& row) {
  for (const char* name : {"series.csv", "summary.json"})
    if (fs::is_regular_file(fs::path(folder) / name)) row.files.emplace_back(name, slurp(folder + "/" + name));
}

}  // namespace

SampleRow runSample(const SweepSetup& setup, const Sample& sample) {
  SampleRow row;
  row.index = sample.index;
  row.cells.assign(setup.columns.size(), "");
  const std::string dir = setup.scratch + "/" + std::to_string(sample.index);
  const std::string folder = dir + (sample.caseName.empty() ? "" : "/" + sample.caseName);
  auto endAs = [&](const std::string& status, const std::string& reason) {
    row.status = status;
    row.reason = reason;
    row.cells.assign(setup.columns.size(), "");  // a run that did not end has no values
  };
  try {
    readCells(setup, runInto(setup, sample, dir, row) + "/series.csv", row);
  } catch (const Interrupted& e) {
    endAs("interrupted", e.what());
  } catch (const InterruptedBeforeRun& e) {
    endAs("interrupted", e.what());
  } catch (const std::exception& e) {
    endAs("failed", e.what());
  }
  if (setup.keepFiles) keepFiles(folder, row);
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::remove(setup.scratch + "/." + std::to_string(sample.index) + ".lock", ec);
  return row;
}

std::string packSampleRow(const SampleRow& row) {
  Packer p;
  p.integer(row.index).text(row.status).text(row.reason).integer(static_cast<long long>(row.cells.size()));
  for (const auto& c : row.cells) p.text(c);
  p.integer(static_cast<long long>(row.files.size()));
  for (const auto& [name, text] : row.files) p.text(name).text(text);
  return p.bytes();
}

SampleRow unpackSampleRow(const std::string& bytes) {
  Unpacker u(bytes);
  SampleRow row;
  row.index = static_cast<int>(u.integer());
  row.status = u.text();
  row.reason = u.text();
  for (long long n = u.integer(), i = 0; i < n; ++i) row.cells.push_back(u.text());
  for (long long n = u.integer(), i = 0; i < n; ++i) {
    std::string name = u.text();
    row.files.emplace_back(std::move(name), u.text());
  }
  return row;
}

}  // namespace flexsens
