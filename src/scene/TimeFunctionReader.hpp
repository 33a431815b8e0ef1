// Scene reader of time functions (core/TimeFunction.hpp), shared by loads and drivers.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/TimeFunction.hpp"
#include "scene/SceneContext.hpp"

namespace flexsens {

/// Reads the map `fn` at key path `path`:
///   {type: constant, value} | {type: ramp, slope, start: 0, offset: 0}
///   | {type: smooth_step, t0, t1, from: 0, to} | {type: harmonic, amplitude, omega, phase: 0, offset: 0}
///   | {type: spin_up, omega, duration} | {type: table, file, scale: 1}
/// (a CSV of `t, f` rows beside the scene; '#' comments and one header line allowed). The
/// function's constants become bindable as "<item>.<constant>" (e.g. "motor.amplitude").
/// Parses a CSV of (t, f) rows (strictly increasing finite t, finite f, at least two rows).
/// Errors name shown:line and what was expected (a std::runtime_error whose text the caller
/// prefixes with the scene's key), never the line's text: the file may be one the user did
/// not mean to share.
void parseTimeTable(const std::string& text, const std::string& shown, std::vector<double>& t, std::vector<double>& f);

std::unique_ptr<TimeFunction> readTimeFunction(SceneContext& ctx, const YAML::Node& fn,
                                               const std::string& path, const std::string& item);

}  // namespace flexsens
