// Scene keys shared by the readers of meshed bodies (solid: elements/SolidReader.cpp, shell:
// elements/ShellReader.cpp): the Gmsh mesh (mesh, group, size, order) and the body's nodes
// (names from Physical Points, ground groups, initial velocity), and the material law.
#pragma once

#include <string>
#include <vector>

#include "elements/Material.hpp"
#include "meshes/GmshMesh.hpp"
#include "scene/SceneContext.hpp"

namespace flexsens {

/// The mesh keys of item `el`: `mesh` (.geo meshed here, or .msh), `group` (a Physical group
/// of dimension elementDim), `size`, and `order` when withOrder. meshKey: the `mesh` node.
BodyMesh readBodyMesh(SceneContext& ctx, const YAML::Node& el, const std::string& path, int elementDim, bool withOrder,
                      YAML::Node& meshKey);

/// One entry of a scene list of mesh node groups: its YAML node, key path, group name and the
/// group's mesh nodes (indices into the mesh).
struct MeshNodeGroup {
  YAML::Node at;
  std::string key, name;
  std::vector<int> nodes;
  bool clamp = true;  ///< false: a shell's simply_supported group (nodes fixed, rotation free)
};

/// A plane of symmetry of a meshed body: the group's mesh nodes, the unit normal, a point [m].
struct SymmetryPlane {
  YAML::Node at;
  std::string key;
  std::vector<int> nodes;
  Eigen::Vector3d normal, point;
};

/// Scene nodes of the mesh's nodes, in mesh order (an existing node of the same name is shared
/// when at the same place), then the keys `ground`, `velocity`, `angular_velocity`, `center`.
/// A planar scene takes x, y of a mesh in the plane z = 0. clamp (shell): when given, the key
/// `clamp` too, a list of groups whose nodes are fixed as by `ground`; its entries are returned
/// there (the caller adds what a clamp holds beyond the nodes), and the key `simply_supported`
/// (nodes fixed, rotation free) with clamp = false.
std::vector<int> addMeshNodes(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name,
                              const BodyMesh& mesh, const YAML::Node& meshKey, const std::string& group,
                              std::vector<MeshNodeGroup>* clamp = nullptr, std::vector<SymmetryPlane>* planes = nullptr);

/// The mesh nodes of a Physical Point or node group g (InputError listing the available ones).
std::vector<int> meshGroupNodes(const YamlReader& r, const BodyMesh& mesh, const std::string& group,
                                const YAML::Node& at, const std::string& key, const std::string& g);

/// The keys `support` ({group, fix: [axes]}), `symmetry` ({group, normal}) and, for shells,
/// `diaphragm` (a group, or {group, normal}: the displacements in the group's plane held):
/// support rows on the group's free nodes (elements/SupportReader.cpp); symmetry planes go to
/// `planes` when given.
void readSupports(SceneContext& ctx, const YAML::Node& el, const std::string& path, const std::string& name,
                  const BodyMesh& mesh, const std::string& group, const std::vector<int>& ids,
                  std::vector<SymmetryPlane>* planes);

/// The key `material`: saint_venant_kirchhoff (default) or neo_hookean.
Law readMaterialLaw(const YamlReader& r, const YAML::Node& el, const std::string& path);

}  // namespace flexsens
