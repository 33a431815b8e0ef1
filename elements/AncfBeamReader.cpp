// Scene reader of ancf_beam (elements/AncfBeam3D.hpp, 3D only): a node chain (listed or
// meshed from a Gmsh curve) becomes fully parameterized ANCF beam elements sharing one
// material and section; each node of the chain carries the gradients r_x, r_y, r_z. A node's
// gradients are the scene's `gradients` or else a frame from the chain: r_x its tangent (as
// the cable's slope), r_y the element's `y_axis` (default: the global axis least aligned with
// r_x) made normal to r_x, r_z = r_x x r_y. Each element's rest shape is straight, of its
// initial chord length, with orthonormal gradients: a chain that starts otherwise is refused
// unless `rest_shape: straight` says it starts deformed on purpose. A ground node is pinned (gradients free)
// unless it is `clamped` (every gradient fixed).
#include <sstream>

#include "elements/AncfBeam3D.hpp"
#include "elements/BeamSectionReader.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

namespace {

/// E, nu, density and section {side} or {width, height}; every entry bindable.
std::shared_ptr<AncfBeamSection> readSection(const YamlReader& r, const YAML::Node& el, const std::string& path) {
  auto sec = std::make_shared<AncfBeamSection>();
  sec->E = {r.physical(r.require(el, "E", path), path + ".E", kModulusRange), -1};
  const double nu = r.number(r.require(el, "nu", path), path + ".nu");
  if (!(nu > -1.0 && nu < 0.5)) r.fail(el["nu"], path + ".nu", "expected -1 < nu < 0.5; got " + std::to_string(nu));
  sec->nu = {nu, -1};
  sec->density = {r.physical(r.require(el, "density", path), path + ".density", kDensityRange), -1};
  const std::string sp = path + ".section";
  const YAML::Node s = r.require(el, "section", path);
  r.requireMap(s, sp);
  r.allowKeys(s, sp, {"side", "width", "height"});
  if (s["side"]) {
    if (s["width"] || s["height"]) r.fail(s, sp, "give either side (square section) or width and height, not both");
    sec->square = true;
    sec->side = {r.positive(s["side"], sp + ".side"), -1};
  } else {
    sec->width = {r.positive(r.require(s, "width", sp), sp + ".width"), -1};
    sec->height = {r.positive(r.require(s, "height", sp), sp + ".height"), -1};
  }
  return sec;
}

/// The element a-b's rest shape is straight, its chord long, with one orthonormal frame (r_x along
/// the chord) at both ends. A chain that starts otherwise (curved, twisted, stretched gradients)
/// would spring towards that straight shape: refused, naming the node and the deviation, unless
/// the scene says `rest_shape: straight`. (Curved rest shapes are not supported by ancf_beam.)
void requireRestAtStart(const YamlReader& r, const Model& m, int a, int b, const Eigen::Vector3d& chord,
                        const YAML::Node& key, const std::string& keyPath) {
  const VecX& ga = m.nodes[a].slope;
  const VecX& gb = m.nodes[b].slope;
  Eigen::Matrix3d Ga = Eigen::Map<const Eigen::Matrix3d>(ga.data());
  Eigen::Matrix3d Gb = Eigen::Map<const Eigen::Matrix3d>(gb.data());
  const double bend = std::max((Ga.col(0) - chord).norm(), (Gb.col(0) - chord).norm());
  const double twist = (Ga - Gb).norm();
  const double frame = (Ga.transpose() * Ga - Eigen::Matrix3d::Identity()).norm();
  if (bend <= 1e-9 && twist <= 1e-9 && frame <= 1e-9) return;
  std::ostringstream os;
  os << "the ancf_beam starts deformed between nodes '" << m.nodes[a].name << "' and '" << m.nodes[b].name
     << "' (r_x off the chord by " << bend << ", the two frames apart by " << twist
     << ", gradients off orthonormal by " << frame << "): its rest shape is straight, so a curved or twisted "
     << "chain would spring towards straight at t = 0. Curved rest shapes are not supported for ancf_beam "
     << "(nodes off one line start it bent): mesh a curved beam as a solid, or say rest_shape: straight to "
     << "start from this deformed shape on purpose";
  r.fail(key, keyPath, os.str());
}

}  // namespace

void readAncfBeam(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  ctx.requireSpatial(el, path, "ancf_beam");
  r.allowKeys(el, path, {"name", "type", "nodes", "curve", "segments", "E", "nu", "density", "section", "y_axis",
                         "rest_shape"});
  const auto ids = el["curve"] ? ctx.curveNodes(el, path) : ctx.nodeList(el, path, 2, 100000);
  auto nodeKey = [&](size_t j) { return el["nodes"] ? el["nodes"][j] : el["curve"]; };
  auto nodePath = [&](size_t j) { return el["nodes"] ? at(path + ".nodes", j) : path + ".curve"; };
  std::vector<Eigen::Vector3d> dir(ids.size() - 1);  // unit chord directions
  for (size_t j = 0; j + 1 < ids.size(); ++j) {
    const Eigen::Vector3d e = m.nodes[ids[j + 1]].position - m.nodes[ids[j]].position;
    if (!(e.norm() > 0))
      r.fail(nodeKey(j + 1), nodePath(j + 1), "coincides with the previous node: zero element length");
    dir[j] = e.normalized();
  }
  Eigen::Vector3d yAxis = Eigen::Vector3d::Zero();
  if (el["y_axis"]) {
    yAxis = r.vector(el["y_axis"], path + ".y_axis", 3);
    if (!(yAxis.norm() > 0)) r.fail(el["y_axis"], path + ".y_axis", "expected a nonzero direction");
  }
  for (size_t j = 0; j < ids.size(); ++j) {
    Node& nd = m.nodes[ids[j]];
    ctx.slopeUsers.insert(ids[j]);
    if (nd.hasSlope() && nd.gradients(3) != 3) {  // one slope, given or from an ancf_cable
      const auto given = ctx.givenSlopes.find(ids[j]);
      r.fail(given != ctx.givenSlopes.end() ? given->second.node : nodeKey(j),
             given != ctx.givenSlopes.end() ? given->second.path : nodePath(j),
             "node '" + nd.name + "' carries one slope (ancf_cable); an ancf_beam node takes gradients (r_x, r_y, r_z)");
    }
    if (ctx.givenSlopes.count(ids[j])) continue;
    const Eigen::Vector3d t = j == 0 ? dir[0] : (j + 1 == ids.size() ? dir[j - 1] : Eigen::Vector3d(dir[j - 1] + dir[j]));
    if (!(t.norm() > 1e-12))
      r.fail(nodeKey(j), nodePath(j), "the chain folds back at this node: give the node gradients");
    const Eigen::Vector3d tx = t.normalized();
    if (ctx.slopeAlong(ids[j], name, tx, nodeKey(j), nodePath(j))) continue;
    Eigen::Vector3d y = yAxis;
    if (!el["y_axis"]) {
      int least = 0;
      for (int c = 1; c < 3; ++c)
        if (std::abs(tx[c]) < std::abs(tx[least]) - 1e-12) least = c;
      y = Eigen::Vector3d::Unit(least);
    }
    y -= y.dot(tx) * tx;
    if (!(y.norm() > 1e-9 * yAxis.norm()) || !(y.norm() > 1e-9))
      r.fail(el["y_axis"], path + ".y_axis", "is along the beam at node '" + nd.name + "': expected a direction across it");
    y.normalize();
    nd.slope.resize(9);
    nd.slope << tx, y, tx.cross(y);
  }
  const bool startsDeformedOnPurpose = readStraightRest(
      r, el, path, "initial (default: the chain starts straight and untwisted) or straight (it may start deformed)");
  if (!startsDeformedOnPurpose)
    for (size_t j = 0; j + 1 < ids.size(); ++j) requireRestAtStart(r, m, ids[j], ids[j + 1], dir[j], nodeKey(j + 1), nodePath(j + 1));
  auto sec = readSection(r, el, path);
  ctx.bindAll(name, sec->properties());
  ctx.bodies[name] = {ids, nullptr, true};
  for (size_t j = 0; j + 1 < ids.size(); ++j) {
    ctx.slopeLinks.push_back({ids[j], ids[j + 1]});
    m.elements.push_back(std::make_unique<AncfBeam3D>(name + ".element" + std::to_string(j),
                                                      std::vector<int>{ids[j], ids[j + 1]}, sec,
                                                      ctx.distance(ids[j], ids[j + 1])));
  }
}

}  // namespace flexsens
