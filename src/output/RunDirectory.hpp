// The output folder of one run (or static run, study, or a run of several PIM cases): locked
// against a concurrent run, written into a fresh staging folder next to it, and moved into
// place when the run ends (complete, failed or interrupted).
//
//   <parent>/.<name>.lock              flock'ed while a run writes <parent>/<name> (OutputLock.hpp)
//   <parent>/.<name>.staging-<pid>     the run's files until commit(); marked .flexsens-staging
//
// flexsens replaces only what it wrote (Manifest.hpp): the folder must be new, empty, or hold
// earlier flexsens output only (every entry listed in a .flexsens-manifest); anything else is
// refused before a file is written (OutputError, exit 4). Replacing removes the earlier
// output's listed files only; a folder is exchanged whole only when everything in it is
// listed, checked again at the moment of the exchange. `--out` through a symbolic link
// writes into the link's target; the link stays.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace flexsens {

class OutputLock;

class RunDirectory {
 public:
  /// Resolves and checks `dir`, locks it and creates the staging folder. `kind` goes into
  /// the manifest: run | static | study | cases (a run of PIM cases: one part per case,
  /// <dir>/<case>, committed one by one). Throws DirectoryBusy when another run holds the
  /// lock; OutputError (path and reason) when `dir` holds anything flexsens did not write,
  /// is not a folder, or cannot be created.
  explicit RunDirectory(const std::string& dir, std::string kind = "run");
  ~RunDirectory();  ///< removes the staging folder (what it still holds was not committed); unlocks
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;

  const std::string& staging() const { return staging_; }
  const std::string& final() const { return final_; }
  /// Staging folder of `part` (a case), created on first use; "" is the whole folder.
  std::string staging(const std::string& part);
  std::string final(const std::string& part) const { return part.empty() ? final_ : final_ + "/" + part; }
  /// Names a file or folder that flexsens' scripts write into the folder later (plots, a
  /// ParaView state, rendered frames): listed as `keep`, so a rerun accepts it as it is and
  /// carries it over. Runs keep view.pvsm and png/ (scripts/render_frames.py, run-main.sh).
  void keep(const std::string& name) { keep_.push_back(name); }
  /// Writes the manifest and moves the staging folder into place (an atomic exchange where
  /// the file system allows it); then removes the earlier output's listed files. Throws
  /// OutputError; if the results could not be moved into place they are kept beside it, under
  /// a name the message gives.
  void commit();
  /// The same for one part: <final>/<part>; the folder's manifest lists the part.
  void commit(const std::string& part);

 private:
  void clearStagingLeftovers() const;
  void place(const std::filesystem::path& from, const std::filesystem::path& to);
  void addPartToFolderManifest(const std::string& part);
  /// Results that could not be moved into `to`: renamed to <to>.unplaced-<pid> (or left in
  /// staging) and never removed; throws OutputError(reason + where they are).
  [[noreturn]] void keepAside(const std::filesystem::path& from, const std::filesystem::path& to,
                              const std::string& reason);
  std::string kind_, final_, staging_;
  std::vector<std::string> keep_;
  std::unique_ptr<OutputLock> lock_;
  bool committed_ = false;
  bool keptStaging_ = false;  ///< the staging folder holds something to keep: not removed
};

}  // namespace flexsens
