// Scene reader of beam (elements/Beam.hpp, elements/BeamHinge3D.hpp): a node chain (listed or
// meshed from a Gmsh curve) becomes axial segments plus bending hinges sharing one section.
#include "elements/Beam.hpp"
#include "elements/BeamHinge3D.hpp"
#include "elements/BeamSectionReader.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

std::shared_ptr<BeamSection> readBeamSection(const YamlReader& r, const YAML::Node& el, const std::string& path) {
  auto sec = std::make_shared<BeamSection>();
  sec->E = {r.positive(r.require(el, "E", path), path + ".E"), -1};
  sec->density = {r.positive(r.require(el, "density", path), path + ".density"), -1};
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

void readBeam(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  r.allowKeys(el, path, {"name", "type", "nodes", "curve", "segments", "E", "density", "section", "rest_shape"});
  const auto ids = el["curve"] ? ctx.curveNodes(el, path) : ctx.nodeList(el, path, 2, 100000);
  // rest_shape: initial (default; rest = initial positions) or straight (rest segment lengths
  // = initial ones, zero rest curvature).
  bool straightRest = false;
  if (el["rest_shape"]) {
    const std::string rs = r.text(el["rest_shape"], path + ".rest_shape");
    if (rs == "straight") straightRest = true;
    else if (rs != "initial")
      r.fail(el["rest_shape"], path + ".rest_shape",
             "expected initial (the rest shape is the initial positions) or straight (rest "
             "segment lengths from the initial positions, zero rest curvature); got '" + rs + "'");
  }
  auto sec = readBeamSection(r, el, path);
  ctx.bindAll(name, sec->properties());
  ctx.bodies[name] = {ids, nullptr};
  for (size_t j = 0; j + 1 < ids.size(); ++j) {
    const double L = ctx.distance(ids[j], ids[j + 1]);
    if (!(L > 0)) r.fail(el["nodes"][j + 1], at(path + ".nodes", j + 1), "coincides with the previous node: zero segment length");
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
      const double L1 = ctx.distance(nd[0], nd[1]), L2 = ctx.distance(nd[1], nd[2]);
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
      r.fail(el["nodes"][j], at(path + ".nodes", j), std::string(e.what()) + "; expected a rest shape that does not turn by 180 degrees (or rest_shape: straight)");
    }
  }
}

}  // namespace flexsens
