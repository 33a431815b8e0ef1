// Scene reader of ancf_cable (elements/AncfCable.hpp): a node chain (listed or meshed from a
// Gmsh curve) becomes ANCF cable elements sharing one section; each node of the chain carries
// a slope. A node's slope is the scene's `slope` (a direction) or else the chain's tangent
// there: the direction of the adjacent segment at the ends, the mean of the two adjacent unit
// directions inside. A ground node is pinned (its slope free) unless it is `clamped`.
#include <map>

#include "elements/AncfCable.hpp"
#include "elements/BeamSectionReader.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

void readAncfCable(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  const int d = m.dim;
  r.allowKeys(el, path, {"name", "type", "nodes", "curve", "segments", "E", "density", "section", "rest_shape",
                        "axial_points"});
  const auto ids = el["curve"] ? ctx.curveNodes(el, path) : ctx.nodeList(el, path, 2, 100000);
  auto nodeKey = [&](size_t j) { return el["nodes"] ? el["nodes"][j] : el["curve"]; };
  auto nodePath = [&](size_t j) { return el["nodes"] ? at(path + ".nodes", j) : path + ".curve"; };
  // straight: along the first axis with the initial element lengths, slopes along it.
  const bool straightRest =
      readStraightRest(r, el, path,
                       "initial (the rest shape is the initial positions and slopes) or straight "
                       "(element lengths from the initial positions, no rest curvature)");
  std::vector<VecX> dir(ids.size() - 1);  // unit chord directions
  for (size_t j = 0; j + 1 < ids.size(); ++j) {
    const VecX e = m.nodes[ids[j + 1]].position - m.nodes[ids[j]].position;
    if (!(e.norm() > 0))
      r.fail(nodeKey(j + 1), nodePath(j + 1), "coincides with the previous node: zero element length");
    dir[j] = e.normalized();
  }
  for (size_t j = 0; j < ids.size(); ++j) {
    Node& nd = m.nodes[ids[j]];
    ctx.slopeUsers.insert(ids[j]);
    if (nd.hasSlope() && nd.gradients(d) != 1) {
      const auto given = ctx.givenSlopes.find(ids[j]);
      r.fail(given != ctx.givenSlopes.end() ? given->second.node : nodeKey(j),
             given != ctx.givenSlopes.end() ? given->second.path : nodePath(j),
             "node '" + nd.name + "' carries the three gradients of an ancf_beam; an ancf_cable node has one slope");
    }
    const bool given = ctx.givenSlopes.count(ids[j]) > 0;
    VecX t = j == 0 ? dir[0] : (j + 1 == ids.size() ? dir[j - 1] : VecX(dir[j - 1] + dir[j]));
    if (!given && !(t.norm() > 1e-12))
      r.fail(nodeKey(j), nodePath(j), "the chain folds back at this node: give the node a slope");
    Eigen::Vector3d t3 = Eigen::Vector3d::Zero();
    if (!given) t3.head(d) = t.normalized();
    if (given || ctx.slopeAlong(ids[j], name, t3, nodeKey(j), nodePath(j))) continue;
    nd.slope = t.normalized();
  }
  // axial_points: 3 (default) or 2 (locking-free for thin beams, but with a zero-energy mode
  // that only a clamped slope removes; see elements/AncfCable.hpp).
  int axialPoints = AncfCable::kAxialPoints;
  if (el["axial_points"]) {
    axialPoints = r.integer(el["axial_points"], path + ".axial_points");
    if (axialPoints != 2 && axialPoints != 3)
      r.fail(el["axial_points"], path + ".axial_points", "expected 3 (default) or 2 (reduced, for thin clamped beams)");
  }
  auto sec = readBeamSection(r, el, path);
  ctx.bindBody(name, sec);
  ctx.bodies[name] = {ids, nullptr, true, sec->massless};
  for (size_t j = 0; j + 1 < ids.size(); ++j) {
    const Node &a = m.nodes[ids[j]], &b = m.nodes[ids[j + 1]];
    VecX rest(4 * d);
    if (straightRest) {
      const VecX e1 = VecX::Unit(d, 0);
      rest << VecX::Zero(d), e1, ctx.distance(ids[j], ids[j + 1]) * e1, e1;
    } else {
      rest << a.position, a.slope, b.position, b.slope;
    }
    try {
      ctx.slopeLinks.push_back({ids[j], ids[j + 1]});
      m.elements.push_back(std::make_unique<AncfCable>(name + ".element" + std::to_string(j),
                                                       std::vector<int>{ids[j], ids[j + 1]},
                                                       ctx.elementProperties(name, sec, int(m.elements.size())), rest,
                                                       axialPoints));
    } catch (const std::invalid_argument& e) {  // e.g. a curved rest shape in 3D
      r.fail(nodeKey(j + 1), nodePath(j + 1), std::string(e.what()) + (d == 3 ? " (or rest_shape: straight)" : ""));
    }
  }
}

// Initial slope rates. A scene gives node velocities; the slopes' rates follow from the motion
// of each element's chord d = r_b - r_a: dv = v_b - v_a = w x d + e d (rotation w normal to d,
// stretch rate e = d.dv / |d|^2, w = d x dv / |d|^2), applied to the slope: r_s' = w x r_s + e r_s.
// Exact for any rigid motion of a planar chain (curved or not) and of a straight spatial one (a
// spin about the chord moves no slope along it); a node between two elements takes the mean.
// Clamped slopes have no rate; a slope rate is zero where its elements only translate.
// The ancf_beam's gradients r_x, r_y, r_z: each turns with w; only r_x stretches with e.
void deriveSlopeRates(SceneContext& ctx) {
  Model& m = ctx.m;
  const int d = m.dim;
  std::map<int, std::pair<VecX, int>> sum;  // node -> (sum of candidates, count)
  for (const auto& [ia, ib] : ctx.slopeLinks) {
    const Node &a = m.nodes[ia], &b = m.nodes[ib];
    Eigen::Vector3d ch = Eigen::Vector3d::Zero(), dv = Eigen::Vector3d::Zero();
    ch.head(d) = b.position.head(d) - a.position.head(d);
    if (a.velocity.size()) dv.head(d) -= a.velocity.head(d);
    if (b.velocity.size()) dv.head(d) += b.velocity.head(d);
    const double dd = ch.squaredNorm();
    const Eigen::Vector3d w = ch.cross(dv) / dd;  // planar: along the third axis
    const double e = ch.dot(dv) / dd;
    for (int id : {ia, ib}) {
      const Node& nd = m.nodes[id];
      if (!nd.slopeFree()) continue;
      VecX rate(nd.slope.size());
      for (int g = 0; g < nd.gradients(d); ++g) {
        Eigen::Vector3d r1 = Eigen::Vector3d::Zero();
        r1.head(d) = nd.slope.segment(g * d, d);
        rate.segment(g * d, d) = (w.cross(r1) + (g == 0 ? e : 0.0) * r1).head(d);
      }
      auto it = sum.find(id);
      if (it == sum.end())
        sum[id] = {rate, 1};
      else {
        it->second.first += rate;
        it->second.second++;
      }
    }
  }
  for (auto& [id, sc] : sum)
    if (m.nodes[id].slopeRate.size() == 0) m.nodes[id].slopeRate = sc.first / sc.second;
}

}  // namespace flexsens
