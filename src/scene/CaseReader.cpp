// PIM cases of a scene: which case is built, its rigid models (F-R twins), its rigidized
// bodies and its SDOFs (pim/Sdof.hpp).
#include <algorithm>
#include <sstream>

#include "pim/Rigidization.hpp"
#include "scene/SceneParts.hpp"

namespace flexsens {

/// A node SDOF's or output's component: an axis, or for a node that carries a slope (ANCF) an axis with a
/// prime, the slope's component ("x'" = dx/ds; on an ancf_beam node r_x's), or for an ancf_beam
/// node an axis, '_' and a reference axis, a gradient's component ("z_y" = dz/dy, of r_y);
/// returned as in Model::dof.
int nodeComponent(const SceneContext& ctx, int nd, const YAML::Node& n, const std::string& path) {
  const std::string t = ctx.r.text(n, path);
  if (t.size() == 3 && t[1] == '_' && ctx.m.dim == 3) {
    const int c = axisIndex(ctx.m, t.substr(0, 1)), j = axisIndex(ctx.m, t.substr(2, 1));
    if (c >= 0 && j >= 0) {
      if (ctx.m.nodes[nd].gradients(3) != 3)
        ctx.r.fail(n, path, "node '" + ctx.m.nodes[nd].name + "' carries no gradients r_x, r_y, r_z (it is on no ancf_beam); "
                            "expected an axis" + std::string(ctx.m.nodes[nd].hasSlope() ? " or a slope component x'" : ""));
      return 3 + 3 * j + c;
    }
  }
  const int c = t.size() == 2 && t[1] == '\'' ? axisIndex(ctx.m, t.substr(0, 1)) : -1;
  if (c < 0) return component(ctx, n, path);
  if (!ctx.m.nodes[nd].hasSlope())
    ctx.r.fail(n, path, "node '" + ctx.m.nodes[nd].name + "' carries no slope (it is on no ancf_cable); expected an axis");
  return ctx.m.dim + c;
}

namespace {

/// The listed bodies (names under `key`), checked to exist as flexible bodies.
std::vector<std::string> bodyList(SceneContext& ctx, const YAML::Node& c, const std::string& key,
                                  const CaseSelection& sel) {
  const YamlReader& r = ctx.r;
  std::vector<std::string> out;
  if (!c[key]) return out;
  const std::string path = sel.path + "." + key;
  r.requireList(c[key], path);
  for (size_t i = 0; i < c[key].size(); ++i) {
    const std::string b = r.text(c[key][i], at(path, i));
    if (!ctx.bodies.count(b)) {
      std::string avail;
      for (const auto& [k, v] : ctx.bodies) avail += (avail.empty() ? "" : ", ") + k;
      r.fail(c[key][i], at(path, i), "no flexible body (beam or spring) named '" + b + "'" +
                                          (avail.empty() ? std::string() : "; the scene has: " + avail));
    }
    out.push_back(b);
  }
  return out;
}

std::string jsonish(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

/// center_of_mass / rotation SDOFs of a rigid body.
std::unique_ptr<Sdof> readBodySdof(SceneContext& ctx, const YAML::Node& z, const std::string& path) {
  const YamlReader& r = ctx.r;
  const bool com = static_cast<bool>(z["center_of_mass"]);
  const std::string key = com ? "center_of_mass" : "rotation";
  const YAML::Node bn = z[key];
  const std::string b = r.text(bn, path + "." + key);
  auto it = ctx.rigidBodies.find(b);
  if (it == ctx.rigidBodies.end()) {
    std::string avail;
    for (const auto& [k, v] : ctx.rigidBodies) avail += (avail.empty() ? "" : ", ") + k;
    r.fail(bn, path + "." + key, "no rigid_body named '" + b + "'; expected the name of a rigid body of the scene (" +
                                     (avail.empty() ? std::string("the scene has none") : "the scene has: " + avail) + ")");
  }
  const SceneContext::RigidBodyInfo& body = it->second;
  const std::array<int, 4> basic{body.basic[0], body.basic[1], body.basic[2], body.basic[3]};
  if (com) {
    const int c = component(ctx, r.require(z, "component", path), path + ".component");
    auto s = centerOfMassSdof(basic, body.X0, body.com, c);
    s->name = "com." + std::string(1, ctx.m.axisName(c)) + "(" + b + ")";
    return s;
  }
  const YAML::Node an = r.require(z, "axis", path);
  const std::string a = r.text(an, path + ".axis");
  static const char* angleNames[3] = {"roll", "pitch", "yaw"};
  int axis = -1;
  for (int c = 0; c < 3; ++c)
    if (a.size() == 1 && a[0] == "xyz"[c]) axis = c;
  if (axis < 0) r.fail(an, path + ".axis", "expected x (roll), y (pitch) or z (yaw); got '" + a + "'");
  auto s = std::make_unique<BodyRotationSdof>(basic, body.X0, axis);
  s->name = std::string(angleNames[axis]) + "(" + b + ")";
  return s;
}

/// As Model::coordinateLabel: "x", the slope's "x'", an ancf_beam gradient's "x_y" (dx/dy).
std::string componentName(const Model& m, int nd, int c) {
  if (c < m.dim) return std::string(1, m.axisName(c));
  const int k = c - m.dim;
  if (m.nodes[nd].gradients(m.dim) != 3) return std::string(1, m.axisName(k)) + "'";
  return std::string(1, m.axisName(k % 3)) + "_" + "xyz"[k / 3];
}

std::unique_ptr<Sdof> readSdof(SceneContext& ctx, const YAML::Node& z, const std::string& path) {
  const YamlReader& r = ctx.r;
  const Model& m = ctx.m;
  r.allowKeys(z, path, {"node", "component", "angle", "combination", "center_of_mass", "rotation", "axis",
                        "dp", "dv", "name"});
  int kinds = 0;
  for (const char* k : {"node", "angle", "combination", "center_of_mass", "rotation"}) kinds += z[k] ? 1 : 0;
  if (kinds > 1)
    r.fail(z, path, "give one SDOF kind: node (with component), angle, combination, center_of_mass "
                    "(with component) or rotation (with axis)");
  if (z["axis"] && !z["rotation"]) r.fail(z["axis"], path + ".axis", "axis belongs to a rotation SDOF (rotation: <rigid body>)");
  if (z["component"] && (z["rotation"] || z["angle"] || z["combination"]))
    r.fail(z["component"], path + ".component", "component belongs to node and center_of_mass SDOFs");
  std::unique_ptr<Sdof> out;
  if (z["center_of_mass"] || z["rotation"]) {
    out = readBodySdof(ctx, z, path);
  } else if (z["angle"]) {
    if (m.dim != 2) r.fail(z["angle"], path + ".angle", "segment angles are planar SDOFs (dimension 2)");
    const YAML::Node a = z["angle"];
    if (!a.IsSequence() || a.size() != 2) r.fail(a, path + ".angle", "expected a list of two node names [from, to]");
    auto s = std::make_unique<AngleSdof>();
    s->a = ctx.node(a[0], path + ".angle[0]");
    s->b = ctx.node(a[1], path + ".angle[1]");
    s->name = "angle(" + m.nodes[s->a].name + "," + m.nodes[s->b].name + ")";
    out = std::move(s);
  } else if (z["combination"]) {
    const YAML::Node list = z["combination"];
    const std::string cp = path + ".combination";
    if (!list.IsSequence() || list.size() == 0) r.fail(list, cp, "expected a list of [coefficient, node, component]");
    auto s = std::make_unique<LinearSdof>();
    for (size_t j = 0; j < list.size(); ++j) {
      const YAML::Node t = list[j];
      if (!t.IsSequence() || t.size() != 3) r.fail(t, at(cp, j), "expected [coefficient, node, component]");
      const double coef = r.number(t[0], at(cp, j) + "[0]");
      const int nd = ctx.node(t[1], at(cp, j) + "[1]");
      const int c = nodeComponent(ctx, nd, t[2], at(cp, j) + "[2]");
      s->terms.push_back({nd, c, coef});
      s->name += (j ? " + " : "") + jsonish(coef) + " " + componentName(m, nd, c) + "(" + m.nodes[nd].name + ")";
    }
    out = std::move(s);
  } else {
    auto s = std::make_unique<LinearSdof>();
    const int nd = ctx.node(r.require(z, "node", path), path + ".node");
    const int c = nodeComponent(ctx, nd, r.require(z, "component", path), path + ".component");
    s->terms.push_back({nd, c, 1.0});
    s->name = componentName(m, nd, c) + "(" + m.nodes[nd].name + ")";
    out = std::move(s);
  }
  if (z["name"]) out->name = r.text(z["name"], path + ".name");
  if (z["dp"]) out->dp = r.number(z["dp"], path + ".dp");
  if (z["dv"]) out->dv = r.number(z["dv"], path + ".dv");
  return out;
}

}  // namespace

int axisIndex(const Model& m, const std::string& a) {
  for (int c = 0; c < m.dim; ++c)
    if (a.size() == 1 && a[0] == m.axisName(c)) return c;
  return -1;
}

int component(const SceneContext& ctx, const YAML::Node& n, const std::string& path) {
  const int c = axisIndex(ctx.m, ctx.r.text(n, path));
  if (c >= 0) return c;
  std::string axes;
  for (int k = 0; k < ctx.m.dim; ++k) axes += std::string(axes.empty() ? "" : ", ") + ctx.m.axisName(k);
  ctx.r.fail(n, path, "expected one of " + axes + " (the scene's axes)");
}

std::optional<YAML::Node> selectCase(SceneContext& ctx, const YAML::Node& list, Scene& sc, CaseSelection& sel) {
  const YamlReader& r = ctx.r;
  r.requireList(list, "cases");
  std::optional<YAML::Node> selected;
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node c = list[i];
    const std::string path = at("cases", i);
    r.allowKeys(c, path, {"name", "parameters", "rigidize", "rigid_model", "sdofs", "description"});
    const std::string name = r.text(r.require(c, "name", path), path + ".name");
    // The case's results go to <output.directory>/<name>: a plain folder name, never a path.
    const bool plain = !name.empty() && name[0] != '.' && name.size() <= 100 &&
                       name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") ==
                           std::string::npos;
    if (!plain)
      r.fail(c["name"], path + ".name", "expected a case name that can name its output folder (letters, digits, "
                                        "'_', '-', '.'; not starting with '.'; at most 100 characters), got '" + name + "'");
    for (const auto& other : sc.caseNames)
      if (other == name) r.fail(c["name"], path + ".name", "duplicate case name '" + name + "'");
    sc.caseNames.push_back(name);
    if (name == sel.name) { selected.emplace(c); sel.path = path; }
  }
  if (!sel.name.empty() && !selected) {
    std::string names;
    for (const auto& n : sc.caseNames) names += (names.empty() ? "" : ", ") + n;
    r.fail(list, "cases", "no case named '" + sel.name + "'; the scene defines: " + names);
  }
  if (selected) {
    const YAML::Node ps = r.require(*selected, "parameters", sel.path);
    sel.paramsPath = sel.path + ".parameters";
    r.requireList(ps, sel.paramsPath);
    for (size_t i = 0; i < ps.size(); ++i) {
      const std::string pn = r.text(ps[i], at(sel.paramsPath, i));
      sel.params.insert(pn);
      sel.paramNodes.emplace_back(pn, ps[i]);
    }
  }
  return selected;
}

void applyRigidModels(SceneContext& ctx, const YAML::Node& c, const CaseSelection& sel) {
  for (const auto& b : bodyList(ctx, c, "rigid_model", sel)) {
    RigidizeOptions opt;
    opt.slopes = ctx.bodies[b].slopes;
    Rigidization R = rigidize(b, ctx.bodies[b].nodes, ctx.m, ctx.positions(),
                              ctx.where(c, sel.path) + ": case '" + sel.name + "'", nullptr, opt);
    for (auto& con : R.constraints) ctx.m.constraints.push_back(std::move(con));
  }
}

std::unique_ptr<PimCase> readPimCase(SceneContext& ctx, const YAML::Node& c, const CaseSelection& sel) {
  const YamlReader& r = ctx.r;
  const Model& m = ctx.m;
  auto pc = std::make_unique<PimCase>();
  pc->name = sel.name;
  // The PIM's own errors (SDOF count, deformed bodies, ...) come when it runs, after reading:
  // they start with this, the case's location "file:line:col: key 'cases[i]'".
  pc->file = ctx.where(c, sel.path);
  pc->rigidModel = bodyList(ctx, c, "rigid_model", sel);
  pc->rigidized = bodyList(ctx, c, "rigidize", sel);
  for (const auto& p : m.parameters) pc->parameters.push_back(p.name);
  for (size_t i = 0; i < pc->rigidized.size(); ++i) {
    const std::string& b = pc->rigidized[i];
    if (std::count(pc->rigidModel.begin(), pc->rigidModel.end(), b))
      r.fail(c["rigidize"][i], at(sel.path + ".rigidize", i), "'" + b + "' is already rigid in this case (rigid_model)");
    if (ctx.bodies[b].massless)  // its nodes move to equilibrium at t = 0; the PIM's equilibrium rows fix them
      r.fail(c["rigidize"][i], at(sel.path + ".rigidize", i),
             "'" + b + "' is massless (inertia: none): the PIM determines its coordinates by their equilibrium, "
             "it cannot be rigidized; remove it from rigidize (the SDOF count drops by its equilibrium equations)");
    RigidizeOptions opt;
    opt.slopes = ctx.bodies[b].slopes;
    Rigidization R = rigidize(b, ctx.bodies[b].nodes, m, ctx.positions(), pc->file + ": case '" + sel.name + "'",
                              ctx.bodies[b].pairLength, opt);
    for (auto& con : R.constraints) pc->lambda.push_back(std::move(con));
  }
  if (c["sdofs"]) {
    const std::string path = sel.path + ".sdofs";
    r.requireList(c["sdofs"], path);
    for (size_t i = 0; i < c["sdofs"].size(); ++i) pc->sdofs.push_back(readSdof(ctx, c["sdofs"][i], at(path, i)));
  }
  return pc;
}

}  // namespace flexsens
