#include "scene/YamlReader.hpp"

#include <cmath>
#include <set>
#include <sstream>

namespace flexsens {

void YamlReader::fail(const YAML::Node& at, const std::string& key, const std::string& msg) const {
  std::ostringstream os;
  const YAML::Mark mk = at.Mark();
  os << file_;
  if (mk.line >= 0) os << ":" << mk.line + 1 << ":" << mk.column + 1;
  os << ": key '" << (key.empty() ? "(top level)" : key) << "': " << msg;
  throw InputError(os.str());
}

void YamlReader::requireMap(const YAML::Node& node, const std::string& path) const {
  if (!node.IsMap()) fail(node, path, "expected a mapping (key: value pairs)");
}

void YamlReader::requireList(const YAML::Node& node, const std::string& path) const {
  if (!node.IsSequence()) fail(node, path, "expected a list");
}

void YamlReader::allowKeys(const YAML::Node& map, const std::string& path,
                           std::initializer_list<const char*> keys) const {
  requireMap(map, path);
  const std::set<std::string> allowed(keys.begin(), keys.end());
  std::set<std::string> seen;
  for (const auto& kv : map) {
    // A list or mapping as a key (`[a, b]: 1`, `? {x: 1}`) is legal YAML but no key of ours.
    if (!kv.first.IsScalar())
      fail(kv.first, path, std::string("a key must be a plain name, got a ") + (kv.first.IsMap() ? "mapping" : "list"));
    const std::string k = kv.first.Scalar();
    if (!seen.insert(k).second)
      fail(kv.first, path.empty() ? k : path + "." + k, "repeated key; give each key once");
    if (allowed.count(k)) continue;
    std::string list;
    for (const auto& a : keys) list += (list.empty() ? "" : ", ") + std::string(a);
    fail(kv.first, path.empty() ? k : path + "." + k, "unknown key; expected one of: " + list);
  }
}

YAML::Node YamlReader::require(const YAML::Node& map, const std::string& key,
                               const std::string& path) const {
  const YAML::Node n = map[key];
  if (!n) fail(map, path.empty() ? key : path + "." + key, "missing; this key is required here");
  return n;
}

double YamlReader::number(const YAML::Node& node, const std::string& path) const {
  double v = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, v))
    fail(node, path, "expected a number, got '" + (node.IsScalar() ? node.Scalar() : std::string("a ") +
                                                       (node.IsMap() ? "mapping" : "list")) + "'");
  if (!std::isfinite(v)) fail(node, path, "expected a finite number, got '" + node.Scalar() + "'");
  // A subnormal (0 < |v| < 2.2e-308) is no physical quantity; it keeps only a few bits, and
  // scaling it by a relative step or a small factor gives 0 (then 0/0 in a derivative).
  if (v != 0 && !std::isnormal(v))
    fail(node, path, "expected 0 or a number of magnitude at least 2.2e-308 (a normal double), got " + node.Scalar());
  return v;
}

double YamlReader::physical(const YAML::Node& node, const std::string& path, const PhysicalRange& range) const {
  const double v = number(node, path);
  if (!(v >= range.low && v <= range.high)) {
    std::ostringstream os;
    os << "expected " << range.what << " between " << range.low << " and " << range.high << " " << range.unit
       << ", got " << node.Scalar();
    fail(node, path, os.str());
  }
  return v;
}

double YamlReader::positive(const YAML::Node& node, const std::string& path) const {
  const double v = number(node, path);
  if (!(v > 0)) fail(node, path, "expected a positive number, got " + node.Scalar());
  return v;
}

double YamlReader::nonNegative(const YAML::Node& node, const std::string& path) const {
  const double v = number(node, path);
  if (v < 0) fail(node, path, "expected a number >= 0, got " + node.Scalar());
  return v;
}

std::string YamlReader::text(const YAML::Node& node, const std::string& path) const {
  if (!node.IsScalar() || node.Scalar().empty()) fail(node, path, "expected a non-empty string");
  return node.Scalar();
}

bool YamlReader::boolean(const YAML::Node& node, const std::string& path) const {
  bool b = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, b))
    fail(node, path, "expected true or false");
  return b;
}

int YamlReader::integer(const YAML::Node& node, const std::string& path) const {
  int i = 0;
  if (!node.IsScalar() || !YAML::convert<int>::decode(node, i))
    fail(node, path, "expected an integer, got '" + (node.IsScalar() ? node.Scalar() : "") + "'");
  return i;
}

VecX YamlReader::vector(const YAML::Node& node, const std::string& path, int size) const {
  if (!node.IsSequence() || static_cast<int>(node.size()) != size)
    fail(node, path, "expected a list of " + std::to_string(size) + " numbers");
  VecX v(size);
  for (int i = 0; i < size; ++i) v[i] = number(node[i], path + "[" + std::to_string(i) + "]");
  return v;
}

bool YamlReader::isAuto(const YAML::Node& node) const {
  return node.IsScalar() && node.Scalar() == "auto";
}

}  // namespace flexsens
