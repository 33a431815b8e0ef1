// Bridge from a Gmsh geometry (.geo) or mesh (.msh) to the elements of one meshed body.
//
// meshBody() opens the file; for a .geo it meshes the whole model with the requested maximum
// element size and order (Mesh.MeshSizeMax, then setOrder 2: midside nodes on curved
// boundaries); a .msh is taken as it is. It returns the triangles (dimension 2) or
// tetrahedra (dimension 3) of one Physical Surface or Physical Volume, in the VTK node order
// of elements/SimplexShape.hpp (mapped from Gmsh's order through the reference coordinates
// Gmsh reports for its element types), the nodes they use, the names of the nodes on
// Physical Points, and node groups with their boundary facets (Physical Curves, and in 3D
// Physical Surfaces other than the body) for loads and ground conditions.
//
// Units: none in Gmsh; coordinates are taken as meters.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/Types.hpp"
#include "elements/SimplexShape.hpp"
#include "meshes/GmshSandbox.hpp"

namespace flexsens {

struct BodyMeshRequest {
  std::string file;     ///< .geo or .msh
  std::string group;    ///< Physical Surface (dim 2) or Physical Volume (dim 3)
  int dim = 2;
  double size = 0.0;    ///< maximum element size [m] (.geo only; 0: the file's own sizes)
  int order = 1;        ///< 1 or 2 (.geo only)
  /// "file:line:col: key '...'" of the scene keys group and size, for the errors that concern
  /// them (the `where` argument of meshBody names the file key).
  std::string groupWhere, sizeWhere;
  GmshOptions gmsh;  ///< limits of the Gmsh child, the scene's folder
};

struct BodyMesh {
  Simplex shape = Simplex::Tri3;
  std::vector<Eigen::Vector3d> positions;           ///< the body's nodes [m]
  std::vector<std::size_t> gmshTags;                ///< their Gmsh node tags
  std::vector<std::vector<int>> cells;              ///< node indices per element (VTK order)
  std::map<std::string, int> points;                ///< Physical Point name -> node index
  std::map<std::string, std::vector<int>> groups;   ///< lower-dimensional Physical group -> nodes
  /// The group's boundary facets (lines of 2/3 nodes in 2D, triangles of 3/6 nodes in 3D,
  /// corners first, then midside nodes), node indices of the body.
  std::map<std::string, std::vector<std::vector<int>>> facets;
};

/// Limits before and after meshing: the estimated cell count (bounding box measure over
/// size^dim), then the memory the body's nodes will need against the memory budget
/// (core/MemoryBudget, --max-memory); a geometry file's size as in GmshCurves.
inline constexpr double kMaxMeshCellsEstimate = 2e5;
/// Peak memory per mesh node of a solve [bytes], twice the measured (peak RSS of `flexsens
/// static` between two mesh sizes, quadratic elements): 9.3 kB per node for triangles (Cook's
/// membrane, 1.8k -> 7k nodes), 49 kB for tetrahedra (bar, 1k -> 6.4k nodes; the sparse LU's
/// fill grows faster in 3D). Surface meshes (planar solids, shells) use the first.
inline constexpr double kMeshBytesPerNode2D = 2e4, kMeshBytesPerNode3D = 1e5;

/// Gmsh runs in a sandboxed child (meshes/GmshSandbox); a .geo is scanned first
/// (meshes/GeoScan), a .msh's headers checked (meshes/GeometryFile).
/// Throws InputError(where + ": ...") when the file cannot be read, Gmsh hits a limit, the group is missing
/// (listing the available ones of that dimension), the mesh would be too large, holds other
/// element types (quadrangles, hexahedra, ...), or a node of the body's entities belongs to
/// no element (a free node).
BodyMesh meshBody(const BodyMeshRequest& req, const std::string& where);

}  // namespace flexsens
