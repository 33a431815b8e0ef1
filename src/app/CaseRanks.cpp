#include "app/CaseRanks.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "core/Interrupt.hpp"
#include "output/Manifest.hpp"
#include "output/RunDirectory.hpp"
#include "parallel/Packer.hpp"
#include "parallel/TaskFarm.hpp"

namespace flexsens {

namespace fs = std::filesystem;

namespace {

/// How a case ended in its child, with the files it wrote.
struct CaseReport {
  std::string status;  ///< complete | suspect | failed
  char errorKind = 0;  ///< failed: 'N' numerical, 'I' input, 'O' output, 'E' other
  std::string error;
  RunResult result;
  std::vector<std::pair<std::string, std::string>> files;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string packReport(const CaseReport& r) {
  Packer p;
  const IntegratorStats& s = r.result.stats;
  p.text(r.status).integer(r.errorKind).text(r.error).text(r.result.suspect).number(r.result.wallSeconds);
  p.integer(s.steps).integer(s.newtonIterations).integer(s.factorizations).number(s.maxConstraintViolation);
  p.integer(static_cast<long long>(r.files.size()));
  for (const auto& [name, text] : r.files) p.text(name).text(text);
  return p.bytes();
}

CaseReport unpackReport(const std::string& bytes) {
  Unpacker u(bytes);
  CaseReport r;
  r.status = u.text();
  r.errorKind = static_cast<char>(u.integer());
  r.error = u.text();
  r.result.suspect = u.text();
  r.result.wallSeconds = u.number();
  IntegratorStats& s = r.result.stats;
  s.steps = u.integer();
  s.newtonIterations = u.integer();
  s.factorizations = u.integer();
  s.maxConstraintViolation = u.number();
  for (long long n = u.integer(), i = 0; i < n; ++i) {
    std::string name = u.text();
    r.files.emplace_back(std::move(name), u.text());
  }
  return r;
}

/// In the child: case `c` alone into `dir`; any failure is the report's.
CaseReport runCaseInto(RunCase& c, const std::string& dir) {
  CaseReport r;
  c.scene.output.directory = dir;
  std::vector<RunCase> one;
  one.push_back(std::move(c));
  auto fail = [&r](char kind, const char* what) {
    r.status = "failed";
    r.errorKind = kind;
    r.error = what;
  };
  try {
    r.result = runCases(one).cases.front();
    r.status = r.result.suspect.empty() ? "complete" : "suspect";
  } catch (const NumericalError& e) {
    fail('N', e.what());
  } catch (const InputError& e) {
    fail('I', e.what());
  } catch (const OutputError& e) {
    fail('O', e.what());
  } catch (const std::exception& e) {
    fail('E', e.what());
  }
  const fs::path folder = fs::path(dir) / one.front().name;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec))
    if (e.is_regular_file() && e.path().filename() != kManifestName)
      r.files.emplace_back(e.path().filename().string(), slurp(e.path()));
  return r;
}

[[noreturn]] void rethrow(char kind, const std::string& message) {
  if (kind == 'N') throw NumericalError(message);
  if (kind == 'I') throw InputError(message);
  if (kind == 'O') throw OutputError(message);
  throw std::runtime_error(message);
}

/// Rank 0's end of a case: its files into the output folder, committed.
RunResult placeCase(RunDirectory& out, const RunCase& c, CaseReport& r) {
  const std::string staging = out.staging(c.name);
  for (const auto& [name, text] : r.files)
    writeFileChecked(staging + "/" + name, out.final(c.name) + "/" + name, text);
  out.commit(c.name);
  r.result.directory = out.final(c.name);
  return r.result;
}

}  // namespace

RunCommandResult runCasesOnRanks(RankSession& session, std::vector<RunCase>& cases,
                                 const std::function<void(const RunCase&, const RunResult&)>& caseDone) {
  std::unique_ptr<RunDirectory> out;
  try {
    if (session.rank() == 0) out = std::make_unique<RunDirectory>(cases.front().scene.output.directory, "cases");
  } catch (...) {
    stopFarmWorkers(session);
    throw;
  }
  const char* tmp = std::getenv("TMPDIR");
  std::string scratch = std::string(tmp && *tmp ? tmp : "/tmp") + "/flexsens-cases-XXXXXX";
  if (!::mkdtemp(scratch.data())) throw OutputError("cannot create a scratch folder " + scratch);
  RunCommandResult result;
  std::vector<std::pair<char, std::string>> failures(cases.size());  // by case index
  auto work = [&](int i) { return packReport(runCaseInto(cases[i], scratch + "/" + std::to_string(i))); };
  auto done = [&](const TaskOutcome& o) {
    const RunCase& c = cases[o.index];
    if (!o.done) {
      failures[o.index] = {'E', "case " + c.name + " did not finish: " + o.lost};
      return;
    }
    CaseReport r = unpackReport(o.payload);
    const RunResult res = placeCase(*out, c, r);
    if (r.status == "failed") {
      failures[o.index] = {r.errorKind, r.error};
      std::cerr << "flexsens: case " << c.name << " failed (summary.json says failed): " << r.error << "\n";
      return;
    }
    result.cases.push_back(res);
    if (!res.suspect.empty()) result.status = 5;
    if (caseDone) caseDone(c, res);
  };
  const FarmSummary f = runTaskFarm(session, static_cast<int>(cases.size()), work, done, FarmOptions{});
  std::error_code ec;
  fs::remove_all(scratch, ec);
  if (session.rank() != 0) return {};
  if (f.interruptedBy && result.cases.empty()) throw InterruptedBeforeRun(f.interruptedBy, "before any case finished");
  result.interruptedBy = f.interruptedBy;
  for (const auto& [kind, message] : failures)
    if (!message.empty() && !f.interruptedBy) rethrow(kind, message);
  return result;
}

}  // namespace flexsens
