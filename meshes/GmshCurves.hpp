// Bridge from a Gmsh geometry (.geo) to node chains for beams.
//
// A scene's beams, springs and bars can be drawn as named curves (Physical Curves) of a Gmsh
// geometry, with named joints (Physical Points). meshCurves() opens the geometry, meshes the
// requested curves with a prescribed number of uniform segments (transfinite), and returns
// each requested group as one ordered chain of named nodes.
//
// Gmsh lifetime: the .geo is scanned for commands that reach outside (meshes/GeoScan), then
// Gmsh (SDK 4.8) runs in a sandboxed child process (meshes/GmshSandbox) with CPU-time and
// memory limits; the chains come back over a pipe. The calling process never initializes
// Gmsh, so scenes without meshes never start it and a caller's own Gmsh session is left alone.
//
// Units: Gmsh has none; the coordinates of the .geo are taken as meters.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/Types.hpp"
#include "meshes/GeometryFile.hpp"
#include "meshes/GmshSandbox.hpp"

namespace flexsens {

/// One requested group: a Physical Curve name and its total number of segments.
struct CurveRequest {
  std::string group;
  int segments = 0;
};

/// A group's nodes, ordered from one free end of its connected curves to the other.
/// names[i] is the name of the Physical Point the node sits on, if any, else "<group>.<i>";
/// two chains that meet at a named point share that node name.
struct NodeChain {
  std::string group;
  std::vector<std::string> names;
  std::vector<Eigen::Vector3d> positions;  ///< [m]
  /// Unit tangents along the chain: the curve's own direction at each node (where two curves
  /// of the group meet, the mean of their two).
  std::vector<Eigen::Vector3d> tangents;
};

struct CurveMesh {
  std::vector<NodeChain> chains;                   ///< in the order of the requests
  std::map<std::string, Eigen::Vector3d> points;  ///< every named Physical Point [m]
};

/// Limit on input before Gmsh sees it: segments per requested curve group (a model of
/// 3 x 10^4 coordinates per curve is already beyond what the dense PIM system handles); the
/// size of a geometry file: kMaxGeometryBytes (meshes/GeometryFile.hpp).
inline constexpr int kMaxSegments = 10000;

/// Meshes the requested Physical Curves of `geoFile` and returns one chain per request.
///
/// A group may hold several curves forming one open chain (e.g. an arc longer than 180
/// degrees split into two Circle arcs). Its `segments` are distributed over its curves in
/// proportion to their lengths (largest remainder, at least one per curve, total exactly
/// `segments`), each curve meshed uniformly in its parameter. The chain starts at a free end,
/// preferring the one where a curve starts (so a group drawn A -> P -> B is listed from A).
/// An end point that is not a Physical Point is allowed; its node is named "<group>.0" (or
/// "<group>.<segments>" at the far end) like any interior node.
///
/// Throws InputError(where + ": ...") when the file cannot be opened, holds a refused command
/// (meshes/GeoScan), Gmsh hits a limit of `options` or reports an error,
/// a requested group is missing (the message lists the available Physical Curves), a group is
/// requested twice or shares a curve with another requested group, segments < 1 or fewer than
/// the group's curves, or the group's curves do not form one open chain (branch, loop, closed
/// curve, disconnected pieces); also when a Physical Point holds several points, two Physical
/// Points share a name or a point.
CurveMesh meshCurves(const std::string& geoFile, const std::vector<CurveRequest>& requests,
                     const std::string& where, const GmshOptions& options = {});

}  // namespace flexsens
