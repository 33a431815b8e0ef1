// The PNG plots of a result folder, drawn by a script of scripts/ beside the build
// (build/flexsens -> scripts/<name>) with Debian's python3 and matplotlib.
#pragma once

#include <string>

namespace flexsens {

/// Runs `python3 scripts/<script> <folder>`: "" when drawn, else why not (the script missing
/// beside the build, python3 not started, the script failed: python3-matplotlib missing?).
std::string drawPlotScript(const std::string& script, const std::string& folder);

}  // namespace flexsens
