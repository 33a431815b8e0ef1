// Reads a scene file, validates every key against what it may hold and builds the Model.
// Validation and building happen in one pass so that every error still has its YAML mark.
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "constraints/Bilinear.hpp"
#include "constraints/Distance.hpp"
#include "elements/Beam.hpp"
#include "elements/BeamHinge3D.hpp"
#include "elements/RigidBar.hpp"
#include "elements/RigidBody.hpp"
#include "elements/RotationalSpring.hpp"
#include "meshes/GmshCurves.hpp"
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
    r_.allowKeys(root, "", {"dimension", "plane", "gravity", "geometry", "nodes", "elements", "constraints",
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
    if (root["geometry"]) readGeometry(root["geometry"], m);
    if (root["nodes"] || !root["geometry"]) readNodes(r_.require(root, "nodes", ""), m);
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
  // ----------------------------------------------------------------------- geometry
  /// geometry: {gmsh: file.geo}: the file's named points become nodes now; beams name its
  /// curves (curve + segments) and get their node chains when they are read. Gmsh is
  /// started only here (meshes/GmshCurves), so scenes without geometry never start it.
  void readGeometry(const YAML::Node& g, Model& m) {
    r_.allowKeys(g, "geometry", {"gmsh"});
    if (m.dim != 3) r_.fail(g, "geometry", "Gmsh geometry is for spatial scenes (dimension 3)");
    const std::string rel = r_.text(r_.require(g, "gmsh", "geometry"), "geometry.gmsh");
    const std::filesystem::path base = std::filesystem::path(r_.file()).parent_path();
    geoFile_ = (base / rel).string();
    const CurveMesh mesh = meshCurves(geoFile_, {}, where(g["gmsh"], "geometry.gmsh"));
    for (const auto& [name, x] : mesh.points) addGeometryNode(name, x, g["gmsh"], "geometry.gmsh", m);
  }

  std::string where(const YAML::Node& n, const std::string& key) const {
    return r_.file() + ":" + std::to_string(n.Mark().line + 1) + ":" + std::to_string(n.Mark().column + 1) +
           ": key '" + key + "'";
  }

  /// A node from the geometry; a name met again must be at the same place.
  int addGeometryNode(const std::string& name, const Eigen::Vector3d& x, const YAML::Node& at,
                      const std::string& key, Model& m) {
    auto it = nodeIndex_.find(name);
    if (it != nodeIndex_.end()) {
      if ((Eigen::Vector3d(m.nodes[it->second].position) - x).norm() > 1e-9)
        r_.fail(at, key, "the geometry places node '" + name + "' at two different positions");
      return it->second;
    }
    Node nd;
    nd.name = name;
    nd.position = x;
    nd.velocity = VecX::Zero(3);
    nodeIndex_[name] = static_cast<int>(m.nodes.size());
    m.nodes.push_back(nd);
    return nodeIndex_[name];
  }

  /// The node chain of element `el`'s `curve` (a Physical Curve of the geometry) meshed with
  /// `segments` uniform segments.
  std::vector<int> curveNodes(const YAML::Node& el, const std::string& path, Model& m) {
    const YAML::Node c = el["curve"];
    if (el["nodes"]) r_.fail(el["nodes"], path + ".nodes", "give either nodes or curve (and segments), not both");
    if (geoFile_.empty()) r_.fail(c, path + ".curve", "curves need a geometry: add geometry: {gmsh: file.geo}");
    const std::string group = r_.text(c, path + ".curve");
    const YAML::Node sn = r_.require(el, "segments", path);
    const int segments = r_.integer(sn, path + ".segments");
    if (segments < 1) r_.fail(sn, path + ".segments", "expected at least 1 segment, got " + std::to_string(segments));
    const CurveMesh mesh = meshCurves(geoFile_, {{group, segments}}, where(c, path + ".curve"));
    std::vector<int> ids;
    const NodeChain& ch = mesh.chains.at(0);
    for (size_t i = 0; i < ch.names.size(); ++i) ids.push_back(addGeometryNode(ch.names[i], ch.positions[i], c, path + ".curve", m));
    return ids;
  }

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
      if (nd["velocity"]) velocitySetBy_[static_cast<int>(m.nodes.size())] = path + ".velocity";
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
                            size_t maxCount, bool allowRepeat = false) const {
    const YAML::Node list = r_.require(item, "nodes", path);
    const std::string p = path + ".nodes";
    if (!list.IsSequence() || list.size() < minCount || list.size() > maxCount)
      r_.fail(list, p, minCount == maxCount ? "expected a list of " + std::to_string(minCount) + " node names"
                                            : "expected a list of at least " + std::to_string(minCount) + " node names");
    std::vector<int> ids;
    std::set<int> seen;
    for (size_t i = 0; i < list.size(); ++i) {
      ids.push_back(node(list[i], at(p, i)));
      if (!seen.insert(ids.back()).second && !allowRepeat) r_.fail(list[i], at(p, i), "the same node appears twice");
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
      } else if (type == "rigid_body") {
        readRigidBody(el, path, name, m);
      } else if (type == "rotational_spring_damper") {
        readRotationalSpring(el, path, name, m);
      } else {
        r_.fail(el["type"], path + ".type", "unknown element type '" + type +
                                               "'; expected rigid_bar, spring_damper, beam, rigid_body or "
                                               "rotational_spring_damper");
      }
    }
  }

  // ------------------------------------------------------------ rigid bodies (3D)
  /// Nodes at fixed distances already: both ground, or both on one earlier rigid body.
  bool linked(int a, int b) const {
    if (model_->nodes[a].ground && model_->nodes[b].ground) return true;
    for (const auto& [name, body] : rigidBodies_)
      if (body.members.count(a) && body.members.count(b)) return true;
    return false;
  }

  void requireSpatial(const YAML::Node& el, const std::string& path, const Model& m, const std::string& what) {
    if (m.dim != 3) r_.fail(el["type"], path + ".type", what + " needs a spatial scene (dimension 3)");
  }

  void readRigidBody(const YAML::Node& el, const std::string& path, const std::string& name, Model& m) {
    r_.allowKeys(el, path, {"name", "type", "nodes", "mass", "center_of_mass", "inertia", "velocity",
                            "angular_velocity"});
    requireSpatial(el, path, m, "a rigid body");
    model_ = &m;
    const auto ids = nodeList(el, path, 4, 100000);
    const Quantity mass{r_.positive(r_.require(el, "mass", path), path + ".mass"), -1};
    const Eigen::Vector3d com = r_.vector(r_.require(el, "center_of_mass", path), path + ".center_of_mass", 3);
    // Inertia about the centre of mass, global axes at t = 0: [Ixx, Iyy, Izz] (principal,
    // along x, y, z) or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] (tensor entries, Ixy = -int x y dm).
    const YAML::Node in = r_.require(el, "inertia", path);
    const std::string ip = path + ".inertia";
    if (!in.IsSequence() || (in.size() != 3 && in.size() != 6))
      r_.fail(in, ip, "expected [Ixx, Iyy, Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] in kg m^2");
    std::array<Quantity, 6> inertia;
    for (size_t i = 0; i < in.size(); ++i) inertia[i] = {r_.number(in[i], at(ip, i)), -1};
    Eigen::Matrix3d I;
    I << inertia[0].constant, inertia[3].constant, inertia[4].constant, inertia[3].constant,
        inertia[1].constant, inertia[5].constant, inertia[4].constant, inertia[5].constant, inertia[2].constant;
    const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(RigidBody::secondMoments(I)).eigenvalues();
    if (!(moments.minCoeff() >= -1e-12 * I.norm()) || !(I.diagonal().minCoeff() > 0))
      r_.fail(in, ip, "not an inertia tensor of a physical body: the moments must be positive and satisfy "
                      "the triangle inequalities (Ixx <= Iyy + Izz, ...)");
    RigidizeOptions opt;
    opt.inOrder = true;
    opt.linked = [this](int a, int b) { return linked(a, b); };
    Rigidization R = rigidize(name, ids, m, positions(m), r_.file() + ":" + std::to_string(el.Mark().line + 1) +
                                                             ": key '" + path + ".nodes'", nullptr, opt);
    if (R.cloudDimension < 3)
      r_.fail(el["nodes"], path + ".nodes", "the nodes of rigid body '" + name + "' are coplanar (" +
                                                std::to_string(R.cloudDimension) + "D cloud); a 3D rigid body "
                                                "needs four non-coplanar basic points: add a point off their plane");
    Eigen::Matrix<double, 3, 4> X0;
    for (int k = 0; k < 4; ++k) X0.col(k) = m.nodes[R.basicPoints[k]].position;
    auto body = std::make_unique<RigidBody>(name, R.basicPoints, X0, mass, com, inertia);
    for (auto& [k, q] : body->properties()) bind(name + "." + k, q);
    m.elements.push_back(std::move(body));
    for (auto& c : R.constraints) m.constraints.push_back(std::move(c));
    RigidBodyInfo info;
    info.basic = R.basicPoints;
    info.X0 = X0;
    info.com = com;
    info.members.insert(ids.begin(), ids.end());
    rigidBodies_[name] = info;
    // Initial twist: v = v_G + omega x (r - r_G) on every node of the body.
    if (el["velocity"] || el["angular_velocity"]) {
      const Eigen::Vector3d vG = el["velocity"] ? r_.vector(el["velocity"], path + ".velocity", 3) : VecX::Zero(3);
      const Eigen::Vector3d w = el["angular_velocity"] ? r_.vector(el["angular_velocity"], path + ".angular_velocity", 3)
                                                       : VecX::Zero(3);
      for (int id : ids) {
        Node& nd = m.nodes[id];
        const Eigen::Vector3d v = vG + w.cross(Eigen::Vector3d(nd.position) - com);
        if (nd.ground) {
          if (v.norm() > 1e-12) r_.fail(el["angular_velocity"] ? el["angular_velocity"] : el["velocity"], path,
                                        "gives ground node '" + nd.name + "' a velocity; a body hinged to the "
                                        "ground turns about an axis through its ground nodes");
          continue;
        }
        setVelocity(id, v, el, path, m);
      }
    }
  }

  /// Sets the initial velocity of a node, failing if another item gave it a different one.
  void setVelocity(int id, const Eigen::Vector3d& v, const YAML::Node& item, const std::string& path, Model& m) {
    Node& nd = m.nodes[id];
    auto it = velocitySetBy_.find(id);
    if (it != velocitySetBy_.end() && (Eigen::Vector3d(nd.velocity) - v).norm() > 1e-9 * std::max(1.0, v.norm()))
      r_.fail(item, path, "gives node '" + nd.name + "' an initial velocity that differs from the one " +
                              it->second + " gives it; the bodies sharing a node must move consistently");
    nd.velocity = v;
    velocitySetBy_[id] = path;
  }

  AngleNodes angleNodes(const YAML::Node& item, const std::string& path) const {
    auto pair = [&](const char* key) {
      const YAML::Node n = r_.require(item, key, path);
      if (!n.IsSequence() || n.size() != 2) r_.fail(n, path + "." + key, "expected a list of two node names [from, to]");
      return std::make_pair(node(n[0], path + "." + key + "[0]"), node(n[1], path + "." + key + "[1]"));
    };
    const auto a = pair("axis"), f = pair("from"), t = pair("to");
    return {a.first, a.second, f.first, f.second, t.first, t.second};
  }

  /// The angle of `nodes` at the initial positions; fails where it is undefined.
  double initialAngle(const AngleNodes& an, const YAML::Node& item, const std::string& path, const Model& m) const {
    VecX x(18);
    const auto list = an.list();
    for (int a = 0; a < 6; ++a) x.segment<3>(3 * a) = m.nodes[list[a]].position;
    const Eigen::Vector3d n = x.segment<3>(3) - x.segment<3>(0);
    const Eigen::Vector3d u = n.normalized();
    auto perp = [&](const Eigen::Vector3d& w) { return (w - u * u.dot(w)).norm(); };
    if (!(n.norm() > 0) || !(perp(x.segment<3>(9) - x.segment<3>(6)) > 1e-9) ||
        !(perp(x.segment<3>(15) - x.segment<3>(12)) > 1e-9))
      r_.fail(item, path, "the angle is undefined at the initial positions: the axis nodes coincide or a "
                          "vector is parallel to the axis");
    return jointAngleT<double>(x, nullptr);
  }

  void readRotationalSpring(const YAML::Node& el, const std::string& path, const std::string& name, Model& m) {
    r_.allowKeys(el, path, {"name", "type", "axis", "from", "to", "stiffness", "damping", "rest_angle"});
    requireSpatial(el, path, m, "a rotational spring-damper");
    const AngleNodes an = angleNodes(el, path);
    const Quantity k{r_.nonNegative(r_.require(el, "stiffness", path), path + ".stiffness"), -1};
    const Quantity c{el["damping"] ? r_.nonNegative(el["damping"], path + ".damping") : 0.0, -1};
    const double theta = initialAngle(an, el, path, m);
    const double rest = (!el["rest_angle"] || r_.isAuto(el["rest_angle"])) ? theta
                                                                           : r_.number(el["rest_angle"], path + ".rest_angle");
    auto sp = std::make_unique<RotationalSpringDamper>(name, an, k, c, rest);
    for (auto& [key, q] : sp->properties()) bind(name + "." + key, q);
    m.elements.push_back(std::move(sp));
  }

  void readBeam(const YAML::Node& el, const std::string& path, const std::string& name, Model& m) {
    r_.allowKeys(el, path, {"name", "type", "nodes", "curve", "segments", "E", "density", "section", "rest_shape"});
    const auto ids = el["curve"] ? curveNodes(el, path, m) : nodeList(el, path, 2, 100000);
    // rest_shape: initial (default; rest = initial positions) or straight (rest segment lengths
    // = initial ones, zero rest curvature).
    bool straightRest = false;
    if (el["rest_shape"]) {
      const std::string rs = r_.text(el["rest_shape"], path + ".rest_shape");
      if (rs == "straight") straightRest = true;
      else if (rs != "initial")
        r_.fail(el["rest_shape"], path + ".rest_shape",
                "expected initial (the rest shape is the initial positions) or straight (rest "
                "segment lengths from the initial positions, zero rest curvature); got '" + rs + "'");
    }
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
    // Hinges: planar BeamHinge (dim 2) or spatial BeamHinge3D (dim 3). Rest positions of the
    // three nodes: initial, or (straight) along the first axis with the initial segment lengths.
    const int d = m.dim;
    for (size_t j = 1; j + 1 < ids.size(); ++j) {
      const std::vector<int> nd{ids[j - 1], ids[j], ids[j + 1]};
      VecX rest = VecX::Zero(3 * d);
      if (straightRest) {
        const double L1 = distance(m, nd[0], nd[1]), L2 = distance(m, nd[1], nd[2]);
        rest[d] = L1;
        rest[2 * d] = L1 + L2;
      } else {
        rest << m.nodes[nd[0]].position, m.nodes[nd[1]].position, m.nodes[nd[2]].position;
      }
      const std::string hn = name + ".hinge" + std::to_string(j);
      try {
        if (d == 2) m.elements.push_back(std::make_unique<BeamHinge>(hn, nd, sec, rest));
        else m.elements.push_back(std::make_unique<BeamHinge3D>(hn, nd, sec, rest));
      } catch (const std::invalid_argument& e) {  // e.g. a rest shape folded back at node j
        r_.fail(el["nodes"][j], at(path + ".nodes", j), std::string(e.what()) + "; expected a rest shape that does not turn by 180 degrees (or rest_shape: straight)");
      }
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
      } else if (type == "spherical") {
        r_.allowKeys(c, path, {"name", "type", "nodes"});
        const auto ids = nodeList(c, path, 2, 2);
        if (distance(m, ids[0], ids[1]) > 1e-9)
          r_.fail(c["nodes"], path + ".nodes", "a spherical joint joins coincident points; these are " +
                                                   std::to_string(distance(m, ids[0], ids[1])) + " m apart");
        m.constraints.push_back(std::make_unique<AttachedPointConstraint>(name, ids, VecX(), m.dim));
      } else if (type == "perpendicular") {
        r_.allowKeys(c, path, {"name", "type", "nodes", "value"});
        const auto ids = nodeList(c, path, 4, 4, true);  // [a, b, c, d]: a = c is common
        const VecX e1 = m.nodes[ids[1]].position - m.nodes[ids[0]].position;
        const VecX e2 = m.nodes[ids[3]].position - m.nodes[ids[2]].position;
        const double c0 = (!c["value"] || r_.isAuto(c["value"])) ? e1.dot(e2) : r_.number(c["value"], path + ".value");
        if (m.dim != 3) r_.fail(c["type"], path + ".type", "perpendicular needs a spatial scene (dimension 3)");
        m.constraints.push_back(BilinearConstraint::perpendicular(name, ids, c0));
      } else if (type == "point_on_plane") {
        readPointOnPlane(c, path, name, m);
      } else {
        r_.fail(c["type"], path + ".type", "unknown constraint type '" + type +
                                               "'; expected distance, fixed, spherical, perpendicular or point_on_plane");
      }
    }
  }

  /// Nodes kept on a plane fixed to a rigid body (or to space): one constraint per node.
  /// Nodes of the plane's own body are skipped: their distance to the plane is fixed already.
  void readPointOnPlane(const YAML::Node& c, const std::string& path, const std::string& name, Model& m) {
    r_.allowKeys(c, path, {"name", "type", "nodes", "beam", "body", "point", "normal"});
    if (m.dim != 3) r_.fail(c["type"], path + ".type", "point_on_plane needs a spatial scene (dimension 3)");
    std::vector<int> ids;
    if (c["beam"]) {  // every node of a beam (e.g. a spring drawn as a curve)
      const std::string b = r_.text(c["beam"], path + ".beam");
      if (!bodies_.count(b)) r_.fail(c["beam"], path + ".beam", "no beam named '" + b + "' (defined under elements)");
      ids = bodies_[b].nodes;
      if (c["nodes"]) r_.fail(c["nodes"], path + ".nodes", "give either nodes or beam, not both");
    } else {
      ids = nodeList(c, path, 1, 100000);
    }
    const Eigen::Vector3d origin = r_.vector(r_.require(c, "point", path), path + ".point", 3);
    const Eigen::Vector3d normal = r_.vector(r_.require(c, "normal", path), path + ".normal", 3);
    if (!(normal.norm() > 0)) r_.fail(c["normal"], path + ".normal", "expected a non-zero normal vector");
    const RigidBodyInfo* body = nullptr;
    if (c["body"]) {
      const std::string b = r_.text(c["body"], path + ".body");
      auto it = rigidBodies_.find(b);
      if (it == rigidBodies_.end()) r_.fail(c["body"], path + ".body", "no rigid_body named '" + b + "' (defined before this constraint)");
      body = &it->second;
    }
    for (size_t i = 0; i < ids.size(); ++i) {
      const Node& nd = m.nodes[ids[i]];
      const double off = normal.normalized().dot(Eigen::Vector3d(nd.position) - origin);
      if (std::abs(off) > 1e-9 * std::max(1.0, origin.norm()))
        r_.fail(c["beam"] ? c["beam"] : c["nodes"][i], c["beam"] ? path + ".beam" : at(path + ".nodes", i),
                "node '" + nd.name + "' is " + std::to_string(off) + " m off the plane at t = 0");
      if (nd.ground || (body && body->members.count(ids[i]))) continue;
      const std::string cn = ids.size() == 1 ? name : name + "[" + nd.name + "]";
      if (body)
        m.constraints.push_back(BilinearConstraint::pointOnBodyPlane(cn, body->basic, body->X0, ids[i], origin, normal));
      else
        m.constraints.push_back(BilinearConstraint::pointOnFixedPlane(cn, ids[i], origin, normal));
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
    r_.allowKeys(z, path, {"node", "component", "angle", "combination", "center_of_mass", "rotation", "axis",
                           "dp", "dv", "name"});
    {
      int kinds = 0;
      for (const char* k : {"node", "angle", "combination", "center_of_mass", "rotation"}) kinds += z[k] ? 1 : 0;
      if (kinds > 1)
        r_.fail(z, path, "give one SDOF kind: node (with component), angle, combination, center_of_mass "
                         "(with component) or rotation (with axis)");
      if (z["axis"] && !z["rotation"]) r_.fail(z["axis"], path + ".axis", "axis belongs to a rotation SDOF (rotation: <rigid body>)");
      if (z["component"] && (z["rotation"] || z["angle"] || z["combination"]))
        r_.fail(z["component"], path + ".component", "component belongs to node and center_of_mass SDOFs");
    }
    std::unique_ptr<Sdof> out;
    if (z["center_of_mass"] || z["rotation"]) {
      const bool com = static_cast<bool>(z["center_of_mass"]);
      const std::string key = com ? "center_of_mass" : "rotation";
      const YAML::Node bn = z[key];
      const std::string b = r_.text(bn, path + "." + key);
      auto it = rigidBodies_.find(b);
      if (it == rigidBodies_.end()) {
        std::string avail;
        for (const auto& [k, v] : rigidBodies_) avail += (avail.empty() ? "" : ", ") + k;
        r_.fail(bn, path + "." + key, "no rigid_body named '" + b + "'; expected the name of a rigid body of the scene (" +
                                          (avail.empty() ? std::string("the scene has none") : "the scene has: " + avail) + ")");
      }
      const RigidBodyInfo& body = it->second;
      const std::array<int, 4> basic{body.basic[0], body.basic[1], body.basic[2], body.basic[3]};
      if (com) {
        const int c = component(r_.require(z, "component", path), path + ".component", m);
        auto s = centerOfMassSdof(basic, body.X0, body.com, c);
        s->name = "com." + std::string(1, m.axisName(c)) + "(" + b + ")";
        out = std::move(s);
      } else {
        const YAML::Node an = r_.require(z, "axis", path);
        const std::string a = r_.text(an, path + ".axis");
        static const char* angleNames[3] = {"roll", "pitch", "yaw"};
        int axis = -1;
        for (int c = 0; c < 3; ++c)
          if (a.size() == 1 && a[0] == "xyz"[c]) axis = c;
        if (axis < 0) r_.fail(an, path + ".axis", "expected x (roll), y (pitch) or z (yaw); got '" + a + "'");
        auto s = std::make_unique<BodyRotationSdof>(basic, body.X0, axis);
        s->name = std::string(angleNames[axis]) + "(" + b + ")";
        out = std::move(s);
      }
    } else if (z["angle"]) {
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
                                    "max_newton_iterations", "frame_interval", "sensitivity_error_control",
                                    "rho_inf"});
    s.type = r_.text(r_.require(in, "type", "integrator"), "integrator.type");
    if (!isIntegratorType(s.type))
      r_.fail(in["type"], "integrator.type", std::string("expected ") + kIntegratorTypes + ", got '" + s.type + "'");
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
    if (in["rho_inf"]) {
      s.rhoInf = r_.number(in["rho_inf"], "integrator.rho_inf");
      if (!(s.rhoInf >= 0.0 && s.rhoInf <= 1.0)) r_.fail(in["rho_inf"], "integrator.rho_inf", "expected a number in [0, 1]");
    }
    if (in["sensitivity_error_control"])
      s.sensitivityErrorControl = r_.boolean(in["sensitivity_error_control"], "integrator.sensitivity_error_control");
  }

  void readOutputs(const YAML::Node& list, Scene& sc) {
    r_.requireList(list, "outputs");
    const Model& m = *sc.model;
    for (size_t i = 0; i < list.size(); ++i) {
      const YAML::Node o = list[i];
      const std::string path = at("outputs", i);
      r_.allowKeys(o, path, {"name", "node", "component", "angle"});
      OutputSpec spec;
      spec.name = r_.text(r_.require(o, "name", path), path + ".name");
      for (const auto& other : sc.outputs)
        if (other.name == spec.name) r_.fail(o["name"], path + ".name", "duplicate output name '" + spec.name + "'");
      if (o["angle"]) {  // signed angle [rad] from-vector -> to-vector about the axis
        if (o["node"] || o["component"]) r_.fail(o, path, "give either angle or node and component, not both");
        if (m.dim != 3) r_.fail(o["angle"], path + ".angle", "angle outputs need a spatial scene (dimension 3)");
        r_.allowKeys(o["angle"], path + ".angle", {"axis", "from", "to"});
        const AngleNodes an = angleNodes(o["angle"], path + ".angle");
        initialAngle(an, o["angle"], path + ".angle", m);
        spec.angle = an.list();
        sc.outputs.push_back(spec);
        continue;
      }
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
  struct RigidBodyInfo {
    std::vector<int> basic;            ///< the four basic points
    Eigen::Matrix<double, 3, 4> X0;    ///< their initial positions
    Eigen::Vector3d com;               ///< centre of mass at t = 0 [m]
    std::set<int> members;             ///< every node of the body
  };
  std::map<std::string, RigidBodyInfo> rigidBodies_;
  std::string geoFile_;  ///< the scene's Gmsh geometry, if any
  std::map<int, std::string> velocitySetBy_;  ///< node -> key path that set its initial velocity
  const Model* model_ = nullptr;
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
