#include "scene/TimeFunctionReader.hpp"

#include <cmath>
#include <sstream>

#include "scene/InputFiles.hpp"

namespace flexsens {

void parseTimeTable(const std::string& text, const std::string& shown, std::vector<double>& t, std::vector<double>& f) {
  std::istringstream in(text);
  std::string line;
  int lineNo = 0;
  bool headerAllowed = true;
  while (std::getline(in, line)) {
    ++lineNo;
    const std::string where = shown + ":" + std::to_string(lineNo) + ": ";
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    for (char& c : line)
      if (c == ',' || c == ';' || c == '\t') c = ' ';
    std::istringstream is(line);
    double a, b;
    std::string extra;
    if (!(is >> a >> b)) {
      if (headerAllowed) {  // a header row (e.g. "t, f") before the first number
        headerAllowed = false;
        continue;
      }
      throw std::runtime_error(where + "expected two numbers 't, f' (time [s], value) separated by a comma, "
                               "semicolon, tab or spaces");
    }
    if (is >> extra) throw std::runtime_error(where + "expected two numbers 't, f', got a third column");
    if (!std::isfinite(a) || !std::isfinite(b)) throw std::runtime_error(where + "expected finite numbers");
    if (!t.empty() && !(a > t.back())) {
      std::ostringstream os;
      os << where << "times must increase strictly: t = " << a << " s after t = " << t.back() << " s";
      throw std::runtime_error(os.str());
    }
    headerAllowed = false;
    t.push_back(a);
    f.push_back(b);
  }
  if (t.size() < 2)
    throw std::runtime_error("'" + shown + "' holds " + std::to_string(t.size()) +
                             " rows of 't, f'; a table needs at least two");
}

std::unique_ptr<TimeFunction> readTimeFunction(SceneContext& ctx, const YAML::Node& fn,
                                               const std::string& path, const std::string& item) {
  const YamlReader& r = ctx.r;
  r.requireMap(fn, path);
  const std::string type = r.text(r.require(fn, "type", path), path + ".type");
  auto num = [&](const char* key, std::optional<double> dflt = std::nullopt) {
    if (!fn[key]) {
      if (dflt) return *dflt;
      r.require(fn, key, path);  // fails naming the key
    }
    return r.number(fn[key], path + "." + key);
  };
  std::unique_ptr<TimeFunction> f;
  if (type == "constant") {
    r.allowKeys(fn, path, {"type", "value"});
    f = makeConstant(num("value"));
  } else if (type == "ramp") {
    r.allowKeys(fn, path, {"type", "slope", "start", "offset"});
    f = makeRamp(num("slope"), num("start", 0.0), num("offset", 0.0));
  } else if (type == "linear") {
    r.allowKeys(fn, path, {"type", "slope", "offset"});
    f = makeLinear(num("slope"), num("offset", 0.0));
  } else if (type == "smooth_step") {
    r.allowKeys(fn, path, {"type", "t0", "t1", "from", "to"});
    const double t0 = num("t0"), t1 = num("t1");
    if (!(t1 > t0)) r.fail(fn["t1"], path + ".t1", "expected t1 > t0 (the step's end after its start) [s]");
    f = makeSmoothStep(t0, t1, num("from", 0.0), num("to"));
  } else if (type == "harmonic") {
    r.allowKeys(fn, path, {"type", "amplitude", "omega", "phase", "offset"});
    f = makeHarmonic(num("amplitude"), num("omega"), num("phase", 0.0), num("offset", 0.0));
  } else if (type == "spin_up") {
    r.allowKeys(fn, path, {"type", "omega", "duration"});
    const double T = r.positive(r.require(fn, "duration", path), path + ".duration");
    f = makeSpinUp(num("omega"), T);
  } else if (type == "table") {
    r.allowKeys(fn, path, {"type", "file", "scale"});
    const std::string name = r.text(r.require(fn, "file", path), path + ".file");
    const std::uintmax_t limit = inputPolicy().maxTableBytes;
    const std::string full = sceneDataFile(r, fn["file"], path + ".file", name, limit);
    std::vector<double> t, v;
    try {
      parseTimeTable(readBoundedFile(full, limit, name), name, t, v);
    } catch (const std::runtime_error& e) {
      r.fail(fn["file"], path + ".file", e.what());
    }
    f = makeTable(std::move(t), std::move(v), num("scale", 1.0));
  } else {
    r.fail(fn["type"], path + ".type",
           "unknown time function '" + type + "'; expected constant, ramp, linear, smooth_step, harmonic, spin_up or table");
  }
  for (auto& [k, q] : f->properties()) ctx.bind(item + "." + k, q);
  return f;
}

}  // namespace flexsens
