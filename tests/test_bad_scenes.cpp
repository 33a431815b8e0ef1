// Malformed scenes (tests/scenes/bad/*.yaml) and bad command lines: `flexsens run` and
// `flexsens check` must exit with status 1 (input error), name the file, the line of the
// offending YAML node and the key path, and write nothing.
//
// Each bad scene starts with a line
//   # expect: <file name>:<line>: key '<key path>'
// stating where the error is. Files that cannot carry that comment (because the comment
// would change what is being tested) have their expectation in kNoCommentExpectations below.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Expectation {
  int line = 0;
  std::string key;  ///< key path, without quotes
};

/// Expectations of the bad scenes that carry no "# expect:" comment.
const std::map<std::string, Expectation> kNoCommentExpectations = {
    // bad_empty.yaml is a truly empty file (a comment would make it a comment-only file,
    // which is not the same input). The error must point at the only place there is,
    // line 1, and name the first required key, 'dimension'.
    {"bad_empty.yaml", {1, "dimension"}},
};

fs::path badSceneDir() { return fs::path(FLEXSENS_SOURCE_DIR) / "tests" / "scenes" / "bad"; }

std::vector<std::string> badSceneFiles() {
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(badSceneDir(), ec))
    if (e.is_regular_file() && e.path().extension() == ".yaml") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Runs `command` through the shell; returns the exit status, or -1 if it did not exit normally.
int runShell(const std::string& command) {
  const int st = std::system(command.c_str());
  if (st == -1 || !WIFEXITED(st)) return -1;
  return WEXITSTATUS(st);
}

/// A fresh scratch directory for one test: removed at the start and at the end.
struct Scratch {
  fs::path base;
  explicit Scratch(const std::string& name) {
    static int counter = 0;
    base = fs::temp_directory_path() /
           ("flexsens_bad_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + "_" + name);
    fs::remove_all(base);
    fs::create_directories(base);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(base, ec);
  }
};

struct Invocation {
  int status = -1;
  std::string err;
};

/// Runs `flexsens <args>` in the working directory `cwd` with stderr captured into `errFile`.
Invocation flexsens(const std::string& args, const fs::path& cwd, const fs::path& errFile) {
  const std::string cmd = "cd " + quote(cwd.string()) + " && " + quote(FLEXSENS_EXE) + " " + args +
                          " >/dev/null 2>" + quote(errFile.string());
  Invocation r;
  r.status = runShell(cmd);
  r.err = readFile(errFile);
  return r;
}

std::vector<std::string> directoryEntries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

/// The test name for a scene file: its stem with anything but [A-Za-z0-9_] replaced.
std::string testName(const testing::TestParamInfo<std::string>& info) {
  std::string s = fs::path(info.param).stem().string();
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  return s;
}

/// Checks the "flexsens: error: <path>:<line>:<column>: key '<key>': ..." line of `err`:
/// the path ends with `fileName`, the line is `ex.line`, the key is `ex.key`.
void expectLocatedError(const std::string& err, const std::string& fileName, const Expectation& ex) {
  const std::string located = fileName + ":" + std::to_string(ex.line) + ":";
  const std::string key = "key '" + ex.key + "'";
  EXPECT_NE(err.find(located), std::string::npos) << "stderr should contain '" << located << "':\n" << err;
  EXPECT_NE(err.find(key), std::string::npos) << "stderr should contain " << key << ":\n" << err;
  // The full form: the path (as given) ends with the file name, then line and column, then the key.
  static const std::regex form(R"(flexsens: error: (.*):([0-9]+):([0-9]+): key '([^']*)': \S.*)");
  std::smatch m;
  std::istringstream lines(err);
  std::string ln;
  bool found = false;
  while (std::getline(lines, ln)) {
    if (!std::regex_match(ln, m, form)) continue;
    found = true;
    const std::string path = m[1];
    const bool endsWith = path == fileName ||
                          (path.size() > fileName.size() &&
                           path.compare(path.size() - fileName.size() - 1, std::string::npos, "/" + fileName) == 0);
    EXPECT_TRUE(endsWith) << "the path '" << path << "' should end with " << fileName;
    EXPECT_EQ(std::stoi(m[2]), ex.line) << ln;
    EXPECT_EQ(m[4].str(), ex.key) << ln;
  }
  EXPECT_TRUE(found) << "no line of the form 'flexsens: error: <file>:<line>:<column>: key '<key>': ...' in:\n"
                     << err;
}

/// The expectation of a bad scene: its first-line comment, or kNoCommentExpectations.
testing::AssertionResult expectationOf(const std::string& file, Expectation& ex) {
  const std::string name = fs::path(file).filename().string();
  const auto it = kNoCommentExpectations.find(name);
  if (it != kNoCommentExpectations.end()) {
    ex = it->second;
    return testing::AssertionSuccess();
  }
  std::ifstream in(file);
  std::string first;
  std::getline(in, first);
  static const std::regex form(R"(#\s*expect:\s*(\S+):([0-9]+):\s*key '([^']*)'\s*)");
  std::smatch m;
  if (!std::regex_match(first, m, form))
    return testing::AssertionFailure() << name << ": the first line should be \"# expect: " << name
                                       << ":<line>: key '<key path>'\", got \"" << first << "\"";
  if (m[1] != name)
    return testing::AssertionFailure() << name << ": the expect comment names another file, " << m[1];
  ex.line = std::stoi(m[2]);
  ex.key = m[3];
  return testing::AssertionSuccess();
}

class BadScene : public testing::TestWithParam<std::string> {};

TEST_P(BadScene, RunAndCheckExitOneNamingLineAndKeyAndWriteNothing) {
  const std::string file = GetParam();
  const std::string name = fs::path(file).filename().string();
  Expectation ex;
  ASSERT_TRUE(expectationOf(file, ex));

  Scratch s(fs::path(file).stem().string());
  const fs::path work = s.base / "work";  // working directory: must stay empty
  const fs::path out = s.base / "out";    // --out: must not be created
  fs::create_directories(work);
  ASSERT_FALSE(fs::exists(out));

  // Bad scenes share the meshes of tests/scenes/ and examples/: the source tree is allowed.
  const std::string allow = " --allow-path " + quote(FLEXSENS_SOURCE_DIR);
  const Invocation run = flexsens("run " + quote(file) + allow + " --out " + quote(out.string()), work, s.base / "run.err");
  EXPECT_EQ(run.status, 1) << "flexsens run " << name << " stderr:\n" << run.err;
  expectLocatedError(run.err, name, ex);
  EXPECT_FALSE(fs::exists(out)) << "flexsens run wrote the output directory for " << name;
  EXPECT_TRUE(directoryEntries(work).empty()) << "flexsens run wrote into the working directory for " << name;

  const Invocation check = flexsens("check " + quote(file) + allow, work, s.base / "check.err");
  EXPECT_EQ(check.status, 1) << "flexsens check " << name << " stderr:\n" << check.err;
  expectLocatedError(check.err, name, ex);
  EXPECT_TRUE(directoryEntries(work).empty()) << "flexsens check wrote into the working directory for " << name;
}

INSTANTIATE_TEST_SUITE_P(BadScenes, BadScene, testing::ValuesIn(badSceneFiles()), testName);

TEST(BadScenes, AtLeastEighteenFilesEachWithAnExpectation) {
  const auto files = badSceneFiles();
  EXPECT_GE(files.size(), 18u) << "in " << badSceneDir();
  for (const auto& f : files) {
    Expectation ex;
    EXPECT_TRUE(expectationOf(f, ex));
  }
  for (const auto& [name, ex] : kNoCommentExpectations)
    EXPECT_TRUE(fs::exists(badSceneDir() / name)) << name;
  EXPECT_EQ(fs::file_size(badSceneDir() / "bad_empty.yaml"), 0u) << "bad_empty.yaml must be truly empty";
}

// ------------------------------------------------------------------- command line

const std::string kValidScene = std::string(FLEXSENS_SOURCE_DIR) + "/examples/fivebar/rigid.yaml";

TEST(CliErrors, RunOnNonexistentFileExitsOneNamingTheFile) {
  Scratch s("nonexistent");
  const fs::path work = s.base / "work", out = s.base / "out";
  fs::create_directories(work);
  const std::string missing = (s.base / "no_such_scene.yaml").string();
  const Invocation r = flexsens("run " + quote(missing) + " --out " + quote(out.string()), work, s.base / "err");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("flexsens: error: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no_such_scene.yaml"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(directoryEntries(work).empty());

  const Invocation c = flexsens("check " + quote(missing), work, s.base / "check.err");
  EXPECT_EQ(c.status, 1) << c.err;
  EXPECT_NE(c.err.find("no_such_scene.yaml"), std::string::npos) << c.err;
}

TEST(CliErrors, InvalidIntegratorOptionExitsOneNamingTheOption) {
  Scratch s("opt_integrator");
  const fs::path work = s.base / "work", out = s.base / "out";
  fs::create_directories(work);
  const Invocation r = flexsens("run " + quote(kValidScene) + " --integrator euler --out " + quote(out.string()),
                                work, s.base / "err");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("--integrator"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("euler"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(directoryEntries(work).empty());
}

TEST(CliErrors, InvalidNewtonOptionExitsOneNamingTheOption) {
  Scratch s("opt_newton");
  const fs::path work = s.base / "work", out = s.base / "out";
  fs::create_directories(work);
  const Invocation r = flexsens("run " + quote(kValidScene) + " --newton quasi --out " + quote(out.string()),
                                work, s.base / "err");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("--newton"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("quasi"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(directoryEntries(work).empty());
}

TEST(CliErrors, NegativeDtOptionExitsOneNamingTheOption) {
  Scratch s("opt_dt");
  const fs::path work = s.base / "work", out = s.base / "out";
  fs::create_directories(work);
  const Invocation r =
      flexsens("run " + quote(kValidScene) + " --dt -1 --out " + quote(out.string()), work, s.base / "err");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("--dt"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(directoryEntries(work).empty());
}

}  // namespace
