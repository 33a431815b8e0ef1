// A lexical scan of a Gmsh .geo file (and the files it includes) before Gmsh evaluates it:
// the commands that reach outside are refused with file:line, since opening a shared scene
// must never execute it. The seccomp filter of the Gmsh child (meshes/SeccompFilter) is the
// backstop where the scan cannot see (a command name built at run time, a plugin).
#pragma once

#include <string>
#include <vector>

namespace flexsens {

/// Refused outright (outside comments and strings, not as an option name after or before a
/// '.'): SystemCall, System, NonBlockingSystemCall, Shell, OnelabRun (run programs), Save,
/// Print (write files), CreateDir, DeleteFile, RenameFile (change the file system), Exit,
/// Abort (end Gmsh before the geometry is returned), Sleep (waits on the wall clock).
/// Printf, Error and Warning with a '>' or '>>' redirection after their parentheses (write
/// files). Include, Merge, MergeWithBoundingBox, ShapeFromFile and ListFromFile need a literal
/// file name (quoted string) that resolves inside one of `roots` (symbolic links followed) to
/// a regular file of at most 64 MiB; included .geo files are scanned in turn.
/// Throws InputError(where + ": <file>:<line>: <command> ...").
void scanGeoFile(const std::string& file, const std::vector<std::string>& roots, const std::string& where);

}  // namespace flexsens
