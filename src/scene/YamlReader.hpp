// Small helpers that read typed values out of yaml-cpp nodes and turn every problem into an
// InputError of the form  "<file>:<line>:<column>: key '<path>': <what was expected>".
#pragma once

#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <optional>
#include <string>

#include "core/Types.hpp"

namespace flexsens {

/// The range a material input can physically take, wide enough for any real material in SI
/// units, narrow enough that what falls outside is a typo or a unit mistake (a density of
/// 5e-324 kg/m^3 gives a mass matrix of denormals the integrators take for "massless").
struct PhysicalRange {
  double low, high;
  const char* unit;
  const char* what;
};
constexpr PhysicalRange kDensityRange{1e-3, 1e6, "kg/m^3", "a density"};        // aerogel ~1, osmium 2.26e4
constexpr PhysicalRange kModulusRange{1e-3, 1e13, "Pa", "a Young's modulus"};   // gels ~1e2, diamond 1.2e12
constexpr PhysicalRange kThicknessRange{1e-9, 1e3, "m", "a thickness"};

class YamlReader {
 public:
  explicit YamlReader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const YAML::Node& at, const std::string& key, const std::string& msg) const;
  /// Unknown keys are errors; the message lists the keys allowed here.
  void allowKeys(const YAML::Node& map, const std::string& path,
                 std::initializer_list<const char*> keys) const;
  void requireMap(const YAML::Node& node, const std::string& path) const;
  void requireList(const YAML::Node& node, const std::string& path) const;
  /// The child `key` of `map`, failing (at the map) if it is missing.
  YAML::Node require(const YAML::Node& map, const std::string& key, const std::string& path) const;

  double number(const YAML::Node& node, const std::string& path) const;  ///< finite number
  double positive(const YAML::Node& node, const std::string& path) const;  ///< > 0
  double nonNegative(const YAML::Node& node, const std::string& path) const;  ///< >= 0
  /// A material input within `range` (file:line, the range and its unit when outside).
  double physical(const YAML::Node& node, const std::string& path, const PhysicalRange& range) const;
  std::string text(const YAML::Node& node, const std::string& path) const;
  bool boolean(const YAML::Node& node, const std::string& path) const;
  int integer(const YAML::Node& node, const std::string& path) const;
  VecX vector(const YAML::Node& node, const std::string& path, int size) const;
  bool isAuto(const YAML::Node& node) const;

 private:
  std::string file_;
};

}  // namespace flexsens
