// Gmsh runs on untrusted input (a scene's .geo or .msh), so every Gmsh call happens in a
// forked child process that cannot do harm and cannot hang the parent:
//   - no new privileges, and a seccomp filter that stops (SIGSYS) any attempt to start a
//     program or process (execve, execveat, fork, vfork, clone without CLONE_THREAD), to
//     open a file for writing or to create, rename, delete or re-own one, to open a socket,
//     or to use io_uring (which would bypass the filter);
//   - RLIMIT_CPU (limits.gmsh_cpu_s), RLIMIT_AS (limits.gmsh_memory_mb), no core files, no
//     file growth (RLIMIT_FSIZE 0), stdin/stdout/stderr on /dev/null, other files closed;
//   - the parent waits at most a wall-clock bound, and kills the child on SIGINT/SIGTERM
//     (core/Interrupt) or when the parent itself dies (PR_SET_PDEATHSIG).
// The child sends its result back over a pipe: a tag byte and a payload (meshes/MeshWire).
#pragma once

#include <functional>
#include <string>

namespace flexsens {

/// Bounds of one Gmsh child. The defaults fit every example and test (the largest, the
/// satellite and the solid pendulum, take well under 1 s and 200 MB of Gmsh work).
struct GmshLimits {
  double cpuSeconds = 4.0;     ///< [s] CPU time (RLIMIT_CPU)
  double memoryMb = 2048.0;    ///< [MiB] address space of the child (RLIMIT_AS)
  /// The scene keys that raise them, named in the errors.
  static constexpr const char* kCpuKey = "limits.gmsh_cpu_s";
  static constexpr const char* kMemoryKey = "limits.gmsh_memory_mb";
  static constexpr double kMaxCpuSeconds = 86400.0;
  static constexpr double kMinMemoryMb = 256.0, kMaxMemoryMb = 1048576.0;
};

/// What a Gmsh bridge (meshBody, meshCurves) needs besides its file: the child's limits and
/// the scene's folder (files a .geo includes must lie there or in the .geo's own folder).
struct GmshOptions {
  GmshLimits limits;
  std::string sceneDir;
};

/// [s] the parent's wall-clock bound on one child: 4 times its CPU limit plus 10 s, so that
/// on a loaded machine the CPU limit ends a busy child first; the bound ends one that waits.
double gmshWallSeconds(const GmshLimits& limits);

/// Runs `work` in a sandboxed child, with a fresh Gmsh session opened before the filter
/// (GmshSession: initializing Gmsh writes FLTK's preferences), and returns the string it produced. `file` names the
/// input in the errors; `where` ("scene.yaml:line:col: key '...'") prefixes them.
/// In the child: InputError and std::string (Gmsh's own errors) become InputError in the
/// parent, std::logic_error a std::logic_error, std::bad_alloc the memory-limit error.
/// The parent raises InputError naming the file and the limit when the child is stopped by
/// its CPU or memory limit or by the seccomp filter, dies otherwise, or exits without a
/// result; and Interrupted when SIGINT/SIGTERM arrives while it waits.
std::string runGmshSandboxed(const std::string& file, const GmshLimits& limits, const std::string& where,
                             const std::function<std::string()>& work);

}  // namespace flexsens
