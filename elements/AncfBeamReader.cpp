// Scene reader of ancf_beam (elements/AncfBeam3D.hpp, 3D only): a node chain (listed or
// meshed from a Gmsh curve) becomes fully parameterized ANCF beam elements sharing one
// material and section; each node of the chain carries the gradients r_x, r_y, r_z. A node's
// gradients are the scene's `gradients` or else a frame from the chain: r_x its tangent (a Gmsh
// curve's own; for listed nodes the bisector of the two chords at an inner node, the first /
// last chord reflected about the neighbour's tangent at an end: exact on a uniformly divided
// circular arc), r_y the element's
// `y_axis` made normal to r_x (default: the global axis least aligned with the first tangent,
// carried along the chain by projection, so the section does not turn about a curved axis),
// r_z = r_x x r_y. The rest shape (`rest_shape: initial`, the default) is the chain as it
// starts, curved or twisted; `rest_shape: straight` makes each element's rest shape straight,
// of its initial chord length, with orthonormal gradients (the chain then starts deformed on
// purpose). A ground node is pinned (gradients free) unless it is `clamped` (every gradient fixed).
#include <cmath>
#include <sstream>

#include "elements/AncfBeam3D.hpp"
#include "elements/BeamSectionReader.hpp"
#include "scene/KindTable.hpp"

namespace flexsens {

namespace {

/// A general section from its area A, Iy = int z^2 dA, Iz = int y^2 dA [m^2, m^4] and torsion
/// constant J [m^4]: a rectangle with the radii of gyration sqrt(Iy / A), sqrt(Iz / A) and the
/// area A (areaScale) carries the axial, bending and shear strains, its shear points moved to
/// scale G (Iy + Iz) to G J.
void setGeneralSection(AncfBeamSection& sec, double A, double Iy, double Iz, double J) {
  sec.general = true;
  sec.width = {std::sqrt(12.0 * Iz / A), -1};
  sec.height = {std::sqrt(12.0 * Iy / A), -1};
  sec.areaScale = A / (sec.width.constant * sec.height.constant);
  sec.torsionScale = std::sqrt(J / (Iy + Iz));
}

/// i_beam {height, width, web, flange}: an I section, its flanges (width x flange thick) across
/// r_y, its web (web thick) along r_z; thin-walled torsion constant (2 b t_f^3 + (h - 2 t_f) t_w^3) / 3.
void readIBeam(const YamlReader& r, const YAML::Node& n, const std::string& ip, AncfBeamSection& sec) {
  r.requireMap(n, ip);
  r.allowKeys(n, ip, {"height", "width", "web", "flange"});
  const double h = r.positive(r.require(n, "height", ip), ip + ".height");
  const double b = r.positive(r.require(n, "width", ip), ip + ".width");
  const double tw = r.positive(r.require(n, "web", ip), ip + ".web");
  const double tf = r.positive(r.require(n, "flange", ip), ip + ".flange");
  if (!(tw < b)) r.fail(n["web"], ip + ".web", "expected a web thinner than the flanges are wide (" + std::to_string(b) + ")");
  if (!(2 * tf < h)) r.fail(n["flange"], ip + ".flange", "expected two flanges thinner than the height (" + std::to_string(h) + ")");
  const double hw = h - 2 * tf;  // the web's height between the flanges
  const double A = 2 * b * tf + hw * tw;
  const double Iy = (b * h * h * h - (b - tw) * hw * hw * hw) / 12.0, Iz = (2 * tf * b * b * b + hw * tw * tw * tw) / 12.0;
  setGeneralSection(sec, A, Iy, Iz, std::min((2 * b * tf * tf * tf + hw * tw * tw * tw) / 3.0, Iy + Iz));
}

/// section {area, Iy, Iz, J}, {diameter} (a circle), {diameter, inner_diameter} (a tube) or
/// {i_beam: {...}}.
void readGeneralSection(const YamlReader& r, const YAML::Node& s, const std::string& sp, AncfBeamSection& sec) {
  if (s["i_beam"]) {
    for (const char* k : {"area", "Iy", "Iz", "J", "diameter", "inner_diameter"})
      if (s[k]) r.fail(s[k], sp + "." + k, "give either i_beam or area, Iy, Iz, J or diameter, not both");
    readIBeam(r, s["i_beam"], sp + ".i_beam", sec);
    return;
  }
  if (s["diameter"]) {
    for (const char* k : {"area", "Iy", "Iz", "J"})
      if (s[k]) r.fail(s[k], sp + "." + k, "give either diameter (a circle or tube) or area, Iy, Iz, J, not both");
    const double d = r.positive(s["diameter"], sp + ".diameter");
    const double di = s["inner_diameter"] ? r.positive(s["inner_diameter"], sp + ".inner_diameter") : 0.0;
    if (!(di < d)) r.fail(s["inner_diameter"], sp + ".inner_diameter", "expected less than the diameter");
    const double A = M_PI / 4 * (d * d - di * di), I = M_PI / 64 * (std::pow(d, 4) - std::pow(di, 4));
    setGeneralSection(sec, A, I, I, 2 * I);  // round: J is the polar moment
    return;
  }
  if (s["inner_diameter"])
    r.fail(s["inner_diameter"], sp + ".inner_diameter", "belongs to a tube: expected diameter beside it (the outer one)");
  const double A = r.positive(r.require(s, "area", sp), sp + ".area");
  const double Iy = r.positive(r.require(s, "Iy", sp), sp + ".Iy"), Iz = r.positive(r.require(s, "Iz", sp), sp + ".Iz");
  const double J = s["J"] ? r.positive(s["J"], sp + ".J") : Iy + Iz;
  if (J > Iy + Iz)
    r.fail(s["J"], sp + ".J", "expected at most Iy + Iz = " + std::to_string(Iy + Iz) +
                                  " (a section's torsion constant does not exceed its polar moment)");
  setGeneralSection(sec, A, Iy, Iz, J);
}

/// rotary_inertia [rho Iy, rho Iz] [kg m] of a general section: given rotary inertia per length.
void readRotaryInertia(const YamlReader& r, const YAML::Node& el, const std::string& path, AncfBeamSection& sec) {
  const YAML::Node n = el["rotary_inertia"];
  if (!n) return;
  if (!sec.general)
    r.fail(n, path + ".rotary_inertia", "belongs to a general section (area, Iy, Iz, diameter or i_beam): a rectangle's "
                                        "rotary inertia follows from density, width and height");
  const VecX v = r.vector(n, path + ".rotary_inertia", 2);
  if (!(v[0] > 0 && v[1] > 0)) r.fail(n, path + ".rotary_inertia", "expected two positive values [rho Iy, rho Iz] in kg m");
  sec.rotaryY = v[0];
  sec.rotaryZ = v[1];
}

/// E, nu, density and section {side}, {width, height} (every entry bindable) or a general
/// section (E, nu, density bindable).
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
  r.allowKeys(s, sp, {"side", "width", "height", "area", "Iy", "Iz", "J", "diameter", "inner_diameter", "i_beam"});
  const bool rectangle = s["side"] || s["width"] || s["height"];
  if (rectangle && (s["area"] || s["Iy"] || s["Iz"] || s["J"] || s["diameter"] || s["inner_diameter"] || s["i_beam"]))
    r.fail(s, sp, "give one kind of section: side, width and height, area with Iy, Iz (and J), diameter, or i_beam");
  if (!rectangle) readGeneralSection(r, s, sp, *sec);
  else if (s["side"]) {
    if (s["width"] || s["height"]) r.fail(s, sp, "give either side (square section) or width and height, not both");
    sec->square = true;
    sec->side = {r.positive(s["side"], sp + ".side"), -1};
  } else {
    sec->width = {r.positive(r.require(s, "width", sp), sp + ".width"), -1};
    sec->height = {r.positive(r.require(s, "height", sp), sp + ".height"), -1};
  }
  readRotaryInertia(r, el, path, *sec);
  return sec;
}

/// The element a-b's coordinates (positions, gradients) as they start.
VecX startCoordinates(const Model& m, int a, int b) {
  VecX e(24);
  e << m.nodes[a].position, m.nodes[a].slope, m.nodes[b].position, m.nodes[b].slope;
  return e;
}

/// True when the element starts straight along its chord with one orthonormal frame at both ends
/// (r_x along the chord): its rest shape is the straight one of its chord length.
bool startsStraight(const VecX& e) {
  const Eigen::Vector3d chord = (e.segment<3>(12) - e.segment<3>(0)).normalized();
  const Eigen::Matrix3d Ga = Eigen::Map<const Eigen::Matrix3d>(e.data() + 3);
  const Eigen::Matrix3d Gb = Eigen::Map<const Eigen::Matrix3d>(e.data() + 15);
  const double bend = std::max((Ga.col(0) - chord).norm(), (Gb.col(0) - chord).norm());
  return bend <= 1e-9 && (Ga - Gb).norm() <= 1e-9 && (Ga.transpose() * Ga - Eigen::Matrix3d::Identity()).norm() <= 1e-9;
}

/// Unit tangents of the chain's nodes from the unit chords dir: the chords' bisector inside,
/// the end chord reflected about the inner neighbour's tangent at an end (r_x along the chord
/// for a two-node chain). The caller checks for a fold (zero bisector).
std::vector<Eigen::Vector3d> chainTangents(const std::vector<Eigen::Vector3d>& dir) {
  const size_t n = dir.size() + 1;
  std::vector<Eigen::Vector3d> t(n);
  for (size_t j = 1; j + 1 < n; ++j) t[j] = dir[j - 1] + dir[j];
  if (n == 2) {
    t[0] = t[1] = dir[0];
    return t;
  }
  auto reflect = [](const Eigen::Vector3d& d, const Eigen::Vector3d& inner) {
    const Eigen::Vector3d ti = inner.normalized();
    return Eigen::Vector3d(2.0 * ti.dot(d) * d - ti);
  };
  t[0] = reflect(dir[0], t[1]);
  t[n - 1] = reflect(dir[n - 2], t[n - 2]);
  return t;
}

/// r_y before it is made normal to r_x = tx where the element gives no y_axis: the previous
/// node's r_y while it stands well across tx (the section does not turn about a curved axis),
/// else the global axis least aligned with tx.
Eigen::Vector3d defaultSectionAxis(const Eigen::Vector3d& carried, const Eigen::Vector3d& tx) {
  if ((carried - carried.dot(tx) * tx).norm() > 0.5) return carried;
  int least = 0;
  for (int c = 1; c < 3; ++c)
    if (std::abs(tx[c]) < std::abs(tx[least]) - 1e-12) least = c;
  return Eigen::Vector3d::Unit(least);
}

}  // namespace

void readAncfBeam(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  ctx.requireSpatial(el, path, "ancf_beam");
  r.allowKeys(el, path, {"name", "type", "nodes", "curve", "segments", "E", "nu", "density", "section", "y_axis",
                         "rest_shape", "rotary_inertia"});
  std::vector<Eigen::Vector3d> curveTangents;  // a Gmsh curve's own, else fitted to the chain below
  const auto ids = el["curve"] ? ctx.curveNodes(el, path, &curveTangents) : ctx.nodeList(el, path, 2, 100000);
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
  const std::vector<Eigen::Vector3d> tangent = curveTangents.empty() ? chainTangents(dir) : curveTangents;
  Eigen::Vector3d carried = Eigen::Vector3d::Zero();  // the previous node's r_y (default frames)
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
    const Eigen::Vector3d& t = tangent[j];
    if (!(t.norm() > 1e-12))
      r.fail(nodeKey(j), nodePath(j), "the chain folds back at this node: give the node gradients");
    const Eigen::Vector3d tx = t.normalized();
    if (ctx.slopeAlong(ids[j], name, tx, nodeKey(j), nodePath(j))) continue;
    Eigen::Vector3d y = el["y_axis"] ? yAxis : defaultSectionAxis(carried, tx);
    y -= y.dot(tx) * tx;
    if (!(y.norm() > 1e-9 * yAxis.norm()) || !(y.norm() > 1e-9))
      r.fail(el["y_axis"], path + ".y_axis", "is along the beam at node '" + nd.name + "': expected a direction across it");
    y.normalize();
    carried = y;
    nd.slope.resize(9);
    nd.slope << tx, y, tx.cross(y);
  }
  const bool straightRest = readStraightRest(
      r, el, path, "initial (default: the chain's starting shape, curved or twisted) or straight (it may start deformed)");
  auto sec = readSection(r, el, path);
  ctx.bindBody(name, sec);
  ctx.bodies[name] = {ids, nullptr, true};
  for (size_t j = 0; j + 1 < ids.size(); ++j) {
    ctx.slopeLinks.push_back({ids[j], ids[j + 1]});
    const VecX start = startCoordinates(m, ids[j], ids[j + 1]);
    const bool curved = !straightRest && !startsStraight(start);
    const std::string elName = name + ".element" + std::to_string(j);
    try {
      m.elements.push_back(std::make_unique<AncfBeam3D>(
          elName, std::vector<int>{ids[j], ids[j + 1]}, ctx.elementProperties(name, sec, int(m.elements.size())),
          curved ? AncfBeam3D::restLength(start) : ctx.distance(ids[j], ids[j + 1]), AncfBeam3D::kNormalPoints,
          AncfBeam3D::kShearPoints, curved ? &start : nullptr));
    } catch (const std::invalid_argument& e) {
      r.fail(nodeKey(j + 1), nodePath(j + 1), std::string(e.what()) + "; give the nodes' gradients along the chain");
    }
  }
}

}  // namespace flexsens
