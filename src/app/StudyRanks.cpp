#include "app/StudyRanks.hpp"

#include <memory>

#include "core/Interrupt.hpp"
#include "core/Types.hpp"
#include "output/RunDirectory.hpp"
#include "parallel/Packer.hpp"
#include "parallel/TaskFarm.hpp"

namespace flexsens {

namespace {

std::string packPart(const StudyPart& p) {
  Packer k;
  k.text(p.report).number(p.cpuSeconds).integer(static_cast<long long>(p.files.size()));
  for (const auto& [name, text] : p.files) k.text(name).text(text);
  return k.bytes();
}

StudyPart unpackPart(const std::string& bytes) {
  Unpacker u(bytes);
  StudyPart p;
  p.report = u.text();
  p.cpuSeconds = u.number();
  for (long long n = u.integer(), i = 0; i < n; ++i) {
    std::string name = u.text();
    p.files.emplace_back(std::move(name), u.text());
  }
  return p;
}

}  // namespace

std::string runStudyOnRanks(RankSession& session, const StudyOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  std::unique_ptr<RunDirectory> dir;
  try {
    if (session.rank() == 0) dir = std::make_unique<RunDirectory>(options.outDir, "study");
  } catch (...) {
    stopFarmWorkers(session);
    throw;
  }
  std::vector<StudyPart> parts(studySectionCount());
  std::string lost;
  const FarmSummary f = runTaskFarm(
      session, studySectionCount(), [&options](int i) { return packPart(runStudySection(options, i)); },
      [&](const TaskOutcome& o) {
        if (o.done) parts[o.index] = unpackPart(o.payload);
        else if (lost.empty()) lost = "study section " + std::to_string(o.index + 1) + " did not finish: " + o.lost;
      },
      FarmOptions{});
  if (session.rank() != 0) return "";
  if (f.interruptedBy) throw InterruptedBeforeRun(f.interruptedBy, "while the study's sections ran");
  if (!lost.empty()) throw NumericalError(lost);
  return writeStudyParts(*dir, options, parts, started);
}

}  // namespace flexsens
