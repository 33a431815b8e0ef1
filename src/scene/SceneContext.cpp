#include "scene/SceneContext.hpp"

#include <algorithm>
#include <sstream>

#include "meshes/GmshCurves.hpp"

namespace flexsens {

int SceneContext::node(const YAML::Node& n, const std::string& path) const {
  const std::string name = r.text(n, path);
  auto it = nodeIndex_.find(name);
  if (it == nodeIndex_.end()) r.fail(n, path, "no node named '" + name + "' is defined under nodes");
  return it->second;
}

std::vector<int> SceneContext::nodeList(const YAML::Node& item, const std::string& path, size_t minCount,
                                        size_t maxCount, bool allowRepeat) const {
  const YAML::Node list = r.require(item, "nodes", path);
  const std::string p = path + ".nodes";
  if (!list.IsSequence() || list.size() < minCount || list.size() > maxCount)
    r.fail(list, p, minCount == maxCount ? "expected a list of " + std::to_string(minCount) + " node names"
                                         : "expected a list of at least " + std::to_string(minCount) + " node names");
  std::vector<int> ids;
  std::set<int> seen;
  for (size_t i = 0; i < list.size(); ++i) {
    ids.push_back(node(list[i], at(p, i)));
    if (!seen.insert(ids.back()).second && !allowRepeat) r.fail(list[i], at(p, i), "the same node appears twice");
  }
  return ids;
}

std::string SceneContext::itemName(const YAML::Node& item, const std::string& path, const std::string& fallback) {
  std::string name = item["name"] ? r.text(item["name"], path + ".name") : fallback;
  if (!names_.insert(name).second)
    r.fail(item["name"] ? item["name"] : item, path + ".name", "duplicate name '" + name + "'");
  return name;
}

int SceneContext::addGeometryNode(const std::string& name, const Eigen::Vector3d& x, const YAML::Node& at,
                                  const std::string& key) {
  auto it = nodeIndex_.find(name);
  if (it != nodeIndex_.end()) {
    if ((Eigen::Vector3d(m.nodes[it->second].position) - x).norm() > 1e-9)
      r.fail(at, key, "the geometry places node '" + name + "' at two different positions");
    return it->second;
  }
  Node nd;
  nd.name = name;
  nd.position = x;
  nd.velocity = VecX::Zero(3);
  addNode(nd);
  return nodeIndex_[name];
}

std::vector<int> SceneContext::curveNodes(const YAML::Node& el, const std::string& path,
                                          std::vector<Eigen::Vector3d>* tangents) {
  const YAML::Node c = el["curve"];
  if (el["nodes"]) r.fail(el["nodes"], path + ".nodes", "give either nodes or curve (and segments), not both");
  if (geoFile.empty()) r.fail(c, path + ".curve", "curves need a geometry: add geometry: {gmsh: file.geo}");
  const std::string group = r.text(c, path + ".curve");
  const YAML::Node sn = r.require(el, "segments", path);
  const int segments = r.integer(sn, path + ".segments");
  if (segments < 1) r.fail(sn, path + ".segments", "expected at least 1 segment, got " + std::to_string(segments));
  if (segments > kMaxSegments)
    r.fail(sn, path + ".segments", "expected at most " + std::to_string(kMaxSegments) + " segments (kMaxSegments), got " +
                                       std::to_string(segments));
  const CurveMesh mesh = meshCurves(geoFile, {{group, segments}}, where(c, path + ".curve"), gmsh);
  std::vector<int> ids;
  const NodeChain& ch = mesh.chains.at(0);
  for (size_t i = 0; i < ch.names.size(); ++i)
    ids.push_back(addGeometryNode(ch.names[i], ch.positions[i], c, path + ".curve"));
  if (tangents) *tangents = ch.tangents;
  return ids;
}

bool SceneContext::slopeAlong(int id, const std::string& body, const Eigen::Vector3d& t, const YAML::Node& key,
                              const std::string& path) {
  const Node& nd = m.nodes[id];
  if (!nd.hasSlope()) {
    slopeOwner[id] = body;
    return false;
  }
  const auto owner = slopeOwner.find(id);
  if (owner == slopeOwner.end() || owner->second == body) return true;  // given in the scene, or this chain's
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  s.head(m.dim) = nd.slope.head(m.dim).normalized();
  if (s.dot(t) > 1 - 1e-9) return true;  // the chains continue each other smoothly
  auto fmt = [&](const Eigen::Vector3d& v) {
    std::ostringstream o;
    o << "(" << v[0] << ", " << v[1];
    if (m.dim == 3) o << ", " << v[2];
    return o.str() + ")";
  };
  r.fail(key, path,
         "node '" + nd.name + "' already carries the slope of ANCF chain '" + owner->second + "' along " + fmt(s) +
             "; '" + body + "' leaves it along " + fmt(t) +
             ": one slope per node would weld the two chains there. For a pin, end one chain at its own node "
             "at the same place and join the two by a spherical constraint; to weld them, give the node " +
             (nd.gradients(m.dim) == 3 ? std::string("its 'gradients' (r_x, r_y, r_z)") : std::string("a 'slope'")));
  return true;
}

void SceneContext::checkSlopes() const {
  for (const auto& [id, k] : givenSlopes)
    if (!slopeUsers.count(id))
      r.fail(k.node, k.path, "node '" + m.nodes[id].name + "' is on no ANCF element (ancf_cable, ancf_beam), so it carries no slope or gradients; remove them");
  for (const auto& [id, k] : clamps)
    if (!slopeUsers.count(id))
      r.fail(k.node, k.path, "clamped fixes a node's slope, but node '" + m.nodes[id].name +
                                 "' is on no ANCF element (ancf_cable, ancf_beam) and has none (a positions-only beam is "
                                 "clamped by a second ground node beside its end)");
}

Quantity SceneContext::length(const YAML::Node& item, const std::string& key, const std::string& path, int a,
                              int b) const {
  const YAML::Node n = item[key];
  if (!n || r.isAuto(n)) {
    const double d = distance(a, b);
    if (!(d > 0)) r.fail(n ? n : item, path, "the two nodes coincide, so 'auto' gives a zero length; give the length");
    return {d, -1};
  }
  return {r.positive(n, path), -1};
}

MatX SceneContext::positions() const {
  MatX X(m.dim, m.nodes.size());
  for (size_t i = 0; i < m.nodes.size(); ++i) X.col(i) = m.nodes[i].position;
  return X;
}

std::string SceneContext::where(const YAML::Node& n, const std::string& key) const {
  return r.file() + ":" + std::to_string(n.Mark().line + 1) + ":" + std::to_string(n.Mark().column + 1) +
         ": key '" + key + "'";
}

void SceneContext::requireSpatial(const YAML::Node& item, const std::string& path, const std::string& what) const {
  if (m.dim != 3) r.fail(item["type"], path + ".type", what + " needs a spatial scene (dimension 3)");
}

bool SceneContext::linked(int a, int b) const {
  if (m.nodes[a].ground && m.nodes[b].ground) return true;
  for (const auto& [name, body] : rigidBodies)
    if (body.members.count(a) && body.members.count(b)) return true;
  return false;
}

void SceneContext::setVelocity(int id, const Eigen::Vector3d& v, const YAML::Node& item, const std::string& path) {
  Node& nd = m.nodes[id];
  auto it = velocitySetBy_.find(id);
  if (it != velocitySetBy_.end() && (Eigen::Vector3d(nd.velocity) - v).norm() > 1e-9 * std::max(1.0, v.norm()))
    r.fail(item, path, "gives node '" + nd.name + "' an initial velocity that differs from the one " +
                           it->second + " gives it; the bodies sharing a node must move consistently");
  nd.velocity = v;
  velocitySetBy_[id] = path;
}

AngleNodes SceneContext::angleNodes(const YAML::Node& item, const std::string& path) const {
  auto pair = [&](const char* key) {
    const YAML::Node n = r.require(item, key, path);
    if (!n.IsSequence() || n.size() != 2) r.fail(n, path + "." + key, "expected a list of two node names [from, to]");
    return std::make_pair(node(n[0], path + "." + key + "[0]"), node(n[1], path + "." + key + "[1]"));
  };
  const auto a = pair("axis"), f = pair("from"), t = pair("to");
  return {a.first, a.second, f.first, f.second, t.first, t.second};
}

double SceneContext::initialAngle(const AngleNodes& an, const YAML::Node& item, const std::string& path) const {
  VecX x(18);
  const auto list = an.list();
  for (int a = 0; a < 6; ++a) x.segment<3>(3 * a) = m.nodes[list[a]].position;
  const Eigen::Vector3d n = x.segment<3>(3) - x.segment<3>(0);
  const Eigen::Vector3d u = n.normalized();
  auto perp = [&](const Eigen::Vector3d& w) { return (w - u * u.dot(w)).norm(); };
  if (!(n.norm() > 0) || !(perp(x.segment<3>(9) - x.segment<3>(6)) > 1e-9) ||
      !(perp(x.segment<3>(15) - x.segment<3>(12)) > 1e-9))
    r.fail(item, path, "the angle is undefined at the initial positions: the axis nodes coincide or a "
                       "vector is parallel to the axis");
  return jointAngleT<double>(x, nullptr);
}

}  // namespace flexsens
