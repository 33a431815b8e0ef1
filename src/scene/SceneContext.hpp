// What a per-kind scene reader sees while the model is being built: the YAML reader (every
// error with its file:line:column and key path), the model so far, and the name tables that
// later items look things up in (nodes, bodies, rigid bodies, bindable properties).
// One SceneContext lives for one readScene call; readers add to it, nothing else keeps it.
#pragma once

#include <yaml-cpp/yaml.h>

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/Model.hpp"
#include "elements/JointAngle.hpp"
#include "meshes/GmshSandbox.hpp"
#include "scene/YamlReader.hpp"

namespace flexsens {

/// "list[i]": the key path of item i of a list.
inline std::string at(const std::string& list, size_t i) { return list + "[" + std::to_string(i) + "]"; }

class SceneContext {
 public:
  SceneContext(const std::string& file, Model& m) : r(file), m(m) {}

  YamlReader r;
  Model& m;

  /// A flexible body (beam or spring) by name: its nodes, for PIM cases and point_on_plane.
  struct Body {
    std::vector<int> nodes;
    const Quantity* pairLength;  ///< a spring's natural length (rigidized pairs keep it), else null
    bool slopes = false;         ///< an ANCF body: rigidizing it fixes its nodes' slopes too
    bool massless = false;       ///< inertia: none (its nodes follow equilibrium; no rigidizing)
  };
  /// A 3D rigid body by name, for joints fixed to it and for SDOFs.
  struct RigidBodyInfo {
    std::vector<int> basic;          ///< the four basic points
    Eigen::Matrix<double, 3, 4> X0;  ///< their initial positions [m]
    Eigen::Vector3d com;             ///< centre of mass at t = 0 [m]
    std::set<int> members;           ///< every node of the body
  };
  std::map<std::string, Body> bodies;
  std::map<int, std::string> slopeOwner;  ///< node -> the ANCF chain that set its slope
  std::map<std::string, RigidBodyInfo> rigidBodies;
  std::map<std::string, std::array<int, 2>> planarRigidBodies;  ///< name -> basic points A, B
  /// Readers that need every element read first (a torque through a node's slope, which its
  /// ANCF chain sets, wherever the chain is listed): run in order after the elements.
  std::vector<std::function<void()>> afterElements;
  /// Meshed body -> its Physical Points and node groups with their node counts (for `check`).
  std::map<std::string, std::vector<std::pair<std::string, int>>> meshGroups;
  std::string geoFile;  ///< the scene's Gmsh geometry, if any
  GmshOptions gmsh;     ///< the Gmsh child's limits (scene key `limits`) and the scene's folder

  // ---------------------------------------------------------------- names and nodes
  /// The node named by scalar `n`; fails naming the key if there is none.
  int node(const YAML::Node& n, const std::string& path) const;
  /// `item.nodes`: a list of minCount..maxCount distinct node names.
  std::vector<int> nodeList(const YAML::Node& item, const std::string& path, size_t minCount,
                            size_t maxCount, bool allowRepeat = false) const;
  /// The item's `name` (or `fallback`), unique among elements and constraints.
  std::string itemName(const YAML::Node& item, const std::string& path, const std::string& fallback);
  void addNode(const Node& nd) {
    nodeIndex_[nd.name] = static_cast<int>(m.nodes.size());
    m.nodes.push_back(nd);
  }
  bool hasNode(const std::string& name) const { return nodeIndex_.count(name) > 0; }
  /// The geometry's named points, which `nodes` may list once by name to make them ground,
  /// clamped, moving or give them slopes; erased when listed.
  std::set<int> geometryPoints;
  int nodeIndex(const std::string& name) const { return nodeIndex_.at(name); }
  /// A node placed by the geometry; a name met again must be at the same place.
  int addGeometryNode(const std::string& name, const Eigen::Vector3d& x, const YAML::Node& at,
                      const std::string& key);
  /// The node chain of `el.curve` (a Physical Curve of the geometry) with `el.segments` segments.
  /// tangents (optional): the curve's unit tangent at each node, in chain order.
  std::vector<int> curveNodes(const YAML::Node& el, const std::string& path,
                              std::vector<Eigen::Vector3d>* tangents = nullptr);

  // ----------------------------------------------------------------------- geometry
  double distance(int a, int b) const { return (m.nodes[a].position - m.nodes[b].position).norm(); }
  /// A length given as a positive number or "auto" (the initial distance of nodes a and b);
  /// `item` is the element or constraint (the error position when the key is absent).
  Quantity length(const YAML::Node& item, const std::string& key, const std::string& path, int a, int b) const;
  /// The initial positions of all nodes, one column each.
  MatX positions() const;
  /// "file:line:col: key 'key'", for errors raised below the reader (Gmsh, rigidization).
  std::string where(const YAML::Node& n, const std::string& key) const;
  void requireSpatial(const YAML::Node& item, const std::string& path, const std::string& what) const;
  /// Nodes at fixed distances already: both ground, or both on one earlier rigid body.
  bool linked(int a, int b) const;
  /// Sets the initial velocity of a node, failing if another item gave it a different one.
  void setVelocity(int id, const Eigen::Vector3d& v, const YAML::Node& item, const std::string& path);
  void velocitySetBy(int id, const std::string& path) { velocitySetBy_[id] = path; }
  /// The key path that gave node `id` its initial velocity, or null when none did (default 0).
  const std::string* velocitySource(int id) const {
    const auto it = velocitySetBy_.find(id);
    return it == velocitySetBy_.end() ? nullptr : &it->second;
  }
  /// `item.axis`, `item.from`, `item.to`: three node pairs of a signed joint angle.
  AngleNodes angleNodes(const YAML::Node& item, const std::string& path) const;
  /// The angle at the initial positions [rad]; fails where it is undefined.
  double initialAngle(const AngleNodes& an, const YAML::Node& item, const std::string& path) const;

  // ---------------------------------------------------------- slopes (ANCF nodes)
  /// A node's `slope` or `clamped` key, kept for the checks that can only run after the
  /// elements are read (checkSlopes).
  struct SlopeKey {
    YAML::Node node;
    std::string path;
  };
  std::map<int, SlopeKey> givenSlopes, clamps;
  std::set<int> slopeUsers;  ///< nodes whose slope an element uses
  std::vector<std::pair<int, int>> slopeLinks;  ///< node pairs of the ANCF elements (a, b)
  /// An ANCF chain `body` passes node `id` along unit tangent `t`. A node has one slope, shared
  /// by every element there: a second chain through a node whose slope an earlier chain set
  /// along another direction would be welded to it at that angle (and, straight at rest,
  /// start strained). Fails then, naming both chains and the remedy (a pin: separate nodes
  /// and a spherical joint; a weld: the node's `slope` key). Returns true if the slope is set.
  bool slopeAlong(int id, const std::string& body, const Eigen::Vector3d& t, const YAML::Node& key,
                  const std::string& path);
  /// After the elements: every slope given is used by an element, every clamp has one to fix.
  void checkSlopes() const;

  // --------------------------------------------------------------------- parameters
  /// Makes `q` bindable as parameter property "<item>.<key>".
  void bind(const std::string& key, Quantity* q) { bindings[key].push_back(q); }
  template <class Props>
  void bindAll(const std::string& item, Props&& props) {
    for (auto& [k, q] : props) bind(item + "." + k, q);
  }
  std::map<std::string, std::vector<Quantity*>> bindings;
  /// Bodies that some parameter binds per element (`per: element`), known before the
  /// elements are read: their readers give each element its own properties ...
  std::set<std::string> perElementBodies;
  /// ... and list them here, "<body>.<property>" -> per element, in order, its quantity and its
  /// index in the model's elements.
  std::map<std::string, std::vector<std::pair<Quantity*, int>>> elementBindings;
  /// The properties of one element of body `item` (`element`: its index in the model's
  /// elements): the body's shared ones, or, when a parameter binds the body per element, a copy
  /// of them bound as that element's own.
  template <class Props>
  std::shared_ptr<Props> elementProperties(const std::string& item, const std::shared_ptr<Props>& shared, int element) {
    if (!perElementBodies.count(item)) return shared;
    auto own = std::make_shared<Props>(*shared);
    for (auto& [k, q] : own->properties()) {
      bind(item + "." + k, q);
      elementBindings[item + "." + k].emplace_back(q, element);
    }
    return own;
  }
  /// Binds a body's shared properties, unless its elements have their own (elementProperties).
  template <class Props>
  void bindBody(const std::string& item, const std::shared_ptr<Props>& shared) {
    if (!perElementBodies.count(item)) bindAll(item, shared->properties());
  }

 private:
  std::map<std::string, int> nodeIndex_;
  std::set<std::string> names_;
  std::map<int, std::string> velocitySetBy_;  ///< node -> key path that set its initial velocity
};

}  // namespace flexsens
