// Reads a scene file, validates every key against what it may hold and builds the Model.
// Validation and building happen in one pass so that every error still has its YAML mark.
// Elements and constraints are read by the per-kind readers of scene/KindTable.hpp; PIM cases
// by CaseReader.cpp; integrator and outputs by SettingsReader.cpp.
#include <algorithm>
#include <map>
#include <sstream>

#include "core/MemoryBudget.hpp"
#include "core/ModelChecks.hpp"
#include "core/RedundantRows.hpp"
#include "elements/SimplexShape.hpp"  // fmtNumber
#include "meshes/GmshCurves.hpp"
#include "scene/InputFiles.hpp"
#include "scene/KindTable.hpp"
#include "scene/SceneParts.hpp"

namespace flexsens {

namespace {
// Meshed bodies default to modified Newton: their Newton matrices are large and change little
// within a step, and keeping the factorization measured 2.96x faster on the solid pendulum and
// 2.4x on the shell panel (full Newton's edge, round-off instead of the tolerance after the
// last iteration, matters for the multibody models' sensitivity checks, not for these).
bool hasMeshedBody(const Model& m) {
  for (const auto& el : m.elements) {
    const std::string k = el->kind();
    if (k == "solid" || k == "shell_triangle") return true;
  }
  return false;
}
}  // namespace

namespace {

/// geometry: {gmsh: file.geo}: the file's named points become nodes now; beams name its
/// curves (curve + segments) and get their node chains when they are read. Gmsh is started
/// only here (meshes/GmshCurves), so scenes without geometry never start it.
void readGeometry(SceneContext& ctx, const YAML::Node& g) {
  const YamlReader& r = ctx.r;
  r.allowKeys(g, "geometry", {"gmsh"});
  if (ctx.m.dim != 3) r.fail(g, "geometry", "Gmsh geometry is for spatial scenes (dimension 3)");
  const std::string rel = r.text(r.require(g, "gmsh", "geometry"), "geometry.gmsh");
  ctx.geoFile = sceneDataFile(r, g["gmsh"], "geometry.gmsh", rel, inputPolicy().maxMeshBytes);
  const CurveMesh mesh = meshCurves(ctx.geoFile, {}, ctx.where(g["gmsh"], "geometry.gmsh"), ctx.gmsh);
  for (const auto& [name, x] : mesh.points) ctx.geometryPoints.insert(ctx.addGeometryNode(name, x, g["gmsh"], "geometry.gmsh"));
}

/// A listed node's position: given, or that of the geometry's named point it lists (`point`
/// >= 0), which a given position must equal.
VecX readNodePosition(SceneContext& ctx, const YAML::Node& nd, const std::string& path, int point) {
  const YamlReader& r = ctx.r;
  if (point >= 0 && !nd["position"]) return ctx.m.nodes[point].position;
  const VecX x = r.vector(r.require(nd, "position", path), path + ".position", ctx.m.dim);
  if (point >= 0 && (x - ctx.m.nodes[point].position).norm() > 1e-9)
    r.fail(nd["position"], path + ".position", "the geometry places point '" + ctx.m.nodes[point].name +
                                                   "' elsewhere; leave position out to take the geometry's");
  if (!(x.lpNorm<Eigen::Infinity>() <= kMaxCoordinate))
    r.fail(nd["position"], path + ".position", "expected coordinates within +-1e6 m (kMaxCoordinate)");
  return x;
}

/// limits: {gmsh_cpu_s, gmsh_memory_mb}: the bounds of the Gmsh child (meshes/GmshSandbox).
void readLimits(SceneContext& ctx, const YAML::Node& lim) {
  const YamlReader& r = ctx.r;
  r.allowKeys(lim, "limits", {"gmsh_cpu_s", "gmsh_memory_mb"});
  GmshLimits& g = ctx.gmsh.limits;
  if (const YAML::Node n = lim["gmsh_cpu_s"]) {
    g.cpuSeconds = r.positive(n, GmshLimits::kCpuKey);
    if (!(g.cpuSeconds <= GmshLimits::kMaxCpuSeconds))
      r.fail(n, GmshLimits::kCpuKey, "expected CPU seconds for Gmsh of at most " + fmtNumber(GmshLimits::kMaxCpuSeconds) + " (a day)");
  }
  if (const YAML::Node n = lim["gmsh_memory_mb"]) {
    g.memoryMb = r.positive(n, GmshLimits::kMemoryKey);
    if (!(g.memoryMb >= GmshLimits::kMinMemoryMb && g.memoryMb <= GmshLimits::kMaxMemoryMb))
      r.fail(n, GmshLimits::kMemoryKey, "expected the memory of Gmsh in MB from " + fmtNumber(GmshLimits::kMinMemoryMb) + " to " +
                                            fmtNumber(GmshLimits::kMaxMemoryMb));
  }
}

void readNodes(SceneContext& ctx, const YAML::Node& list) {
  const YamlReader& r = ctx.r;
  const int dim = ctx.m.dim;
  r.requireList(list, "nodes");
  if (list.size() == 0) r.fail(list, "nodes", "expected at least one node");
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node nd = list[i];
    const std::string path = at("nodes", i);
    r.allowKeys(nd, path, {"name", "position", "velocity", "ground", "slope", "gradients", "clamped"});
    Node node;
    node.name = r.text(r.require(nd, "name", path), path + ".name");
    const int point = ctx.hasNode(node.name) && ctx.geometryPoints.count(ctx.nodeIndex(node.name)) ? ctx.nodeIndex(node.name) : -1;
    if (ctx.hasNode(node.name) && point < 0) r.fail(nd["name"], path + ".name", "duplicate node name '" + node.name + "'");
    node.position = readNodePosition(ctx, nd, path, point);
    node.velocity = nd["velocity"] ? r.vector(nd["velocity"], path + ".velocity", dim) : VecX::Zero(dim);
    if (!(node.velocity.lpNorm<Eigen::Infinity>() <= kMaxVelocity))
      r.fail(nd["velocity"], path + ".velocity", "expected velocity components within +-1e6 m/s (kMaxVelocity)");
    node.ground = nd["ground"] ? r.boolean(nd["ground"], path + ".ground") : false;
    if (node.ground && node.velocity.norm() > 0)
      r.fail(nd["velocity"], path + ".velocity", "a ground node cannot have a velocity");
    const int id = point >= 0 ? point : static_cast<int>(ctx.m.nodes.size());
    if (nd["velocity"]) ctx.velocitySetBy(id, path + ".velocity");
    // slope: the initial position gradient of an ANCF node (a direction; stored with unit
    // length, the reference arc length's). clamped: the slope stays fixed.
    if (nd["slope"]) {
      node.slope = r.vector(nd["slope"], path + ".slope", dim);
      if (!(node.slope.norm() > 0)) r.fail(nd["slope"], path + ".slope", "expected a nonzero direction");
      node.slope.normalize();
      ctx.givenSlopes[id] = {nd["slope"], path + ".slope"};
    }
    // gradients (3D, ancf_beam): the initial r_x, r_y, r_z, a right-handed orthonormal frame.
    if (nd["gradients"]) {
      const std::string gp = path + ".gradients";
      const YAML::Node gn = nd["gradients"];
      if (dim != 3) r.fail(gn, gp, "gradients (r_x, r_y, r_z) belong to the spatial ancf_beam; a planar node takes slope");
      if (nd["slope"]) r.fail(gn, gp, "give either slope (ancf_cable) or gradients (ancf_beam), not both");
      r.requireList(gn, gp);
      if (gn.size() != 3)
        r.fail(gn, gp, "expected three vectors r_x, r_y, r_z (a right-handed orthonormal frame); got " +
                           std::to_string(gn.size()));
      Eigen::Matrix3d J;
      for (int g = 0; g < 3; ++g) J.col(g) = r.vector(gn[g], at(gp, g), 3);
      if (!((J.transpose() * J - Eigen::Matrix3d::Identity()).norm() < 1e-6 && J.determinant() > 0))
        r.fail(gn, gp, "expected three vectors r_x, r_y, r_z forming a right-handed orthonormal frame");
      node.slope = Eigen::Map<const VecX>(J.data(), 9);
      ctx.givenSlopes[id] = {gn, gp};
    }
    if (nd["clamped"]) {
      node.clamped = r.boolean(nd["clamped"], path + ".clamped");
      if (node.clamped) ctx.clamps[id] = {nd["clamped"], path + ".clamped"};
    }
    if (point >= 0) {  // the geometry's point, now listed
      ctx.m.nodes[point] = node;
      ctx.geometryPoints.erase(point);
    } else {
      ctx.addNode(node);
    }
  }
}

/// Beams on geometry curves: the segments of all of them, before any is meshed. Reading a
/// segment (its nodes, a 3D beam element, the hinge between segments) takes about 4.3 kB
/// (measured: `check` of 10 spatial beams of 10000 segments peaks at 491 MB, 60 MB of it the
/// program), so 100 beams of 10000 segments would need 4.7 GB before any matrix exists.
void requireSegmentMemory(const SceneContext& ctx, const YAML::Node& elements) {
  constexpr double kBytesPerSegment = 5e3;
  double total = 0.0;
  for (const auto& item : elements) {
    int segments = 0;
    // Counts beyond 1..kMaxSegments get their own located error when the beam is read.
    if (item.IsMap() && item["curve"] && item["segments"] && YAML::convert<int>::decode(item["segments"], segments) &&
        segments >= 1 && segments <= kMaxSegments)
      total += segments;
  }
  if (total <= 0) return;
  std::ostringstream what;
  what << ctx.r.file() << ": key 'elements': the beams' " << static_cast<long long>(total) << " segments in all";
  requireMemory(total * kBytesPerSegment, what.str(), "use fewer segments (the beams' segments key)");
}

/// `elements:` or `constraints:`: each item's `type` picks its reader from the kind table.
void readItems(SceneContext& ctx, const YAML::Node& list, const std::string& key, const char* what,
               const KindTable& kinds) {
  const YamlReader& r = ctx.r;
  r.requireList(list, key);
  // A YAML alias (*name) of a whole earlier item repeats it on the same nodes: a copy that adds
  // nothing a model needs (a 2.4 MB scene of 1e5 aliases of one rigid bar expands to 1e5
  // constraints on two coordinates). An alias is the anchored node itself, so it carries the
  // anchor's position: a position met twice in one list is such a repeat.
  std::map<std::pair<int, int>, size_t> seen;
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node item = list[i];
    const std::string path = at(key, i);
    r.requireMap(item, path);
    const auto [first, fresh] = seen.emplace(std::make_pair(item.Mark().line, item.Mark().column), i);
    if (!fresh)
      r.fail(item, path, "repeats " + at(key, first->second) + " through a YAML alias (*name): an identical " +
                             std::string(what) + " on the same nodes; give each its own entry (an anchor may "
                             "still share keys through a merge, <<: *name)");
    const std::string type = r.text(r.require(item, "type", path), path + ".type");
    const std::string name = ctx.itemName(item, path, type + std::to_string(i));
    auto it = kinds.readers.find(type);
    if (it == kinds.readers.end())
      r.fail(item["type"], path + ".type", "unknown " + std::string(what) + " type '" + type + "'; expected " + kinds.names());
    it->second(ctx, item, path, name);
  }
}

/// `per: element`: parameters <name>[0] ... <name>[k-1], one per element of the body, each
/// bound to that element's property (the reader gave each its own: perElementBodies).
void addPerElementParameters(SceneContext& ctx, const YAML::Node& pn, const std::string& path, const Parameter& family,
                             const CaseSelection* sel) {
  const YamlReader& r = ctx.r;
  const std::string per = r.text(pn["per"], path + ".per");
  if (per != "element") r.fail(pn["per"], path + ".per", "expected element, got '" + per + "'");
  const auto it = ctx.elementBindings.find(family.boundTo);
  if (it == ctx.elementBindings.end()) {
    const std::string of = family.boundTo.substr(0, family.boundTo.find('.'));
    if (ctx.bindings.count(family.boundTo))
      r.fail(pn["per"], path + ".per", "per: element binds a property of each element of a solid, a shell (bending: "
                                       "kirchhoff), a beam, an ancf_cable or an ancf_beam; '" + of + "' is none of these");
    r.fail(pn["property"], path + ".property", "'" + family.boundTo + "' is no property of a body's elements");
  }
  if (sel && !sel->params.count(family.name)) return;  // not a parameter of this case
  Model& m = ctx.m;
  for (size_t i = 0; i < it->second.size(); ++i) {
    const auto& [q, element] = it->second[i];
    Parameter par = family;
    par.name = family.name + "[" + std::to_string(i) + "]";
    par.boundTo = family.boundTo + "[" + std::to_string(i) + "]";
    par.family = family.name;
    par.element = element;
    par.nominal = q->constant;
    if (q->param >= 0) r.fail(pn, path, "'" + family.boundTo + "' is bound to another parameter already");
    q->param = int(m.parameters.size());
    m.parameters.push_back(par);
  }
}

/// parameters: each binds one property of an element or constraint (or a gravity component).
/// With a case selected, only the case's parameters become model parameters.
void readParameters(SceneContext& ctx, const YAML::Node& list, const CaseSelection* sel) {
  const YamlReader& r = ctx.r;
  Model& m = ctx.m;
  r.requireList(list, "parameters");
  std::set<std::string> seen;
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node pn = list[i];
    const std::string path = at("parameters", i);
    r.allowKeys(pn, path, {"name", "of", "property", "per"});
    Parameter par;
    par.name = r.text(r.require(pn, "name", path), path + ".name");
    if (!seen.insert(par.name).second) r.fail(pn["name"], path + ".name", "duplicate parameter name '" + par.name + "'");
    const std::string of = r.text(r.require(pn, "of", path), path + ".of");
    const std::string prop = r.text(r.require(pn, "property", path), path + ".property");
    par.boundTo = of + "." + prop;
    if (pn["per"]) {
      addPerElementParameters(ctx, pn, path, par, sel);
      continue;
    }
    auto it = ctx.bindings.find(par.boundTo);
    if (of == "gravity") {
      if (axisIndex(m, prop) < 0)
        r.fail(pn["property"], path + ".property", "gravity has the components of the scene's axes; got '" + prop + "'");
    } else if (it == ctx.bindings.end()) {
      std::string avail;
      for (const auto& [k, v] : ctx.bindings)
        if (k.rfind(of + ".", 0) == 0) avail += (avail.empty() ? "" : ", ") + k.substr(of.size() + 1);
      r.fail(pn["property"], path + ".property",
             avail.empty() ? "no element or constraint named '" + of + "' has parameters"
                           : "'" + of + "' has no property '" + prop + "'; expected one of: " + avail);
    }
    if (sel && !sel->params.count(par.name)) continue;  // not a parameter of this case
    const int k = static_cast<int>(m.parameters.size());
    if (of == "gravity") {  // gravity components are model-level quantities
      m.gravityParam.resize(m.dim, -1);
      const int c = axisIndex(m, prop);
      if (m.gravityParam[c] >= 0) r.fail(pn, path, "'gravity." + prop + "' is bound to another parameter already");
      m.gravityParam[c] = k;
      par.nominal = m.gravity[c];
      m.parameters.push_back(par);
      continue;
    }
    par.nominal = it->second.front()->constant;
    for (Quantity* q : it->second) {
      if (q->param >= 0) r.fail(pn, path, "'" + par.boundTo + "' is bound to another parameter already");
      q->param = k;
    }
    m.parameters.push_back(par);
  }
  if (sel)
    for (const auto& [name, node] : sel->paramNodes)
      if (!seen.count(name)) r.fail(node, sel->paramsPath, "no parameter named '" + name + "' under parameters");
}

/// Values given to scene parameters from outside the scene (a sweep's sample): every
/// quantity bound to a named parameter takes the value as if the scene had said it, before
/// PIM cases, rigid models and the parameters' nominal values are read. Entries the list
/// cannot bind are left to readParameters to report.
void applyParameterValues(SceneContext& ctx, const YAML::Node& list, const ParameterValues& values) {
  if (values.empty()) return;
  std::set<std::string> found;
  std::string names;
  for (size_t i = 0; list && list.IsSequence() && i < list.size(); ++i) {
    const YAML::Node pn = list[i];
    if (!pn.IsMap() || !pn["name"] || !pn["of"] || !pn["property"] || !pn["name"].IsScalar()) continue;
    const std::string name = pn["name"].Scalar(), of = pn["of"].Scalar(), prop = pn["property"].Scalar();
    names += (names.empty() ? "" : ", ") + name;
    const auto v = values.find(name);
    if (v == values.end()) continue;
    found.insert(name);
    if (of == "gravity") {
      if (axisIndex(ctx.m, prop) >= 0) ctx.m.gravity[axisIndex(ctx.m, prop)] = v->second;
    } else if (const auto b = ctx.bindings.find(of + "." + prop); b != ctx.bindings.end()) {
      for (Quantity* q : b->second) q->constant = v->second;
    }
  }
  for (const auto& [name, value] : values)
    if (!found.count(name))
      throw InputError(ctx.r.file() + ": a value is given for '" + name + "', but the scene has no parameter of that "
                       "name under parameters" + (names.empty() ? " (it defines none)" : " (its parameters: " + names + ")"));
}

/// Fails at node `name`'s entry under `nodes`, or at `geometry` for a node from Gmsh.
[[noreturn]] void failAtNode(const SceneContext& ctx, const YAML::Node& root, const std::string& name,
                             const std::string& what) {
  const YAML::Node list = root["nodes"];
  for (size_t i = 0; list && list.IsSequence() && i < list.size(); ++i)
    if (list[i]["name"] && list[i]["name"].Scalar() == name) ctx.r.fail(list[i], at("nodes", i), what);
  ctx.r.fail(root["geometry"] ? root["geometry"] : root, "geometry", what);
}

/// A free node nothing acts on has no mass and no equation: `check` must not call valid what
/// every integrator can only fail on (ModelChecks.hpp says which massless nodes pass).
void requireMass(const SceneContext& ctx, const YAML::Node& root, Scene& sc) {
  for (int id : nodesActedOnByNothing(ctx.m)) {
    const std::string& name = ctx.m.nodes[id].name;
    failAtNode(ctx, root, name, "free node '" + name + "' belongs to no element or constraint: it has no mass "
                                "and no equation; connect it to a massive element, make it ground, or remove it");
  }
  // Touched, but with a massless direction nothing restrains (a node held by one spring or one
  // distance only): the same singular matrix at the first step, so the same input error.
  // Kept as the scene's `dynamicsError`, raised by run, check and modes (not by the reader:
  // kernel tests build such models on purpose to check derivatives only).
  const UnrestrainedMassless u = unrestrainedMasslessDirection(ctx.m);
  if (u.nodes.empty()) return;
  const std::string& name = ctx.m.nodes[u.nodes.front()].name;
  try {
    failAtNode(ctx, root, name,
               "node '" + name + "' has no mass in the direction " + u.direction +
                   " and no stiffness, damping or constraint restrains it there at the initial state (every "
                   "integrator's matrix is singular); give it mass (an element with density), a constraint in "
                   "that direction, or a stiffness");
  } catch (const InputError& e) {
    sc.dynamicsError = e.what();
  }
}

Scene build(const std::string& file, const YAML::Node& root, const std::string& caseName,
            const ParameterValues& values) {
  Scene sc;
  sc.file = file;
  if (!root || root.IsNull())
    throw InputError(file + ":1:1: key 'dimension': the scene is empty; expected a mapping "
                     "with at least the keys dimension, nodes and integrator");
  sc.model = std::make_unique<Model>();
  Model& m = *sc.model;
  SceneContext ctx(file, m);
  const YamlReader& r = ctx.r;
  r.allowKeys(root, "", {"dimension", "plane", "gravity", "geometry", "nodes", "elements", "constraints",
                         "parameters", "integrator", "static", "outputs", "objectives", "optimize", "output", "description",
                         "cases", "limits"});
  const YAML::Node dimNode = r.require(root, "dimension", "");
  m.dim = r.integer(dimNode, "dimension");
  if (m.dim != 2 && m.dim != 3) r.fail(dimNode, "dimension", "expected 2 or 3");
  if (root["plane"]) {
    if (m.dim != 2) r.fail(root["plane"], "plane", "only planar (dimension 2) scenes name a plane");
    m.plane = r.text(root["plane"], "plane");
    if (m.plane != "xy" && m.plane != "xz" && m.plane != "yz") r.fail(root["plane"], "plane", "expected xy, xz or yz");
  }
  m.gravity = root["gravity"] ? r.vector(root["gravity"], "gravity", m.dim) : VecX::Zero(m.dim);
  ctx.gmsh.sceneDir = std::filesystem::path(file).parent_path().string();
  if (root["limits"]) readLimits(ctx, root["limits"]);
  if (root["geometry"]) readGeometry(ctx, root["geometry"]);
  // Nodes may all come from Gmsh: the geometry's named points or a meshed body (type: solid or shell).
  bool meshedBody = false;
  if (root["elements"] && root["elements"].IsSequence())
    for (const auto& item : root["elements"])
      if (item.IsMap() && item["type"] && item["type"].IsScalar() &&
          (item["type"].Scalar() == "solid" || item["type"].Scalar() == "shell"))
        meshedBody = true;
  if (root["nodes"] || !(root["geometry"] || meshedBody)) readNodes(ctx, r.require(root, "nodes", ""));
  // Bodies with per-element parameters, before their elements are read (checked later).
  if (root["parameters"] && root["parameters"].IsSequence())
    for (const auto& pn : root["parameters"])
      if (pn.IsMap() && pn["per"] && pn["of"] && pn["of"].IsScalar()) ctx.perElementBodies.insert(pn["of"].Scalar());
  if (root["elements"] && root["elements"].IsSequence()) requireSegmentMemory(ctx, root["elements"]);
  if (root["elements"]) readItems(ctx, root["elements"], "elements", "element", elementKinds());
  for (const auto& finish : ctx.afterElements) finish();
  sc.meshGroups = ctx.meshGroups;
  ctx.checkSlopes();
  deriveSlopeRates(ctx);
  if (root["constraints"]) readItems(ctx, root["constraints"], "constraints", "constraint", constraintKinds());
  applyParameterValues(ctx, root["parameters"], values);
  CaseSelection sel;
  sel.name = caseName;
  if (!caseName.empty() && !root["cases"])
    r.fail(root, "cases", "no case named '" + caseName + "': the scene defines no PIM cases");
  // yaml-cpp: a default Node is "defined" (null) and '=' assigns content, hence optional.
  const std::optional<YAML::Node> caseNode =
      root["cases"] ? selectCase(ctx, root["cases"], sc, sel) : std::optional<YAML::Node>();
  if (caseNode) applyRigidModels(ctx, *caseNode, sel);
  m.finalize();
  if (root["parameters"]) readParameters(ctx, root["parameters"], caseNode ? &sel : nullptr);
  else if (!sel.paramNodes.empty())
    r.fail(sel.paramNodes.front().second, sel.paramsPath, "the scene defines no parameters (add a 'parameters' list)");
  // Redundant rows (dependent at the initial positions) leave the model here, before the PIM
  // counts d - m_r and before any matrix is factorized; `check` and summary.json name them.
  leaveOutRedundantRows(m);
  if (caseNode) sc.pimCase = readPimCase(ctx, *caseNode, sel);
  if (root["static"]) readStaticSettings(r, root["static"], sc.statics);
  sc.hasIntegrator = root["integrator"] || !root["static"];
  if (sc.hasIntegrator) readIntegrator(r, r.require(root, "integrator", ""), sc.integrator);
  if (sc.hasIntegrator && !root["integrator"]["newton"] && hasMeshedBody(m)) sc.integrator.newton = "modified";
  if (root["outputs"]) readOutputs(ctx, root["outputs"], sc);
  if (root["objectives"]) readObjectives(ctx, root["objectives"], sc);
  if (root["optimize"]) readOptimize(ctx, root["optimize"], sc);
  readOutputSettings(r, root["output"], sc);
  if (m.n == 0) r.fail(root["nodes"], "nodes", "the scene has no free node: nothing can move");
  requireMass(ctx, root, sc);
  return sc;
}

}  // namespace

Scene readSceneText(const std::string& text, const std::string& name, const std::string& caseName,
                    const ParameterValues& values) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    std::ostringstream os;
    os << name << ":" << e.mark.line + 1 << ":" << e.mark.column + 1 << ": key '(syntax)': "
       << "YAML syntax error: " << e.msg;
    throw InputError(os.str());
  }
  return build(name, root, caseName, values);
}

Scene readScene(const std::string& path, const std::string& caseName, const ParameterValues& values) {
  std::string text;
  try {
    text = readBoundedFile(path, inputPolicy().maxSceneBytes, path);
  } catch (const std::runtime_error& e) {
    throw InputError(path + ": cannot read the scene file: " + e.what());
  }
  return readSceneText(text, path, caseName, values);
}

}  // namespace flexsens
