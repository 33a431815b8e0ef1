// Checks of a geometry (.geo) or mesh (.msh) file that need no Gmsh, made by the parent
// before a Gmsh child sees the file (meshes/GmshSandbox): Gmsh's reader would block on a
// FIFO, read /dev/zero or a /proc pseudo-file for ever, or allocate what a header claims.
#pragma once

#include <cstdint>
#include <string>

namespace flexsens {

/// [bytes] the largest geometry or mesh file read (64 MiB).
inline constexpr std::uintmax_t kMaxGeometryBytes = 64u << 20;

/// The file's contents. Throws InputError(where + ": ...") unless it exists and is a readable
/// regular file of at most kMaxGeometryBytes whose contents are as long as its size says (a
/// /proc or /sys pseudo-file reports 0 bytes and holds more). `kind`: "geometry file",
/// "mesh file", ... as named in the message.
std::string readGeometryFile(const std::string& file, const std::string& kind, const std::string& where);

/// A .msh file's $Nodes and $Elements headers (MSH 2 and 4, text or binary): every count
/// claimed must fit the file (each node or element takes more than one byte), so a header
/// claiming 2e9 nodes is refused with its line and count before any reader allocates them.
void checkMshCounts(const std::string& file, const std::string& contents, const std::string& where);

}  // namespace flexsens
