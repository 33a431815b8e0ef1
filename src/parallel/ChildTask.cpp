#include "parallel/ChildTask.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <stdexcept>
#include <vector>

#include "parallel/Packer.hpp"

namespace flexsens {

namespace {

/// The first byte of what a child sends: a result follows, or the message of an exception.
constexpr char kResult = 'R', kException = 'E';

void writeAll(int fd, const std::string& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the parent is gone or stopped reading: nobody to tell
    done += static_cast<size_t>(n);
  }
}

/// The child's side: runs `work`, sends its result, and ends without running the parent's
/// exit handlers (MPI, static destructors, buffered output that belongs to the parent).
[[noreturn]] void runChild(const std::function<std::string()>& work, bool quiet, int fd, pid_t parent) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(111);  // the parent died before prctl
  if (quiet) {
    const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (null >= 0) {
      ::dup2(null, STDOUT_FILENO);
      ::dup2(null, STDERR_FILENO);
    }
  }
  std::string message;
  const auto start = std::chrono::steady_clock::now();
  try {
    std::string result = work();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    message = kResult + Packer().number(seconds).text(result).bytes();
  } catch (const std::exception& e) {
    message = kException + std::string(e.what());
  } catch (...) {
    message = kException + std::string("an unknown exception");
  }
  std::cout.flush();
  std::cerr.flush();
  writeAll(fd, message);
  ::close(fd);  // end of file for the parent now, before the exit tears down the address space
  ::_exit(0);
}

/// Children whose result arrived before they had exited: reaped later, without waiting.
std::vector<pid_t>& unreaped() {
  static std::vector<pid_t> pids;
  return pids;
}

}  // namespace

void ChildTask::reapFinished(bool wait) {
  auto& pids = unreaped();
  auto gone = [wait](pid_t p) { return ::waitpid(p, nullptr, wait ? 0 : WNOHANG) != 0; };  // 0: still exiting
  pids.erase(std::remove_if(pids.begin(), pids.end(), gone), pids.end());
}

namespace {

std::string signalName(int sig) {
  const char* d = ::strsignal(sig);
  return "signal " + std::to_string(sig) + (d ? " (" + std::string(d) + ")" : "");
}

}  // namespace

ChildTask::ChildTask(const std::function<std::string()>& work, bool quiet) : start_(std::chrono::steady_clock::now()) {
  reapFinished(false);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
  std::cout.flush();  // what the parent buffered must not be written twice
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t parent = ::getpid();
  pid_ = ::fork();
  if (pid_ < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error(std::string("cannot start a child process: ") + std::strerror(err));
  }
  if (pid_ == 0) {
    ::close(fds[0]);
    runChild(work, quiet, fds[1], parent);
  }
  ::close(fds[1]);
  fd_ = fds[0];
  ::fcntl(fd_, F_SETFL, O_NONBLOCK);  // poll() drains what is there without waiting for more
}

ChildTask::~ChildTask() {
  if (!ended_) kill("abandoned");
  if (fd_ >= 0) ::close(fd_);
}

double ChildTask::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

bool ChildTask::poll(double wait) {
  if (ended_) return true;
  pollfd p{fd_, POLLIN, 0};
  const long ns = static_cast<long>(wait * 1e9);
  const timespec timeout{ns / 1000000000L, ns % 1000000000L};
  if (::ppoll(&p, 1, &timeout, nullptr) <= 0) return false;
  char buf[65536];
  for (;;) {  // drains what is there; a full pipe would stop the child
    const ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n > 0) {
      received_.append(buf, static_cast<size_t>(n));
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EAGAIN) return false;
    break;  // end of file: the child closed its end (it is exiting) or died
  }
  reap();
  return true;
}

/// A whole result message (marker, task seconds, payload): the outcome is done.
bool ChildTask::takeResult() {
  if (received_.empty() || received_[0] != kResult) return false;
  try {
    const std::string packed = received_.substr(1);
    Unpacker u(packed);
    const double seconds = u.number();
    std::string payload = u.text();
    if (!u.atEnd()) return false;
    outcome_.done = true;
    outcome_.taskSeconds = seconds;
    outcome_.payload = std::move(payload);
    return true;
  } catch (const std::exception&) {
    return false;  // cut short: the child died while it wrote
  }
}

void ChildTask::reap() {
  ended_ = true;
  outcome_.seconds = elapsed();
  if (takeResult()) {  // done, however long the exit still takes: reaped later
    if (::waitpid(pid_, nullptr, WNOHANG) == 0) unreaped().push_back(pid_);
    received_.clear();
    return;
  }
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status))
    outcome_.lost = "its process was killed by " + signalName(WTERMSIG(status));
  else if (!received_.empty() && received_[0] == kException)
    outcome_.lost = "it stopped on an error: " + received_.substr(1);
  else
    outcome_.lost = "its process ended with exit status " + std::to_string(WEXITSTATUS(status)) + " without a result";
  received_.clear();
}

void ChildTask::kill(const std::string& reason) {
  if (ended_) return;
  ::kill(pid_, SIGKILL);
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  ended_ = true;
  outcome_ = ChildOutcome{};
  outcome_.lost = reason;
  outcome_.seconds = elapsed();
}

}  // namespace flexsens
