#include "output/OutputLock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/Types.hpp"

namespace flexsens {

namespace fs = std::filesystem;

fs::path resolveOutputFolder(const std::string& dir) {
  if (dir.empty()) throw OutputError("the output folder is empty (--out or output.directory)");
  fs::path p = fs::absolute(dir);
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(p, ec);
  if (fs::is_symlink(link) && !fs::exists(fs::status(p, ec)))
    throw OutputError("cannot write the results into " + dir + ": it is a symbolic link to " +
                      fs::read_symlink(p, ec).string() + ", which does not exist; create that folder or choose another --out");
  // The existing part through its links, the rest appended: what the kernel would open.
  fs::path r = fs::weakly_canonical(p, ec);
  if (ec) throw OutputError("cannot resolve the output folder " + dir + ": " + ec.message());
  if (r.filename().empty()) r = r.parent_path();  // "out/" names "out"
  if (r == r.root_path()) throw OutputError("cannot write the results into " + dir + ": it is the root folder");
  return r;
}

OutputLock::OutputLock(const fs::path& dir) {
  const fs::path parent = dir.parent_path();
  // The folders above first: only their existing lock files (creating one beside every
  // ancestor would litter the user's folders), shared, so that sibling runs D/F1 and D/R go
  // on together while a run into D excludes both.
  for (fs::path a = parent; a.has_relative_path(); a = a.parent_path()) {
    const std::string up = (a.parent_path() / ("." + a.filename().string() + ".lock")).string();
    const int ufd = ::open(up.c_str(), O_RDONLY | O_CLOEXEC);
    if (ufd < 0) continue;
    fds_.push_back(ufd);
    if (::flock(ufd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK) {
      release();
      throw DirectoryBusy("another flexsens run is writing " + a.string() + ", which holds " + dir.string() +
                          " (it holds the lock " + up + "); wait for it to end or choose another --out");
    }
  }
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec) {
    release();
    throw OutputError("cannot create the directory " + parent.string() + ": " + ec.message());
  }
  lockFile_ = (parent / ("." + dir.filename().string() + ".lock")).string();
  const int fd = ::open(lockFile_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int err = errno;
    release();
    throw OutputError("cannot create the lock file " + lockFile_ + ": " + std::strerror(err));
  }
  fds_.push_back(fd);
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    release();
    if (err == EWOULDBLOCK)
      throw DirectoryBusy("another flexsens run is writing " + dir.string() + " (it holds the lock " + lockFile_ +
                          "); wait for it to end or choose another --out");
    throw OutputError("cannot lock " + lockFile_ + ": " + std::strerror(err));
  }
}

void OutputLock::release() {
  for (const int fd : fds_) ::close(fd);  // closing releases the flock
  fds_.clear();
}

OutputLock::~OutputLock() { release(); }

}  // namespace flexsens
