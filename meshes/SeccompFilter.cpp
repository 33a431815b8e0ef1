// Seccomp filter of the Gmsh child; see SeccompFilter.hpp.
#include "meshes/SeccompFilter.hpp"

#include <fcntl.h>
#include <sched.h>
#include <seccomp.h>

#include <cerrno>
#include <cstdlib>
#include <initializer_list>
#include <iterator>
#include <string>

namespace flexsens {

namespace {

const char* const kStartsProcess[] = {"execve", "execveat", "fork", "vfork", "clone"};
const char* const kChangesFiles[] = {
    "creat", "truncate", "rename", "renameat", "renameat2", "unlink", "unlinkat", "rmdir", "mkdir", "mkdirat",
    "link", "linkat", "symlink", "symlinkat", "mknod", "mknodat", "chmod", "fchmod", "fchmodat", "chown",
    "fchown", "lchown", "fchownat", "utime", "utimes", "utimensat", "futimesat", "setxattr", "lsetxattr",
    "fsetxattr", "removexattr", "lremovexattr", "fremovexattr", "mount", "umount2"};
const char* const kReachesOut[] = {"io_uring_setup", "io_uring_enter", "io_uring_register", "socket", "socketpair",
                                   "ptrace", "process_vm_writev", "open_by_handle_at"};

/// Flags that make open/openat write or create (O_TMPFILE's own bit, without O_DIRECTORY).
constexpr unsigned kWriteFlags[] = {O_WRONLY, O_RDWR, O_CREAT, O_TRUNC, O_APPEND, 020000000};

bool denyAll(scmp_filter_ctx ctx, std::initializer_list<const char*> names) {
  for (const char* n : names) {
    const int nr = seccomp_syscall_resolve_name(n);
    if (nr == __NR_SCMP_ERROR) continue;  // not on this architecture (e.g. fork on arm64)
    if (seccomp_rule_add(ctx, SCMP_ACT_TRAP, nr, 0) != 0) return false;
  }
  return true;
}

bool addRules(scmp_filter_ctx ctx) {
  for (const char* n : kStartsProcess)
    if (std::string(n) != "clone" && !denyAll(ctx, {n})) return false;
  for (const char* n : kChangesFiles)
    if (!denyAll(ctx, {n})) return false;
  for (const char* n : kReachesOut)
    if (!denyAll(ctx, {n})) return false;
  // clone: threads (CLONE_THREAD) are fine, a new process is not.
  if (seccomp_rule_add(ctx, SCMP_ACT_TRAP, SCMP_SYS(clone), 1, SCMP_A0(SCMP_CMP_MASKED_EQ, CLONE_THREAD, 0)) != 0)
    return false;
  for (const char* n : {"clone3", "openat2"}) {
    const int nr = seccomp_syscall_resolve_name(n);
    if (nr != __NR_SCMP_ERROR && seccomp_rule_add(ctx, SCMP_ACT_ERRNO(ENOSYS), nr, 0) != 0) return false;
  }
  for (unsigned flag : kWriteFlags) {
    const unsigned mask = (flag == O_WRONLY || flag == O_RDWR) ? O_ACCMODE : flag;
    if (seccomp_rule_add(ctx, SCMP_ACT_TRAP, SCMP_SYS(open), 1, SCMP_A1(SCMP_CMP_MASKED_EQ, mask, flag)) != 0 ||
        seccomp_rule_add(ctx, SCMP_ACT_TRAP, SCMP_SYS(openat), 1, SCMP_A2(SCMP_CMP_MASKED_EQ, mask, flag)) != 0)
      return false;
  }
  return true;
}

bool listed(const std::string& name, const char* const* begin, const char* const* end) {
  for (auto p = begin; p != end; ++p)
    if (name == *p) return true;
  return false;
}

}  // namespace

bool installSeccompFilter() {
  scmp_filter_ctx ctx = seccomp_init(SCMP_ACT_ALLOW);
  if (!ctx) return false;
  const bool ok = addRules(ctx) && seccomp_load(ctx) == 0;
  seccomp_release(ctx);
  return ok;
}

std::string describeForbiddenCall(int nr) {
  char* raw = seccomp_syscall_resolve_num_arch(SCMP_ARCH_NATIVE, nr);
  const std::string name = raw ? raw : "system call " + std::to_string(nr);
  std::free(raw);
  if (listed(name, std::begin(kStartsProcess), std::end(kStartsProcess)))
    return name + " (starting a program or process: a SystemCall?)";
  if (name == "open" || name == "openat" || name == "creat" || name == "truncate")
    return name + " (opening a file for writing: a Printf > file, Save or Print?)";
  if (listed(name, std::begin(kChangesFiles), std::end(kChangesFiles)))
    return name + " (creating, renaming or deleting a file)";
  return name + " (reaching outside the process)";
}

}  // namespace flexsens
