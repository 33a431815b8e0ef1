// Which files a scene may make flexsens read, and how large they may be. A scene names files
// (a mesh, a Gmsh geometry, a time-function table); it is shared between users, so it may
// only reach files in its own folder and below, unless the command line allows more folders
// (--allow-path DIR). Paths are compared after resolving symlinks and '..' (real paths).
// Scene and data files must be regular files under a size limit: /dev/zero, a FIFO or a
// /proc file is refused before a byte is read.
#pragma once

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/YamlReader.hpp"

namespace flexsens {

struct InputPolicy {
  std::vector<std::filesystem::path> allowedDirs;  ///< real paths of the folders allowed beyond the scene's
  std::uintmax_t maxSceneBytes = 16u << 20;        ///< a scene file [bytes] (16 MiB)
  std::uintmax_t maxTableBytes = 64u << 20;        ///< a time-function table [bytes] (64 MiB)
  std::uintmax_t maxMeshBytes = 64u << 20;         ///< a .msh or .geo file [bytes] (64 MiB, as kMaxGeometryBytes)
};

/// The process's policy (the CLI fills allowedDirs from --allow-path).
InputPolicy& inputPolicy();
/// Adds a folder to inputPolicy().allowedDirs; InputError (naming `option`) if it is not one.
void allowInputDirectory(const std::string& dir, const std::string& option = "--allow-path");

/// The real path of the file that scene key `key` (at node `n`) names as `name`, relative to
/// the scene's folder. Fails (file:line, key) when the file does not exist, lies outside the
/// scene's folder and the allowed ones, is not a regular file or is larger than maxBytes.
std::string sceneDataFile(const YamlReader& r, const YAML::Node& n, const std::string& key, const std::string& name,
                          std::uintmax_t maxBytes);

/// The contents of `file`, read only if it is a regular file of at most maxBytes (and read no
/// further than that, for files whose size the kernel does not report); the message of the
/// std::runtime_error thrown otherwise names `shown`.
std::string readBoundedFile(const std::string& file, std::uintmax_t maxBytes, const std::string& shown);

}  // namespace flexsens
