// The seccomp filter of the Gmsh child (meshes/GmshSandbox): what a geometry file must never
// make Gmsh do. A deny list on top of "allow": Gmsh and OpenCASCADE use a wide and
// version-dependent set of system calls for reading and meshing, none of the ones below.
#pragma once

#include <string>

namespace flexsens {

/// Loads the filter into the calling process (needs PR_SET_NO_NEW_PRIVS first). Denied calls
/// raise SIGSYS (SCMP_ACT_TRAP), so the child can name the call before it ends:
///   - starting programs or processes: execve, execveat, fork, vfork, clone without
///     CLONE_THREAD (threads stay allowed); clone3 fails with ENOSYS (its flags sit in
///     memory the filter cannot read; glibc falls back to clone);
///   - writing files: open/openat with O_WRONLY, O_RDWR, O_CREAT, O_TRUNC, O_APPEND or
///     O_TMPFILE, creat, truncate; openat2 fails with ENOSYS (flags in memory, as clone3);
///   - changing the file system: rename*, unlink*, rmdir, mkdir*, link*, symlink*, mknod*,
///     chmod/chown families, utime families, xattr writes, mount, umount2;
///   - escaping the filter or reaching out: io_uring_* (file operations seccomp cannot see),
///     socket, socketpair, ptrace, process_vm_writev, open_by_handle_at.
/// Returns false when the filter could not be loaded.
bool installSeccompFilter();

/// "execve (start a program)" for a denied system call number.
std::string describeForbiddenCall(int syscallNumber);

}  // namespace flexsens
