// Scene reader of shell (elements/ShellMesh.hpp): a thin body meshed by Gmsh in a 3D scene.
//
//   - type: shell
//     mesh: panel.geo          # .geo (meshed here) or .msh (taken as is), relative to the scene
//     group: panel             # Physical Surface: linear triangles (flat or curved)
//     size: 0.05               # maximum element size [m] (.geo only; default: the file's sizes)
//     material: neo_hookean    # membrane law in plane stress; default saint_venant_kirchhoff
//     E: 7.0e10                # [Pa]
//     nu: 0.33                 # [-], -1 < nu < 0.5
//     density: 2700            # [kg/m^3]
//     thickness: 0.002         # [m]
//     rest_shape: initial      # or flat: hinges at rest when flat (dihedral angle 0)
//     bending: hinges          # or kirchhoff (elements/ShellKirchhoff.hpp); default hinges
//     membrane: patch          # or cst; default patch with kirchhoff (elements/ShellPatchMembrane.hpp), cst with hinges
//     damping: {alpha: 0.5, beta: 1e-4}  # optional Rayleigh: alpha M v [1/s], Kelvin-Voigt beta [s]
//     ground: [hinge_edge]     # Physical Points or node groups whose nodes are fixed
//     clamp: [root_edge]       # Physical Curves on the boundary: nodes fixed, edges clamped
//     simply_supported: [edge] # Physical Curves on the boundary: nodes fixed, rotation free
//     diaphragm: [ends]        # Physical Curves each on a plane: displacements in it held
//     velocity: [0, 0, 1]      # optional initial velocity [m/s] of every free node, plus
//     angular_velocity: [0, 0, 2]  # omega [rad/s] about center (default 0)
// rest_shape: the membranes' rest state is always the mesh; `initial` (default) takes each
// hinge's rest angle from the mesh too (the body starts at rest), `flat` makes it 0 (a curved
// mesh then starts bent and springs towards flat). Nodes on Physical Points take the point's
// name; the others are "<body>.<Gmsh node tag>". Properties E, nu, density, thickness, alpha,
// beta are bindable as parameters. clamp: the group's nodes are fixed as by ground, and each
// boundary edge of the mesh with both nodes in a clamp group gets a ShellClampHinge
// (elements/ShellClampHinge.hpp) holding its triangle's rest orientation (slope zero across the
// edge); a group with no such edge (a point, an interior curve, a curve of another surface) is
// an error. With bending: kirchhoff the clamped and symmetry-plane boundary edges hold the
// tangent across the edge instead (KirchhoffBoundaries), the other boundary edges are free.
#include <algorithm>
#include <map>

#include "elements/MeshedBodyReader.hpp"
#include "elements/ShellClampHinge.hpp"
#include "elements/ShellMesh.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

namespace {

/// symmetry: each boundary edge with both nodes on the plane gets the mirror hinge
/// (elements/ShellClampHinge.hpp) with its triangle's third node; a plane group with no such
/// edge is an error.
void addSymmetryHinges(SceneContext& ctx, const std::string& name, const BodyMesh& mesh,
                       const std::vector<std::array<int, 3>>& tris, const std::vector<int>& ids,
                       const std::shared_ptr<ShellProperties>& props, const std::vector<SymmetryPlane>& planes) {
  std::map<std::pair<int, int>, std::vector<int>> opposite;  // sorted edge -> third nodes
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k)
      opposite[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}].push_back(t[(k + 2) % 3]);
  int count = 0;
  for (const SymmetryPlane& pl : planes) {
    std::vector<bool> in(mesh.positions.size(), false);
    for (int i : pl.nodes) in[i] = true;
    bool hasEdge = false;
    for (const auto& [e, third] : opposite) {
      if (third.size() != 1 || !in[e.first] || !in[e.second]) continue;
      hasEdge = true;
      VecX rest(9);
      rest << mesh.positions[e.first], mesh.positions[e.second], mesh.positions[third[0]];
      ctx.m.elements.push_back(std::make_unique<ShellClampHinge>(name + ".symmetry" + std::to_string(count++),
                                                                 std::vector<int>{ids[e.first], ids[e.second], ids[third[0]]},
                                                                 props, rest, pl.normal, pl.point));
    }
    if (!hasEdge)
      ctx.r.fail(pl.at, pl.key, "the group holds no boundary edge of the shell (no edge of a single triangle with both "
                                "nodes in it); expected a Physical Curve on the boundary, where the shell meets its plane of symmetry");
  }
}

/// The fixed boundary edges of a Kirchhoff shell: clamped (both nodes clamped) and on a plane of
/// symmetry (both nodes in its group); the other boundary edges are free.
KirchhoffBoundaries kirchhoffBoundaries(const std::vector<std::array<int, 3>>& tris, const std::vector<bool>& clamped,
                                        const std::vector<SymmetryPlane>& planes) {
  KirchhoffBoundaries out;
  for (const auto& [i, j] : shellBoundaryEdges(tris)) {
    if (!clamped.empty() && clamped[i] && clamped[j]) out[{i, j}].fixed = true;
    for (const SymmetryPlane& pl : planes) {
      const bool inI = std::find(pl.nodes.begin(), pl.nodes.end(), i) != pl.nodes.end();
      const bool inJ = std::find(pl.nodes.begin(), pl.nodes.end(), j) != pl.nodes.end();
      if (inI && inJ) out[{i, j}] = {true, pl.normal, 0.0};
    }
  }
  return out;
}

/// A symmetry group of a Kirchhoff shell must hold a boundary edge (as for the hinges).
void checkSymmetryEdges(SceneContext& ctx, const std::vector<std::array<int, 3>>& tris,
                        const std::vector<SymmetryPlane>& planes, size_t nodes) {
  const auto boundary = shellBoundaryEdges(tris);
  for (const SymmetryPlane& pl : planes) {
    std::vector<bool> in(nodes, false);
    for (int i : pl.nodes) in[i] = true;
    bool hasEdge = false;
    for (const auto& [i, j] : boundary) hasEdge = hasEdge || (in[i] && in[j]);
    if (!hasEdge)
      ctx.r.fail(pl.at, pl.key, "the group holds no boundary edge of the shell (no edge of a single triangle with both "
                                "nodes in it); expected a Physical Curve on the boundary, where the shell meets its plane of symmetry");
  }
}

}  // namespace

void readShell(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  r.allowKeys(el, path, {"name", "type", "mesh", "group", "size", "material", "E", "nu", "density", "thickness",
                        "rest_shape", "bending", "membrane", "damping", "ground", "support", "symmetry", "diaphragm", "attach", "clamp", "simply_supported", "velocity", "angular_velocity", "center"});
  ctx.requireSpatial(el, path, "a shell");
  auto props = std::make_shared<ShellProperties>();
  props->law.law = readMaterialLaw(r, el, path);
  props->E = {r.physical(r.require(el, "E", path), path + ".E", kModulusRange), -1};
  const double nu = r.number(r.require(el, "nu", path), path + ".nu");
  if (!(nu > -1.0 && nu < 0.5))
    r.fail(el["nu"], path + ".nu", "expected -1 < nu < 0.5 (a compressible isotropic material); got " + fmtNumber(nu));
  props->nu = {nu, -1};
  props->density = {r.physical(r.require(el, "density", path), path + ".density", kDensityRange), -1};
  props->thickness = {r.physical(r.require(el, "thickness", path), path + ".thickness", kThicknessRange), -1};
  bool flatRest = false;
  if (el["rest_shape"]) {
    const std::string rs = r.text(el["rest_shape"], path + ".rest_shape");
    if (rs == "flat") flatRest = true;
    else if (rs != "initial") r.fail(el["rest_shape"], path + ".rest_shape", "expected initial or flat; got '" + rs + "'");
  }
  bool kirchhoff = false;
  if (el["bending"]) {
    const std::string b = r.text(el["bending"], path + ".bending");
    if (b == "kirchhoff") kirchhoff = true;
    else if (b != "hinges") r.fail(el["bending"], path + ".bending", "expected hinges or kirchhoff; got '" + b + "'");
  }
  if (ctx.perElementBodies.count(name) && !kirchhoff)
    r.fail(el["bending"] ? el["bending"] : el["type"], path + ".bending",
           "a parameter binds this shell per element, which needs bending: kirchhoff (each triangle's bending its "
           "own element); the default hinges bend across the edge between two triangles");
  bool patchMembrane = kirchhoff;  // the default membrane: patch with kirchhoff, cst with hinges
  if (el["membrane"]) {
    const std::string mk = r.text(el["membrane"], path + ".membrane");
    patchMembrane = mk == "patch";
    if (!patchMembrane && mk != "cst") r.fail(el["membrane"], path + ".membrane", "expected cst or patch; got '" + mk + "'");
    if (patchMembrane && !kirchhoff)
      r.fail(el["membrane"], path + ".membrane", "membrane: patch needs bending: kirchhoff (its fits); expected cst with bending: hinges");
  }
  if (el["damping"]) {
    const YAML::Node dn = el["damping"];
    const std::string dp = path + ".damping";
    r.allowKeys(dn, dp, {"alpha", "beta"});
    if (dn["alpha"]) props->alpha = {r.nonNegative(dn["alpha"], dp + ".alpha"), -1};
    if (dn["beta"] && kirchhoff)
      r.fail(dn["beta"], dp + ".beta", "the Kelvin-Voigt beta is built for bending: hinges only; expected alpha alone with bending: kirchhoff");
    if (dn["beta"]) props->beta = {r.nonNegative(dn["beta"], dp + ".beta"), -1};
  }
  YAML::Node meshKey;
  const BodyMesh mesh = readBodyMesh(ctx, el, path, 2, false, meshKey);
  const std::string group = r.text(el["group"], path + ".group");
  if (mesh.shape != Simplex::Tri3)
    r.fail(meshKey, path + ".mesh", "Physical Surface '" + group + "' holds " + simplexName(mesh.shape) +
                                        " elements; expected linear triangles (3 nodes) for a shell");
  std::vector<MeshNodeGroup> clampGroups;
  std::vector<SymmetryPlane> planes;
  const std::vector<int> ids = addMeshNodes(ctx, el, path, name, mesh, meshKey, group, &clampGroups, &planes);
  std::vector<std::array<int, 3>> tris;
  for (const auto& c : mesh.cells) tris.push_back({c[0], c[1], c[2]});
  std::vector<bool> clamped;
  if (!clampGroups.empty()) {
    clamped.assign(mesh.positions.size(), false);
    const auto boundary = shellBoundaryEdges(tris);
    for (const MeshNodeGroup& cg : clampGroups) {
      std::vector<bool> in(mesh.positions.size(), false);
      for (int i : cg.nodes) in[i] = true, clamped[i] = clamped[i] || cg.clamp;
      bool hasEdge = false;
      for (const auto& [i, j] : boundary) hasEdge = hasEdge || (in[i] && in[j]);
      if (!hasEdge)
        r.fail(cg.at, cg.key, "group '" + cg.name + "' holds no boundary edge of the shell (no edge of a single triangle with both "
                              "nodes in the group); expected a Physical Curve on the boundary of " + group +
                              (cg.clamp ? " (a clamp holds the rotation about an edge)" : " (a simple support is an edge condition; ground fixes points)"));
    }
  }
  KirchhoffSettings boundaries;
  if (kirchhoff) boundaries.boundary = kirchhoffBoundaries(tris, clamped, planes);
  boundaries.patchMembrane = patchMembrane;
  if (kirchhoff && ctx.perElementBodies.count(name))  // triangle k is element `first + k` (ShellMesh.cpp)
    for (size_t k = 0, first = m.elements.size(); k < tris.size(); ++k)
      boundaries.perTriangle.push_back(ctx.elementProperties(name, props, int(first + k)));
  try {
    buildShell(name, mesh.positions, tris, ids, props, flatRest, m.elements,
               [&](int i) { return std::to_string(mesh.gmshTags[i]); }, clamped, kirchhoff ? &boundaries : nullptr);
  } catch (const std::invalid_argument& e) {
    r.fail(meshKey, path + ".mesh", std::string(e.what()) + "; the node numbers are Gmsh node tags");
  }
  if (kirchhoff) checkSymmetryEdges(ctx, tris, planes, mesh.positions.size());
  else addSymmetryHinges(ctx, name, mesh, tris, ids, props, planes);
  ctx.bindBody(name, props);
  // A PIM body: its cloud is all its mesh nodes (a flat shell's is a planar cloud in 3D).
  ctx.bodies[name] = {ids, nullptr};
}

}  // namespace flexsens
