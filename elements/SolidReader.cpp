// Scene reader of solid (elements/Solid.hpp): a meshed body from a Gmsh file (meshes/GmshMesh).
//
//   - type: solid
//     mesh: plate.geo          # .geo (meshed here) or .msh (taken as is), relative to the scene
//     group: plate             # Physical Surface (dimension 2) or Physical Volume (dimension 3)
//     size: 0.05               # maximum element size [m] (.geo only; default: the file's sizes)
//     order: 2                 # 1 (default) or 2 (.geo only)
//     material: neo_hookean    # or saint_venant_kirchhoff (default)
//     state: plane_stress      # planar only: plane_stress (default) or plane_strain
//     E: 2.1e11                # [Pa]
//     nu: 0.3                  # [-], -1 < nu < 0.5
//     density: 7800            # [kg/m^3]
//     thickness: 0.01          # [m], planar only (plane strain: the depth the forces act on)
//     damping: {alpha: 0, beta: 1e-4}  # optional: alpha M v [1/s], Kelvin-Voigt beta [s]
//     ground: [root]           # Physical Points or node groups whose nodes are fixed
//     traction: [{group: tip, force: [0, -100]}]  # total dead force [N] spread uniformly
//                                                 # over the group's boundary facets
//     velocity: [1, 0]         # optional initial velocity [m/s] of every free node, plus
//     angular_velocity: 2      # omega [rad/s] (planar) or [wx, wy, wz] about center (default 0)
// Nodes on Physical Points take the point's name (joints and loads name them); the others
// are "<body>.<Gmsh node tag>". A planar scene reads the mesh's x, y (z must be 0) as its two
// axes. Every property (E, nu, density, thickness, alpha, beta) is bindable as a parameter.
#include <cmath>

#include "elements/PointForce.hpp"
#include "elements/Solid.hpp"
#include "elements/MeshedBodyReader.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

namespace {

/// Consistent nodal loads of a uniform traction on one straight facet (line or triangle, of
/// order 1 or 2), per unit traction: the facet's measure times the shape integrals.
std::vector<double> facetWeights(const std::vector<Eigen::Vector3d>& X, int dim) {
  const int n = static_cast<int>(X.size());
  if (dim == 2) {  // lines: 2 nodes (1/2, 1/2) or 3 nodes (1/6, 1/6, 2/3) times the length
    const double L = (X[1] - X[0]).norm();
    if (n == 2) return {L / 2, L / 2};
    return {L / 6, L / 6, 2 * L / 3};
  }
  const double A = 0.5 * (X[1] - X[0]).cross(X[2] - X[0]).norm();  // triangles: 1/3 or (0, 1/3)
  if (n == 3) return {A / 3, A / 3, A / 3};
  return {0, 0, 0, A / 3, A / 3, A / 3};
}

}  // namespace

void readSolid(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  const int d = m.dim;
  r.allowKeys(el, path, {"name", "type", "mesh", "group", "size", "order", "material", "state", "E", "nu", "density",
                        "thickness", "damping", "ground", "support", "symmetry", "attach", "traction", "velocity", "angular_velocity", "center"});
  auto props = std::make_shared<SolidProperties>();
  props->dim = d;
  // --- material -------------------------------------------------------------------------
  props->law.law = readMaterialLaw(r, el, path);
  props->law.planar = d == 3 ? PlanarState::None : PlanarState::PlaneStress;
  if (el["state"]) {
    if (d == 3) r.fail(el["state"], path + ".state", "a spatial solid has no planar state: remove state");
    const std::string st = r.text(el["state"], path + ".state");
    if (st == "plane_strain") props->law.planar = PlanarState::PlaneStrain;
    else if (st != "plane_stress")
      r.fail(el["state"], path + ".state", "expected plane_stress or plane_strain; got '" + st + "'");
  }
  props->E = {r.physical(r.require(el, "E", path), path + ".E", kModulusRange), -1};
  const double nu = r.number(r.require(el, "nu", path), path + ".nu");
  if (!(nu > -1.0 && nu < 0.5))
    r.fail(el["nu"], path + ".nu", "expected -1 < nu < 0.5: the compressible laws' lambda = E nu / ((1 + nu)(1 - 2 nu)) is "
                                   "infinite at nu = 0.5 (incompressible bodies are not supported); got " + fmtNumber(nu));
  props->nu = {nu, -1};
  props->density = {r.physical(r.require(el, "density", path), path + ".density", kDensityRange), -1};
  if (d == 2) props->thickness = {r.physical(r.require(el, "thickness", path), path + ".thickness", kThicknessRange), -1};
  else if (el["thickness"]) r.fail(el["thickness"], path + ".thickness", "a spatial solid has no thickness: remove it");
  if (el["damping"]) {
    const YAML::Node dn = el["damping"];
    const std::string dp = path + ".damping";
    r.allowKeys(dn, dp, {"alpha", "beta"});
    if (dn["alpha"]) props->alpha = {r.nonNegative(dn["alpha"], dp + ".alpha"), -1};
    if (dn["beta"]) props->beta = {r.nonNegative(dn["beta"], dp + ".beta"), -1};
  }
  // --- mesh and nodes ---------------------------------------------------------------------
  YAML::Node meshKey;
  const BodyMesh mesh = readBodyMesh(ctx, el, path, d, true, meshKey);
  const std::string group = r.text(el["group"], path + ".group");
  const std::vector<int> ids = addMeshNodes(ctx, el, path, name, mesh, meshKey, group);
  // --- elements -------------------------------------------------------------------------
  const int n = simplexNodes(mesh.shape);
  for (size_t c = 0; c < mesh.cells.size(); ++c) {
    std::vector<int> cell = mesh.cells[c];
    MatX X(d, n);
    auto fill = [&] {
      for (int j = 0; j < n; ++j) X.col(j) = mesh.positions[cell[j]].head(d);
    };
    fill();
    if (d == 2) {  // counterclockwise in the scene's plane: swap corners 1, 2 (and the midsides)
      const Eigen::Vector2d a = X.col(1) - X.col(0), b = X.col(2) - X.col(0);
      if (a.x() * b.y() - a.y() * b.x() < 0) {
        std::swap(cell[1], cell[2]);
        if (n == 6) std::swap(cell[3], cell[5]);
        fill();
      }
    }
    std::vector<int> nodes(n);
    for (int j = 0; j < n; ++j) nodes[j] = ids[cell[j]];
    try {
      auto cellProps = ctx.elementProperties(name, props, int(m.elements.size()));
      m.elements.push_back(std::make_unique<Solid>(name + ".cell" + std::to_string(c), nodes, cellProps, mesh.shape, X));
    } catch (const std::invalid_argument& e) {
      std::string gn;
      for (int j : cell) gn += (gn.empty() ? "" : " ") + std::to_string(mesh.gmshTags[j]);
      r.fail(meshKey, path + ".mesh", std::string(e.what()) + " (Gmsh nodes " + gn + ")");
    }
  }
  ctx.bindBody(name, props);
  std::vector<int> all;
  for (int id : ids) all.push_back(id);
  ctx.bodies[name] = {all, nullptr};
  // --- tractions ------------------------------------------------------------------------
  if (el["traction"]) {
    const YAML::Node tl = el["traction"];
    r.requireList(tl, path + ".traction");
    for (size_t k = 0; k < tl.size(); ++k) {
      const std::string key = at(path + ".traction", k);
      r.allowKeys(tl[k], key, {"group", "force"});
      const std::string g = r.text(r.require(tl[k], "group", key), key + ".group");
      const VecX F = r.vector(r.require(tl[k], "force", key), key + ".force", d);
      auto fit = mesh.facets.find(g);
      if (fit == mesh.facets.end() || fit->second.empty())
        r.fail(tl[k]["group"], key + ".group", "no boundary " + std::string(d == 2 ? "Physical Curve" : "Physical Surface") +
                                                   " '" + g + "' on the mesh of " + group);
      std::map<int, double> w;  // node -> share of the measure
      double total = 0.0;
      for (const auto& f : fit->second) {
        std::vector<Eigen::Vector3d> Xf;
        for (int i : f) Xf.push_back(mesh.positions[i]);
        const auto wf = facetWeights(Xf, d);
        for (size_t j = 0; j < f.size(); ++j) {
          w[f[j]] += wf[j];
          total += wf[j];
        }
      }
      if (!(total > 0)) r.fail(tl[k]["group"], key + ".group", "the group's facets have zero measure");
      for (const auto& [i, wi] : w) {
        if (m.nodes[ids[i]].ground || wi == 0.0) continue;
        std::vector<Quantity> comps;
        for (int cc = 0; cc < d; ++cc) comps.push_back({F[cc] * wi / total, -1});
        m.elements.push_back(std::make_unique<PointForce>(name + ".traction" + std::to_string(k) + "." + m.nodes[ids[i]].name,
                                                          ids[i], comps));
      }
    }
  }
}

}  // namespace flexsens
