// One lock per output folder, taken by every kind of run (run, its PIM cases, static, study;
// a sweep of many runs into one folder would take it once for the folder).
//
// The folder is first resolved: the existing part of the path through its symbolic links
// (realpath), the rest appended, so `--out link` and `--out real` are the same folder and
// `a/../b` is the folder the kernel would open. The lock is flock(2) on
//   <resolved parent>/.<name>.lock        exclusive while a run writes <name>
// and, shared, on the lock files that already exist for the folders above it: a run into
// D/F1 and a run into D (or D's PIM cases) exclude each other once D has been written.
// A second run refuses at once (DirectoryBusy, exit 6); it does not wait.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace flexsens {

/// The absolute folder `dir` names, resolved as above. Throws OutputError when `dir` is
/// empty, is "/", or is a symbolic link to nothing.
std::filesystem::path resolveOutputFolder(const std::string& dir);

class OutputLock {
 public:
  /// Locks the resolved folder `dir` (resolveOutputFolder), creating its parent. Throws
  /// DirectoryBusy naming the folder and the lock when another run holds it, OutputError
  /// when the lock file cannot be created.
  explicit OutputLock(const std::filesystem::path& dir);
  ~OutputLock();  ///< unlocks
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  const std::string& lockFile() const { return lockFile_; }

 private:
  void release();
  std::string lockFile_;
  std::vector<int> fds_;
};

}  // namespace flexsens
