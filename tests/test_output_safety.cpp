// flexsens deletes or replaces only what it wrote (issue 34): the manifest of an output folder,
// the refusal of folders holding anything else, replacement by the manifest, the one lock per
// resolved folder (through symbolic links, shared by a run of PIM cases and a plain run, and
// by nested folders), symbolic links followed and kept, and checked writes (a full disk, a
// file-size limit) that never pass a study off as written.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/Study.hpp"
#include "core/Types.hpp"
#include "output/Manifest.hpp"
#include "output/OutputLock.hpp"
#include "output/RunDirectory.hpp"

using namespace flexsens;
namespace fs = std::filesystem;

namespace {

struct Scratch {
  fs::path base;
  explicit Scratch(const std::string& name) {
    base = fs::temp_directory_path() / ("flexsens_outsafe_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(base);
    fs::create_directories(base);
    base = fs::canonical(base);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(base, ec);
  }
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void put(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

/// Names in `dir` (not recursive), sorted; folders end in '/'.
std::vector<std::string> names(const fs::path& dir) {
  std::vector<std::string> r;
  for (const auto& e : fs::directory_iterator(dir))
    r.push_back(e.path().filename().string() + (e.is_directory() && !e.is_symlink() ? "/" : ""));
  std::sort(r.begin(), r.end());
  return r;
}

std::vector<std::string> sorted(std::vector<std::string> v) {
  std::sort(v.begin(), v.end());
  return v;
}

/// A finished run into `dir` writing `files` (name -> text).
void writeRun(const fs::path& dir, const std::vector<std::pair<std::string, std::string>>& files,
              const std::string& part = "", const std::string& kind = "run") {
  RunDirectory d(dir.string(), kind);
  const std::string stage = d.staging(part);
  for (const auto& [n, t] : files) put(fs::path(stage) / n, t);
  d.commit(part);
}

template <class F>
std::string outputError(F f) {
  try {
    f();
  } catch (const OutputError& e) {
    return e.what();
  }
  return "";
}

template <class F>
std::string busyError(F f) {
  try {
    f();
  } catch (const DirectoryBusy& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// ------------------------------------------------------------------ the manifest

TEST(OutputManifest, ListsWhatIsNotListedThroughSubfolders) {
  Scratch s("foreign");
  const fs::path d = s.base / "d";
  put(d / kManifestName, "flexsens-manifest 1\nkind cases\ndir F1\nfile a.csv\n");
  put(d / "a.csv", "t\n");
  put(d / "F1" / kManifestName, "flexsens-manifest 1\nkind run\nfile series.csv\n");
  put(d / "F1" / "series.csv", "t\n");
  put(d / "F1" / "notes.txt", "mine");  // inside a listed subfolder, not listed there
  put(d / "photos" / "a.jpg", "jpg");
  put(d / "thesis.tex", "mine");
  put(d / ".F1.lock", "");  // flexsens' own lock file of a run into d/F1
  const ForeignEntries f = foreignEntries(d);
  EXPECT_EQ(sorted(f.entries), (std::vector<std::string>{"F1/notes.txt", "photos/", "thesis.tex"}));
  EXPECT_EQ(describeEntries({"a", "b/", "c", "d", "e", "f"}), "a, b/, c, d and 2 more");
}

TEST(OutputManifest, ListedNamesMustBeTheThingItselfAndPlainNames) {
  Scratch s("names");
  const fs::path d = s.base / "d";
  put(s.base / "precious.txt", "mine");
  put(d / kManifestName, "flexsens-manifest 1\nkind run\nfile series.csv\n");
  fs::create_symlink(s.base / "precious.txt", d / "series.csv");  // listed, but a link
  EXPECT_EQ(foreignEntries(d).entries, std::vector<std::string>{"series.csv"});
  EXPECT_FALSE(removeListed(d));  // the link is not a listed regular file: it stays, so does d
  EXPECT_TRUE(fs::is_symlink(d / "series.csv"));
  EXPECT_EQ(slurp(s.base / "precious.txt"), "mine");

  const fs::path e = s.base / "e";
  put(e / kManifestName, "flexsens-manifest 1\nkind run\nfile ../precious.txt\n");
  std::string problem;
  EXPECT_FALSE(readManifest(e, problem));
  EXPECT_NE(problem.find("line 3"), std::string::npos) << problem;
  EXPECT_FALSE(removeListed(e));
  EXPECT_EQ(slurp(s.base / "precious.txt"), "mine");
  const ForeignEntries f = foreignEntries(e);
  EXPECT_EQ(f.entries, std::vector<std::string>{kManifestName});
  EXPECT_NE(f.note.find("plain name"), std::string::npos) << f.note;

  put(e / kManifestName, "flexsens-manifest 2\nkind run\n");  // another format: not ours
  EXPECT_FALSE(readManifest(e, problem));
  EXPECT_NE(problem.find("line 1"), std::string::npos) << problem;
}

TEST(OutputManifest, RemoveListedKeepsEverythingElse) {
  Scratch s("remove");
  const fs::path d = s.base / "d";
  put(d / kManifestName, "flexsens-manifest 1\nkind run\nfile a.csv\ndir F1\nkeep view.pvsm\n");
  put(d / "a.csv", "t\n");
  put(d / "F1" / kManifestName, "flexsens-manifest 1\nkind run\nfile b.csv\n");
  put(d / "F1" / "b.csv", "t\n");
  put(d / "view.pvsm", "state");
  put(d / "late.txt", "written while the run ran");
  EXPECT_FALSE(removeListed(d));
  EXPECT_EQ(names(d), (std::vector<std::string>{"late.txt", "view.pvsm"}));

  const fs::path e = s.base / "e";
  put(e / kManifestName, "flexsens-manifest 1\nkind run\nfile a.csv\n");
  put(e / "a.csv", "t\n");
  EXPECT_TRUE(removeListed(e));
  EXPECT_FALSE(fs::exists(e));
}

// ------------------------------------------------------------------ refusal and replacement

TEST(RunDirectorySafety, RefusesAFolderWithUserFilesTouchingNothing) {
  Scratch s("refuse");
  const fs::path proj = s.base / "proj";
  put(proj / "thesis.tex", "three years of work");
  put(proj / "src" / "main.c", "int main(){}");
  writeRun(proj / "run1", {{"series.csv", "t\n"}});  // an earlier run one level down
  const auto before = names(s.base);
  const auto inside = names(proj);
  const std::string err = outputError([&] { RunDirectory d(proj.string()); });
  // thesis.tex, src/, run1/ (proj has no manifest); run1's lock file .run1.lock is flexsens'
  EXPECT_NE(err.find(proj.string() + ": it holds 3 entries flexsens did not write"), std::string::npos) << err;
  EXPECT_NE(err.find("thesis.tex"), std::string::npos) << err;
  EXPECT_NE(err.find("src/"), std::string::npos) << err;
  EXPECT_EQ(names(s.base), before);  // no lock file, no staging folder beside it
  EXPECT_EQ(names(proj), inside);
  EXPECT_EQ(slurp(proj / "thesis.tex"), "three years of work");

  // Results of a flexsens without manifests: refused too, with a hint.
  const fs::path old = s.base / "old";
  put(old / "summary.json", "{}");
  const std::string hint = outputError([&] { RunDirectory d(old.string()); });
  EXPECT_NE(hint.find("did not list its files"), std::string::npos) << hint;
  // A file, not a folder.
  put(s.base / "file", "x");
  EXPECT_NE(outputError([&] { RunDirectory d((s.base / "file").string()); }).find("not a directory"),
            std::string::npos);
}

TEST(RunDirectorySafety, NewAndEmptyFoldersAreFineAndARerunReplacesOnlyListedFiles) {
  Scratch s("rerun");
  const fs::path empty = s.base / "empty";
  fs::create_directories(empty);
  writeRun(empty, {{"series.csv", "1"}});
  EXPECT_EQ(names(empty), (std::vector<std::string>{kManifestName, "series.csv"}));

  const fs::path d = s.base / "nested" / "new";
  writeRun(d, {{"series.csv", "old"}, {"frame_00001.vtu", "old"}});
  put(d / "view.pvsm", "ParaView state of scripts/render_frames.py");
  put(d / "png" / "frame_00000.png", "rendered");
  writeRun(d, {{"series.csv", "new"}});
  EXPECT_EQ(names(d), (std::vector<std::string>{kManifestName, "png/", "series.csv", "view.pvsm"}));
  EXPECT_EQ(slurp(d / "png" / "frame_00000.png"), "rendered");
  EXPECT_EQ(slurp(d / "series.csv"), "new");
  EXPECT_EQ(slurp(d / "view.pvsm"), "ParaView state of scripts/render_frames.py");  // carried over
  const std::string m = slurp(d / kManifestName);
  EXPECT_NE(m.find("file series.csv\n"), std::string::npos) << m;
  EXPECT_NE(m.find("keep view.pvsm\n"), std::string::npos) << m;
  EXPECT_EQ(m.find("frame_00001"), std::string::npos) << m;
  for (const auto& n : names(s.base / "nested")) EXPECT_EQ(n.find("staging"), std::string::npos) << n;
}

TEST(RunDirectorySafety, AFileThatAppearsDuringTheRunStaysAndTheResultsAreKept) {
  Scratch s("appears");
  const fs::path d = s.base / "d";
  writeRun(d, {{"series.csv", "old"}});
  RunDirectory run(d.string());
  put(fs::path(run.staging()) / "series.csv", "new");
  put(d / "notes.txt", "written by the user while the run ran");
  const std::string err = outputError([&] { run.commit(); });
  const fs::path aside = s.base / ("d.unplaced-" + std::to_string(::getpid()));
  EXPECT_NE(err.find("notes.txt"), std::string::npos) << err;
  EXPECT_NE(err.find(aside.string()), std::string::npos) << err;
  EXPECT_EQ(slurp(d / "notes.txt"), "written by the user while the run ran");
  EXPECT_EQ(slurp(d / "series.csv"), "old");
  EXPECT_EQ(slurp(aside / "series.csv"), "new");  // the finished result is not lost
}

TEST(RunDirectorySafety, ASymlinkedFolderIsFollowedAndStaysASymlink) {
  Scratch s("symlink");
  const fs::path real = s.base / "bigdisk" / "results";
  writeRun(real, {{"series.csv", "old"}});
  fs::create_symlink(real, s.base / "link");
  writeRun(s.base / "link", {{"series.csv", "new"}});
  EXPECT_TRUE(fs::is_symlink(s.base / "link"));
  EXPECT_EQ(slurp(real / "series.csv"), "new");
  EXPECT_EQ(resolveOutputFolder((s.base / "link").string()), real);
  // a/../b with a -> deep/inner is deep/b, as the kernel opens it
  fs::create_directories(s.base / "deep" / "inner");
  fs::create_symlink(s.base / "deep" / "inner", s.base / "a");
  EXPECT_EQ(resolveOutputFolder((s.base / "a" / ".." / "b").string()), s.base / "deep" / "b");
  fs::create_symlink(s.base / "missing", s.base / "dangling");
  EXPECT_NE(outputError([&] { resolveOutputFolder((s.base / "dangling").string()); }).find("does not exist"),
            std::string::npos);
  EXPECT_NE(outputError([&] { resolveOutputFolder("/"); }).find("root folder"), std::string::npos);
}

// ------------------------------------------------------------------ one lock per folder

TEST(RunDirectorySafety, OneLockPerResolvedFolderForEveryKindOfRun) {
  Scratch s("lock");
  const fs::path real = s.base / "real";
  fs::create_directories(real);
  fs::create_symlink(real, s.base / "link");
  {
    RunDirectory first(real.string());
    const std::string err = busyError([&] { RunDirectory second((s.base / "link").string(), "static"); });
    EXPECT_NE(err.find("another flexsens run is writing " + real.string()), std::string::npos) << err;
  }
  // A run of PIM cases into D and a plain run into D take the same lock.
  const fs::path d = s.base / "D";
  {
    RunDirectory cases(d.string(), "cases");
    EXPECT_NE(busyError([&] { RunDirectory plain(d.string()); }), "");
    EXPECT_NE(busyError([&] { RunDirectory study(d.string(), "study"); }), "");
    const std::string nested = busyError([&] { RunDirectory inner((d / "F1").string()); });
    EXPECT_NE(nested.find("which holds " + (d / "F1").string()), std::string::npos) << nested;
  }
  {
    RunDirectory inner((d / "F1").string());  // D's lock file exists now: taken shared
    EXPECT_NE(busyError([&] { RunDirectory outer(d.string(), "cases"); }), "");
    RunDirectory sibling((d / "R").string());  // siblings go on together
  }
  RunDirectory again(d.string(), "cases");  // released with the runs
}

TEST(RunDirectorySafety, CasesAdoptAnEarlierRunKeepOtherCasesAndAPlainRunReplacesThem) {
  Scratch s("cases");
  const fs::path d = s.base / "D";
  writeRun(d, {{"series.csv", "plain"}});
  {
    RunDirectory cases(d.string(), "cases");
    put(fs::path(cases.staging("F1")) / "series.csv", "F1");
    put(fs::path(cases.staging("R")) / "series.csv", "R");
    cases.commit("F1");
    cases.commit("R");
  }
  EXPECT_EQ(names(d), (std::vector<std::string>{kManifestName, "F1/", "R/"}));  // the plain run's files went
  EXPECT_TRUE(foreignEntries(d).entries.empty());
  writeRun(d, {{"series.csv", "F1 again"}}, "F1", "cases");  // --case F1: R stays
  EXPECT_EQ(slurp(d / "F1" / "series.csv"), "F1 again");
  EXPECT_EQ(slurp(d / "R" / "series.csv"), "R");
  writeRun(d, {{"series.csv", "plain again"}});
  EXPECT_EQ(names(d), (std::vector<std::string>{kManifestName, "series.csv"}));
  for (const auto& n : names(s.base)) EXPECT_EQ(n.find("staging"), std::string::npos) << n;
}

TEST(RunDirectorySafety, KilledRunsStagingIsRemovedOnlyWhenMarked) {
  Scratch s("leftover");
  const fs::path d = s.base / "d";
  put(s.base / ".d.staging-99999" / kStagingMarker, "flexsens writes d here (pid 99999)\n");
  put(s.base / ".d.staging-99999" / "series.csv", "partial");
  put(s.base / ".d.staging-88888" / "mine.txt", "not flexsens'");
  writeRun(d, {{"series.csv", "1"}});
  EXPECT_FALSE(fs::exists(s.base / ".d.staging-99999"));
  EXPECT_EQ(slurp(s.base / ".d.staging-88888" / "mine.txt"), "not flexsens'");
}

// ------------------------------------------------------------------ checked writes

TEST(CheckedWrites, AFullDiskIsAnOutputErrorNamingTheFile) {
  const std::string err = outputError([] { writeFileChecked("/dev/full", "out/study.md", std::string(10000, 'x')); });
  EXPECT_NE(err.find("cannot write out/study.md: No space left on device"), std::string::npos) << err;
}

// The study's last step with a write that fails half-way (a file-size limit: the study.md
// exceeds it, as on a disk that fills up): an OutputError naming the file, nothing moved
// into place, no staging folder left.
TEST(CheckedWrites, AStudyThatCannotWriteIsNotPassedOffAsWritten) {
  Scratch s("study");
  const fs::path out = s.base / "study";
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  rlimit small = saved;
  small.rlim_cur = 16384;  // bytes
  const auto oldHandler = ::signal(SIGXFSZ, SIG_IGN);  // write() then fails with EFBIG
  std::string err;
  {
    RunDirectory dir(out.string(), "study");
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
    err = outputError([&] {
      writeStudyOutput(dir, {{"cost.csv", "model\n"}, {"study.md", std::string(100000, '#')}}, {"cost.png"});
    });
    ::setrlimit(RLIMIT_FSIZE, &saved);
  }
  ::signal(SIGXFSZ, oldHandler);
  EXPECT_NE(err.find("cannot write " + (out / "study.md").string() + ": File too large"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(names(s.base), std::vector<std::string>{".study.lock"});

  RunDirectory dir(out.string(), "study");
  EXPECT_EQ(writeStudyOutput(dir, {{"study.md", "# report\n"}}, {"cost.png"}), (out / "study.md").string());
  EXPECT_EQ(slurp(out / "study.md"), "# report\n");
  EXPECT_NE(slurp(out / kManifestName).find("keep cost.png\n"), std::string::npos);
}
