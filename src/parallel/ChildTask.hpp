// One task in a child process: fork, run, send the result back through a pipe. A child that
// hangs can be killed at a time limit, and one that dies (a crash, the kernel's OOM killer,
// kill -9) loses its task, not the process that started it. Each task starts from the same
// state of its parent, so its numbers do not depend on which tasks ran before it.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <functional>
#include <string>

namespace flexsens {

/// How a child's task ended.
struct ChildOutcome {
  bool done = false;    ///< payload holds the task's result
  std::string payload;  ///< the bytes the task returned
  std::string lost;     ///< why not done (killed, died, an exception escaped)
  double seconds = 0;   ///< [s] wall time from the start to the end of the child
  double taskSeconds = 0;  ///< [s] wall time of the task itself in the child (done only)
};

class ChildTask {
 public:
  /// Starts `work` in a child process; what it returns is the payload. `quiet`: the child's
  /// stdout and stderr go to /dev/null. The child dies with its parent (PR_SET_PDEATHSIG).
  ChildTask(const std::function<std::string()>& work, bool quiet);
  ~ChildTask();  ///< kills a child still running
  ChildTask(const ChildTask&) = delete;
  ChildTask& operator=(const ChildTask&) = delete;

  /// Reads what the child sent for up to `wait` seconds; true once the child has ended
  /// (outcome() then holds how).
  bool poll(double wait);
  /// Kills the child now (SIGKILL); its outcome is lost with `reason`.
  void kill(const std::string& reason);
  double elapsed() const;
  bool ended() const { return ended_; }
  const ChildOutcome& outcome() const { return outcome_; }
  /// Children whose result came before they had exited are reaped later: now, waiting for
  /// them (`wait`), or those already gone.
  static void reapFinished(bool wait);

 private:
  void reap();
  bool takeResult();
  pid_t pid_ = -1;
  int fd_ = -1;
  bool ended_ = false;
  std::string received_;
  ChildOutcome outcome_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace flexsens
