// A shell from a triangle mesh: one ShellTriangle (membrane, mass) per triangle and either (the
// discrete shell) one ShellHinge (bending) per interior edge, the edge shared by exactly two
// triangles, or (bending: kirchhoff) one ShellKirchhoffBending per triangle
// (elements/ShellKirchhoff.hpp), with an optional patch membrane (elements/ShellPatchMembrane.hpp).
// Boundary edges (one triangle) carry no hinge: a free or simply supported edge (the
// rotation about it costs nothing), unless both its nodes are clamped: then a ShellClampHinge
// (elements/ShellClampHinge.hpp) holds its triangle's rotation about it. An edge of three or
// more triangles (non-manifold) is an error: one dihedral angle per edge is then undefined.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/Element.hpp"
#include "elements/ShellProperties.hpp"

namespace flexsens {

struct ShellMeshCounts {
  int triangles = 0, hinges = 0, boundaryEdges = 0, clamps = 0;
  int kirchhoff = 0;  ///< Kirchhoff bending triangles (bending: kirchhoff)
};

/// A boundary edge of a Kirchhoff shell (elements/ShellKirchhoff.hpp): free (slope free, an
/// optional applied edge moment per length [N m/m], positive lifting the outward side) or fixed
/// (the tangent across the edge held: a clamp, normal zero, or a symmetry plane of that normal).
struct KirchhoffBoundary {
  bool fixed = false;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double moment = 0.0;
};
/// Boundary edges (mesh node pairs i < j) with a condition; the others are free.
using KirchhoffBoundaries = std::map<std::pair<int, int>, KirchhoffBoundary>;
/// A Kirchhoff shell's edges and membrane: patch (elements/ShellPatchMembrane.hpp, from the
/// same fits) or the triangles' own CST.
struct KirchhoffSettings {
  KirchhoffBoundaries boundary;
  bool patchMembrane = false;
  /// Each triangle's own properties (its membrane, bending and mass: `per: element`
  /// parameters); empty: every triangle has the shell's.
  std::vector<std::shared_ptr<ShellProperties>> perTriangle;
};

/// The Kirchhoff bending triangles (<name>.bend<k>) of triangles tris, one per triangle, their
/// stencils from 6-node quadratic fits (ShellKirchhoffMesh.cpp), and with patchMembrane one
/// ShellPatchMembrane (<name>.membrane<k>) per triangle. Throws std::invalid_argument when no
/// well-posed fit exists near a triangle (a mesh too small or too distorted). Returns their count.
int buildKirchhoffBending(const std::string& name, const std::vector<Eigen::Vector3d>& rest,
                          const std::vector<std::array<int, 3>>& tris, const std::vector<int>& ids,
                          const std::shared_ptr<ShellProperties>& props, bool flatRest,
                          std::vector<std::unique_ptr<Element>>& out, const std::function<std::string(int)>& label,
                          const KirchhoffBoundaries& boundary, bool patchMembrane = false,
                          const std::vector<std::shared_ptr<ShellProperties>>& perTriangle = {});

/// rest: rest positions of the mesh nodes [m]; tris: node indices (into rest and ids) of each
/// triangle; ids: model node of each mesh node. Elements are named <name>.tri<k> and
/// <name>.hinge<k>, <name>.clamp<k>. flatRest: every hinge's rest angle is 0 (else the rest mesh's angle).
/// label(i) names mesh node i in messages. clamped (empty, or one flag per mesh node): a
/// boundary edge whose two nodes are both clamped gets a clamp hinge (the caller fixes those
/// nodes). kirchhoff (not null): Kirchhoff bending triangles instead of hinges and clamps
/// (clamped is then ignored; the clamps are in *kirchhoff). Throws std::invalid_argument for a degenerate
/// triangle or a non-manifold edge.
ShellMeshCounts buildShell(const std::string& name, const std::vector<Eigen::Vector3d>& rest,
                           const std::vector<std::array<int, 3>>& tris, const std::vector<int>& ids,
                           const std::shared_ptr<ShellProperties>& props, bool flatRest,
                           std::vector<std::unique_ptr<Element>>& out, const std::function<std::string(int)>& label,
                           const std::vector<bool>& clamped = {}, const KirchhoffSettings* kirchhoff = nullptr);

/// The boundary edges (node pairs i < j, each in one triangle only) of triangles tris.
std::vector<std::pair<int, int>> shellBoundaryEdges(const std::vector<std::array<int, 3>>& tris);

}  // namespace flexsens
