#include "elements/MeshedBodyReader.hpp"

#include "elements/PlanarRigidBody.hpp"
#include "pim/Rigidization.hpp"  // AttachedPointConstraint
#include "scene/InputFiles.hpp"

namespace flexsens {

BodyMesh readBodyMesh(SceneContext& ctx, const YAML::Node& el, const std::string& path, int elementDim, bool withOrder,
                      YAML::Node& meshKey) {
  const YamlReader& r = ctx.r;
  BodyMeshRequest req;
  req.dim = elementDim;
  meshKey = r.require(el, "mesh", path);
  const std::string rel = r.text(meshKey, path + ".mesh");
  req.file = sceneDataFile(r, meshKey, path + ".mesh", rel, inputPolicy().maxMeshBytes);
  const bool isMsh = rel.size() > 4 && rel.substr(rel.size() - 4) == ".msh";
  req.group = r.text(r.require(el, "group", path), path + ".group");
  for (const char* k : {"size", "order"})
    if (isMsh && el[k]) r.fail(el[k], path + "." + k, "a .msh file is used as it is: remove " + std::string(k));
  if (el["size"]) req.size = r.positive(el["size"], path + ".size");
  if (withOrder && el["order"]) {
    req.order = r.integer(el["order"], path + ".order");
    if (req.order != 1 && req.order != 2) r.fail(el["order"], path + ".order", "expected 1 (linear) or 2 (quadratic elements)");
  }
  req.groupWhere = ctx.where(el["group"], path + ".group");
  req.sizeWhere = el["size"] ? ctx.where(el["size"], path + ".size") : ctx.where(meshKey, path + ".mesh");
  req.gmsh = ctx.gmsh;
  return meshBody(req, ctx.where(meshKey, path + ".mesh"));
}

namespace {

/// The mesh's nodes as scene nodes (named by their Physical Point, else <name>.<gmsh tag>); a
/// node of an existing name must sit where that node is. Returns the scene index of each.
std::vector<int> createMeshNodes(SceneContext& ctx, const std::string& path, const std::string& name,
                                 const BodyMesh& mesh, const YAML::Node& meshKey) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  const int d = m.dim;
  std::map<int, std::string> pointName;
  for (const auto& [pn, i] : mesh.points) pointName[i] = pn;
  std::vector<int> ids(mesh.positions.size());
  double extent = 0.0;
  for (const auto& x : mesh.positions) extent = std::max(extent, x.lpNorm<Eigen::Infinity>());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const Eigen::Vector3d& x3 = mesh.positions[i];
    if (d == 2 && std::abs(x3.z()) > 1e-12 * std::max(1.0, extent))
      r.fail(meshKey, path + ".mesh", "a planar scene needs a mesh in the plane z = 0; node " + std::to_string(mesh.gmshTags[i]) +
                                          " has z = " + fmtNumber(x3.z()));
    if (!(x3.lpNorm<Eigen::Infinity>() <= 1e6)) r.fail(meshKey, path + ".mesh", "expected mesh coordinates within +-1e6 m");
    const VecX x = x3.head(d);
    const auto pit = pointName.find(static_cast<int>(i));
    const std::string nn = pit != pointName.end() ? pit->second : name + "." + std::to_string(mesh.gmshTags[i]);
    if (ctx.hasNode(nn)) {
      const int id = ctx.nodeIndex(nn);
      if ((m.nodes[id].position - x).norm() > 1e-9)
        r.fail(meshKey, path + ".mesh", "the mesh places node '" + nn + "' away from the node of that name (" +
                                            fmtNumber((m.nodes[id].position - x).norm()) + " m)");
      ids[i] = id;
      continue;
    }
    Node nd;
    nd.name = nn;
    nd.position = x;
    nd.velocity = VecX::Zero(d);
    ctx.addNode(nd);
    ids[i] = ctx.nodeIndex(nn);
  }
  return ids;
}

}  // namespace

std::vector<int> meshGroupNodes(const YamlReader& r, const BodyMesh& mesh, const std::string& group,
                                const YAML::Node& at, const std::string& key, const std::string& g) {
  if (mesh.points.count(g)) return std::vector<int>{mesh.points.at(g)};
  auto it = mesh.groups.find(g);
  if (it == mesh.groups.end()) {
    std::string avail;
    for (const auto& [pn, i] : mesh.points) avail += (avail.empty() ? "" : ", ") + pn;
    for (const auto& [gn, ns] : mesh.groups) avail += (avail.empty() ? "" : ", ") + gn;
    r.fail(at, key, "no Physical Point or node group '" + g + "' on the mesh of " + group + "; available: " +
                        (avail.empty() ? "(none)" : avail));
  }
  return it->second;
}

namespace {

/// ground: and clamp: groups fixed (clamp only where the element takes it: clamp != nullptr).
void fixMeshGroups(SceneContext& ctx, const YAML::Node& el, const std::string& path, const BodyMesh& mesh,
                   const std::string& group, const std::vector<int>& ids, std::vector<MeshNodeGroup>* clamp) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  const int d = m.dim;
  auto groupNodes = [&](const YAML::Node& at, const std::string& key, const std::string& g) {
    return meshGroupNodes(r, mesh, group, at, key, g);
  };
  for (const char* fixKey : {"ground", "clamp", "simply_supported"}) {
    const bool isClamp = std::string(fixKey) != "ground";
    if (!el[fixKey] || (isClamp && !clamp)) continue;
    const YAML::Node gl = el[fixKey];
    r.requireList(gl, path + "." + fixKey);
    for (size_t k = 0; k < gl.size(); ++k) {
      const std::string key = at(path + "." + fixKey, k), g = r.text(gl[k], key);
      const std::vector<int> nodes = groupNodes(gl[k], key, g);
      for (int i : nodes) {
        m.nodes[ids[i]].ground = true;
        m.nodes[ids[i]].velocity = VecX::Zero(d);
      }
      if (isClamp) clamp->push_back({gl[k], key, g, nodes, std::string(fixKey) == "clamp"});
    }
  }
}

/// The rigid body's basic nodes (3D: A, B, C, D of a rigid_body; planar: A, B of a
/// planar_rigid_body) read before this element; InputError listing the available ones.
std::vector<int> attachBodyBasis(SceneContext& ctx, const YAML::Node& at, const std::string& key,
                                 const std::string& b) {
  const int d = ctx.m.dim;
  std::vector<int> basic;
  if (d == 3 && ctx.rigidBodies.count(b)) basic = ctx.rigidBodies.at(b).basic;
  if (d == 2 && ctx.planarRigidBodies.count(b))
    basic = {ctx.planarRigidBodies.at(b)[0], ctx.planarRigidBodies.at(b)[1]};
  if (basic.empty()) {
    std::string avail;
    if (d == 3)
      for (const auto& [bn, info] : ctx.rigidBodies) avail += (avail.empty() ? "" : ", ") + bn;
    else
      for (const auto& [bn, ab] : ctx.planarRigidBodies) avail += (avail.empty() ? "" : ", ") + bn;
    ctx.r.fail(at, key, "no " + std::string(d == 3 ? "rigid_body" : "planar_rigid_body") + " '" + b +
                            "' listed before this element; available: " + (avail.empty() ? "(none)" : avail));
  }
  return basic;
}

/// Node `id` welded to the body of basic nodes `basic` by a linear constraint named cname.
void attachNode(SceneContext& ctx, const std::vector<int>& basic, const MatX& X0, int id, const std::string& cname,
                const std::string& b) {
  Model& m = ctx.m;
  const VecX x = m.nodes[id].position;
  std::vector<int> cn = basic;
  cn.push_back(id);
  if (m.dim == 3) {
    const Eigen::Matrix3d B = X0.rightCols(3).colwise() - X0.col(0);
    const VecX c = B.inverse() * (x - X0.col(0));
    m.constraints.push_back(std::make_unique<AttachedPointConstraint>(cname, cn, c, 3));
    ctx.rigidBodies.at(b).members.insert(id);
  } else {
    const Eigen::Vector2d c = PlanarRigidBody::bodyCoordinates(X0.col(0), X0.col(1), x);
    Eigen::Matrix2d R;
    R << 0, -1, 1, 0;
    MatX J(2, 6);
    J << -(1 - c[0]) * Eigen::Matrix2d::Identity() + c[1] * R, -c[0] * Eigen::Matrix2d::Identity() - c[1] * R,
        Eigen::Matrix2d::Identity();
    m.constraints.push_back(std::make_unique<AttachedPointConstraint>(cname, cn, J));
  }
}

// --- attach: groups welded to a rigid body read before this element -----------------------
// Each node keeps its coordinates in the body's frame: r_i = r_A + sum_j c_j (r_Bj - r_A) for
// a rigid_body (basic points A, B, C, D), r_i = (1 - xi) r_A + xi r_B + eta R90 (r_B - r_A) for
// a planar_rigid_body (A, B): linear constraints (pim/Rigidization.hpp), as the bodies' own
// attached points.
void attachMeshGroups(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name,
                      const BodyMesh& mesh, const std::string& group, const std::vector<int>& ids) {
  if (!el["attach"]) return;
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  const YAML::Node al = el["attach"];
  r.requireList(al, path + ".attach");
  for (size_t k = 0; k < al.size(); ++k) {
    const std::string key = at(path + ".attach", k);
    r.allowKeys(al[k], key, {"group", "body"});
    const std::string g = r.text(r.require(al[k], "group", key), key + ".group");
    const std::string b = r.text(r.require(al[k], "body", key), key + ".body");
    const std::vector<int> nodes = meshGroupNodes(r, mesh, group, al[k]["group"], key + ".group", g);
    const std::vector<int> basic = attachBodyBasis(ctx, al[k]["body"], key + ".body", b);
    MatX X0(m.dim, basic.size());
    for (size_t j = 0; j < basic.size(); ++j) X0.col(j) = m.nodes[basic[j]].position;
    for (int i : nodes) {
      const int id = ids[i];
      if (std::find(basic.begin(), basic.end(), id) != basic.end()) continue;  // a basic point itself
      if (m.nodes[id].ground)
        r.fail(al[k]["group"], key + ".group", "node '" + m.nodes[id].name + "' of group '" + g +
                                                   "' is fixed (ground or clamp) and cannot also be attached to '" + b +
                                                   "'; attach the group or fix it, not both");
      attachNode(ctx, basic, X0, id, name + ".attach(" + m.nodes[id].name + ")", b);
    }
  }
}

/// Initial velocity: v_i = velocity + omega x (x_i - center) on the nodes not fixed.
void setMeshVelocities(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::vector<int>& ids) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  const int d = m.dim;
  if (el["velocity"] || el["angular_velocity"]) {
    if (el["center"] && !el["angular_velocity"])
      r.fail(el["center"], path + ".center", "center is the point angular_velocity turns about: give angular_velocity");
    const VecX v0 = el["velocity"] ? r.vector(el["velocity"], path + ".velocity", d) : VecX(VecX::Zero(d));
    const VecX c0 = el["center"] ? r.vector(el["center"], path + ".center", d) : VecX(VecX::Zero(d));
    Eigen::Vector3d w = Eigen::Vector3d::Zero();
    if (el["angular_velocity"]) {
      if (d == 2) w.z() = r.number(el["angular_velocity"], path + ".angular_velocity");
      else w = r.vector(el["angular_velocity"], path + ".angular_velocity", 3);
    }
    const std::string key = el["velocity"] ? path + ".velocity" : path + ".angular_velocity";
    const YAML::Node at0 = el["velocity"] ? el["velocity"] : el["angular_velocity"];
    for (int id : ids) {
      if (m.nodes[id].ground) continue;
      Eigen::Vector3d rel3 = Eigen::Vector3d::Zero();
      rel3.head(d) = m.nodes[id].position - c0;
      const VecX v = v0 + VecX(w.cross(rel3)).head(d);
      if (!(v.lpNorm<Eigen::Infinity>() <= 1e6)) r.fail(at0, key, "expected node velocities within +-1e6 m/s");
      if (d == 3) {
        ctx.setVelocity(id, Eigen::Vector3d(v), at0, key);  // checks a node shared with another body
      } else {
        m.nodes[id].velocity = v;
        ctx.velocitySetBy(id, key);
      }
    }
  }
}

}  // namespace

std::vector<int> addMeshNodes(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name,
                              const BodyMesh& mesh, const YAML::Node& meshKey, const std::string& group,
                              std::vector<MeshNodeGroup>* clamp, std::vector<SymmetryPlane>* planes) {
  const std::vector<int> ids = createMeshNodes(ctx, path, name, mesh, meshKey);
  fixMeshGroups(ctx, el, path, mesh, group, ids, clamp);
  attachMeshGroups(ctx, el, path, name, mesh, group, ids);
  readSupports(ctx, el, path, name, mesh, group, ids, planes);
  auto& listed = ctx.meshGroups[name];  // for `flexsens check`: each named point and node group
  for (const auto& [pn, i] : mesh.points) listed.push_back({pn, 1});
  for (const auto& [gn, ns] : mesh.groups) listed.push_back({gn, static_cast<int>(ns.size())});
  setMeshVelocities(ctx, el, path, ids);
  return ids;
}

Law readMaterialLaw(const YamlReader& r, const YAML::Node& el, const std::string& path) {
  if (!el["material"]) return Law::SaintVenantKirchhoff;
  const std::string law = r.text(el["material"], path + ".material");
  if (law == "neo_hookean") return Law::NeoHookean;
  if (law != "saint_venant_kirchhoff")
    r.fail(el["material"], path + ".material", "expected saint_venant_kirchhoff or neo_hookean; got '" + law + "'");
  return Law::SaintVenantKirchhoff;
}

}  // namespace flexsens
