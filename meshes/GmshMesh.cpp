// Gmsh geometry or mesh -> one meshed body; see GmshMesh.hpp.
#include "meshes/GmshMesh.hpp"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <unordered_map>

#include "core/MemoryBudget.hpp"
#include "meshes/GmshCurves.hpp"
#include "meshes/GeoScan.hpp"
#include "meshes/GeometryFile.hpp"
#include "meshes/GmshSession.hpp"
#include "meshes/MeshWire.hpp"

namespace flexsens {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// Our shape for a Gmsh element type, false for any other type.
bool shapeOfGmshType(int type, Simplex& s) {
  switch (type) {
    case 2: s = Simplex::Tri3; return true;
    case 9: s = Simplex::Tri6; return true;
    case 4: s = Simplex::Tet4; return true;
    case 11: s = Simplex::Tet10; return true;
    default: return false;
  }
}

/// perm[k] = Gmsh local index of our (VTK-order) node k, from Gmsh's reference coordinates.
std::vector<int> gmshToVtk(int type, Simplex s) {
  std::string name;
  int dim, order, numNodes, primary;
  std::vector<double> local;
  gmsh::model::mesh::getElementProperties(type, name, dim, order, numNodes, local, primary);
  const int n = simplexNodes(s);
  std::vector<int> perm(n, -1);
  for (int k = 0; k < n; ++k) {
    const VecX ref = simplexNode(s, k);
    for (int g = 0; g < numNodes; ++g) {
      double dist = 0.0;
      for (int c = 0; c < dim; ++c) dist += std::abs(local[g * dim + c] - ref[c]);
      if (dist < 1e-9) perm[k] = g;
    }
    if (perm[k] < 0) throw std::logic_error("Gmsh element type " + name + ": no node at reference node " + std::to_string(k));
  }
  return perm;
}

std::string gmshTypeName(int type) {
  std::string name;
  int dim, order, numNodes, primary;
  std::vector<double> local;
  gmsh::model::mesh::getElementProperties(type, name, dim, order, numNodes, local, primary);
  return name;
}

using Fail = std::function<InputError(const std::string&)>;

/// The tag of the body's Physical Surface or Volume (naming); InputError listing the ones there.
int bodyGroupTag(const BodyMeshRequest& req, const gmsh::vectorpair& groups, const std::string& groupKind) {
  int bodyTag = -1;
  std::string avail;
  for (const auto& [dim, tag] : groups) {
    if (dim != req.dim) continue;
    std::string name;
    gmsh::model::getPhysicalName(dim, tag, name);
    avail += (avail.empty() ? "" : ", ") + name;
    if (name == req.group) bodyTag = tag;
  }
  if (bodyTag < 0)
    throw InputError(req.groupWhere + ": " + "no " + groupKind + " '" + req.group + "' in '" + req.file +
                     "'; available: " + (avail.empty() ? "(none)" : avail));
  return bodyTag;
}

/// Meshes a .geo (geometry): checks the element size against the cells it would give first.
void generateMesh(const BodyMeshRequest& req, const std::vector<int>& entities, const Fail& fail) {
  if (req.size > 0) {
    double measure = 0.0;
    for (int e : entities) {
      double x0, y0, z0, x1, y1, z1;
      gmsh::model::getBoundingBox(req.dim, e, x0, y0, z0, x1, y1, z1);
      const double ex = x1 - x0, ey = y1 - y0, ez = z1 - z0;
      measure += req.dim == 2 ? std::max({ex * ey, ex * ez, ey * ez}) : ex * ey * ez;
    }
    const double estimate = measure / std::pow(req.size, req.dim);
    if (!(estimate <= kMaxMeshCellsEstimate))
      throw InputError(req.sizeWhere + ": " + "element size " + fmtNumber(req.size) + " m would give about " +
                       fmtNumber(estimate) + " cells of size^" + std::to_string(req.dim) + " in the bounding box of '" +
                       req.group + "'; expected at most " + fmtNumber(kMaxMeshCellsEstimate) +
                       " (kMaxMeshCellsEstimate): a larger size");
    gmsh::option::setNumber("Mesh.MeshSizeMax", req.size);
  }
  gmsh::model::mesh::generate(req.dim);
  if (req.order == 2) gmsh::model::mesh::setOrder(2);
  std::string err;
  gmsh::logger::getLastError(err);
  if (!err.empty()) throw fail("Gmsh cannot mesh '" + req.file + "': " + err);
}

/// The body's nodes as they are met in its elements: Gmsh tag -> body node.
struct BodyNodes {
  std::unordered_map<std::size_t, Eigen::Vector3d> xyz;  ///< every node of the model
  std::unordered_map<std::size_t, int> index;
  BodyNodes() {
    std::vector<std::size_t> tags;
    std::vector<double> coord, param;
    gmsh::model::mesh::getNodes(tags, coord, param, -1, -1, true, false);
    for (std::size_t i = 0; i < tags.size(); ++i) xyz[tags[i]] = {coord[3 * i], coord[3 * i + 1], coord[3 * i + 2]};
  }
  int nodeOf(std::size_t tag, BodyMesh& out) {
    auto [it, fresh] = index.emplace(tag, static_cast<int>(out.positions.size()));
    if (fresh) {
      out.positions.push_back(xyz.at(tag));
      out.gmshTags.push_back(tag);
    }
    return it->second;
  }
};

/// The body's cells in our node order (geometry), one simplex type (checking).
void readCells(const BodyMeshRequest& req, const std::vector<int>& entities, const std::string& groupKind,
               BodyNodes& nodes, BodyMesh& out, const Fail& fail) {
  bool haveShape = false;
  for (int e : entities) {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> elTags, nodeTags;
    gmsh::model::mesh::getElements(types, elTags, nodeTags, req.dim, e);
    for (std::size_t k = 0; k < types.size(); ++k) {
      Simplex s;
      if (!shapeOfGmshType(types[k], s) || simplexDim(s) != req.dim)
        throw fail(groupKind + " '" + req.group + "' holds elements of type " + gmshTypeName(types[k]) + "; expected " +
                   (req.dim == 2 ? "triangles (3 or 6 nodes; no Recombine)" : "tetrahedra (4 or 10 nodes)"));
      if (haveShape && s != out.shape)
        throw fail(groupKind + " '" + req.group + "' mixes " + simplexName(out.shape) + " and " + simplexName(s) +
                   " elements; expected one element type");
      out.shape = s;
      haveShape = true;
      const std::vector<int> perm = gmshToVtk(types[k], s);
      const int n = simplexNodes(s);
      for (std::size_t c = 0; c * n < nodeTags[k].size(); ++c) {
        std::vector<int> cell(n);
        for (int j = 0; j < n; ++j) cell[j] = nodes.nodeOf(nodeTags[k][c * n + perm[j]], out);
        out.cells.push_back(cell);
      }
    }
  }
}

/// Checking: some cells, no free node (classified on the body's entities
/// but in no element).
void checkBodyNodes(const BodyMeshRequest& req, const std::vector<int>& entities, const std::string& groupKind,
                    const BodyNodes& nodes, const BodyMesh& out, const Fail& fail) {
  if (out.cells.empty()) throw fail(groupKind + " '" + req.group + "' has no elements in '" + req.file + "'");
  for (int e : entities) {
    std::vector<std::size_t> tags;
    std::vector<double> coord, param;
    gmsh::model::mesh::getNodes(tags, coord, param, req.dim, e, false, false);
    for (std::size_t i = 0; i < tags.size(); ++i)
      if (!nodes.index.count(tags[i]))
        throw fail("node " + std::to_string(tags[i]) + " at (" + fmtNumber(coord[3 * i]) + ", " +
                   fmtNumber(coord[3 * i + 1]) + ", " + fmtNumber(coord[3 * i + 2]) + ") of " + groupKind + " '" +
                   req.group + "' belongs to no element (a free node: no mass, no stiffness); expected every node in an element");
  }
}

/// The facets (lower-dimensional elements) of a boundary group whose nodes are all the body's.
std::vector<std::vector<int>> groupFacets(int dim, int tag, const BodyNodes& nodes) {
  std::vector<std::vector<int>> facets;
  std::vector<int> ents;
  gmsh::model::getEntitiesForPhysicalGroup(dim, tag, ents);
  for (int e : ents) {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> elTags, nodeTags;
    gmsh::model::mesh::getElements(types, elTags, nodeTags, dim, e);
    for (std::size_t k = 0; k < types.size(); ++k) {
      std::string tn;
      int d, order, numNodes, primary;
      std::vector<double> local;
      gmsh::model::mesh::getElementProperties(types[k], tn, d, order, numNodes, local, primary);
      for (std::size_t c = 0; (c + 1) * numNodes <= nodeTags[k].size(); ++c) {
        std::vector<int> f;
        for (int j = 0; j < numNodes; ++j) {
          auto it = nodes.index.find(nodeTags[k][c * numNodes + j]);
          if (it != nodes.index.end()) f.push_back(it->second);
        }
        if (static_cast<int>(f.size()) == numNodes) facets.push_back(f);
      }
    }
  }
  return facets;
}

/// Naming: the body's named points, node groups and, for boundary groups, their facets.
void readNamedGroups(const BodyMeshRequest& req, const gmsh::vectorpair& groups, const BodyNodes& nodes,
                     BodyMesh& out, const Fail& fail) {
  for (const auto& [dim, tag] : groups) {
    if (dim >= req.dim) continue;
    std::string name;
    gmsh::model::getPhysicalName(dim, tag, name);
    if (name.empty()) continue;
    std::vector<std::size_t> tags;
    std::vector<double> coord;
    gmsh::model::mesh::getNodesForPhysicalGroup(dim, tag, tags, coord);
    std::vector<int> members;
    for (std::size_t t : tags)
      if (nodes.index.count(t)) members.push_back(nodes.index.at(t));
    if (members.empty()) continue;  // not on this body
    if (dim == 0) {
      if (tags.size() != 1) throw fail("Physical Point '" + name + "' holds " + std::to_string(tags.size()) + " nodes; expected one");
      out.points[name] = members[0];
      continue;
    }
    out.groups[name] = members;
    if (dim != req.dim - 1) continue;
    auto& facets = out.facets[name];
    for (auto& f : groupFacets(dim, tag, nodes)) facets.push_back(std::move(f));
  }
}

/// The body's mesh, computed with Gmsh in this process (the sandboxed child).
BodyMesh meshBodyHere(const BodyMeshRequest& req, const std::string& where) {
  const Fail fail = [&](const std::string& what) { return InputError(where + ": " + what); };
  const std::string& file = req.file;
  const bool isMsh = endsWith(file, ".msh");
  const std::string groupKind = req.dim == 2 ? "Physical Surface" : "Physical Volume";
  BodyMesh out;
  try {
    gmsh::logger::start();
    gmsh::open(file);
    {
      std::string err;
      gmsh::logger::getLastError(err);
      if (!err.empty()) throw fail("Gmsh cannot read '" + file + "': " + err);
    }
    gmsh::vectorpair groups;
    gmsh::model::getPhysicalGroups(groups);
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(req.dim, bodyGroupTag(req, groups, groupKind), entities);
    if (!isMsh) generateMesh(req, entities, fail);
    BodyNodes nodes;
    readCells(req, entities, groupKind, nodes, out, fail);
    checkBodyNodes(req, entities, groupKind, nodes, out, fail);
    readNamedGroups(req, groups, nodes, out, fail);
  } catch (const std::string& gmshError) {  // Gmsh 4.8 throws its error text as std::string
    throw fail("Gmsh error with '" + file + "': " + gmshError);
  }
  return out;
}

}  // namespace

BodyMesh meshBody(const BodyMeshRequest& req, const std::string& where) {
  const bool isMsh = endsWith(req.file, ".msh");
  const std::string contents = readGeometryFile(req.file, "mesh file", where);
  if (isMsh)
    checkMshCounts(req.file, contents, where);
  else
    scanGeoFile(req.file, {req.gmsh.sceneDir}, where);
  BodyMesh mesh = decodeBodyMesh(
      runGmshSandboxed(req.file, req.gmsh.limits, where, [&] { return encodeBodyMesh(meshBodyHere(req, where)); }));
  const double nodes = static_cast<double>(mesh.positions.size());
  requireMemory(nodes * (req.dim == 3 ? kMeshBytesPerNode3D : kMeshBytesPerNode2D),
                where + ": " + (req.dim == 2 ? "Physical Surface '" : "Physical Volume '") + req.group + "' of " +
                    fmtNumber(nodes) + " nodes",
                isMsh ? std::string("use a coarser mesh") : std::string("use a larger size (the element's size key) or order 1"));
  return mesh;
}

}  // namespace flexsens
