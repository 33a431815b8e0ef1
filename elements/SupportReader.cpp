// The keys `support` and `symmetry` of a meshed body (solid, shell): node groups held in some
// directions by SupportConstraint rows (constraints/Support.hpp), through the constraint path.
//   support:  [{group: edge, fix: [y, z]}]   the listed axes of every node of the group held
//   symmetry: [{group: mid, normal: x}]      the group lies on a plane of symmetry; the normal
//                                            displacement held (normal: an axis or a vector)
//   diaphragm: [ends]                        (shells) the group's plane: its two in-plane
//                                            displacements held, the normal one free
// A shell's symmetry plane also holds the rotation it forbids (ShellReader.cpp adds the mirror
// hinges); fixed (ground, clamp) nodes are skipped, they are held already.
#include <Eigen/Eigenvalues>
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

/// The unit normal of the plane through points P (3D) and their largest distance from it [m];
/// false when the points are (nearly) collinear: their plane is undetermined.
bool fittedPlane(const std::vector<Eigen::Vector3d>& P, Eigen::Vector3d& normal) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& x : P) c += x / static_cast<double>(P.size());
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (const auto& x : P) S += (x - c) * (x - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(S);
  normal = es.eigenvectors().col(0);
  return es.eigenvalues()[1] > 1e-12 * es.eigenvalues()[2];
}

/// `diaphragm: [ends, {group: edge, normal: x}]` (3D): each free node's two displacement
/// components normal to `normal` are held (a diaphragm rigid in its plane, free out of it; the
/// rotation free). Without `normal` the group must lie on one plane, whose normal it takes
/// (several parallel end sections, or a straight edge, need `normal`).
void readDiaphragms(SceneContext& ctx, const YAML::Node& list, const std::string& path, const std::string& name,
                    const BodyMesh& mesh, const std::string& group, const std::vector<int>& ids) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  r.requireList(list, path);
  if (m.dim != 3) r.fail(list, path, "a diaphragm is a plane in a 3D scene; expected dimension: 3");
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string key = at(path, k);
    const bool named = list[k].IsScalar();
    if (!named) r.allowKeys(list[k], key, {"group", "normal"});
    const YAML::Node gNode = named ? list[k] : r.require(list[k], "group", key);
    const std::string gKey = named ? key : key + ".group";
    const std::string g = r.text(gNode, gKey);
    const std::vector<int> nodes = meshGroupNodes(r, mesh, group, gNode, gKey, g);
    std::vector<Eigen::Vector3d> P;
    for (int i : nodes) P.push_back(m.nodes[ids[i]].position);
    Eigen::Vector3d normal;
    const bool given = !named && list[k]["normal"];
    if (given) {
      normal = planeNormal(ctx, list[k]["normal"], key + ".normal").row(0).transpose();
    } else if (!fittedPlane(P, normal)) {
      r.fail(gNode, gKey, "the nodes of group '" + g + "' lie on a line, so the diaphragm's plane is undetermined; "
                          "expected {group: " + g + ", normal: <axis or vector>}");
    }
    double extent = 0.0;
    for (const auto& x : P) extent = std::max(extent, (x - P[0]).norm());
    for (size_t i = 0; i < P.size() && !given; ++i) {
      const double off = normal.dot(P[i] - P[0]);
      if (std::abs(off) > 1e-9 * std::max(1.0, extent))
        r.fail(gNode, gKey, "node '" + m.nodes[ids[nodes[i]]].name + "' of group '" + g + "' lies " + fmtNumber(off) +
                                " m off the diaphragm's plane through node '" + m.nodes[ids[nodes[0]]].name +
                                "'; expected the group on one plane (or give {group, normal} for parallel sections)");
    }
    // two unit directions spanning the plane
    const Eigen::Vector3d a = normal.unitOrthogonal(), b = normal.cross(a);
    MatX N(2, 3);
    N.row(0) = a.transpose();
    N.row(1) = b.transpose();
    for (int i : nodes) {
      const Node& nd = m.nodes[ids[i]];
      if (nd.ground) continue;
      m.constraints.push_back(std::make_unique<SupportConstraint>(name + ".diaphragm" + std::to_string(k) + "(" + nd.name + ")",
                                                                  ids[i], N, nd.position));
    }
  }
}

}  // namespace

void readSupports(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name,
                  const BodyMesh& mesh, const std::string& group, const std::vector<int>& ids,
                  std::vector<SymmetryPlane>* planes) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  if (el["diaphragm"]) readDiaphragms(ctx, el["diaphragm"], path + ".diaphragm", name, mesh, group, ids);
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
