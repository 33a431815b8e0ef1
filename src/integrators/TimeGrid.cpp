#include "integrators/TimeGrid.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "core/Types.hpp"

namespace flexsens {

namespace {

constexpr double kRoundOff = 1e-6;  ///< in steps: t_end/dt carries ~1e-16 N of round-off

std::string num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::optional<TimeProblem> checkSteps(double tEnd, double dt) {
  const double r = tEnd / dt;
  if (!(r <= kMaxSteps))
    return TimeProblem{"dt", "t_end / dt = " + num(r) + " steps (t_end = " + num(tEnd) + " s, dt = " + num(dt) +
                                 " s) exceeds the limit of " + num(kMaxSteps) + " steps; choose a larger dt"};
  if (r < 1.0 - kRoundOff)
    return TimeProblem{"dt", "dt = " + num(dt) + " s is longer than t_end = " + num(tEnd) +
                                 " s; a fixed-step run ends exactly at t_end, so dt must divide t_end"};
  const double n = std::round(r);
  if (std::abs(r - n) > kRoundOff) {
    std::ostringstream os;
    os << "dt = " << dt << " s does not divide t_end = " << tEnd << " s (" << std::setprecision(10) << r
       << " steps); a fixed-step run ends exactly at t_end: choose dt = t_end / N, e.g. "
       << std::setprecision(10) << tEnd / std::floor(r) << " or " << tEnd / std::ceil(r) << " s";
    return TimeProblem{"dt", os.str()};
  }
  return std::nullopt;
}

}  // namespace

std::optional<TimeProblem> checkTimes(const IntegratorSettings& s) {
  if (!(s.tEnd > 0) || !std::isfinite(s.tEnd))
    return TimeProblem{"t_end", "expected a positive finite time in seconds, got " + num(s.tEnd)};
  if (!(s.dt >= 0) || !std::isfinite(s.dt))
    return TimeProblem{"dt", "expected a positive finite step in seconds, got " + num(s.dt)};
  if (!(s.frameInterval > 0) || !std::isfinite(s.frameInterval))
    return TimeProblem{"frame_interval", "expected a positive finite time in seconds, got " + num(s.frameInterval)};
  const bool fixed = s.type != "idas";
  if (fixed && !(s.dt > 0))
    return TimeProblem{"dt", "the " + s.type + " integrator needs a fixed step dt > 0"};
  if (fixed) {
    if (auto p = checkSteps(s.tEnd, s.dt)) return p;
  } else if (s.dt > 0 && !(s.tEnd / s.dt <= kMaxSteps)) {
    return TimeProblem{"dt", "t_end / dt = " + num(s.tEnd / s.dt) + " steps at the largest step dt = " + num(s.dt) +
                                 " s exceeds the limit of " + num(kMaxSteps) + " steps; choose a larger dt"};
  }
  const double frames = s.tEnd / (fixed ? std::max(s.frameInterval, s.dt) : s.frameInterval);
  if (!(frames <= kMaxFrames))
    return TimeProblem{"frame_interval", "t_end / frame_interval = " + num(frames) + " frames (t_end = " +
                                             num(s.tEnd) + " s, frame_interval = " + num(s.frameInterval) +
                                             " s) exceeds the limit of " + num(kMaxFrames) +
                                             " frames; choose a larger frame_interval"};
  return std::nullopt;
}

long fixedStepCount(double span, double h) {
  if (!(h > 0) || !(span > 0)) throw InputError("fixed step: need t_end > t0 and dt > 0, got span " + num(span) + " s, dt " + num(h) + " s");
  if (auto p = checkSteps(span, h)) throw InputError("integrator." + p->key + ": " + p->message);
  return std::lround(span / h);
}

long frameEvery(const IntegratorSettings& s) {
  const double k = std::round(s.frameInterval / s.dt);
  return k < 1 ? 1L : (k > kMaxSteps ? static_cast<long>(kMaxSteps) : static_cast<long>(k));
}

double frameSpacing(const IntegratorSettings& s) {
  return s.type == "idas" ? s.frameInterval : frameEvery(s) * s.dt;
}

long outputCount(double span, double interval) {
  const double r = span / interval;
  if (!(r <= kMaxFrames) || !(r > 0)) throw InputError("integrator.frame_interval: " + num(r) + " frames exceed the limit of " + num(kMaxFrames));
  // A last interval shorter than 1e-9 of frame_interval is round-off: t_end takes its place.
  return std::max(1L, static_cast<long>(std::ceil(r - 1e-9)));
}

}  // namespace flexsens
