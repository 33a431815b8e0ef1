// MPI for the commands that spread their work over ranks (sweep, run over PIM cases, study).
// OpenMPI when flexsens was built with it (CMake option FLEXSENS_MPI), initialized only when
// an MPI launcher (mpirun, srun) started the process: a plain `flexsens ...` never touches
// MPI (an OpenMPI singleton MPI_Init would start a daemon, and refuses to as root).
#pragma once

#include <string>

namespace flexsens {

/// Whether this build has MPI (FLEXSENS_MPI and OpenMPI found).
bool mpiBuilt();

/// MPI for the life of one command: MPI_Init when a launcher started the process, MPI_Finalize
/// at the end (MPI the caller initialized is used as it is and left to it); without a
/// launcher one rank. A build without MPI started by a launcher with
/// more than one rank is an InputError naming `command` (each process would run the whole
/// command into the same folder).
class RankSession {
 public:
  explicit RankSession(const std::string& command);
  ~RankSession();
  RankSession(const RankSession&) = delete;
  RankSession& operator=(const RankSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }
  /// More than one rank: the command spreads its work.
  bool spread() const { return size_ > 1; }
  /// A rank was lost: end without MPI_Finalize, which would wait for it forever (mpirun
  /// --enable-recovery lets the job end when every rank has exited).
  void abandon() { abandoned_ = true; }
  bool abandoned() const { return abandoned_; }

 private:
  bool initialized_ = false, abandoned_ = false;
  int rank_ = 0, size_ = 1;
};

/// Point-to-point messages of the task farm (parallel/TaskFarm.hpp): byte strings with a tag,
/// on MPI_COMM_WORLD with errors returned, not fatal (a rank that died is a lost rank).
namespace ranks {
/// Sends `bytes` to rank `to`; false when it was not delivered within `timeout` seconds.
bool send(int to, int tag, const std::string& bytes, double timeout);
/// The source and tag of a message waiting for this rank; false when there is none.
bool waiting(int& from, int& tag);
/// Receives the message `waiting` announced.
std::string receive(int from, int tag);
/// This machine's name, for reports of lost ranks.
std::string hostName();
}  // namespace ranks

}  // namespace flexsens
