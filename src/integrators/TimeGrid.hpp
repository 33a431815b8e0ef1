// Step and frame counts from t_end, dt and frame_interval: checked against each other before
// a run starts (scene reader, command-line overrides) and computed without overflow.
//
// The rule: a fixed-step run ends exactly at t_end, so t_end must be a whole number N of
// steps dt (within round-off, |t_end/dt - N| <= 1e-6), 1 <= N <= 1e9. Fixed-step frames come
// every k = round(frame_interval/dt) >= 1 steps and at t_end; IDAS frames at multiples of
// frame_interval and at t_end; at most 1e6 frames. IDAS' largest step dt, when given, may
// not ask for more than 1e9 steps.
#pragma once

#include <optional>
#include <string>

#include "integrators/Settings.hpp"

namespace flexsens {

inline constexpr double kMaxSteps = 1e9;   ///< far beyond any run here (the satellite: 5e2)
inline constexpr double kMaxFrames = 1e6;  ///< each frame is a CSV row and a VTK file

/// What is wrong with the times: the settings key ("t_end", "dt", "frame_interval") and why.
struct TimeProblem {
  std::string key, message;
};

/// Checks t_end, dt and frame_interval of `s` against each other (the rule above).
std::optional<TimeProblem> checkTimes(const IntegratorSettings& s);
/// Number of fixed steps h covering `span` exactly (the rule above; InputError otherwise).
long fixedStepCount(double span, double h);
/// Fixed-step integrators: a frame every this many steps (and at the end).
long frameEvery(const IntegratorSettings& s);
/// Time between frames as they land: k dt for the fixed-step integrators, frame_interval for
/// IDAS (the last frame at t_end in both cases).
double frameSpacing(const IntegratorSettings& s);
/// IDAS: output times after the start (multiples of `interval` below `span`, then `span`).
long outputCount(double span, double interval);

}  // namespace flexsens
