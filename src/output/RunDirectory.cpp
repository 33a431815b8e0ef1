#include "output/RunDirectory.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "core/Types.hpp"
#include "output/Manifest.hpp"
#include "output/OutputLock.hpp"

namespace flexsens {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const std::string& what, const std::string& path, int err) {
  throw OutputError("cannot " + what + " " + path + ": " + std::strerror(err));
}

bool present(const fs::path& p) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(p, ec));
}

/// Refuses `dir` unless it is new, empty, or holds flexsens output only (Manifest.hpp).
void requireOnlyOurs(const fs::path& dir) {
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (!fs::exists(st)) return;
  if (!fs::is_directory(st))
    throw OutputError("cannot write the results into " + dir.string() + ": it exists and is not a directory");
  const ForeignEntries f = foreignEntries(dir);
  if (f.entries.empty()) return;
  throw OutputError("cannot write the results into " + dir.string() + ": it holds " +
                    std::to_string(f.entries.size()) + (f.entries.size() == 1 ? " entry" : " entries") +
                    " flexsens did not write (" + describeEntries(f.entries) + ")" +
                    (f.note.empty() ? "" : "; " + f.note) +
                    ". flexsens writes only into a new or empty folder or one holding its own earlier output "
                    "(listed in " + kManifestName + ") and never deletes what it did not write: choose another "
                    "--out or output.directory (a new folder, e.g. " + (dir / "results").string() + ")");
}

bool listed(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

/// After `fresh` took the earlier output's place (now at `earlier`): the files flexsens'
/// scripts keep there move over; the earlier output's listed files go. Whatever else is left
/// (appeared while the run wrote) is kept, visibly, beside the folder. Returns the folder
/// it was kept in, or "" when nothing was left.
std::string disposeEarlier(const fs::path& earlier, const fs::path& fresh, const std::vector<std::string>& keep) {
  std::string problem;
  if (const auto m = readManifest(earlier, problem))
    for (const auto& k : m->keep)
      if (listed(keep, k) && !fs::is_symlink(fs::symlink_status(earlier / k)) && !present(fresh / k))
        ::rename((earlier / k).c_str(), (fresh / k).c_str());
  if (removeListed(earlier)) return "";
  const fs::path kept = fresh.string() + ".earlier-" + std::to_string(::getpid());
  if (::rename(earlier.c_str(), kept.c_str()) != 0) return earlier.string();
  return kept.string();
}

}  // namespace

RunDirectory::RunDirectory(const std::string& dir, std::string kind) : kind_(std::move(kind)) {
  const fs::path fin = resolveOutputFolder(dir);
  final_ = fin.string();
  requireOnlyOurs(fin);  // before anything is created (no lock file beside a refused folder)
  lock_ = std::make_unique<OutputLock>(fin);
  requireOnlyOurs(fin);  // again under the lock: this check decides
  clearStagingLeftovers();
  staging_ = (fin.parent_path() / ("." + fin.filename().string() + ".staging-" + std::to_string(::getpid()))).string();
  if (::mkdir(staging_.c_str(), 0755) != 0) {
    const int err = errno;
    staging_.clear();
    fail("create the directory", fin.parent_path().string() + "/." + fin.filename().string() + ".staging-*", err);
  }
  std::error_code ec;
  try {
    // Marks the folder as flexsens' own (a killed run's is removed by the next run), and
    // finds a full disk before the run computes anything.
    writeFileChecked(staging_ + "/" + kStagingMarker, staging_ + "/" + kStagingMarker,
                     "flexsens writes " + final_ + " here (pid " + std::to_string(::getpid()) + ")\n");
  } catch (...) {
    fs::remove_all(staging_, ec);
    throw;
  }
  // scripts/render_frames.py's ParaView state; its frames where the main job puts them
  if (kind_ == "run" || kind_ == "static" || kind_ == "cases") keep_ = {"view.pvsm", "png"};
}

RunDirectory::~RunDirectory() {
  std::error_code ec;
  if (!staging_.empty() && !committed_ && !keptStaging_) fs::remove_all(staging_, ec);  // written by this run only
}

void RunDirectory::clearStagingLeftovers() const {
  const fs::path fin(final_);
  const std::string prefix = "." + fin.filename().string() + ".staging-";
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const auto& e : fs::directory_iterator(fin.parent_path(), ec)) {
    const std::string f = e.path().filename().string();
    // Killed runs' staging folders: the lock says nobody owns them; the marker that they are ours.
    if (f.compare(0, prefix.size(), prefix) == 0 && fs::is_regular_file(fs::symlink_status(e.path() / kStagingMarker)))
      stale.push_back(e.path());
  }
  for (const auto& p : stale) fs::remove_all(p, ec);
}

std::string RunDirectory::staging(const std::string& part) {
  if (part.empty()) return staging_;
  const std::string p = staging_ + "/" + part;
  if (::mkdir(p.c_str(), 0755) != 0 && errno != EEXIST) fail("create the directory", p, errno);
  return p;
}

void RunDirectory::commit() {
  writeManifestOfContents(staging_, final_, kind_, keep_);
  std::error_code ec;
  fs::remove(fs::path(staging_) / kStagingMarker, ec);
  place(staging_, final_);
  committed_ = true;
}

void RunDirectory::commit(const std::string& part) {
  if (part.empty()) return commit();
  const fs::path from = fs::path(staging_) / part, to = fs::path(final_) / part;
  writeManifestOfContents(from, to.string(), "run", keep_);
  try {
    addPartToFolderManifest(part);
  } catch (const OutputError& e) {
    keepAside(from, to, e.what());
  }
  place(from, to);
}

void RunDirectory::addPartToFolderManifest(const std::string& part) {
  const fs::path dir(final_);
  if (::mkdir(dir.c_str(), 0755) != 0 && errno != EEXIST) fail("create the directory", final_, errno);
  requireOnlyOurs(dir);  // nothing foreign appeared while the run wrote
  std::string problem;
  const std::optional<Manifest> earlier = readManifest(dir, problem);
  Manifest next;
  next.kind = "cases";
  if (earlier && earlier->kind == "cases") {
    next = *earlier;  // the cases not rerun now stay
  } else if (earlier) {
    // The folder held one run's output: it goes (its listed files only), its kept files stay.
    std::error_code ec;
    for (const auto& f : earlier->files)
      if (fs::is_regular_file(fs::symlink_status(dir / f))) fs::remove(dir / f, ec);
    for (const auto& d : earlier->dirs) removeListed(dir / d);
    next.keep = earlier->keep;
  }
  if (!listed(next.dirs, part)) next.dirs.push_back(part);
  const std::string tmp = staging_ + "/" + kManifestName;
  writeFileChecked(tmp, final_ + "/" + kManifestName, manifestText(next));
  if (::rename(tmp.c_str(), (dir / kManifestName).c_str()) != 0) fail("write", final_ + "/" + kManifestName, errno);
}

void RunDirectory::place(const fs::path& from, const fs::path& to) {
  try {
    requireOnlyOurs(to);  // checked again at the moment of the exchange
    if (!present(to)) {
      if (::rename(from.c_str(), to.c_str()) != 0) fail("move the results into", to.string(), errno);
      return;
    }
    fs::path earlier = from;  // after the exchange: the earlier output
    if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_EXCHANGE) != 0) {
      if (errno != EINVAL && errno != ENOSYS) fail("replace", to.string(), errno);
      // File systems without exchange: move the earlier output aside first.
      earlier = from.string() + ".old";
      if (::rename(to.c_str(), earlier.c_str()) != 0) fail("move aside", to.string(), errno);
      if (::rename(from.c_str(), to.c_str()) != 0) {
        const int err = errno;
        ::rename(earlier.c_str(), to.c_str());
        fail("move the results into", to.string(), err);
      }
    }
    const std::string kept = disposeEarlier(earlier, to, keep_);
    if (kept.empty()) return;
    if (kept == from.string()) {  // stays in the staging folder, which is then no leftover to remove
      keptStaging_ = true;
      std::error_code ec;
      fs::remove(fs::path(staging_) / kStagingMarker, ec);
    }
    std::cerr << "flexsens: note: the earlier output in " << to.string() << " held files flexsens did not write "
              << "(they appeared while this run wrote); kept them in " << kept << "\n";
  } catch (const OutputError& e) {
    keepAside(from, to, e.what());
  }
}

void RunDirectory::keepAside(const fs::path& from, const fs::path& to, const std::string& reason) {
  std::error_code ec;
  fs::remove(from / kStagingMarker, ec);
  const fs::path aside = to.string() + ".unplaced-" + std::to_string(::getpid());
  std::string where = aside.string();
  if (::rename(from.c_str(), aside.c_str()) != 0) {
    where = from.string();
    keptStaging_ = true;
    fs::remove(fs::path(staging_) / kStagingMarker, ec);  // not a leftover for the next run to remove
  }
  throw OutputError(reason + "; the finished results are kept in " + where);
}

}  // namespace flexsens
