// The keys `support` and `symmetry` of a meshed body (solid, shell): node groups held in some
// directions by SupportConstraint rows (constraints/Support.hpp), through the constraint path.
//   support:  [{group: edge, fix: [y, z]}]   the listed axes of every node of the group held
//   symmetry: [{group: mid, normal: x}]      the group lies on a plane of symmetry; the normal
//                                            displacement held (normal: an axis or a vector)
// A shell's symmetry plane also holds the rotation it forbids (ShellReader.cpp adds the mirror
// hinges); fixed (ground, clamp) nodes are skipped, they are held already.
#include <cmath>

#include "constraints/Support.hpp"
#include "elements/MeshedBodyReader.hpp"
#include "scene/SceneParts.hpp"

namespace flexsens {

namespace {

std::string axesOf(const Model& m) {
  std::string axes;
  for (int k = 0; k < m.dim; ++k) axes += std::string(axes.empty() ? "" : ", ") + m.axisName(k);
  return axes;
}

/// `fix: [y, z]`: unit rows of the named axes (distinct, at least one).
MatX fixedAxes(const SceneContext& ctx, const YAML::Node& fix, const std::string& key) {
  const YamlReader& r = ctx.r;
  r.requireList(fix, key);
  if (fix.size() == 0) r.fail(fix, key, "expected at least one axis (" + axesOf(ctx.m) + ")");
  MatX N = MatX::Zero(fix.size(), ctx.m.dim);
  for (size_t k = 0; k < fix.size(); ++k) {
    const std::string a = r.text(fix[k], at(key, k));
    const int c = axisIndex(ctx.m, a);
    if (c < 0) r.fail(fix[k], at(key, k), "expected one of the scene's axes (" + axesOf(ctx.m) + "); got '" + a + "'");
    for (size_t j = 0; j < k; ++j)
      if (N(j, c) != 0.0) r.fail(fix[k], at(key, k), "axis '" + a + "' is listed twice");
    N(k, c) = 1.0;
  }
  return N;
}

/// `normal: x` (an axis) or `normal: [nx, ny(, nz)]` (normalized): one unit row.
MatX planeNormal(const SceneContext& ctx, const YAML::Node& n, const std::string& key) {
  const YamlReader& r = ctx.r;
  MatX N = MatX::Zero(1, ctx.m.dim);
  if (n.IsScalar()) {
    const std::string a = r.text(n, key);
    const int c = axisIndex(ctx.m, a);
    if (c < 0) r.fail(n, key, "expected an axis (" + axesOf(ctx.m) + ") or a vector; got '" + a + "'");
    N(0, c) = 1.0;
    return N;
  }
  const VecX v = r.vector(n, key, ctx.m.dim);
  if (!(v.norm() > 0)) r.fail(n, key, "expected a nonzero normal");
  N.row(0) = v.normalized().transpose();
  return N;
}

}  // namespace

void readSupports(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name,
                  const BodyMesh& mesh, const std::string& group, const std::vector<int>& ids,
                  std::vector<SymmetryPlane>* planes) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  for (const char* listKey : {"support", "symmetry"}) {
    if (!el[listKey]) continue;
    const bool symmetry = std::string(listKey) == "symmetry";
    const YAML::Node list = el[listKey];
    r.requireList(list, path + "." + listKey);
    for (size_t k = 0; k < list.size(); ++k) {
      const std::string key = at(path + "." + listKey, k);
      if (symmetry) r.allowKeys(list[k], key, {"group", "normal"});
      else r.allowKeys(list[k], key, {"group", "fix"});
      const std::string g = r.text(r.require(list[k], "group", key), key + ".group");
      const std::vector<int> nodes = meshGroupNodes(r, mesh, group, list[k]["group"], key + ".group", g);
      const MatX N = symmetry ? planeNormal(ctx, r.require(list[k], "normal", key), key + ".normal")
                              : fixedAxes(ctx, r.require(list[k], "fix", key), key + ".fix");
      if (symmetry) {  // the group must lie on the plane through its first node
        double extent = 0.0;
        for (int i : nodes) extent = std::max(extent, (m.nodes[ids[i]].position - m.nodes[ids[nodes[0]]].position).norm());
        for (int i : nodes) {
          const double off = (N * (m.nodes[ids[i]].position - m.nodes[ids[nodes[0]]].position))(0);
          if (std::abs(off) > 1e-9 * std::max(1.0, extent))
            r.fail(list[k]["group"], key + ".group", "node '" + m.nodes[ids[i]].name + "' of group '" + g + "' lies " +
                                                        fmtNumber(off) + " m off the symmetry plane through node '" +
                                                        m.nodes[ids[nodes[0]]].name + "'; expected the group on one plane normal to `normal`");
        }
        if (planes) planes->push_back({list[k]["group"], key + ".group", nodes, N.row(0).transpose(),
                                       m.nodes[ids[nodes[0]]].position});
      }
      for (int i : nodes) {
        const Node& nd = m.nodes[ids[i]];
        if (nd.ground) continue;
        m.constraints.push_back(std::make_unique<SupportConstraint>(name + "." + listKey + std::to_string(k) + "(" + nd.name + ")",
                                                                    ids[i], N, nd.position));
      }
    }
  }
}

}  // namespace flexsens
