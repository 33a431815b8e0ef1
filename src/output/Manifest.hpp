// What a flexsens output folder holds, so that flexsens deletes or replaces only what it wrote.
//
// Every folder a run, static run, study or case writes carries `.flexsens-manifest`:
//
//   flexsens-manifest 1        format (layout) marker: other formats are not ours to touch
//   kind run                   run | static | cases | study (informative)
//   file series.csv            a file flexsens wrote
//   dir F1                     a subfolder flexsens wrote, with its own manifest
//   keep view.pvsm             a file or folder flexsens' scripts write there later (render,
//                              plots): accepted as it is, carried over to a rerun, never deleted
//
// Names are single path components (no '/', '.', '..'): a manifest cannot point outside its
// folder. Besides listed entries a folder may hold flexsens' own housekeeping: empty lock
// files `.<name>.lock` and marked staging folders `.<name>.staging-<pid>` of killed runs.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace flexsens {

constexpr const char* kManifestName = ".flexsens-manifest";
constexpr const char* kStagingMarker = ".flexsens-staging";  ///< inside a staging folder while a run writes it

struct Manifest {
  std::string kind = "run";
  std::vector<std::string> files, dirs, keep;
};

/// The manifest's text (format line first).
std::string manifestText(const Manifest& m);
/// Reads `dir`'s manifest; nullopt with `problem` set when it is absent, not a regular file,
/// of another format, or names an entry that is not a plain name.
std::optional<Manifest> readManifest(const std::filesystem::path& dir, std::string& problem);

/// What of a folder flexsens did not write.
struct ForeignEntries {
  std::vector<std::string> entries;  ///< relative paths (folders end in '/'), in directory order
  std::string note;                  ///< why a manifest was not accepted, or a hint
};
/// The entries of `dir` that no manifest lists (through its listed subfolders); empty when
/// `dir` is empty or holds only flexsens output. A listed file must be a regular file and a
/// listed folder a folder (not a symbolic link) to count as listed.
ForeignEntries foreignEntries(const std::filesystem::path& dir);
/// "a, b/, c and 3 more": the first few of `entries` for a message.
std::string describeEntries(const std::vector<std::string>& entries);

/// Removes what `dir`'s manifest lists (files, listed subfolders the same way), the manifest,
/// flexsens' housekeeping and then `dir` itself if nothing else is left. Never removes an
/// unlisted entry or a `keep` file. Returns whether `dir` is gone.
bool removeListed(const std::filesystem::path& dir);

/// Writes the manifest of a folder flexsens has just written whole (a staging folder): every
/// regular file and subfolder in it, except the manifest and the staging marker, plus `keep`.
/// Throws OutputError (shownDir names the folder in the message).
void writeManifestOfContents(const std::filesystem::path& dir, const std::string& shownDir, const std::string& kind,
                             const std::vector<std::string>& keep);

/// Writes `text` to `path` with every system call checked (open, each write, close).
/// Throws OutputError naming `shownPath` and the OS reason (a full disk: ENOSPC).
void writeFileChecked(const std::string& path, const std::string& shownPath, const std::string& text);

}  // namespace flexsens
