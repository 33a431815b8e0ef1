// Runs never lose or fake data (issue 13): results are written whole or marked, a full disk
// or an unwritable directory is an error naming the file, Ctrl-C leaves an `interrupted`
// summary and the rows up to it, a second run into the same directory refuses, and a rerun
// replaces earlier results whole. The CLI is run as a child process, as users run it.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string kPendulum = std::string(FLEXSENS_SOURCE_DIR) + "/examples/seed000/double_pendulum.yaml";

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Scratch {
  fs::path base;
  explicit Scratch(const std::string& name) {
    base = fs::temp_directory_path() / ("flexsens_integrity_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(base);
    fs::create_directories(base);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(base, ec);
  }
};

/// `flexsens run <args...>` as a child with stdout and stderr in files; returns its pid.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
  std::fflush(nullptr);  // or the child's freopen writes the parent's pending output again
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string out = log.string() + ".out", err = log.string() + ".err";
    if (!std::freopen(out.c_str(), "w", stdout) || !std::freopen(err.c_str(), "w", stderr)) ::_exit(120);
    std::vector<char*> argv{const_cast<char*>(FLEXSENS_EXE), const_cast<char*>("run")};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(FLEXSENS_EXE, argv.data());
    ::_exit(121);
  }
  return pid;
}

/// Exit status of a finished child (-signal when a signal ended it).
int wait(pid_t pid) {
  int st = 0;
  if (::waitpid(pid, &st, 0) != pid) return -1000;
  return WIFEXITED(st) ? WEXITSTATUS(st) : -WTERMSIG(st);
}

int run(const std::vector<std::string>& args, const fs::path& log) { return wait(spawn(args, log)); }

/// Waits until the run `pid` has written `frames` VTK frames into its staging directory
/// (next to `out`). False if the child ended first, or after 300 s (not a timing check: a
/// guard against a run that never progresses).
bool progressed(pid_t pid, const fs::path& out, int frames) {
  const fs::path staging = out.parent_path() / ("." + out.filename().string() + ".staging-" + std::to_string(pid));
  const fs::path probe = staging / ("frame_" + std::string(5 - std::to_string(frames).size(), '0') +
                                    std::to_string(frames) + ".vtu");
  for (int i = 0; i < 6000; ++i) {
    if (fs::exists(probe)) return true;
    int st = 0;
    if (::waitpid(pid, &st, WNOHANG) == pid) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

std::string jsonField(const std::string& json, const std::string& key) {
  std::smatch m;
  const std::regex re("\"" + key + "\": (\"[^\"]*\"|[-+0-9.eE]+)");
  return std::regex_search(json, m, re) ? m[1].str() : std::string();
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> r;
  std::istringstream is(text);
  for (std::string l; std::getline(is, l);) r.push_back(l);
  return r;
}

/// The frame files frames.pvd references, and the frame files the directory holds.
std::vector<std::string> pvdFiles(const fs::path& dir) {
  std::vector<std::string> r;
  const std::string pvd = readFile(dir / "frames.pvd");
  static const std::regex re("file=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), re); it != std::sregex_iterator(); ++it)
    r.push_back((*it)[1]);
  return r;
}
std::vector<std::string> vtuFiles(const fs::path& dir) {
  std::vector<std::string> r;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".vtu") r.push_back(e.path().filename().string());
  std::sort(r.begin(), r.end());
  return r;
}

/// An earlier run's results, more frames than the runs below write, with the manifest a run
/// writes (output/Manifest.hpp) listing them and `extra`.
void fakeEarlierResults(const fs::path& dir, const std::string& extra = "") {
  fs::create_directories(dir);
  std::ofstream(dir / "summary.json") << "{\"status\": \"complete\", \"t_reached\": 99}\n";
  std::ofstream(dir / "series.csv") << "t,old\n0,1\n";
  std::ofstream manifest(dir / ".flexsens-manifest");
  manifest << "flexsens-manifest 1\nkind run\nfile summary.json\nfile series.csv\nfile frames.pvd\n";
  if (!extra.empty()) manifest << "file " << extra << "\n";
  std::ofstream pvd(dir / "frames.pvd");
  for (int i = 0; i < 900; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.vtu", i);
    std::ofstream(dir / name) << "old";
    pvd << "<DataSet timestep=\"" << i << "\" part=\"0\" file=\"" << name << "\"/>\n";
    manifest << "file " << name << "\n";
  }
}

/// No file under `dir` (recursively) says a run completed.
bool nothingClaimsCompleteness(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return true;
  for (const auto& e : fs::recursive_directory_iterator(dir, ec))
    if (e.path().filename() == "summary.json" && readFile(e.path()).find("\"complete\"") != std::string::npos)
      return false;
  return true;
}

/// No staging directory left next to the output directory.
void expectNoStaging(const fs::path& parent) {
  for (const auto& e : fs::directory_iterator(parent))
    EXPECT_EQ(e.path().filename().string().find(".staging-"), std::string::npos) << "left behind: " << e.path();
}

/// Mounts a tmpfs (root only); unmounts it when done.
struct Tmpfs {
  fs::path at;
  bool ok = false;
  Tmpfs(const fs::path& dir, const std::string& options, unsigned long flags) : at(dir) {
    fs::create_directories(at);
    ok = ::geteuid() == 0 && ::mount("tmpfs", at.c_str(), "tmpfs", flags, options.c_str()) == 0;
  }
  ~Tmpfs() {
    if (ok) ::umount2(at.c_str(), MNT_DETACH);
  }
};

// ------------------------------------------------------------------ interrupts

TEST(RunIntegrity, SigintLeavesAnInterruptedSummaryWholeRowsAndOnlyItsOwnFrames) {
  Scratch s("sigint");
  const fs::path out = s.base / "out";
  fakeEarlierResults(out);
  // 500 s of the double pendulum: far more than it reaches before the signal.
  const pid_t pid = spawn({kPendulum, "--t-end", "500", "--out", out.string()}, s.base / "run");
  ASSERT_TRUE(progressed(pid, out, 20)) << readFile(s.base / "run.err");
  ASSERT_EQ(::kill(pid, SIGINT), 0);
  const int status = wait(pid);
  const std::string err = readFile(s.base / "run.err");
  EXPECT_EQ(status, 130) << err;
  EXPECT_NE(err.find("interrupted"), std::string::npos) << err;

  const std::string summary = readFile(out / "summary.json");
  EXPECT_EQ(jsonField(summary, "status"), "\"interrupted\"") << summary;
  const double tReached = std::stod(jsonField(summary, "t_reached"));
  EXPECT_GT(tReached, 0.19);  // 20 frames at 0.01 s were written before the signal
  EXPECT_LT(tReached, 500.0);
  EXPECT_GT(std::stol(jsonField(summary, "steps")), 190);  // statistics up to the signal, not zeros

  // series.csv: the header, then whole rows of as many fields, ending at the time reached.
  const auto rows = lines(readFile(out / "series.csv"));
  ASSERT_GE(rows.size(), 22u);
  const auto fields = [](const std::string& l) { return std::count(l.begin(), l.end(), ',') + 1; };
  for (const auto& r : rows) EXPECT_EQ(fields(r), fields(rows[0])) << r;
  EXPECT_NEAR(std::stod(rows.back().substr(0, rows.back().find(','))), tReached, 1e-9 * (1 + tReached));

  // Frames: every file frames.pvd names exists, and no other (the earlier 900 are gone).
  const auto named = pvdFiles(out);
  EXPECT_EQ(named.size(), rows.size() - 1);
  EXPECT_EQ(named, vtuFiles(out));
  EXPECT_EQ(readFile(out / "frame_00000.vtu").find("old"), std::string::npos);
  expectNoStaging(s.base);
}

// ------------------------------------------------------------------ one run per directory

TEST(RunIntegrity, SecondConcurrentRunRefusesNamingTheDirectory) {
  Scratch s("concurrent");
  const fs::path out = s.base / "out";
  const pid_t first = spawn({kPendulum, "--t-end", "500", "--out", out.string()}, s.base / "first");
  ASSERT_TRUE(progressed(first, out, 5)) << readFile(s.base / "first.err");
  const int second = run({kPendulum, "--t-end", "0.1", "--out", out.string()}, s.base / "second");
  const std::string err = readFile(s.base / "second.err");
  EXPECT_EQ(second, 6) << err;
  EXPECT_NE(err.find(out.string()), std::string::npos) << err;
  EXPECT_NE(err.find("another flexsens run"), std::string::npos) << err;

  ::kill(first, SIGINT);
  EXPECT_EQ(wait(first), 130) << readFile(s.base / "first.err");
  // One writer: one header, times strictly increasing.
  const auto rows = lines(readFile(out / "series.csv"));
  ASSERT_GE(rows.size(), 2u);
  EXPECT_EQ(rows[0].substr(0, 2), "t,");
  double last = -1;
  for (size_t i = 1; i < rows.size(); ++i) {
    const double t = std::stod(rows[i].substr(0, rows[i].find(',')));
    EXPECT_GT(t, last) << "row " << i;
    last = t;
  }
}

TEST(RunIntegrity, RerunReplacesEarlierResultsWhole) {
  Scratch s("rerun");
  const fs::path out = s.base / "out";
  fakeEarlierResults(out, "notes_from_an_old_run.txt");
  std::ofstream(out / "notes_from_an_old_run.txt") << "stale";
  ASSERT_EQ(run({kPendulum, "--t-end", "0.05", "--out", out.string()}, s.base / "run"), 0)
      << readFile(s.base / "run.err");
  EXPECT_EQ(jsonField(readFile(out / "summary.json"), "status"), "\"complete\"");
  EXPECT_EQ(pvdFiles(out), vtuFiles(out));
  EXPECT_EQ(vtuFiles(out).size(), 6u);  // t = 0, 0.01, ..., 0.05
  EXPECT_FALSE(fs::exists(out / "notes_from_an_old_run.txt"));
  EXPECT_EQ(lines(readFile(out / "series.csv")).size(), 7u);
}

// ------------------------------------------------------------------ unwritable outputs

TEST(RunIntegrity, FullDiskIsAnOutputErrorNamingTheFileAndLeavesNothingComplete) {
  Scratch s("fulldisk");
  Tmpfs disk(s.base / "disk", "size=256k", 0);
  if (!disk.ok) GTEST_SKIP() << "needs root to mount a small tmpfs (euid " << ::geteuid() << ")";
  const fs::path out = disk.at / "out";
  // 500 frames of a few kB each: more than 256 kB.
  const int status = run({kPendulum, "--out", out.string()}, s.base / "run");
  const std::string err = readFile(s.base / "run.err");
  EXPECT_EQ(status, 4) << err;
  EXPECT_NE(err.find("No space left on device"), std::string::npos) << err;
  EXPECT_NE(err.find(out.string() + "/"), std::string::npos) << "names the file:\n" << err;
  EXPECT_TRUE(nothingClaimsCompleteness(disk.at));
  EXPECT_FALSE(fs::exists(out));
  expectNoStaging(disk.at);
  EXPECT_EQ(readFile(s.base / "run.out").find("results written"), std::string::npos);
}

TEST(RunIntegrity, ReadOnlyDirectoryIsAnOutputErrorNamingIt) {
  Scratch s("readonly");
  Tmpfs ro(s.base / "ro", "size=64k", MS_RDONLY);
  if (!ro.ok) GTEST_SKIP() << "needs root to mount a read-only tmpfs (euid " << ::geteuid() << ")";
  const fs::path out = ro.at / "out";
  const int status = run({kPendulum, "--t-end", "0.05", "--out", out.string()}, s.base / "run");
  const std::string err = readFile(s.base / "run.err");
  EXPECT_EQ(status, 4) << err;
  EXPECT_NE(err.find("Read-only file system"), std::string::npos) << err;
  EXPECT_NE(err.find(ro.at.string()), std::string::npos) << err;
  EXPECT_TRUE(fs::is_empty(ro.at));
}

TEST(RunIntegrity, OutNamingAFileIsAnOutputErrorAndTheFileStays) {
  Scratch s("outfile");
  const fs::path file = s.base / "results.txt";
  std::ofstream(file) << "mine";
  const int status = run({kPendulum, "--t-end", "0.05", "--out", file.string()}, s.base / "run");
  const std::string err = readFile(s.base / "run.err");
  EXPECT_EQ(status, 4) << err;
  EXPECT_NE(err.find(file.string()), std::string::npos) << err;
  EXPECT_NE(err.find("not a directory"), std::string::npos) << err;
  EXPECT_EQ(readFile(file), "mine");
}

TEST(RunIntegrity, ForeignNonEmptyDirectoryIsNotReplaced) {
  Scratch s("foreign");
  const fs::path dir = s.base / "home";
  fs::create_directories(dir);
  std::ofstream(dir / "thesis.tex") << "precious";
  const int status = run({kPendulum, "--t-end", "0.05", "--out", dir.string()}, s.base / "run");
  const std::string err = readFile(s.base / "run.err");
  EXPECT_EQ(status, 4) << err;
  EXPECT_NE(err.find("flexsens did not write (thesis.tex)"), std::string::npos) << err;
  EXPECT_EQ(readFile(dir / "thesis.tex"), "precious");
}

}  // namespace
