#include "app/SweepPlan.hpp"

#include <cmath>
#include <cstdlib>
#include <random>
#include <set>

#include "core/Types.hpp"

namespace flexsens {

namespace {

const char* kForms =
    "expected NAME=VALUE (fixed), NAME=LOW:HIGH:COUNT (a grid axis) or NAME=LOW:HIGH (a Latin-hypercube range, "
    "with --samples)";

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts(1);
  for (char c : s) {
    if (c == sep) parts.emplace_back();
    else parts.back() += c;
  }
  return parts;
}

double finiteNumber(const std::string& text, const std::string& spec) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end || !std::isfinite(v))
    throw InputError("option --parameter '" + spec + "': '" + text + "' is not a finite number; " + kForms);
  return v;
}

int wholeCount(const std::string& text, const std::string& spec) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end || v < 1 || v > kMaxSweepSamples)
    throw InputError("option --parameter '" + spec + "': COUNT must be a whole number from 1 to " +
                     std::to_string(kMaxSweepSamples) + ", got '" + text + "'");
  return static_cast<int>(v);
}

/// Grid points (one index per parameter) in order: the first parameter varies slowest.
std::vector<std::vector<double>> gridPoints(const std::vector<ParameterRange>& ranges) {
  std::vector<std::vector<double>> points(1);
  for (const ParameterRange& r : ranges) {
    std::vector<std::vector<double>> next;
    for (const auto& p : points)
      for (int i = 0; i < r.count; ++i) {
        next.push_back(p);
        next.back().push_back(gridValue(r, i));
      }
    points = std::move(next);
  }
  return points;
}

/// Latin-hypercube points: fixed parameters keep their value, the others take their turn
/// of the unit hypercube's dimensions.
std::vector<std::vector<double>> hypercubePoints(const SweepDesign& d) {
  int dims = 0;
  for (const ParameterRange& r : d.ranges) dims += r.swept();
  const auto unit = latinHypercube(d.samples, dims, d.seed);
  std::vector<std::vector<double>> points;
  for (const auto& u : unit) {
    std::vector<double> p;
    int k = 0;
    for (const ParameterRange& r : d.ranges) p.push_back(r.fixed() ? r.low : r.low + (r.high - r.low) * u[k++]);
    points.push_back(p);
  }
  return points;
}

}  // namespace

ParameterRange parseParameterRange(const std::string& spec) {
  const size_t eq = spec.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError("option --parameter: " + std::string(kForms) + ", got '" + spec + "'");
  ParameterRange r;
  r.name = spec.substr(0, eq);
  const std::vector<std::string> parts = split(spec.substr(eq + 1), ':');
  if (parts.size() > 3) throw InputError("option --parameter '" + spec + "': " + kForms);
  r.low = finiteNumber(parts[0], spec);
  r.high = parts.size() > 1 ? finiteNumber(parts[1], spec) : r.low;
  r.count = parts.size() == 3 ? wholeCount(parts[2], spec) : parts.size() == 1 ? 1 : 0;
  if (r.count == 1 && r.low != r.high)
    throw InputError("option --parameter '" + spec + "': COUNT 1 is one value; give it as NAME=VALUE");
  if (r.count != 1 && !(r.low < r.high))
    throw InputError("option --parameter '" + spec + "': expected LOW < HIGH");
  return r;
}

void checkDesign(const SweepDesign& d) {
  std::set<std::string> names;
  const ParameterRange *grid = nullptr, *cube = nullptr;
  for (const ParameterRange& r : d.ranges) {
    if (!names.insert(r.name).second) throw InputError("option --parameter: '" + r.name + "' is given twice");
    if (r.grid() && !grid) grid = &r;
    if (r.count == 0 && !cube) cube = &r;
  }
  if (!grid && !cube)
    throw InputError("option --parameter: give at least one parameter to sweep, NAME=LOW:HIGH:COUNT (a grid) or "
                     "NAME=LOW:HIGH with --samples N (a Latin hypercube)");
  if (grid && cube)
    throw InputError("option --parameter: '" + grid->name + "' is a grid axis (LOW:HIGH:COUNT) and '" + cube->name +
                     "' a Latin-hypercube range (LOW:HIGH); a sweep is one or the other");
  if (cube && d.samples < 1)
    throw InputError("option --samples: the Latin-hypercube ranges (NAME=LOW:HIGH) need the number of samples, "
                     "e.g. --samples 40");
  if (grid && d.samples > 0)
    throw InputError("option --samples: a grid (NAME=LOW:HIGH:COUNT) has its COUNT values per parameter; --samples "
                     "is for Latin-hypercube ranges NAME=LOW:HIGH");
  if (grid && d.seedGiven) throw InputError("option --seed: a grid has no randomness; --seed is for --samples");
  double points = cube ? d.samples : 1.0;
  for (const ParameterRange& r : d.ranges) points *= grid ? r.count : 1;
  if (points * static_cast<double>(d.cases.size()) > kMaxSweepSamples)
    throw InputError("option --parameter: the sweep would run " + std::to_string(static_cast<long long>(points)) +
                     " points x " + std::to_string(d.cases.size()) + " cases; at most " +
                     std::to_string(kMaxSweepSamples) + " samples");
}

std::vector<Sample> planSamples(const SweepDesign& d) {
  checkDesign(d);
  const auto points = d.samples > 0 ? hypercubePoints(d) : gridPoints(d.ranges);
  std::vector<Sample> samples;
  for (const auto& p : points)
    for (const auto& c : d.cases) {
      Sample s;
      s.index = static_cast<int>(samples.size());
      for (size_t k = 0; k < d.ranges.size(); ++k) s.values[d.ranges[k].name] = p[k];
      s.caseName = c;
      samples.push_back(s);
    }
  return samples;
}

std::vector<std::vector<double>> latinHypercube(int n, int dims, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  // 53 random bits in [0, 1): not std::uniform_real_distribution, whose algorithm the
  // standard leaves to the library.
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  std::vector<std::vector<double>> points(n, std::vector<double>(dims));
  for (int k = 0; k < dims; ++k) {
    std::vector<int> stratum(n);
    for (int i = 0; i < n; ++i) stratum[i] = i;
    for (int i = n - 1; i > 0; --i) std::swap(stratum[i], stratum[rng() % static_cast<std::uint64_t>(i + 1)]);
    for (int i = 0; i < n; ++i) points[i][k] = (stratum[i] + uniform()) / n;
  }
  return points;
}

double gridValue(const ParameterRange& r, int i) {
  if (r.count <= 1) return r.low;
  if (i == r.count - 1) return r.high;
  return r.low + (r.high - r.low) * i / (r.count - 1);
}

}  // namespace flexsens
