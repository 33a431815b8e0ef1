// Scene reader of beam (elements/Beam.hpp, elements/BeamHinge3D.hpp): a node chain (listed or
// meshed from a Gmsh curve) becomes axial segments plus bending hinges sharing one section (with
// per-element parameters each segment has its own, and a hinge the two it joins: HingeSections).
#include "elements/Beam.hpp"
#include "elements/BeamHinge3D.hpp"
#include "elements/BeamSectionReader.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

/// section: {side} (square) or {area, inertia}; every entry bindable as a parameter.
/// inertia: consistent (default: consistent segment masses from density) or none (massless:
/// no density, no mass, no gravity load; the free nodes' equations become equilibrium ones).
/// Shared with the ANCF cable (elements/BeamSectionReader.hpp).
std::shared_ptr<BeamSection> readBeamSection(const YamlReader& r, const YAML::Node& el, const std::string& path) {
  auto sec = std::make_shared<BeamSection>();
  sec->E = {r.physical(r.require(el, "E", path), path + ".E", kModulusRange), -1};
  if (el["inertia"]) {
    const std::string in = r.text(el["inertia"], path + ".inertia");
    if (in == "none") sec->massless = true;
    else if (in != "consistent")
      r.fail(el["inertia"], path + ".inertia",
             "expected consistent (segment masses from density, the default) or none (a massless beam: "
             "its free nodes carry no mass from it); got '" + in + "'");
  }
  if (sec->massless) {
    if (el["density"])
      r.fail(el["density"], path + ".density", "a beam with inertia: none has no mass: remove density");
    sec->density = {0.0, -1};
  } else {
    sec->density = {r.physical(r.require(el, "density", path), path + ".density", kDensityRange), -1};
  }
  const YAML::Node s = r.require(el, "section", path);
  const std::string sp = path + ".section";
  r.allowKeys(s, sp, {"side", "area", "inertia"});
  if (s["side"]) {
    if (s["area"] || s["inertia"]) r.fail(s, sp, "give either side (square section) or area and inertia, not both");
    sec->square = true;
    sec->side = {r.positive(s["side"], sp + ".side"), -1};
  } else {
    sec->area = {r.positive(r.require(s, "area", sp), sp + ".area"), -1};
    sec->inertia = {r.positive(r.require(s, "inertia", sp), sp + ".inertia"), -1};
  }
  return sec;
}

bool readStraightRest(const YamlReader& r, const YAML::Node& el, const std::string& path, const std::string& meaning) {
  if (!el["rest_shape"]) return false;
  const std::string rs = r.text(el["rest_shape"], path + ".rest_shape");
  if (rs != "straight" && rs != "initial")
    r.fail(el["rest_shape"], path + ".rest_shape", "expected " + meaning + "; got '" + rs + "'");
  return rs == "straight";
}

namespace {

/// clamp: start | end | both. The end node is a ground node and the beam's tangent there is
/// held by a bending hinge over a ghost ground node one segment length outside the beam on
/// the end segment's line, with the Voronoi length of half a segment (the half cell the end
/// node owns). Bending rest angle zero. The tip deflection of a linear cantilever then
/// converges as O(1/N^2) (tests/test_static_scene.cpp), where the end segment's distance to a
/// ground node one segment behind (no half cell) gives O(1/N).
void readClamp(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name,
               const std::vector<int>& ids, const std::vector<std::shared_ptr<BeamSection>>& segmentSections) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  const YAML::Node cn = el["clamp"];
  const std::string which = r.text(cn, path + ".clamp");
  if (which != "start" && which != "end" && which != "both")
    r.fail(cn, path + ".clamp", "expected start, end or both (the beam end held at its position and tangent); got '" + which + "'");
  for (const bool atStart : {true, false}) {
    if (which != "both" && (which == "start") != atStart) continue;
    const int root = atStart ? ids.front() : ids.back();
    const int next = atStart ? ids[1] : ids[ids.size() - 2];
    if (!m.nodes[root].ground)
      r.fail(cn, path + ".clamp", "a clamp holds the beam's end to the ground: node '" + m.nodes[root].name +
                                      "' must be a ground node (ground: true)");
    const VecX x0 = m.nodes[root].position, seg = x0 - m.nodes[next].position;
    Node ghost;
    ghost.name = name + (atStart ? ".clamp_start" : ".clamp_end");
    ghost.position = x0 + seg;  // one segment outside, on the end segment's line
    ghost.velocity = VecX::Zero(m.dim);
    ghost.ground = true;
    if (ctx.hasNode(ghost.name)) r.fail(cn, path + ".clamp", "a node named '" + ghost.name + "' exists already");
    ctx.addNode(ghost);
    const std::vector<int> nd{ctx.nodeIndex(ghost.name), root, next};
    VecX rest(3 * m.dim);
    rest << ghost.position, x0, m.nodes[next].position;
    const double half = 0.5 * seg.norm();
    const auto& sec = atStart ? segmentSections.front() : segmentSections.back();  // the end segment's
    if (m.dim == 2) m.elements.push_back(std::make_unique<BeamHinge>(ghost.name, nd, sec, rest, half));
    else m.elements.push_back(std::make_unique<BeamHinge3D>(ghost.name, nd, sec, rest, half));
  }
}

}  // namespace

void readBeam(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  r.allowKeys(el, path, {"name", "type", "nodes", "curve", "segments", "E", "density", "inertia", "section", "rest_shape", "clamp"});
  const auto ids = el["curve"] ? ctx.curveNodes(el, path) : ctx.nodeList(el, path, 2, 100000);
  const bool straightRest =
      readStraightRest(r, el, path,
                       "initial (the rest shape is the initial positions) or straight (rest "
                       "segment lengths from the initial positions, zero rest curvature)");
  auto sec = readBeamSection(r, el, path);
  ctx.bindBody(name, sec);
  ctx.bodies[name] = {ids, nullptr, false, sec->massless};
  std::vector<std::shared_ptr<BeamSection>> segmentSections;  // each its own with per-element parameters
  for (size_t j = 0; j + 1 < ids.size(); ++j) {
    const double L = ctx.distance(ids[j], ids[j + 1]);
    if (!(L > 0)) r.fail(el["nodes"][j + 1], at(path + ".nodes", j + 1), "coincides with the previous node: zero segment length");
    segmentSections.push_back(ctx.elementProperties(name, sec, int(m.elements.size())));
    m.elements.push_back(std::make_unique<BeamSegment>(name + ".segment" + std::to_string(j),
                                                       std::vector<int>{ids[j], ids[j + 1]}, segmentSections.back(), L));
  }
  if (el["clamp"]) readClamp(ctx, el, path, name, ids, segmentSections);
  // Hinges: planar BeamHinge (dim 2) or spatial BeamHinge3D (dim 3). Rest positions of the
  // three nodes: initial, or (straight) along the first axis with the initial segment lengths.
  const int d = m.dim;
  for (size_t j = 1; j + 1 < ids.size(); ++j) {
    const std::vector<int> nd{ids[j - 1], ids[j], ids[j + 1]};
    VecX rest = VecX::Zero(3 * d);
    if (straightRest) {
      const double L1 = ctx.distance(nd[0], nd[1]), L2 = ctx.distance(nd[1], nd[2]);
      rest[d] = L1;
      rest[2 * d] = L1 + L2;
    } else {
      rest << m.nodes[nd[0]].position, m.nodes[nd[1]].position, m.nodes[nd[2]].position;
    }
    const std::string hn = name + ".hinge" + std::to_string(j);
    try {
      // Between segments j - 1 and j: their sections (one and the same without per-element parameters).
      const auto &before = segmentSections[j - 1], &after = segmentSections[j];
      if (d == 2) m.elements.push_back(std::make_unique<BeamHinge>(hn, nd, before, rest, 0.0, after));
      else m.elements.push_back(std::make_unique<BeamHinge3D>(hn, nd, before, rest, 0.0, after));
    } catch (const std::invalid_argument& e) {  // e.g. a rest shape folded back at node j
      r.fail(el["nodes"][j], at(path + ".nodes", j), std::string(e.what()) + "; expected a rest shape that does not turn by 180 degrees (or rest_shape: straight)");
    }
  }
}

}  // namespace flexsens
