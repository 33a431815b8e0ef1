#include "output/RunDirectory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/Types.hpp"

namespace flexsens {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const std::string& what, const std::string& path, int err) {
  throw OutputError("cannot " + what + " " + path + ": " + std::strerror(err));
}

bool holdsResults(const fs::path& d) {
  std::error_code ec;
  for (const char* f : {"summary.json", "series.csv", "frames.pvd"})
    if (fs::exists(d / f, ec)) return true;
  return false;
}

/// Replacing a directory wholesale is safe only when it holds flexsens results (or nothing;
/// or the per-case directories of a scene with PIM cases): `--out ~` must not delete a home
/// directory.
bool replaceable(const fs::path& d) {
  std::error_code ec;
  if (fs::is_empty(d, ec) || holdsResults(d)) return true;
  for (const auto& e : fs::directory_iterator(d, ec))
    if (e.is_directory(ec) && holdsResults(e.path())) return true;
  return false;
}

}  // namespace

RunDirectory::RunDirectory(const std::string& dir) {
  fs::path fin = fs::absolute(dir).lexically_normal();
  if (fin.filename().empty()) fin = fin.parent_path();  // "out/" names "out"
  final_ = fin.string();
  const fs::path parent = fin.parent_path();
  const std::string name = fin.filename().string();
  std::error_code ec;
  const fs::file_status st = fs::status(fin, ec);
  if (fs::exists(st) && !fs::is_directory(st))
    throw OutputError("cannot write the results into " + final_ + ": it exists and is not a directory");
  fs::create_directories(parent, ec);
  if (ec) throw OutputError("cannot create the directory " + parent.string() + ": " + ec.message());

  lock_ = (parent / ("." + name + ".lock")).string();
  lockFd_ = ::open(lock_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lockFd_ < 0) fail("create the lock file", lock_, errno);
  try {
    if (::flock(lockFd_, LOCK_EX | LOCK_NB) != 0) {
      if (errno == EWOULDBLOCK)
        throw DirectoryBusy("another flexsens run is writing " + final_ + " (it holds the lock " + lock_ +
                            "); wait for it to end or choose another --out");
      fail("lock", lock_, errno);
    }
    if (fs::is_directory(st) && !replaceable(fin))
      throw OutputError("cannot write the results into " + final_ +
                        ": it is a non-empty directory without flexsens results (no summary.json, series.csv "
                        "or frames.pvd), and a run replaces its directory whole; choose another --out");
    // Staging directories of this name left by killed runs: the lock says nobody owns them.
    const std::string prefix = "." + name + ".staging-";
    for (const auto& e : fs::directory_iterator(parent, ec)) {
      const std::string f = e.path().filename().string();
      if (f.compare(0, prefix.size(), prefix) == 0) fs::remove_all(e.path(), ec);
    }
    staging_ = (parent / (prefix + std::to_string(::getpid()))).string();
    if (::mkdir(staging_.c_str(), 0755) != 0) fail("create the directory", staging_, errno);
  } catch (...) {
    ::close(lockFd_);  // also releases the lock
    throw;
  }
}

RunDirectory::~RunDirectory() {
  std::error_code ec;
  if (!committed_ && !staging_.empty()) fs::remove_all(staging_, ec);
  if (lockFd_ >= 0) ::close(lockFd_);
}

void RunDirectory::commit() {
  std::error_code ec;
  if (fs::exists(final_, ec)) {
    // Exchange in one step: readers see the old results or the new ones, never a mixture.
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, final_.c_str(), RENAME_EXCHANGE) == 0) {
      committed_ = true;
      fs::remove_all(staging_, ec);  // now the earlier results
      return;
    }
    if (errno != EINVAL && errno != ENOSYS) fail("replace", final_, errno);
    // File systems without exchange: move the old results aside first.
    const std::string old = staging_ + ".old";
    if (::rename(final_.c_str(), old.c_str()) != 0) fail("move aside", final_, errno);
    if (::rename(staging_.c_str(), final_.c_str()) != 0) fail("move into place", staging_, errno);
    committed_ = true;
    fs::remove_all(old, ec);
    return;
  }
  if (::rename(staging_.c_str(), final_.c_str()) != 0) fail("move into place", staging_, errno);
  committed_ = true;
}

}  // namespace flexsens
