// Byte encoding of the Gmsh child's results (meshes/GmshSandbox): BodyMesh and CurveMesh as
// little-endian-native fixed-size integers and doubles, strings and lists with their counts
// first. Parent and child are the same binary, so no versioning; decoding checks every count
// against the bytes left and every node index against the node count, and throws
// std::logic_error on a malformed message.
#pragma once

#include <string>

#include "meshes/GmshCurves.hpp"
#include "meshes/GmshMesh.hpp"

namespace flexsens {

std::string encodeBodyMesh(const BodyMesh& mesh);
BodyMesh decodeBodyMesh(const std::string& bytes);

std::string encodeCurveMesh(const CurveMesh& mesh);
CurveMesh decodeCurveMesh(const std::string& bytes);

}  // namespace flexsens
