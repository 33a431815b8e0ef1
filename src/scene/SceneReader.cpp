// Reads a scene file, validates every key against what it may hold and builds the Model.
// Validation and building happen in one pass so that every error still has its YAML mark.
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "constraints/Distance.hpp"
#include "elements/Beam.hpp"
#include "elements/RigidBar.hpp"
#include "pim/Rigidization.hpp"
#include "scene/Scene.hpp"
#include "scene/YamlReader.hpp"

namespace flexsens {

namespace {

std::string at(const std::string& list, size_t i) { return list + "[" + std::to_string(i) + "]"; }

class Builder {
 public:
  Builder(const std::string& file, std::string caseName) : r_(file), caseName_(std::move(caseName)) {}

  Scene build(const YAML::Node& root) {
    Scene sc;
    sc.file = r_.file();
    if (!root || root.IsNull())
      throw InputError(r_.file() + ":1:1: key 'dimension': the scene is empty; expected a mapping "
                       "with at least the keys dimension, nodes and integrator");
    r_.allowKeys(root, "", {"dimension", "plane", "gravity", "nodes", "elements", "constraints",
                            "parameters", "integrator", "outputs", "output", "description", "cases"});
    sc.model = std::make_unique<Model>();
    Model& m = *sc.model;
    const YAML::Node dimNode = r_.require(root, "dimension", "");
    m.dim = r_.integer(dimNode, "dimension");
    if (m.dim != 2 && m.dim != 3) r_.fail(dimNode, "dimension", "expected 2 or 3");
    if (root["plane"]) {
      if (m.dim != 2) r_.fail(root["plane"], "plane", "only planar (dimension 2) scenes name a plane");
      m.plane = r_.text(root["plane"], "plane");
      if (m.plane != "xy" && m.plane != "xz" && m.plane != "yz")
        r_.fail(root["plane"], "plane", "expected xy, xz or yz");
    }
    m.gravity = root["gravity"] ? r_.vector(root["gravity"], "gravity", m.dim) : VecX::Zero(m.dim);
    readNodes(r_.require(root, "nodes", ""), m);
    if (root["elements"]) readElements(root["elements"], m);
    if (root["constraints"]) readConstraints(root["constraints"], m);
    // yaml-cpp: a default Node is "defined" (null) and '=' assigns content, hence optional.
    const std::optional<YAML::Node> caseNode =
        root["cases"] ? selectCase(root["cases"], sc) : std::optional<YAML::Node>();
    if (caseNode) applyRigidModels(*caseNode, m);
    m.finalize();
    if (root["parameters"]) readParameters(root["parameters"], m, caseNode.has_value());
    else if (!caseParamNodes_.empty())
      r_.fail(caseParamNodes_.front().second, caseParamPath_, "the scene defines no parameters (add a 'parameters' list)");
    if (caseNode) sc.pimCase = readPimCase(*caseNode, m);
    readIntegrator(r_.require(root, "integrator", ""), sc.integrator);
    if (root["outputs"]) readOutputs(root["outputs"], sc);
    readOutputSettings(root["output"], sc);
    if (m.n == 0) r_.fail(root["nodes"], "nodes", "the scene has no free node: nothing can move");
    return sc;
  }

 private:
  // -------------------------------------------------------------------------- nodes
  void readNodes(const YAML::Node& list, Model& m) {
    r_.requireList(list, "nodes");
    if (list.size() == 0) r_.fail(list, "nodes", "expected at least one node");
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node nd = list[i];
      const std::string path = at("nodes", i);
      r_.allowKeys(nd, path, {"name", "position", "velocity", "ground"});
      Node node;
      node.name = r_.text(r_.require(nd, "name", path), path + ".name");
      if (nodeIndex_.count(node.name)) r_.fail(nd["name"], path + ".name", "duplicate node name '" + node.name + "'");
      node.position = r_.vector(r_.require(nd, "position", path), path + ".position", m.dim);
      node.velocity = nd["velocity"] ? r_.vector(nd["velocity"], path + ".velocity", m.dim)
                                     : VecX::Zero(m.dim);
      node.ground = nd["ground"] ? r_.boolean(nd["ground"], path + ".ground") : false;
      if (node.ground && node.velocity.norm() > 0)
        r_.fail(nd["velocity"], path + ".velocity", "a ground node cannot have a velocity");
      nodeIndex_[node.name] = static_cast<int>(m.nodes.size());
      m.nodes.push_back(node);
    }
  }

  int node(const YAML::Node& n, const std::string& path) const {
    const std::string name = r_.text(n, path);
    auto it = nodeIndex_.find(name);
    if (it == nodeIndex_.end()) r_.fail(n, path, "no node named '" + name + "' is defined under nodes");
    return it->second;
  }

  std::vector<int> nodeList(const YAML::Node& item, const std::string& path, size_t minCount,
                            size_t maxCount) const {
    const YAML::Node list = r_.require(item, "nodes", path);
    const std::string p = path + ".nodes";
    if (!list.IsSequence() || list.size() < minCount || list.size() > maxCount)
      r_.fail(list, p, minCount == maxCount ? "expected a list of " + std::to_string(minCount) + " node names"
                                            : "expected a list of at least " + std::to_string(minCount) + " node names");
    std::vector<int> ids;
    std::set<int> seen;
    for (size_t i = 0; i < list.size(); ++i) {
      ids.push_back(node(list[i], at(p, i)));
      if (!seen.insert(ids.back()).second) r_.fail(list[i], at(p, i), "the same node appears twice");
    }
    return ids;
  }

  std::string itemName(const YAML::Node& item, const std::string& path, const std::string& fallback) {
    std::string name = item["name"] ? r_.text(item["name"], path + ".name") : fallback;
    if (!names_.insert(name).second) r_.fail(item["name"] ? item["name"] : item, path + ".name", "duplicate name '" + name + "'");
    return name;
  }

  double distance(const Model& m, int a, int b) const {
    return (m.nodes[a].position - m.nodes[b].position).norm();
  }

  /// A length given as a positive number or "auto" (the initial distance of the nodes).
  /// `item` is the element or constraint (for the error position when the key is absent).
  Quantity length(const YAML::Node& item, const std::string& key, const std::string& path,
                  const Model& m, int a, int b) const {
    const YAML::Node n = item[key];
    if (!n || r_.isAuto(n)) {
      const double d = distance(m, a, b);
      if (!(d > 0)) r_.fail(n ? n : item, path, "the two nodes coincide, so 'auto' gives a zero length; give the length");
      return {d, -1};
    }
    return {r_.positive(n, path), -1};
  }

  void bind(const std::string& key, Quantity* q) { bindings_[key].push_back(q); }

  // ----------------------------------------------------------------------- elements
  void readElements(const YAML::Node& list, Model& m) {
    r_.requireList(list, "elements");
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node el = list[i];
      const std::string path = at("elements", i);
      r_.requireMap(el, path);
      const std::string type = r_.text(r_.require(el, "type", path), path + ".type");
      const std::string name = itemName(el, path, type + std::to_string(i));
      if (type == "rigid_bar") {
        r_.allowKeys(el, path, {"name", "type", "nodes", "mass", "length"});
        const auto ids = nodeList(el, path, 2, 2);
        const Quantity mass{r_.positive(r_.require(el, "mass", path), path + ".mass"), -1};
        auto bar = std::make_unique<RigidBar>(name, ids[0], ids[1], mass);
        auto con = std::make_unique<DistanceConstraint>(name + ".length", ids[0], ids[1],
                                                        length(el, "length", path + ".length", m, ids[0], ids[1]));
        for (auto& [k, q] : bar->properties()) bind(name + "." + k, q);
        for (auto& [k, q] : con->properties()) bind(name + "." + k, q);
        m.elements.push_back(std::move(bar));
        m.constraints.push_back(std::move(con));
      } else if (type == "spring_damper") {
        r_.allowKeys(el, path, {"name", "type", "nodes", "stiffness", "damping", "natural_length"});
        const auto ids = nodeList(el, path, 2, 2);
        const Quantity k{r_.nonNegative(r_.require(el, "stiffness", path), path + ".stiffness"), -1};
        const Quantity c{el["damping"] ? r_.nonNegative(el["damping"], path + ".damping") : 0.0, -1};
        auto sp = std::make_unique<SpringDamper>(name, ids[0], ids[1], k, c,
                                                 length(el, "natural_length", path + ".natural_length", m, ids[0], ids[1]));
        for (auto& [key, q] : sp->properties()) bind(name + "." + key, q);
        bodies_[name] = {ids, sp->properties()[2].second};
        m.elements.push_back(std::move(sp));
      } else if (type == "beam") {
        readBeam(el, path, name, m);
      } else {
        r_.fail(el["type"], path + ".type", "unknown element type '" + type +
                                               "'; expected rigid_bar, spring_damper or beam");
      }
    }
  }

  void readBeam(const YAML::Node& el, const std::string& path, const std::string& name, Model& m) {
    r_.allowKeys(el, path, {"name", "type", "nodes", "E", "density", "section"});
    if (m.dim != 2) r_.fail(el["type"], path + ".type", "the beam element is planar for now (dimension 2)");
    const auto ids = nodeList(el, path, 2, 100000);
    auto sec = std::make_shared<BeamSection>();
    sec->E = {r_.positive(r_.require(el, "E", path), path + ".E"), -1};
    sec->density = {r_.positive(r_.require(el, "density", path), path + ".density"), -1};
    const YAML::Node s = r_.require(el, "section", path);
    const std::string sp = path + ".section";
    r_.allowKeys(s, sp, {"side", "area", "inertia"});
    if (s["side"]) {
      if (s["area"] || s["inertia"]) r_.fail(s, sp, "give either side (square section) or area and inertia, not both");
      sec->square = true;
      sec->side = {r_.positive(s["side"], sp + ".side"), -1};
    } else {
      sec->area = {r_.positive(r_.require(s, "area", sp), sp + ".area"), -1};
      sec->inertia = {r_.positive(r_.require(s, "inertia", sp), sp + ".inertia"), -1};
    }
    for (auto& [k, q] : sec->properties()) bind(name + "." + k, q);
    bodies_[name] = {ids, nullptr};
    for (size_t j = 0; j + 1 < ids.size(); ++j) {
      const double L = distance(m, ids[j], ids[j + 1]);
      if (!(L > 0)) r_.fail(el["nodes"][j + 1], at(path + ".nodes", j + 1), "coincides with the previous node: zero segment length");
      m.elements.push_back(std::make_unique<BeamSegment>(name + ".segment" + std::to_string(j),
                                                         std::vector<int>{ids[j], ids[j + 1]}, sec, L));
    }
    for (size_t j = 1; j + 1 < ids.size(); ++j) {
      VecX rest(6);
      rest << m.nodes[ids[j - 1]].position, m.nodes[ids[j]].position, m.nodes[ids[j + 1]].position;
      m.elements.push_back(std::make_unique<BeamHinge>(name + ".hinge" + std::to_string(j),
                                                       std::vector<int>{ids[j - 1], ids[j], ids[j + 1]}, sec, rest));
    }
  }

  // -------------------------------------------------------------------- constraints
  void readConstraints(const YAML::Node& list, Model& m) {
    r_.requireList(list, "constraints");
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node c = list[i];
      const std::string path = at("constraints", i);
      r_.requireMap(c, path);
      const std::string type = r_.text(r_.require(c, "type", path), path + ".type");
      const std::string name = itemName(c, path, type + std::to_string(i));
      if (type == "distance") {
        r_.allowKeys(c, path, {"name", "type", "nodes", "length"});
        const auto ids = nodeList(c, path, 2, 2);
        auto con = std::make_unique<DistanceConstraint>(name, ids[0], ids[1],
                                                        length(c, "length", path + ".length", m, ids[0], ids[1]));
        for (auto& [k, q] : con->properties()) bind(name + "." + k, q);
        m.constraints.push_back(std::move(con));
      } else if (type == "fixed") {
        r_.allowKeys(c, path, {"name", "type", "node", "position"});
        const int id = node(r_.require(c, "node", path), path + ".node");
        if (m.nodes[id].ground) r_.fail(c["node"], path + ".node", "node '" + m.nodes[id].name + "' is a ground node already");
        const VecX pos = c["position"] ? r_.vector(c["position"], path + ".position", m.dim) : m.nodes[id].position;
        m.constraints.push_back(std::make_unique<FixedNodeConstraint>(name, id, pos));
      } else {
        r_.fail(c["type"], path + ".type", "unknown constraint type '" + type + "'; expected distance or fixed");
      }
    }
  }

  // --------------------------------------------------------------------- parameters
  void readParameters(const YAML::Node& list, Model& m, bool forCase) {
    r_.requireList(list, "parameters");
    std::set<std::string> seen;
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node pn = list[i];
      const std::string path = at("parameters", i);
      r_.allowKeys(pn, path, {"name", "of", "property"});
      Parameter par;
      par.name = r_.text(r_.require(pn, "name", path), path + ".name");
      if (!seen.insert(par.name).second)
        r_.fail(pn["name"], path + ".name", "duplicate parameter name '" + par.name + "'");
      allParams_.insert(par.name);
      const std::string of = r_.text(r_.require(pn, "of", path), path + ".of");
      const std::string prop = r_.text(r_.require(pn, "property", path), path + ".property");
      par.boundTo = of + "." + prop;
      auto it = bindings_.find(par.boundTo);
      if (of == "gravity") {
        if (axisIndex(m, prop) < 0)
          r_.fail(pn["property"], path + ".property", "gravity has the components of the scene's axes; got '" + prop + "'");
      } else if (it == bindings_.end()) {
        std::string avail;
        for (const auto& [k, v] : bindings_)
          if (k.rfind(of + ".", 0) == 0) avail += (avail.empty() ? "" : ", ") + k.substr(of.size() + 1);
        r_.fail(pn["property"], path + ".property",
                avail.empty() ? "no element or constraint named '" + of + "' has parameters"
                              : "'" + of + "' has no property '" + prop + "'; expected one of: " + avail);
      }
      if (forCase && !caseParams_.count(par.name)) continue;  // not a parameter of this case
      const int k = static_cast<int>(m.parameters.size());
      if (of == "gravity") {  // gravity components are model-level quantities
        m.gravityParam.resize(m.dim, -1);
        const int c = axisIndex(m, prop);
        if (m.gravityParam[c] >= 0) r_.fail(pn, path, "'gravity." + prop + "' is bound to another parameter already");
        m.gravityParam[c] = k;
        par.nominal = m.gravity[c];
        m.parameters.push_back(par);
        continue;
      }
      par.nominal = it->second.front()->constant;
      for (Quantity* q : it->second) {
        if (q->param >= 0) r_.fail(pn, path, "'" + par.boundTo + "' is bound to another parameter already");
        q->param = k;
      }
      m.parameters.push_back(par);
    }
    for (const auto& [name, node] : caseParamNodes_)
      if (!allParams_.count(name)) r_.fail(node, caseParamPath_, "no parameter named '" + name + "' under parameters");
  }

  // -------------------------------------------------------------------------- cases
  /// Validates every case's keys and names; returns the selected one (or null).
  std::optional<YAML::Node> selectCase(const YAML::Node& list, Scene& sc) {
    r_.requireList(list, "cases");
    std::optional<YAML::Node> selected;
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node c = list[i];
      const std::string path = at("cases", i);
      r_.allowKeys(c, path, {"name", "parameters", "rigidize", "rigid_model", "sdofs", "description"});
      const std::string name = r_.text(r_.require(c, "name", path), path + ".name");
      for (const auto& other : sc.caseNames)
        if (other == name) r_.fail(c["name"], path + ".name", "duplicate case name '" + name + "'");
      sc.caseNames.push_back(name);
      if (name == caseName_) { selected.emplace(c); casePath_ = path; }
    }
    if (!caseName_.empty() && !selected) {
      std::string names;
      for (const auto& n : sc.caseNames) names += (names.empty() ? "" : ", ") + n;
      r_.fail(list, "cases", "no case named '" + caseName_ + "'; the scene defines: " + names);
    }
    if (selected) {
      const YAML::Node ps = r_.require(*selected, "parameters", casePath_);
      caseParamPath_ = casePath_ + ".parameters";
      r_.requireList(ps, caseParamPath_);
      for (size_t i = 0; i < ps.size(); ++i) {
        const std::string pn = r_.text(ps[i], at(caseParamPath_, i));
        caseParams_.insert(pn);
        caseParamNodes_.emplace_back(pn, ps[i]);
      }
    }
    return selected;
  }

  /// The listed bodies (names under `key`), checked to exist as flexible bodies.
  std::vector<std::string> bodyList(const YAML::Node& c, const std::string& key) {
    std::vector<std::string> out;
    if (!c[key]) return out;
    const std::string path = casePath_ + "." + key;
    r_.requireList(c[key], path);
    for (size_t i = 0; i < c[key].size(); ++i) {
      const std::string b = r_.text(c[key][i], at(path, i));
      if (!bodies_.count(b)) {
        std::string avail;
        for (const auto& [k, v] : bodies_) avail += (avail.empty() ? "" : ", ") + k;
        r_.fail(c[key][i], at(path, i), "no flexible body (beam or spring) named '" + b + "'" +
                                             (avail.empty() ? std::string() : "; the scene has: " + avail));
      }
      out.push_back(b);
    }
    return out;
  }

  static MatX positions(const Model& m) {
    MatX X(m.dim, m.nodes.size());
    for (size_t i = 0; i < m.nodes.size(); ++i) X.col(i) = m.nodes[i].position;
    return X;
  }

  /// F-R twins: bodies modelled rigid become rigid bodies through the rigidization generator.
  void applyRigidModels(const YAML::Node& c, Model& m) {
    for (const auto& b : bodyList(c, "rigid_model")) {
      Rigidization R = rigidize(b, bodies_[b].nodes, m, positions(m), r_.file() + ": case '" + caseName_ + "'");
      for (auto& con : R.constraints) m.constraints.push_back(std::move(con));
    }
  }

  std::unique_ptr<PimCase> readPimCase(const YAML::Node& c, const Model& m) {
    auto pc = std::make_unique<PimCase>();
    pc->name = caseName_;
    pc->file = r_.file();
    pc->rigidModel = bodyList(c, "rigid_model");
    pc->rigidized = bodyList(c, "rigidize");
    for (const auto& p : m.parameters) pc->parameters.push_back(p.name);
    for (size_t i = 0; i < pc->rigidized.size(); ++i) {
      const std::string& b = pc->rigidized[i];
      if (std::count(pc->rigidModel.begin(), pc->rigidModel.end(), b))
        r_.fail(c["rigidize"][i], at(casePath_ + ".rigidize", i), "'" + b + "' is already rigid in this case (rigid_model)");
      Rigidization R = rigidize(b, bodies_[b].nodes, m, positions(m), r_.file() + ": case '" + caseName_ + "'",
                                bodies_[b].pairLength);
      for (auto& con : R.constraints) pc->lambda.push_back(std::move(con));
    }
    if (c["sdofs"]) {
      const std::string path = casePath_ + ".sdofs";
      r_.requireList(c["sdofs"], path);
      for (size_t i = 0; i < c["sdofs"].size(); ++i) pc->sdofs.push_back(readSdof(c["sdofs"][i], at(path, i), m));
    }
    return pc;
  }

  static int axisIndex(const Model& m, const std::string& a) {
    for (int c = 0; c < m.dim; ++c)
      if (a.size() == 1 && a[0] == m.axisName(c)) return c;
    return -1;
  }

  int component(const YAML::Node& n, const std::string& path, const Model& m) const {
    const std::string comp = r_.text(n, path);
    for (int c = 0; c < m.dim; ++c)
      if (comp.size() == 1 && comp[0] == m.axisName(c)) return c;
    std::string axes;
    for (int c = 0; c < m.dim; ++c) axes += std::string(axes.empty() ? "" : ", ") + m.axisName(c);
    r_.fail(n, path, "expected one of " + axes + " (the scene's axes)");
  }

  std::unique_ptr<Sdof> readSdof(const YAML::Node& z, const std::string& path, const Model& m) {
    r_.allowKeys(z, path, {"node", "component", "angle", "combination", "dp", "dv", "name"});
    std::unique_ptr<Sdof> out;
    if (z["angle"]) {
      if (m.dim != 2) r_.fail(z["angle"], path + ".angle", "segment angles are planar SDOFs (dimension 2)");
      const YAML::Node a = z["angle"];
      if (!a.IsSequence() || a.size() != 2) r_.fail(a, path + ".angle", "expected a list of two node names [from, to]");
      auto s = std::make_unique<AngleSdof>();
      s->a = node(a[0], path + ".angle[0]");
      s->b = node(a[1], path + ".angle[1]");
      s->name = "angle(" + m.nodes[s->a].name + "," + m.nodes[s->b].name + ")";
      out = std::move(s);
    } else if (z["combination"]) {
      const YAML::Node list = z["combination"];
      const std::string cp = path + ".combination";
      if (!list.IsSequence() || list.size() == 0) r_.fail(list, cp, "expected a list of [coefficient, node, component]");
      auto s = std::make_unique<LinearSdof>();
      for (size_t j = 0; j < list.size(); ++j) {
        const YAML::Node t = list[j];
        if (!t.IsSequence() || t.size() != 3) r_.fail(t, at(cp, j), "expected [coefficient, node, component]");
        const double coef = r_.number(t[0], at(cp, j) + "[0]");
        const int nd = node(t[1], at(cp, j) + "[1]");
        const int c = component(t[2], at(cp, j) + "[2]", m);
        s->terms.push_back({nd, c, coef});
        s->name += (j ? " + " : "") + jsonish(coef) + " " + std::string(1, m.axisName(c)) + "(" + m.nodes[nd].name + ")";
      }
      out = std::move(s);
    } else {
      auto s = std::make_unique<LinearSdof>();
      const int nd = node(r_.require(z, "node", path), path + ".node");
      const int c = component(r_.require(z, "component", path), path + ".component", m);
      s->terms.push_back({nd, c, 1.0});
      s->name = std::string(1, m.axisName(c)) + "(" + m.nodes[nd].name + ")";
      out = std::move(s);
    }
    if (z["name"]) out->name = r_.text(z["name"], path + ".name");
    if (z["dp"]) out->dp = r_.number(z["dp"], path + ".dp");
    if (z["dv"]) out->dv = r_.number(z["dv"], path + ".dv");
    return out;
  }

  static std::string jsonish(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  }

  // --------------------------------------------------------------------- integrator
  void readIntegrator(const YAML::Node& in, IntegratorSettings& s) {
    r_.allowKeys(in, "integrator", {"type", "t_end", "dt", "rtol", "atol", "newton_tol",
                                    "max_newton_iterations", "frame_interval", "sensitivity_error_control"});
    s.type = r_.text(r_.require(in, "type", "integrator"), "integrator.type");
    if (s.type != "idas" && s.type != "trapezoidal" && s.type != "bdf1")
      r_.fail(in["type"], "integrator.type", "expected idas, trapezoidal or bdf1, got '" + s.type + "'");
    s.tEnd = r_.positive(r_.require(in, "t_end", "integrator"), "integrator.t_end");
    if (in["dt"]) s.dt = r_.positive(in["dt"], "integrator.dt");
    else if (s.type != "idas") r_.require(in, "dt", "integrator");
    else s.dt = 0.0;
    if (in["rtol"]) s.rtol = r_.positive(in["rtol"], "integrator.rtol");
    if (in["atol"]) s.atol = r_.positive(in["atol"], "integrator.atol");
    if (in["newton_tol"]) s.newtonTol = r_.positive(in["newton_tol"], "integrator.newton_tol");
    if (in["max_newton_iterations"]) {
      s.maxNewtonIterations = r_.integer(in["max_newton_iterations"], "integrator.max_newton_iterations");
      if (s.maxNewtonIterations < 1) r_.fail(in["max_newton_iterations"], "integrator.max_newton_iterations", "expected at least 1");
    }
    s.frameInterval = in["frame_interval"] ? r_.positive(in["frame_interval"], "integrator.frame_interval")
                                           : std::max(s.dt, s.tEnd / 200.0);
    if (in["sensitivity_error_control"])
      s.sensitivityErrorControl = r_.boolean(in["sensitivity_error_control"], "integrator.sensitivity_error_control");
  }

  void readOutputs(const YAML::Node& list, Scene& sc) {
    r_.requireList(list, "outputs");
    const Model& m = *sc.model;
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node o = list[i];
      const std::string path = at("outputs", i);
      r_.allowKeys(o, path, {"name", "node", "component"});
      OutputSpec spec;
      spec.name = r_.text(r_.require(o, "name", path), path + ".name");
      for (const auto& other : sc.outputs)
        if (other.name == spec.name) r_.fail(o["name"], path + ".name", "duplicate output name '" + spec.name + "'");
      spec.node = node(r_.require(o, "node", path), path + ".node");
      const std::string comp = r_.text(r_.require(o, "component", path), path + ".component");
      spec.component = -1;
      for (int c = 0; c < m.dim; ++c)
        if (comp.size() == 1 && comp[0] == m.axisName(c)) spec.component = c;
      if (spec.component < 0) {
        std::string axes;
        for (int c = 0; c < m.dim; ++c) axes += std::string(axes.empty() ? "" : ", ") + m.axisName(c);
        r_.fail(o["component"], path + ".component", "expected one of " + axes + " (the scene's axes)");
      }
      sc.outputs.push_back(spec);
    }
  }

  void readOutputSettings(const YAML::Node& o, Scene& sc) {
    sc.output.directory = "results/" + std::filesystem::path(sc.file).stem().string();
    if (!o) return;
    r_.allowKeys(o, "output", {"directory", "vtk", "plots"});
    if (o["directory"]) sc.output.directory = r_.text(o["directory"], "output.directory");
    if (o["vtk"]) sc.output.vtk = r_.boolean(o["vtk"], "output.vtk");
    if (o["plots"]) sc.output.plots = r_.boolean(o["plots"], "output.plots");
  }

  struct Body { std::vector<int> nodes; const Quantity* pairLength; };
  YamlReader r_;
  std::string caseName_, casePath_, caseParamPath_;
  std::set<std::string> caseParams_, allParams_;
  std::vector<std::pair<std::string, YAML::Node>> caseParamNodes_;
  std::map<std::string, Body> bodies_;
  std::map<std::string, int> nodeIndex_;
  std::set<std::string> names_;
  std::map<std::string, std::vector<Quantity*>> bindings_;
};

}  // namespace

Scene readSceneText(const std::string& text, const std::string& name, const std::string& caseName) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    std::ostringstream os;
    os << name << ":" << e.mark.line + 1 << ":" << e.mark.column + 1 << ": key '(syntax)': "
       << "YAML syntax error: " << e.msg;
    throw InputError(os.str());
  }
  return Builder(name, caseName).build(root);
}

Scene readScene(const std::string& path, const std::string& caseName) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the scene file (does it exist and is it readable?)");
  std::stringstream ss;
  ss << in.rdbuf();
  return readSceneText(ss.str(), path, caseName);
}

}  // namespace flexsens
