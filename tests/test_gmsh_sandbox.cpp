// The Gmsh sandbox (meshes/GmshSandbox, SeccompFilter), the .geo scan (meshes/GeoScan) and
// the file checks before Gmsh (meshes/GeometryFile): hostile inputs end in a clear error that
// names the file and the limit, and nothing they try outside the process happens.
// The hostile files are those of tests/scenes/bad/hostile/ (also used by the bad scenes).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/Interrupt.hpp"
#include "meshes/GeoScan.hpp"
#include "meshes/GeometryFile.hpp"
#include "meshes/GmshMesh.hpp"
#include "meshes/GmshSandbox.hpp"

namespace {

namespace fs = std::filesystem;
using flexsens::GmshLimits;
using flexsens::InputError;
using flexsens::runGmshSandboxed;

fs::path hostile(const std::string& name) { return fs::path(FLEXSENS_SOURCE_DIR) / "tests/scenes/bad/hostile" / name; }

/// A fresh scratch folder, removed at the end.
struct Scratch {
  fs::path dir;
  explicit Scratch(const std::string& name) {
    dir = fs::temp_directory_path() / ("flexsens_sandbox_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = dir / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p;
  }
};

template <class F> std::string inputErrorOf(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

GmshLimits limits(double cpu, double mb = 2048) {
  GmshLimits l;
  l.cpuSeconds = cpu;
  l.memoryMb = mb;
  return l;
}

// --- the child process ----------------------------------------------------------------------

TEST(GmshSandbox, ReturnsTheChildsResultAndItsErrors) {
  EXPECT_EQ(runGmshSandboxed("f.geo", limits(2), "w", [] { return std::string("mesh\0bytes", 10); }),
            std::string("mesh\0bytes", 10));
  const std::string msg = inputErrorOf([] {
    runGmshSandboxed("f.geo", limits(2), "w", []() -> std::string { throw InputError("s.yaml:3:4: key 'k': bad group"); });
  });
  EXPECT_EQ(msg, "s.yaml:3:4: key 'k': bad group");
  EXPECT_THROW(runGmshSandboxed("f.geo", limits(2), "w", []() -> std::string { throw std::logic_error("bug"); }),
               std::logic_error);
}

TEST(GmshSandbox, StartingAProgramIsStoppedAndRunsNothing) {
  Scratch s("exec");
  const fs::path marker = s.dir / "marker.txt";
  const std::string msg = inputErrorOf([&] {
    runGmshSandboxed("x.geo", limits(2), "s.yaml:1:1: key 'elements[0].mesh'", [&] {
      std::system(("echo RAN > " + marker.string()).c_str());
      return std::string("returned");
    });
  });
  EXPECT_TRUE(has(msg, "s.yaml:1:1: key 'elements[0].mesh': Gmsh on 'x.geo': stopped at a forbidden operation")) << msg;
  EXPECT_TRUE(has(msg, "starting a program")) << msg;
  EXPECT_FALSE(fs::exists(marker));
}

TEST(GmshSandbox, OpeningAFileForWritingIsStopped) {
  Scratch s("write");
  const fs::path marker = s.dir / "marker.txt";
  const std::string msg = inputErrorOf([&] {
    runGmshSandboxed("x.geo", limits(2), "w", [&] {
      if (std::FILE* f = std::fopen(marker.c_str(), "a")) std::fclose(f);
      return std::string("returned");
    });
  });
  EXPECT_TRUE(has(msg, "opening a file for writing")) << msg;
  EXPECT_FALSE(fs::exists(marker));
  // Reading stays allowed: Gmsh must read its .geo and includes.
  EXPECT_EQ(runGmshSandboxed("x.geo", limits(2), "w", [] {
              std::ifstream in(hostile("panel.geo"));
              std::string first;
              std::getline(in, first);
              return first.substr(0, 2);
            }),
            "//");
}

TEST(GmshSandbox, EndlessLoopStopsAtTheCpuLimitNamingTheKey) {
  const std::string msg = inputErrorOf([] {
    runGmshSandboxed("loop.geo", limits(1), "w", [] {
      volatile unsigned long spin = 0;
      while (true) spin = spin + 1;
      return std::string();
    });
  });
  EXPECT_TRUE(has(msg, "Gmsh on 'loop.geo': stopped at the CPU-time limit of 1 s")) << msg;
  EXPECT_TRUE(has(msg, "limits.gmsh_cpu_s")) << msg;
}

// Under AddressSanitizer a failed operator new is ASan's fatal report, not std::bad_alloc.
#if defined(__SANITIZE_ADDRESS__)
#define SKIP_UNDER_ASAN() GTEST_SKIP() << "ASan reports a failed allocation itself"
#else
#define SKIP_UNDER_ASAN() (void)0
#endif

TEST(GmshSandbox, HugeAllocationStopsAtTheMemoryLimitNamingTheKey) {
  SKIP_UNDER_ASAN();
  const std::string msg = inputErrorOf([] {
    runGmshSandboxed("big.geo", limits(2, 256), "w", [] {
      std::vector<char> v(std::size_t(80) << 30, 'x');  // 80 GiB
      return std::string(1, v.back());
    });
  });
  EXPECT_TRUE(has(msg, "Gmsh on 'big.geo': stopped at the memory limit of 256 MB")) << msg;
  EXPECT_TRUE(has(msg, "limits.gmsh_memory_mb")) << msg;
}

TEST(GmshSandbox, ExitWithoutResultIsAnError) {
  const std::string msg = inputErrorOf([] {
    runGmshSandboxed("exit.geo", limits(2), "w", []() -> std::string { std::exit(0); });
  });
  EXPECT_TRUE(has(msg, "without a result")) << msg;
}

TEST(GmshSandbox, InterruptOfTheParentKillsTheChild) {
  flexsens::requestInterrupt(SIGTERM);
  // Without the kill this would end at the CPU limit with an InputError instead.
  EXPECT_THROW(runGmshSandboxed("loop.geo", limits(30), "w",
                                [] {
                                  volatile unsigned long spin = 0;
                                  while (true) spin = spin + 1;
                                  return std::string();
                                }),
               flexsens::InterruptedBeforeRun);
  flexsens::clearInterrupt();
}

// --- meshBody on the hostile files ----------------------------------------------------------

std::string meshError(const std::string& file, double cpu = 2, double mb = 512) {
  flexsens::BodyMeshRequest req;
  req.file = hostile(file).string();
  req.group = file == "huge_nodes.msh" ? "sheet" : "panel";
  req.size = 0.05;
  if (file.size() > 4 && file.substr(file.size() - 4) == ".msh") req.size = 0;
  req.groupWhere = req.sizeWhere = "s.yaml:2:3: key 'g'";
  req.gmsh.limits = limits(cpu, mb);
  return inputErrorOf([&] { flexsens::meshBody(req, "s.yaml:1:2: key 'elements[0].mesh'"); });
}

TEST(GmshHostile, EndlessForLoopEndsAtTheCpuLimit) {
  const std::string msg = meshError("endless_loop.geo", 1);
  EXPECT_TRUE(has(msg, "s.yaml:1:2: key 'elements[0].mesh': Gmsh on '")) << msg;
  EXPECT_TRUE(has(msg, "endless_loop.geo': stopped at the CPU-time limit of 1 s")) << msg;
}

TEST(GmshHostile, EightyGigabyteListEndsAtTheMemoryLimit) {
  SKIP_UNDER_ASAN();
  const std::string msg = meshError("big_array.geo", 5, 256);
  EXPECT_TRUE(has(msg, "big_array.geo'")) << msg;
  EXPECT_TRUE(has(msg, "memory limit of 256 MB")) << msg;
}

TEST(GmshHostile, MeshingInsideTheGeoEndsAtALimit) {
  const std::string msg = meshError("mesh_bomb.geo", 1, 256);
  EXPECT_TRUE(has(msg, "mesh_bomb.geo'")) << msg;
  EXPECT_TRUE(has(msg, "CPU-time limit of 1 s") || has(msg, "memory limit of 256 MB")) << msg;
}

TEST(GmshHostile, HeaderClaimingTwoBillionNodesIsRefusedWithItsLine) {
  // The counts "2 2000000000 1 2000000000" follow $Nodes on line 15 ($Elements: line 28).
  const std::string msg = meshError("huge_nodes.msh");
  EXPECT_TRUE(has(msg, "huge_nodes.msh' line 15: $Nodes claims 2e+09 nodes in a file of 336 bytes")) << msg;
  const std::string el = meshError("huge_elems.msh");
  EXPECT_TRUE(has(el, "huge_elems.msh' line 28: $Elements claims 2e+09 elements")) << el;
}

TEST(GmshHostile, ProcPseudoFileIsRefused) {
  const std::string msg = inputErrorOf([] { flexsens::readGeometryFile("/proc/self/pagemap", "mesh file", "w"); });
  EXPECT_TRUE(has(msg, "w: the mesh file '/proc/self/pagemap' holds more than the 0 bytes its size says")) << msg;
  EXPECT_TRUE(has(inputErrorOf([] { flexsens::readGeometryFile("/dev/zero", "mesh file", "w"); }), "not a regular file"));
}

// --- the scan -------------------------------------------------------------------------------

std::string scanError(const fs::path& file, const fs::path& root) {
  return inputErrorOf([&] { flexsens::scanGeoFile(file.string(), {root.string()}, "w"); });
}

TEST(GeoScan, RefusesCommandsThatReachOutsideWithFileAndLine) {
  const fs::path root = hostile("");
  EXPECT_TRUE(has(scanError(hostile("systemcall.geo"), root), "systemcall.geo:2: SystemCall runs a shell command"));
  EXPECT_TRUE(has(scanError(hostile("printf_redirect.geo"), root), "printf_redirect.geo:3: Printf > writes to a file"));
  EXPECT_TRUE(has(scanError(hostile("include_dev_zero.geo"), root),
                  "include_dev_zero.geo:3: Include \"/dev/zero\" names a file outside the scene's folder"));
  EXPECT_TRUE(has(scanError(hostile("exit.geo"), root), "exit.geo:3: Exit ends Gmsh"));
}

TEST(GeoScan, LooksIntoIncludesAndIgnoresCommentsStringsAndOptionNames) {
  Scratch s("scan");
  s.write("sub/part.geo", "Point(1) = {0, 0, 0};\n");
  const fs::path ok = s.write("ok.geo",
                              "// SystemCall \"id\" in a comment\n/* Save \"x.msh\";\n Exit; */\n"
                              "Include \"sub/part.geo\";\nPrint.Width = 3; General.Terminal = 0;\n"
                              "Printf(\"a > b %g\", 1);\nname = \"Save\";\n");
  EXPECT_NO_THROW(flexsens::scanGeoFile(ok.string(), {s.dir.string()}, "w"));
  s.write("sub/evil.geo", "x = 1;\n\nSystemCall 'id';\n");
  const fs::path nested = s.write("nested.geo", "Include \"sub/evil.geo\";\n");
  EXPECT_TRUE(has(scanError(nested, s.dir), "evil.geo:3: SystemCall")) << scanError(nested, s.dir);
  const fs::path up = s.write("sub/up.geo", "Include \"../../outside.geo\";\n");
  EXPECT_TRUE(has(scanError(up, s.dir), "up.geo:1: Include \"../../outside.geo\" names a file outside"));
  const fs::path computed = s.write("computed.geo", "Include StrCat(\"/dev/\", \"zero\");\n");
  EXPECT_TRUE(has(scanError(computed, s.dir), "computed.geo:1: Include takes a file name built at run time"));
  const fs::path append = s.write("append.geo", "Printf(\"%g\", 1) >> \"log.txt\";\n");
  EXPECT_TRUE(has(scanError(append, s.dir), "append.geo:1: Printf >> writes to a file"));
}

// --- end to end: a shared scene never acts ---------------------------------------------------

TEST(GmshHostile, CheckOfASceneWithSystemCallAndPrintfWritesNoMarker) {
  Scratch s("marker");
  for (const char* f : {"panel.geo", "systemcall.geo", "printf_redirect.geo", "curves_systemcall.geo"})
    fs::copy_file(hostile(f), s.dir / f);
  const std::string shell = "dimension: 3\nelements:\n  - {name: p, type: shell, mesh: MESH, group: panel, size: 0.05,"
                            " E: 4.0e9, nu: 0.38, density: 1380, thickness: 0.0005, ground: [hinge]}\n"
                            "integrator: {type: trapezoidal, t_end: 0.004, dt: 0.001}\n";
  for (const char* geo : {"systemcall.geo", "printf_redirect.geo"}) {
    std::string text = shell;
    text.replace(text.find("MESH"), 4, geo);
    s.write(std::string("scene_") + geo + ".yaml", text);
  }
  s.write("beams.yaml", "dimension: 3\ngeometry: {gmsh: curves_systemcall.geo}\nelements:\n"
                        "  - {name: rod, type: beam, curve: rod, segments: 4, E: 1.0e9, density: 1000, section: {side: 0.01}}\n"
                        "integrator: {type: trapezoidal, t_end: 0.004, dt: 0.001}\n");
  for (const char* scene : {"scene_systemcall.geo.yaml", "scene_printf_redirect.geo.yaml", "beams.yaml"}) {
    const std::string cmd = "cd '" + s.dir.string() + "' && '" + FLEXSENS_EXE + "' check " + scene + " >/dev/null 2>&1";
    const int st = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(st)) << scene;
    EXPECT_EQ(WEXITSTATUS(st), 1) << scene;
  }
  for (const char* marker : {"syscall_marker.txt", "printf_marker.txt", "geometry_marker.txt"})
    EXPECT_FALSE(fs::exists(s.dir / marker)) << marker;
}

}  // namespace
