// The output directory of one run: locked against a concurrent run, written as a fresh
// staging directory next to it, and moved into place whole when the run ends (complete,
// failed or interrupted), replacing earlier results wholesale.
//
//   <parent>/.<name>.lock            flock'ed while a run writes <parent>/<name>
//   <parent>/.<name>.staging-<pid>   the run's files until commit()
#pragma once

#include <string>

namespace flexsens {

class RunDirectory {
 public:
  /// Locks `dir` and creates the staging directory. Throws DirectoryBusy when another run
  /// holds the lock, OutputError (path and OS reason) when `dir` is not a directory, is a
  /// non-empty directory without flexsens results, or cannot be created.
  explicit RunDirectory(const std::string& dir);
  ~RunDirectory();  ///< removes the staging directory unless committed; unlocks
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;

  const std::string& staging() const { return staging_; }
  const std::string& final() const { return final_; }
  /// Replaces `dir` by the staging directory (an atomic exchange where the file system
  /// allows it) and removes the earlier results. Throws OutputError.
  void commit();

 private:
  std::string final_, staging_, lock_;
  int lockFd_ = -1;
  bool committed_ = false;
};

}  // namespace flexsens
