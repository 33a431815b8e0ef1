// ParaView rendering of a run's VTK series (scripts/render-frames.sh -> pvbatch ->
// scripts/render_frames.py): PNG count, size and content, and the error exits. Skipped, with the
// reason in the CTest output, when ParaView is not installed (scripts/install-paraview.sh).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "TestModels.hpp"

using namespace flexsens::test;
namespace fs = std::filesystem;

namespace {

std::string quote(const std::string& s) { return "'" + s + "'"; }

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int exitCode(const std::string& cmd) {
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128;
}

std::string renderScript() { return sourceDir() + "/scripts/render-frames.sh"; }

bool paraviewInstalled() { return exitCode("bash " + quote(renderScript()) + " --check > /dev/null 2>&1") == 0; }

#define SKIP_WITHOUT_PARAVIEW()                                                                       \
  if (!paraviewInstalled())                                                                          \
  GTEST_SKIP() << "ParaView (pvbatch) is not installed: run scripts/install-paraview.sh"

/// A fresh, empty scratch directory removed at the end of the test.
struct Scratch {
  fs::path dir;
  explicit Scratch(const std::string& tag)
      : dir(fs::temp_directory_path() / ("flexsens_paraview_" + tag + "_" + std::to_string(::getpid()))) {
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
};

/// Width and height from a PNG's IHDR chunk (bytes 16-23, big-endian); {0, 0} if not a PNG.
std::pair<std::uint32_t, std::uint32_t> pngSize(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  unsigned char h[24] = {};
  in.read(reinterpret_cast<char*>(h), 24);
  const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (!in || !std::equal(sig, sig + 8, h) || std::string(reinterpret_cast<char*>(h + 12), 4) != "IHDR") return {0, 0};
  auto be = [&](int o) {
    return (std::uint32_t(h[o]) << 24) | (std::uint32_t(h[o + 1]) << 16) | (std::uint32_t(h[o + 2]) << 8) | h[o + 3];
  };
  return {be(16), be(20)};
}

std::vector<fs::path> filesMatching(const fs::path& dir, const std::string& prefix, const std::string& ext) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && e.path().extension() == ext) out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST(Paraview, RendersEveryNthFrameOfARunAsNonBlankPngs) {
  SKIP_WITHOUT_PARAVIEW();
  Scratch tmp("render");
  // A short planar run: frames every 0.01 s, t = 0 ... 0.1 -> 11 frames.
  const fs::path runDir = tmp.dir / "run" / "R1";
  ASSERT_EQ(exitCode(quote(FLEXSENS_EXE) + " run " + quote(sourceDir() + "/examples/fivebar/rigid.yaml") +
                     " --case R1 --t-end 0.1 --out " + quote((tmp.dir / "run").string()) + " > " +
                     quote((tmp.dir / "run.log").string()) + " 2>&1"),
            0)
      << slurp(tmp.dir / "run.log");
  const std::size_t frames = filesMatching(runDir, "frame_", ".vtu").size();
  ASSERT_EQ(frames, 11u);

  const fs::path png = tmp.dir / "png";
  const fs::path log = tmp.dir / "render.log";
  const int rc = exitCode("bash " + quote(renderScript()) + " " + quote(runDir.string()) + " " +
                          quote(png.string()) + " L_A1 --every 2 --size 320x240 > " + quote(log.string()) +
                          " 2>&1");
  ASSERT_EQ(rc, 0) << slurp(log);
  EXPECT_NE(slurp(log).find(png.string()), std::string::npos) << "prints where the PNGs are:\n" << slurp(log);

  // Frames 0, 2, ..., 10 -> frame_00000.png ... frame_00005.png, each 320x240.
  const auto pngs = filesMatching(png, "frame_", ".png");
  ASSERT_EQ(pngs.size(), (frames + 1) / 2) << slurp(log);
  for (std::size_t k = 0; k < pngs.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05zu.png", k);
    EXPECT_EQ(pngs[k].filename().string(), name);
    const auto [w, h] = pngSize(pngs[k]);
    EXPECT_EQ(w, 320u) << pngs[k];
    EXPECT_EQ(h, 240u) << pngs[k];
  }

  // Content (decoded by matplotlib, from Debian's python3): many colours (mechanism coloured
  // by the colour map, colour bar, text), a visible share of non-background pixels, and the
  // first and last frames differ (the mechanism moves, the time text changes).
  const fs::path stats = tmp.dir / "stats.txt";
  const std::string py =
      "import sys, numpy as np, matplotlib.image as mi\n"
      "a = mi.imread(sys.argv[1])[..., :3]; b = mi.imread(sys.argv[2])[..., :3]\n"
      "colours = len(np.unique((a * 255).round().astype(np.uint8).reshape(-1, 3), axis=0))\n"
      "bg = a[0, a.shape[1] // 2]\n"
      "ink = float(np.mean(np.any(np.abs(a - bg) > 0.05, axis=2)))\n"
      "diff = float(np.mean(np.any(np.abs(a - b) > 0.02, axis=2)))\n"
      "print(colours, ink, diff)\n";
  std::ofstream(tmp.dir / "stats.py") << py;
  ASSERT_EQ(exitCode("/usr/bin/python3 " + quote((tmp.dir / "stats.py").string()) + " " +
                     quote(pngs.front().string()) + " " + quote(pngs.back().string()) + " > " +
                     quote(stats.string()) + " 2>&1"),
            0)
      << slurp(stats);
  std::istringstream in(slurp(stats));
  int colours = 0;
  double ink = 0, diff = 0;
  ASSERT_TRUE(in >> colours >> ink >> diff) << slurp(stats);
  EXPECT_GT(colours, 20) << "image is (nearly) a single colour";
  EXPECT_GT(ink, 0.005) << "almost nothing drawn on the background";
  EXPECT_LT(ink, 0.9) << "no background left";
  EXPECT_GT(diff, 0.0005) << "first and last frames are the same picture";
}

TEST(Paraview, ReportsMissingSeriesAndSensitivitiesWithExitCode1) {
  SKIP_WITHOUT_PARAVIEW();
  Scratch tmp("errors");
  const fs::path log = tmp.dir / "log";
  auto render = [&](const fs::path& runDir, const std::string& extra = "") {
    return exitCode("bash " + quote(renderScript()) + " " + quote(runDir.string()) + " " +
                    quote((tmp.dir / "png").string()) + extra + " > " + quote(log.string()) + " 2>&1");
  };
  // No frames.pvd.
  EXPECT_EQ(render(tmp.dir), 1);
  EXPECT_NE(slurp(log).find("no frames.pvd"), std::string::npos) << slurp(log);

  // A run without design parameters has no dq/d* arrays.
  std::ofstream(tmp.dir / "pendulum.yaml") << R"(dimension: 2
plane: xz
gravity: [0, -9.81]
nodes:
  - {name: A, position: [0, 0], ground: true}
  - {name: n1, position: [1, 0]}
elements:
  - {name: bar, type: rigid_bar, nodes: [A, n1], mass: 1.0}
integrator: {type: trapezoidal, t_end: 0.02, dt: 1.0e-3, frame_interval: 0.01}
)";
  const fs::path run = tmp.dir / "run";
  ASSERT_EQ(exitCode(quote(FLEXSENS_EXE) + " run " + quote((tmp.dir / "pendulum.yaml").string()) + " --out " +
                     quote(run.string()) + " > " + quote(log.string()) + " 2>&1"),
            0)
      << slurp(log);
  ASSERT_TRUE(fs::exists(run / "frames.pvd"));
  EXPECT_EQ(render(run), 1);
  EXPECT_NE(slurp(log).find("no dq/d<param> point arrays"), std::string::npos) << slurp(log);
  EXPECT_FALSE(fs::exists(tmp.dir / "png" / "frame_00000.png"));
}

// Meshed bodies are drawn as surfaces in the field's colours (element_kind 5 and 8 cells through
// a threshold: the tube filter draws lines only, so before they showed as their nodes alone):
// a grounded shell plate sagging under gravity, seen obliquely, must cover a visible share of
// the picture left of the colour bar with saturated (colour-map) pixels; the grey cell edges,
// the axes and the text are not saturated. The run directory gets the ParaView state view.pvsm.
TEST(Paraview, DrawsMeshedBodiesAsSurfacesColouredByTheField) {
  SKIP_WITHOUT_PARAVIEW();
  Scratch tmp("mesh");
  const fs::path scene = tmp.dir / "plate.yaml";
  std::ofstream(scene) << "dimension: 3\ngravity: [0, 0, -9.81]\nelements:\n"
                          "  - {name: plate, type: shell, mesh: " << sourceDir()
                       << "/tests/scenes/shell/square.geo, group: plate, size: 0.25, E: 2.1e11, nu: 0.3,"
                          " density: 7800, thickness: 0.002, ground: [edges]}\n"
                          "parameters:\n  - {name: t, of: plate, property: thickness}\n"
                          "integrator: {type: trapezoidal, t_end: 0.02, dt: 0.002, frame_interval: 0.01}\n";
  const fs::path runDir = tmp.dir / "run";
  ASSERT_EQ(exitCode(quote(FLEXSENS_EXE) + " run " + quote(scene.string()) + " --allow-path " + quote(sourceDir()) +
                     " --out " + quote(runDir.string()) + " > " + quote((tmp.dir / "run.log").string()) + " 2>&1"),
            0)
      << slurp(tmp.dir / "run.log");
  const fs::path png = tmp.dir / "png";
  const fs::path log = tmp.dir / "render.log";
  ASSERT_EQ(exitCode("bash " + quote(renderScript()) + " " + quote(runDir.string()) + " " + quote(png.string()) +
                     " t --size 640x360 > " + quote(log.string()) + " 2>&1"),
            0)
      << slurp(log);
  const auto pngs = filesMatching(png, "frame_", ".png");
  ASSERT_EQ(pngs.size(), 3u) << slurp(log);
  EXPECT_TRUE(fs::exists(runDir / "view.pvsm"));
  const fs::path stats = tmp.dir / "stats.txt";
  std::ofstream(tmp.dir / "stats.py") << "import sys, numpy as np, matplotlib.image as mi\n"
                                         "a = mi.imread(sys.argv[1])[..., :3]\n"
                                         "a = a[:, : int(0.8 * a.shape[1])]  # left of the colour bar\n"
                                         "print(float(np.mean(a.max(axis=2) - a.min(axis=2) > 0.15)))\n";
  ASSERT_EQ(exitCode("/usr/bin/python3 " + quote((tmp.dir / "stats.py").string()) + " " +
                     quote(pngs.back().string()) + " > " + quote(stats.string()) + " 2>&1"),
            0)
      << slurp(stats);
  double coloured = 0.0;
  std::istringstream in(slurp(stats));
  ASSERT_TRUE(in >> coloured) << slurp(stats);
  std::printf("share of colour-map pixels left of the colour bar: %.3f\n", coloured);
  EXPECT_GT(coloured, 0.03) << "the plate is not drawn as a coloured surface";
}
