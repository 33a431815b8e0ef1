// Sandboxed Gmsh child process; see GmshSandbox.hpp.
#include "meshes/GmshSandbox.hpp"

#include <fcntl.h>
#include <poll.h>
#include <seccomp.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <optional>
#include <stdexcept>

#include "core/Interrupt.hpp"
#include "core/Types.hpp"
#include "elements/SimplexShape.hpp"  // fmtNumber
#include "meshes/GmshSession.hpp"
#include "meshes/SeccompFilter.hpp"

namespace flexsens {

namespace {

/// Tags of the child's message: the first byte on the pipe.
enum : char {
  kResult = 'R', kInputError = 'E', kLogicError = 'L', kOutOfMemory = 'M', kForbidden = 'S', kExited = 'X'
};
constexpr int kResultFd = 3;                    ///< the pipe's write end in the child
constexpr std::size_t kMaxMessage = 256u << 20; ///< [bytes] a result larger than this is refused
volatile std::sig_atomic_t gReported = 0;       ///< child: a message has been written

void writeAll(const char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(kResultFd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return;
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
}

void report(char tag, const std::string& payload) {
  if (gReported) return;
  gReported = 1;
  std::string msg(1, tag);
  msg += payload;
  writeAll(msg.data(), msg.size());
}

/// SIGSYS from the seccomp filter: report the system call (async-signal-safe) and end.
extern "C" void onForbiddenCall(int, siginfo_t* info, void*) {
  if (!gReported) {
    gReported = 1;
    char msg[1 + sizeof(int)];
    msg[0] = kForbidden;
    const int nr = info->si_syscall;
    std::memcpy(msg + 1, &nr, sizeof nr);
    writeAll(msg, sizeof msg);
  }
  ::_exit(97);
}

/// operator new at the address-space limit: say so before anything else can fail.
void onOutOfMemory() {
  const char tag = kOutOfMemory;
  if (!gReported) {
    gReported = 1;
    writeAll(&tag, 1);
  }
  ::_exit(98);
}

/// exit() called inside Gmsh (an Exit command, a fatal error): no result will come.
extern "C" void onExit() { report(kExited, ""); }

/// [bytes] the process's address space now (/proc/self/statm, first field in pages).
double addressSpaceBytes() {
  std::ifstream in("/proc/self/statm");
  double pages = 0.0;
  in >> pages;
  return pages * static_cast<double>(::sysconf(_SC_PAGESIZE));
}

void setLimit(int resource, rlim_t soft, rlim_t hard) {
  struct rlimit cur;
  if (::getrlimit(resource, &cur) == 0 && cur.rlim_max != RLIM_INFINITY) {
    soft = std::min(soft, cur.rlim_max);  // never above what the parent may use
    hard = std::min(hard, cur.rlim_max);
  }
  struct rlimit rl{soft, hard};
  ::setrlimit(resource, &rl);
}

/// Descriptors: the pipe on kResultFd, /dev/null on 0-2, everything else closed.
void isolateDescriptors(int pipeWrite) {
  if (pipeWrite != kResultFd) {
    ::dup2(pipeWrite, kResultFd);
    ::close(pipeWrite);
  }
  const int devnull = ::open("/dev/null", O_RDWR);
  for (int fd = 0; fd <= 2; ++fd) ::dup2(devnull, fd);
  for (int fd = kResultFd + 1; fd < 65536; ++fd) ::close(fd);  // close_range needs glibc 2.34
}

void resetSignals() {
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = SIG_DFL;
  for (int s : {SIGINT, SIGTERM, SIGXCPU, SIGXFSZ, SIGSEGV, SIGBUS, SIGABRT, SIGPIPE, SIGCHLD}) ::sigaction(s, &sa, nullptr);
  sa.sa_handler = nullptr;
  sa.sa_sigaction = onForbiddenCall;
  sa.sa_flags = SA_SIGINFO;
  ::sigaction(SIGSYS, &sa, nullptr);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
}

[[noreturn]] void childMain(int pipeWrite, pid_t parent, const GmshLimits& limits, const std::function<std::string()>& work) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(99);  // the parent died before the line above
  isolateDescriptors(pipeWrite);
  resetSignals();
  const rlim_t cpu = static_cast<rlim_t>(std::ceil(limits.cpuSeconds));
  setLimit(RLIMIT_CPU, cpu, cpu + 1);  // SIGXCPU at the soft limit, SIGKILL one second later
  const double as = addressSpaceBytes() + limits.memoryMb * 1048576.0;
  setLimit(RLIMIT_AS, static_cast<rlim_t>(as), static_cast<rlim_t>(as));
  setLimit(RLIMIT_CORE, 0, 0);
  std::set_new_handler(onOutOfMemory);
  std::atexit(onExit);
  // Gmsh starts before the filter, on no input of the scene's: its FLTK options read
  // rewrites /etc/fltk/fltk.org/fltk.prefs (Fl::option, once per process).
  std::optional<GmshSession> session;
  try {
    session.emplace();
  } catch (...) {
    report(kLogicError, "Gmsh could not be initialized in its child process");
    ::_exit(95);
  }
  setLimit(RLIMIT_FSIZE, 0, 0);  // from here on, a write to any file opened anyway: SIGXFSZ
  if (::prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0 || !installSeccompFilter()) {
    report(kLogicError, "cannot install the seccomp filter of the Gmsh sandbox; Gmsh is not run unconfined");
    ::_exit(96);
  }
  try {
    const std::string result = work();
    report(kResult, result);
  } catch (const InputError& e) {
    report(kInputError, e.what());
  } catch (const std::string& gmshError) {  // Gmsh 4.8 throws its error text as std::string
    report(kInputError, "Gmsh error: " + gmshError);
  } catch (const std::bad_alloc&) {
    report(kOutOfMemory, "");
  } catch (const std::logic_error& e) {
    report(kLogicError, e.what());
  } catch (const std::exception& e) {
    report(kInputError, e.what());
  } catch (...) {
    report(kInputError, "Gmsh raised an unknown exception");
  }
  ::_exit(0);
}

/// What the parent saw of one child.
struct ChildEnd {
  std::string message;   ///< tag byte and payload, as received
  int status = 0;        ///< wait status
  double cpuSeconds = 0; ///< user + system [s]
  double maxRssMb = 0;   ///< [MiB]
  bool timedOut = false;
  int interrupt = 0;     ///< SIGINT/SIGTERM received by the parent while waiting
};

double seconds(const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); }

void reap(pid_t pid, ChildEnd& end, bool kill) {
  if (kill) ::kill(pid, SIGKILL);
  struct rusage ru;
  std::memset(&ru, 0, sizeof ru);
  while (::wait4(pid, &end.status, 0, &ru) < 0 && errno == EINTR) {
  }
  end.cpuSeconds = seconds(ru.ru_utime) + seconds(ru.ru_stime);
  end.maxRssMb = static_cast<double>(ru.ru_maxrss) / 1024.0;
}

/// Reads the child's message until EOF, then reaps it; kills it on the wall-clock bound, on
/// an interrupt of the parent or on an oversized message.
ChildEnd collect(pid_t pid, int fd, double wallSeconds) {
  ChildEnd end;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(wallSeconds);
  char buf[65536];
  while (true) {
    if ((end.interrupt = interruptSignal()) != 0) break;
    if (std::chrono::steady_clock::now() > deadline) {
      end.timedOut = true;
      break;
    }
    struct pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, 50);
    if (ready <= 0) continue;  // timeout or EINTR: look at the signal and the clock again
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // EOF: the child has ended or closed the pipe
    end.message.append(buf, static_cast<std::size_t>(n));
    if (end.message.size() > kMaxMessage) {
      end.message.clear();
      break;
    }
  }
  // EOF: the child exits right away; give it until the deadline, then kill it.
  bool exited = false;
  while (!end.interrupt && !end.timedOut && std::chrono::steady_clock::now() < deadline) {
    siginfo_t si;
    std::memset(&si, 0, sizeof si);
    if (::waitid(P_PID, static_cast<id_t>(pid), &si, WEXITED | WNOHANG | WNOWAIT) != 0 || si.si_pid != 0) {
      exited = true;
      break;
    }
    ::usleep(2000);
  }
  reap(pid, end, !exited);
  return end;
}

std::string signalName(int sig) {
  const char* d = ::sigabbrev_np(sig);
  return d ? std::string("SIG") + d : "signal " + std::to_string(sig);
}

std::string fmtMb(double mb) { return std::to_string(static_cast<long long>(std::llround(mb))) + " MB"; }

/// The parent's reading of a child that sent no result: an InputError naming the limit.
InputError failure(const ChildEnd& end, const std::string& file, const GmshLimits& limits, const std::string& where) {
  const std::string in = "Gmsh on '" + file + "': ";
  const std::string cpuHint = "; raise " + std::string(GmshLimits::kCpuKey) + " (now " + fmtNumber(limits.cpuSeconds) + " s) if the geometry needs longer";
  const std::string memHint = "; raise " + std::string(GmshLimits::kMemoryKey) + " (now " + fmtNumber(limits.memoryMb) + ") if the geometry needs more";
  if (end.timedOut)
    return InputError(where + ": " + in + "no result within " + fmtNumber(gmshWallSeconds(limits)) + " s of wall-clock time (" +
                      fmtNumber(end.cpuSeconds) + " s CPU); stopped (the wall-clock bound follows " + GmshLimits::kCpuKey + ")" + cpuHint);
  if (!end.message.empty() && end.message[0] == kOutOfMemory)
    return InputError(where + ": " + in + "stopped at the memory limit of " + fmtNumber(limits.memoryMb) +
                      " MB (a huge list or a mesh too fine?)" + memHint);
  if (!end.message.empty() && end.message[0] == kForbidden && end.message.size() >= 1 + sizeof(int)) {
    int nr = 0;
    std::memcpy(&nr, end.message.data() + 1, sizeof nr);
    return InputError(where + ": " + in + "stopped at a forbidden operation: " + describeForbiddenCall(nr) +
                      "; a geometry file may only be read and meshed (remove the command that does this)");
  }
  if (!end.message.empty() && end.message[0] == kExited)
    return InputError(where + ": " + in + "Gmsh ended the process without a result (an Exit command, or a fatal Gmsh error); "
                      "expected a geometry that Gmsh reads to the end");
  if (WIFSIGNALED(end.status)) {
    const int sig = WTERMSIG(end.status);
    if (sig == SIGXCPU || (sig == SIGKILL && end.cpuSeconds >= std::ceil(limits.cpuSeconds) - 0.05))
      return InputError(where + ": " + in + "stopped at the CPU-time limit of " + fmtNumber(limits.cpuSeconds) +
                        " s (an endless loop, or meshing too fine?)" + cpuHint);
    // SIGSYS unreported: the call came with signals blocked (glibc's posix_spawn, behind
    // system()), so the kernel ended the child before the handler could name it.
    if (sig == SIGSYS)
      return InputError(where + ": " + in + "stopped at a forbidden operation (SIGSYS from the seccomp filter: starting "
                        "a program or process, writing a file, or another call a geometry never needs); a geometry file "
                        "may only be read and meshed (remove the command that does this)");
    if (sig == SIGXFSZ)
      return InputError(where + ": " + in + "stopped at a forbidden operation (SIGXFSZ: writing to a file); a geometry "
                        "file may only be read and meshed (remove the command that does this)");
    return InputError(where + ": " + in + "Gmsh crashed (" + signalName(sig) + ") after using " + fmtMb(end.maxRssMb) +
                      " of memory; at the memory limit of " + fmtNumber(limits.memoryMb) + " MB" + memHint +
                      ", else the file triggers a Gmsh defect");
  }
  return InputError(where + ": " + in + "Gmsh ended (exit status " + std::to_string(WEXITSTATUS(end.status)) +
                    ") without a result; expected a geometry that Gmsh reads to the end");
}

}  // namespace

double gmshWallSeconds(const GmshLimits& limits) { return 4.0 * std::ceil(limits.cpuSeconds) + 10.0; }

std::string runGmshSandboxed(const std::string& file, const GmshLimits& limits, const std::string& where,
                             const std::function<std::string()>& work) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("cannot create a pipe for the Gmsh child: " + std::string(std::strerror(errno)));
  const pid_t parent = ::getpid();
  std::fflush(nullptr);  // an exit() in the child must not write the parent's buffered output twice
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error("cannot start the Gmsh child process: " + std::string(std::strerror(errno)));
  }
  if (pid == 0) {
    ::close(fds[0]);
    childMain(fds[1], parent, limits, work);
  }
  ::close(fds[1]);
  const ChildEnd end = collect(pid, fds[0], gmshWallSeconds(limits));
  ::close(fds[0]);
  if (end.interrupt) throw InterruptedBeforeRun(end.interrupt, "while Gmsh read '" + file + "'");
  if (!end.message.empty() && end.message[0] == kResult) return end.message.substr(1);
  if (!end.message.empty() && end.message[0] == kInputError) {
    const std::string text = end.message.substr(1);
    if (text.find("Out of memory") != std::string::npos) {  // Gmsh's own allocator (Malloc) at RLIMIT_AS
      ChildEnd oom = end;
      oom.message = std::string(1, kOutOfMemory);
      throw failure(oom, file, limits, where);
    }
    // Errors of the meshing code carry their location already; Gmsh's own get this one.
    if (text.rfind("Gmsh error: ", 0) == 0) throw InputError(where + ": " + text.substr(0, 12) + "'" + file + "': " + text.substr(12));
    throw InputError(text);
  }
  if (!end.message.empty() && end.message[0] == kLogicError) throw std::logic_error(end.message.substr(1));
  throw failure(end, file, limits, where);
}

}  // namespace flexsens
