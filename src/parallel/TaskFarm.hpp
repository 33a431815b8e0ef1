// Tasks 0..count-1 spread over the MPI ranks of a RankSession, or run one after the other
// when there is one rank. Rank 0 is the master: it hands out task indices one at a time as
// ranks ask for work (dynamic scheduling: tasks differ in cost by 10x), collects the results,
// and runs tasks itself meanwhile. Every task runs in a child process (ChildTask.hpp), on
// rank 0 too, so that
//  - a task past the time limit is killed, and a task whose process dies is lost, not its rank;
//  - a rank that stops answering (killed, its machine gone) for `rankTimeout` seconds while it
//    runs a task is lost with that task, and the other ranks finish the rest (OpenMPI ends
//    the whole job when a rank dies unless mpirun runs with --enable-recovery);
//  - SIGINT or SIGTERM on rank 0 stops every rank: running tasks are killed, what finished is
//    kept;
//  - a task's numbers do not depend on the rank or on the tasks that ran before it.
//
// Messages (tags in TaskFarm.cpp): a worker says READY (its host and pid), then gets TASK i or
// NO_MORE; while its child runs it sends HEARTBEAT every second, and at the end RESULT (the
// outcome), which also asks for the next task. Rank 0 ends the farm with END to every rank.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "parallel/Ranks.hpp"

namespace flexsens {

struct FarmOptions {
  double timeLimit = 0.0;     ///< [s] wall time per task; 0: none. A task past it is killed and lost
  double rankTimeout = 10.0;  ///< [s] of silence from a rank running a task before it counts as lost
  bool quiet = false;         ///< the tasks' stdout and stderr go to /dev/null
};

/// How one task ended (seen on rank 0).
struct TaskOutcome {
  int index = -1;
  bool done = false;         ///< payload holds the task's result
  bool interrupted = false;  ///< not done: the farm was stopped by a signal while it ran
  std::string payload;
  std::string lost;          ///< why not done
  int rank = 0;              ///< the rank that ran it
  double seconds = 0.0;      ///< [s] wall time of its child process
  double taskSeconds = 0.0;  ///< [s] of which the task itself ran (done only)
};

struct FarmSummary {
  int interruptedBy = 0;               ///< the signal that stopped rank 0; later tasks did not run
  std::vector<std::string> lostRanks;  ///< "rank 1 (host vm, pid 42): ..." per rank lost
  int ranks = 1;
  /// [s] mean per task of rank 0's time from handing it out to holding its result, less the
  /// task's own wall time in its child: what the scheduling costs (fork, pipe, messages,
  /// polling).
  double overheadPerTask = 0.0;
};

/// Runs on every rank of `session`. `work(i)` runs task i in a child process and returns its
/// result; on rank 0, `done` sees each task as it ends (in the order they end). Returns on
/// every rank when all tasks ended or rank 0 was interrupted (the summary is rank 0's). When
/// a rank was lost, every rank's session is abandoned (no MPI_Finalize: it would wait for
/// the lost rank).
FarmSummary runTaskFarm(RankSession& session, int count, const std::function<std::string(int)>& work,
                        const std::function<void(const TaskOutcome&)>& done, const FarmOptions& options);

/// Rank 0, when it cannot go on before handing out any task (its output folder refused):
/// tells the other ranks, which wait in runTaskFarm, to stop.
void stopFarmWorkers(const RankSession& session);

}  // namespace flexsens
