// Gmsh geometry -> node chains; see GmshCurves.hpp.
#include "meshes/GmshCurves.hpp"
#include "meshes/GeoScan.hpp"
#include "meshes/GmshSession.hpp"
#include "meshes/MeshWire.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace flexsens {

namespace {

/// Polyline length of a curve from 256 chords of its parametrization (only the ratios of the
/// lengths of a group's curves are used, to share the segments out).
double curveLength(int tag) {
  std::vector<double> lo, hi;
  gmsh::model::getParametrizationBounds(1, tag, lo, hi);
  if (lo.empty() || hi.empty()) return 0.0;
  const int n = 256;
  std::vector<double> u(n + 1), xyz;
  for (int i = 0; i <= n; ++i) u[i] = lo[0] + (hi[0] - lo[0]) * i / n;
  gmsh::model::getValue(1, tag, u, xyz);
  double len = 0.0;
  for (int i = 0; i < n && 3 * (i + 1) + 2 < static_cast<int>(xyz.size()); ++i) {
    const double dx = xyz[3 * (i + 1)] - xyz[3 * i];
    const double dy = xyz[3 * (i + 1) + 1] - xyz[3 * i + 1];
    const double dz = xyz[3 * (i + 1) + 2] - xyz[3 * i + 2];
    len += std::sqrt(dx * dx + dy * dy + dz * dz);
  }
  return len;
}

/// Parameter bounds of a curve whose parametrization has constant speed |dx/du|, so that
/// equal parameter steps are equal arc lengths: straight lines and circle arcs (of both the
/// built-in and the OpenCASCADE kernel); false for any other curve. Decided by the curve's
/// type, since Gmsh 4.8 evaluates dx/du by finite differences (~1e-8 relative).
bool constantSpeed(int tag, double& lo, double& hi) {
  std::string type;
  gmsh::model::getType(1, tag, type);
  if (type != "Line" && type != "Circle") return false;
  std::vector<double> a, b;
  gmsh::model::getParametrizationBounds(1, tag, a, b);
  if (a.empty() || b.empty() || !(b[0] > a[0])) return false;
  lo = a[0];
  hi = b[0];
  return true;
}

/// Shares `total` segments out over curves of the given lengths: proportional, at least one
/// each, largest remainder, sum exactly `total` (requires total >= lengths.size()).
std::vector<int> distributeSegments(int total, const std::vector<double>& lengths) {
  const std::size_t k = lengths.size();
  double sum = 0.0;
  for (double l : lengths) sum += l;
  std::vector<double> ideal(k);
  for (std::size_t j = 0; j < k; ++j)
    ideal[j] = sum > 0.0 ? total * lengths[j] / sum : double(total) / double(k);
  std::vector<int> n(k);
  int have = 0;
  for (std::size_t j = 0; j < k; ++j) {
    // The small tolerance keeps 10 * 9 / 10 = 8.999... from losing its segment to rounding.
    n[j] = std::max(1, static_cast<int>(std::floor(ideal[j] + 1e-9)));
    have += n[j];
  }
  while (have < total) {
    std::size_t best = 0;
    for (std::size_t j = 1; j < k; ++j)
      if (ideal[j] - n[j] > ideal[best] - n[best]) best = j;
    ++n[best];
    ++have;
  }
  while (have > total) {
    std::size_t best = k;
    for (std::size_t j = 0; j < k; ++j)
      if (n[j] > 1 && (best == k || ideal[j] - n[j] < ideal[best] - n[best])) best = j;
    --n[best];
    --have;
  }
  return n;
}

/// One curve of a chain, traversed forward (begin -> end) or backward.
struct Step {
  int curve = 0;
  bool forward = true;
  int segments = 1;
};

struct CurveInfo {
  int begin = 0, end = 0;  ///< geometric end points (begin = parameter minimum)
  double length = 0.0;
};

/// Checks of the requests that need no Gmsh.
void checkRequests(const std::vector<CurveRequest>& requests, const std::string& where) {
  {
    std::set<std::string> seen;
    for (const CurveRequest& r : requests) {
      if (r.segments > kMaxSegments)
        throw InputError(where + ": Physical Curve '" + r.group + "': " + std::to_string(r.segments) +
                         " segments; expected at most " + std::to_string(kMaxSegments) + " (kMaxSegments)");
      if (r.segments < 1)
        throw InputError(where + ": Physical Curve '" + r.group + "': " +
                         (r.segments == 0 ? std::string("zero segments")
                                          : std::to_string(r.segments) + " segments") +
                         "; expected at least 1");
      if (!seen.insert(r.group).second)
        throw InputError(where + ": Physical Curve '" + r.group +
                         "' is requested twice; expected each group once");
    }
  }
}

/// The Physical Curves and Physical Points of the open model (naming): curve groups by name
/// (curve tags in order), each named point's position into `points` and its name by point.
struct GroupNames {
  std::map<std::string, std::vector<int>> curveGroups;  ///< name -> curve tags (in order)
  std::map<int, std::string> pointName;                 ///< geometric point -> name
  std::string pointLabel(int p) const {
    auto it = pointName.find(p);
    return it != pointName.end() ? "'" + it->second + "'" : "point " + std::to_string(p);
  }
};

GroupNames readGroupNames(CurveMesh& result, const std::function<InputError(const std::string&)>& fail) {
  GroupNames g;
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups);
  for (const auto& [dim, tag] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(dim, tag, name);
    if (name.empty()) continue;  // unnamed groups cannot be requested or name nodes
    std::vector<int> ents;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, ents);
    if (dim == 1) {
      auto& list = g.curveGroups[name];
      for (int e : ents) list.push_back(std::abs(e));
    } else if (dim == 0) {
      if (ents.size() != 1)
        throw fail("Physical Point '" + name + "' holds " + std::to_string(ents.size()) +
                   " points; expected exactly one (it names one node)");
      if (result.points.count(name))
        throw fail("two Physical Points are named '" + name + "'; expected unique names");
      const int p = std::abs(ents[0]);
      if (g.pointName.count(p))
        throw fail("point " + std::to_string(p) + " belongs to Physical Points '" + g.pointName[p] + "' and '" +
                   name + "'; expected one name per point");
      std::vector<double> xyz;
      gmsh::model::getValue(0, p, {}, xyz);
      if (xyz.size() < 3) throw fail("cannot evaluate Physical Point '" + name + "'");
      result.points[name] = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
      g.pointName[p] = name;
    }
  }
  return g;
}

/// The distinct curves of request r's group (checking: the group exists, no curve shared with
/// another requested group, at least one segment per curve).
std::vector<int> groupCurves(const CurveRequest& r, const GroupNames& g, std::map<int, std::string>& owner,
                             const std::string& geoFile, const std::function<InputError(const std::string&)>& fail) {
  auto git = g.curveGroups.find(r.group);
  if (git == g.curveGroups.end() || git->second.empty()) {
    std::string avail;
    for (const auto& [name, tags] : g.curveGroups) avail += (avail.empty() ? "" : ", ") + name;
    throw fail("no Physical Curve '" + r.group + "' in '" + geoFile + "'; available: " +
               (avail.empty() ? "(none)" : avail));
  }
  const std::string what = "Physical Curve '" + r.group + "'";
  std::vector<int> curves;
  for (int c : git->second)
    if (std::find(curves.begin(), curves.end(), c) == curves.end()) curves.push_back(c);
  for (int c : curves) {
    auto [it, fresh] = owner.emplace(c, r.group);
    if (!fresh)
      throw fail(what + " shares curve " + std::to_string(c) + " with Physical Curve '" + it->second +
                 "'; a curve can be meshed for one group only");
  }
  if (r.segments < static_cast<int>(curves.size()))
    throw fail(what + " has " + std::to_string(curves.size()) + " curves but " + std::to_string(r.segments) +
               " segments; expected at least one per curve");
  return curves;
}

/// The curves of one group in chain order (checking: one open chain, no branch, no loop, no
/// separate piece), with the group's segments shared out by length and set transfinite.
std::vector<Step> planChain(const CurveRequest& r, const std::vector<int>& curves, const GroupNames& g,
                            const std::function<InputError(const std::string&)>& fail) {
  const std::string what = "Physical Curve '" + r.group + "'";
  std::map<int, CurveInfo> info;
  std::map<int, std::vector<int>> incident;  // point -> curves of this group
  for (int c : curves) {
    gmsh::vectorpair bnd;
    gmsh::model::getBoundary({{1, c}}, bnd, false, false, false);
    if (bnd.size() != 2 || std::abs(bnd[0].second) == std::abs(bnd[1].second))
      throw fail(what + ": curve " + std::to_string(c) +
                 " is closed (no two distinct end points); its curves must form one open chain");
    CurveInfo ci;
    ci.begin = std::abs(bnd[0].second);
    ci.end = std::abs(bnd[1].second);
    ci.length = curveLength(c);
    info[c] = ci;
    incident[ci.begin].push_back(c);
    incident[ci.end].push_back(c);
  }
  std::vector<int> ends;
  for (const auto& [p, cs] : incident) {
    if (cs.size() > 2)
      throw fail(what + ": " + std::to_string(cs.size()) + " of its curves meet at " + g.pointLabel(p) +
                 "; its curves must form one open chain (no branches)");
    if (cs.size() == 1) ends.push_back(p);
  }
  if (ends.empty()) throw fail(what + ": its curves form a closed loop; expected one open chain");
  // Start at a free end; prefer the one where its curve begins (the drawing direction),
  // then the one whose curve is listed first in the group.
  auto rank = [&](int p) {
    const int c = incident[p][0];
    const auto pos = std::find(curves.begin(), curves.end(), c) - curves.begin();
    return std::make_pair(info[c].begin == p ? 0 : 1, pos);
  };
  int start = ends[0];
  for (int p : ends)
    if (rank(p) < rank(start)) start = p;
  std::vector<Step> plan;
  std::set<int> used;
  int at = start;
  while (true) {
    int next = 0;
    for (int c : incident[at])
      if (!used.count(c)) next = c;
    if (next == 0) break;
    used.insert(next);
    const bool fwd = info[next].begin == at;
    plan.push_back({next, fwd, 1});
    at = fwd ? info[next].end : info[next].begin;
  }
  if (plan.size() != curves.size())
    throw fail(what + ": its curves are not connected (" +
               (ends.size() > 2 ? std::to_string(ends.size() / 2) + " separate pieces"
                                : std::string("an open piece and a separate loop")) +
               "); expected one open chain");
  std::vector<double> lengths;
  for (const Step& s : plan) lengths.push_back(info[s.curve].length);
  const std::vector<int> n = distributeSegments(r.segments, lengths);
  for (std::size_t j = 0; j < plan.size(); ++j) {
    plan[j].segments = n[j];
    gmsh::model::mesh::setTransfiniteCurve(plan[j].curve, n[j] + 1);
  }
  return plan;
}

/// Gmsh places transfinite nodes at equal arc lengths found by numerical integration (off by
/// ~1e-9 relative). Where equal parameter steps are equal arc lengths (lines, circle arcs), the
/// interior nodes (xyz, in chain order `order`) are re-evaluated at exactly uniform parameters,
/// which replace their parameters u.
void placeUniformly(const Step& s, const std::vector<std::size_t>& order, std::vector<double>& xyz,
                    std::vector<double>& u) {
  double lo = 0.0, hi = 0.0;
  if (order.size() <= 2 || !constantSpeed(s.curve, lo, hi)) return;
  const std::size_t n = order.size() - 1;
  std::vector<double> uu, exact;
  for (std::size_t i = 1; i < n; ++i) uu.push_back(lo + (hi - lo) * double(i) / n);
  gmsh::model::getValue(1, s.curve, uu, exact);
  if (exact.size() != 3 * uu.size()) return;
  // order is by increasing u: its k-th entry (k = 1..n-1) sits at uu[k - 1].
  std::vector<std::size_t> ascending(order);
  if (!s.forward) std::reverse(ascending.begin(), ascending.end());
  for (std::size_t k = 1; k < n; ++k) {
    for (int a = 0; a < 3; ++a) xyz[3 * ascending[k] + a] = exact[3 * (k - 1) + a];
    u[ascending[k]] = uu[k - 1];
  }
}

/// The mesh node on geometric point p (0: none).
std::size_t vertexNode(int p) {
  std::vector<std::size_t> tags;
  std::vector<double> xyz, u;
  gmsh::model::mesh::getNodes(tags, xyz, u, 0, p, false, false);
  return tags.empty() ? 0 : tags[0];
}

/// The meshed chain of one request (geometry), its nodes named by the Physical Points they sit
/// on, else "<group>.<i>".
NodeChain readChain(const CurveRequest& r, const std::vector<Step>& plan, const GroupNames& g,
                    const std::function<InputError(const std::string&)>& fail) {
  NodeChain chain;
  chain.group = r.group;
  std::vector<std::size_t> nodeTags;
  std::vector<int> onPoint;  // geometric point of each node, or 0
  for (const Step& s : plan) {
    std::vector<std::size_t> tags;
    std::vector<double> xyz, u;
    gmsh::model::mesh::getNodes(tags, xyz, u, 1, s.curve, true, true);
    if (u.size() != tags.size() || tags.size() != static_cast<std::size_t>(s.segments + 1))
      throw fail("Physical Curve '" + r.group + "': curve " + std::to_string(s.curve) + " got " +
                 std::to_string(tags.size()) + " nodes; expected " + std::to_string(s.segments + 1));
    std::vector<std::size_t> order(tags.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return u[a] < u[b]; });
    if (!s.forward) std::reverse(order.begin(), order.end());
    gmsh::vectorpair bnd;
    gmsh::model::getBoundary({{1, s.curve}}, bnd, false, false, false);
    const int first = std::abs(s.forward ? bnd[0].second : bnd[1].second);
    const int last = std::abs(s.forward ? bnd[1].second : bnd[0].second);
    if (tags[order.front()] != vertexNode(first) || tags[order.back()] != vertexNode(last))
      throw fail("Physical Curve '" + r.group + "': the nodes of curve " + std::to_string(s.curve) +
                 " do not end on its end points");
    placeUniformly(s, order, xyz, u);
    std::vector<double> derivative;  // d x / d u at each node, 3 per node in tag order
    gmsh::model::getDerivative(1, s.curve, u, derivative);
    for (std::size_t i = 0; i < order.size(); ++i) {
      const std::size_t j = order[i];
      Eigen::Vector3d t(derivative.at(3 * j), derivative.at(3 * j + 1), derivative.at(3 * j + 2));
      t = (s.forward ? 1.0 : -1.0) * t.normalized();
      if (i == 0 && !nodeTags.empty()) {  // shared with the previous curve
        chain.tangents.back() = (chain.tangents.back() + t).normalized();
        continue;
      }
      chain.tangents.push_back(t);
      nodeTags.push_back(tags[j]);
      onPoint.push_back(i == 0 ? first : i + 1 == order.size() ? last : 0);
      chain.positions.emplace_back(xyz[3 * j], xyz[3 * j + 1], xyz[3 * j + 2]);
    }
  }
  for (std::size_t i = 0; i < nodeTags.size(); ++i) {
    auto it = onPoint[i] ? g.pointName.find(onPoint[i]) : g.pointName.end();
    chain.names.push_back(it != g.pointName.end() ? it->second : r.group + "." + std::to_string(i));
  }
  return chain;
}

/// Gmsh's last logged error as an InputError naming `what` (nothing when there is none).
void checkGmshLog(const std::function<InputError(const std::string&)>& fail, const std::string& what) {
  std::string err;
  gmsh::logger::getLastError(err);
  if (!err.empty()) throw fail(what + err);
}

/// The chains, computed with Gmsh in this process (the sandboxed child).
CurveMesh meshCurvesHere(const std::string& geoFile, const std::vector<CurveRequest>& requests,
                         const std::string& where) {
  const std::function<InputError(const std::string&)> fail = [&](const std::string& what) {
    return InputError(where + ": " + what);
  };
  CurveMesh result;
  try {
    gmsh::logger::start();
    gmsh::open(geoFile);
    checkGmshLog(fail, "Gmsh cannot read '" + geoFile + "': ");
    const GroupNames names = readGroupNames(result, fail);
    std::map<int, std::string> owner;  // curve -> requested group
    std::vector<std::vector<Step>> plans;
    for (const CurveRequest& r : requests)
      plans.push_back(planChain(r, groupCurves(r, names, owner, geoFile, fail), names, fail));
    gmsh::model::mesh::generate(1);
    checkGmshLog(fail, "Gmsh cannot mesh '" + geoFile + "': ");
    for (std::size_t k = 0; k < requests.size(); ++k) result.chains.push_back(readChain(requests[k], plans[k], names, fail));
  } catch (const std::string& gmshError) {  // Gmsh 4.8 throws its error text as std::string
    throw fail("Gmsh error with '" + geoFile + "': " + gmshError);
  }
  return result;
}

}  // namespace

CurveMesh meshCurves(const std::string& geoFile, const std::vector<CurveRequest>& requests, const std::string& where,
                     const GmshOptions& options) {
  checkRequests(requests, where);
  readGeometryFile(geoFile, "geometry file", where);
  scanGeoFile(geoFile, {options.sceneDir}, where);
  return decodeCurveMesh(runGmshSandboxed(geoFile, options.limits, where, [&] {
    return encodeCurveMesh(meshCurvesHere(geoFile, requests, where));
  }));
}

}  // namespace flexsens
