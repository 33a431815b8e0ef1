// The samples of `flexsens sweep`: a grid or a Latin hypercube over scene parameters, each
// point run for every requested PIM case, in sample order. Pure: the same samples on every
// rank and machine for the same options.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene/Scene.hpp"

namespace flexsens {

constexpr int kMaxSweepSamples = 1000000;  ///< points x cases: one table row each

/// One --parameter: NAME=VALUE (fixed), NAME=LOW:HIGH:COUNT (a grid axis: COUNT equally spaced
/// values from LOW to HIGH) or NAME=LOW:HIGH (the bounds of a Latin hypercube).
struct ParameterRange {
  std::string name;
  double low = 0.0, high = 0.0;
  int count = 0;  ///< grid values; 1: fixed at low; 0: Latin-hypercube bounds
  bool fixed() const { return count == 1; }
  bool grid() const { return count > 1; }
  bool swept() const { return count != 1; }
};

/// Parses one --parameter; InputError naming the option, the text and the forms expected.
ParameterRange parseParameterRange(const std::string& spec);

struct SweepDesign {
  std::vector<ParameterRange> ranges;
  int samples = 0;                 ///< Latin hypercube: points (--samples); 0: a grid
  std::uint64_t seed = 1;          ///< Latin hypercube: --seed
  bool seedGiven = false;
  std::vector<std::string> cases;  ///< PIM cases in order; {""} for a scene without cases
};

/// One run of the sweep.
struct Sample {
  int index = 0;
  ParameterValues values;  ///< the value of every --parameter
  std::string caseName;    ///< "" for a scene without cases
};

/// InputError naming the option unless the design is a grid or a Latin hypercube (not both)
/// with at least one swept parameter, each named once, and at most kMaxSweepSamples samples.
void checkDesign(const SweepDesign& d);
/// The samples in order: points (grid: the first parameter varies slowest; Latin hypercube:
/// as drawn), each point with every case in turn (index = point * cases + case).
std::vector<Sample> planSamples(const SweepDesign& d);
/// n points in [0, 1)^dims: each dimension's n strata [i/n, (i+1)/n) used once, a uniform
/// point inside each, strata paired by seeded permutations (std::mt19937_64, whose sequence
/// the C++ standard fixes: the same points everywhere). Drawn per dimension: a permutation,
/// then the n offsets.
std::vector<std::vector<double>> latinHypercube(int n, int dims, std::uint64_t seed);
/// Grid value i of r.count from r.low to r.high (the last exactly r.high).
double gridValue(const ParameterRange& r, int i);

}  // namespace flexsens
