#include "parallel/TaskFarm.hpp"

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <memory>
#include <sstream>
#include <thread>

#include "core/Interrupt.hpp"
#include "parallel/ChildTask.hpp"
#include "parallel/Packer.hpp"

namespace flexsens {

namespace {

// Worker to rank 0: READY (host, pid), RESULT (an outcome; asks for the next task),
// HEARTBEAT (while a task runs), LEAVING (stopped by a signal). Rank 0 to a worker: TASK i,
// NO_MORE (wait for END), ALIVE (while it waits), END ("finalize", or "abandon" when a rank
// was lost: MPI_Finalize would wait for it forever).
enum Tag { kReady = 1, kResult = 2, kHeartbeat = 3, kLeaving = 4, kTask = 10, kNoMore = 11, kAlive = 12, kEnd = 13 };

constexpr double kHeartbeatInterval = 1.0;  ///< [s] between a worker's heartbeats, and rank 0's ALIVE
/// [s] rank 0 waits on its own task's pipe before it looks for messages again, and a worker
/// between looks for rank 0's answer: the latency a sample's round trip adds (a wake-up
/// costs microseconds).
constexpr double kPollInterval = 0.0005;
constexpr double kSendTimeout = 30.0;       ///< [s] for one message to be taken

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void pause(double seconds) { std::this_thread::sleep_for(std::chrono::duration<double>(seconds)); }

std::string signalText(int sig) { return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal"; }

std::string packOutcome(const TaskOutcome& o) {
  Packer p;
  p.integer(o.index).integer(o.done).text(o.payload).text(o.lost).number(o.seconds).number(o.taskSeconds);
  return p.bytes();
}

TaskOutcome unpackOutcome(const std::string& bytes, int rank) {
  Unpacker u(bytes);
  TaskOutcome o;
  o.index = static_cast<int>(u.integer());
  o.done = u.integer() != 0;
  o.payload = u.text();
  o.lost = u.text();
  o.seconds = u.number();
  o.taskSeconds = u.number();
  o.rank = rank;
  return o;
}

/// A task ended in a child of this process: its outcome.
TaskOutcome childOutcome(int index, const ChildTask& child, int rank) {
  const ChildOutcome& c = child.outcome();
  TaskOutcome o;
  o.index = index;
  o.done = c.done;
  o.payload = c.payload;
  o.lost = c.lost;
  o.seconds = c.seconds;
  o.taskSeconds = c.taskSeconds;
  o.rank = rank;
  return o;
}

std::string timeLimitText(double limit) {
  std::ostringstream os;
  os << "exceeded the time limit of " << limit << " s and was killed";
  return os.str();
}

// ------------------------------------------------------------------ rank 0
/// Another rank, as rank 0 sees it.
struct Worker {
  int rank = 0;
  std::string name;           ///< "rank 1 (host vm, pid 42)"
  int task = -1;              ///< the task it runs, -1: none
  double assignedAt = 0.0;
  double lastHeard = 0.0;
  bool waiting = false;       ///< told NO_MORE: waits for END
  bool lost = false;
};

class Master {
 public:
  Master(RankSession& s, int count, const std::function<std::string(int)>& work,
         const std::function<void(const TaskOutcome&)>& done, const FarmOptions& opt)
      : session_(s), count_(count), work_(work), done_(done), opt_(opt) {
    summary_.ranks = s.size();
    for (int r = 1; r < s.size(); ++r) {
      Worker w;
      w.rank = r;
      w.name = "rank " + std::to_string(r);
      w.lastHeard = now();
      workers_.push_back(w);
    }
  }
  FarmSummary run();

 private:
  bool finished() const;
  void runLocal();
  void drainMessages();
  void handle(Worker& w, int tag, const std::string& bytes);
  void assign(Worker& w);
  void loseSilentWorkers();
  void lose(Worker& w, const std::string& why);
  void end(const TaskOutcome& o, double assignedAt);
  void interrupt(int sig);
  void reassureWaiting();
  void endWorkers();

  RankSession& session_;
  const int count_;
  const std::function<std::string(int)>& work_;
  const std::function<void(const TaskOutcome&)>& done_;
  const FarmOptions& opt_;
  FarmSummary summary_;
  std::vector<Worker> workers_;
  int next_ = 0;
  std::unique_ptr<ChildTask> local_;
  int localTask_ = -1;
  double localAssignedAt_ = 0.0;
  double overheadSum_ = 0.0;
  int overheadCount_ = 0;
  double lastAlive_ = 0.0;
};

FarmSummary Master::run() {
  while (!finished()) {
    if (const int sig = interruptSignal()) {
      interrupt(sig);
      break;
    }
    runLocal();
    drainMessages();
    loseSilentWorkers();
    reassureWaiting();
  }
  endWorkers();
  if (overheadCount_) summary_.overheadPerTask = overheadSum_ / overheadCount_;
  return summary_;
}

bool Master::finished() const {
  if (next_ < count_ || localTask_ >= 0) return false;
  for (const Worker& w : workers_)
    if (w.task >= 0 && !w.lost) return false;
  return true;
}

/// Rank 0's own share: one task at a time in a child; waits on it briefly (the loop's pace).
void Master::runLocal() {
  if (localTask_ < 0 && next_ < count_) {
    localTask_ = next_++;
    localAssignedAt_ = now();
    const int index = localTask_;
    local_ = std::make_unique<ChildTask>([this, index] { return work_(index); }, opt_.quiet);
  }
  if (localTask_ < 0) {
    pause(kPollInterval);
    return;
  }
  if (!local_->poll(kPollInterval) && opt_.timeLimit > 0 && local_->elapsed() > opt_.timeLimit)
    local_->kill(timeLimitText(opt_.timeLimit));
  if (!local_->ended()) return;
  const int index = localTask_;
  localTask_ = -1;
  end(childOutcome(index, *local_, 0), localAssignedAt_);
  local_.reset();
}

void Master::drainMessages() {
  int from = 0, tag = 0;
  while (ranks::waiting(from, tag)) {
    const std::string bytes = ranks::receive(from, tag);
    if (from >= 1 && from <= static_cast<int>(workers_.size())) handle(workers_[from - 1], tag, bytes);
  }
}

void Master::handle(Worker& w, int tag, const std::string& bytes) {
  if (w.lost) return;  // counted lost already: a late word changes nothing
  w.lastHeard = now();
  if (tag == kReady) {
    w.name = "rank " + std::to_string(w.rank) + " (" + bytes + ")";
    assign(w);
  } else if (tag == kResult) {
    w.task = -1;
    end(unpackOutcome(bytes, w.rank), w.assignedAt);
    assign(w);
  } else if (tag == kLeaving) {
    lose(w, "it left: " + bytes);
  }
}

void Master::assign(Worker& w) {
  if (next_ >= count_ || interruptSignal()) {
    w.waiting = true;
    ranks::send(w.rank, kNoMore, "", kSendTimeout);
    return;
  }
  w.task = next_++;
  w.assignedAt = now();
  if (!ranks::send(w.rank, kTask, std::to_string(w.task), kSendTimeout)) lose(w, "it could not be reached");
}

void Master::loseSilentWorkers() {
  const double t = now();
  for (Worker& w : workers_)
    if (!w.lost && w.task >= 0 && t - w.lastHeard > opt_.rankTimeout) {
      std::ostringstream os;
      os << "no word from it for " << opt_.rankTimeout << " s while it ran a task (died or unreachable)";
      lose(w, os.str());
    }
}

void Master::lose(Worker& w, const std::string& why) {
  w.lost = true;
  session_.abandon();  // MPI_Finalize would wait for the lost rank
  summary_.lostRanks.push_back(w.name + ": " + why);
  if (w.task < 0) return;
  TaskOutcome o;
  o.index = w.task;
  o.rank = w.rank;
  o.lost = w.name + " was lost: " + why;
  w.task = -1;
  done_(o);
}

void Master::end(const TaskOutcome& o, double assignedAt) {
  if (o.done) {
    overheadSum_ += (now() - assignedAt) - o.taskSeconds;
    ++overheadCount_;
  }
  done_(o);
}

/// Stops everything: the running tasks are killed and reported interrupted.
void Master::interrupt(int sig) {
  summary_.interruptedBy = sig;
  // Under mpirun a signal usually means the job is being torn down (Ctrl-C, a rank died):
  // MPI_Finalize could wait for ranks that are gone, and the launcher kills soon after.
  session_.abandon();
  const std::string why = "interrupted by " + signalText(sig);
  if (localTask_ >= 0) {
    local_->kill(why);
    TaskOutcome o = childOutcome(localTask_, *local_, 0);
    o.interrupted = true;
    localTask_ = -1;
    done_(o);
  }
  for (Worker& w : workers_) {
    if (w.lost || w.task < 0) continue;
    TaskOutcome o;
    o.index = w.task;
    o.rank = w.rank;
    o.interrupted = true;
    o.lost = why;
    w.task = -1;
    done_(o);
  }
}

/// ALIVE every second to the ranks waiting for END, so that they know rank 0 still runs.
void Master::reassureWaiting() {
  if (now() - lastAlive_ < kHeartbeatInterval) return;
  lastAlive_ = now();
  for (Worker& w : workers_)
    if (w.waiting && !w.lost) ranks::send(w.rank, kAlive, "", 1.0);
}

/// END to every rank not lost (also those never heard from): finalize together, or abandon
/// MPI_Finalize when a rank was lost.
void Master::endWorkers() {
  const std::string how = session_.abandoned() ? "abandon" : "finalize";
  for (Worker& w : workers_)
    if (!w.lost) ranks::send(w.rank, kEnd, how, 1.0);
}

// ------------------------------------------------------------------ ranks 1..P-1
class Helper {
 public:
  Helper(RankSession& s, const std::function<std::string(int)>& work, const FarmOptions& opt)
      : session_(s), work_(work), opt_(opt) {}
  void run();

 private:
  /// The next task from rank 0; -1 when there is none (END received, an interrupt, or rank 0
  /// silent for ten rank timeouts: gone).
  int nextTask();
  /// Runs it in a child; false when stopped on the way (nothing more to send).
  bool runTask(int index, TaskOutcome& out);
  /// Reads rank 0's words; true once END came (its "abandon" applied).
  bool endReceived(int* task = nullptr);
  void leave(const std::string& why);

  RankSession& session_;
  const std::function<std::string(int)>& work_;
  const FarmOptions& opt_;
  double lastWord_ = now();
};

void Helper::run() {
  const std::string me = "host " + ranks::hostName() + ", pid " + std::to_string(::getpid());
  if (!ranks::send(0, kReady, me, kSendTimeout)) return leave("");
  for (int index; (index = nextTask()) >= 0;) {
    TaskOutcome out;
    if (!runTask(index, out)) return;
    if (!ranks::send(0, kResult, packOutcome(out), kSendTimeout)) return leave("");
  }
}

void Helper::leave(const std::string& why) {
  if (!why.empty()) ranks::send(0, kLeaving, why, 1.0);
  session_.abandon();  // rank 0 counts this rank lost and does not finalize either
}

bool Helper::endReceived(int* task) {
  int from = 0, tag = 0;
  while (ranks::waiting(from, tag)) {
    const std::string bytes = ranks::receive(from, tag);
    if (from != 0) continue;
    lastWord_ = now();
    if (tag == kEnd) {
      if (bytes == "abandon") session_.abandon();
      return true;
    }
    if (tag == kTask && task) *task = std::stoi(bytes);
  }
  return false;
}

int Helper::nextTask() {
  // Rank 0 answers at once (TASK or NO_MORE), then says ALIVE every second until END.
  for (int task = -1;;) {
    if (endReceived(&task)) return -1;
    if (task >= 0) return task;
    if (const int sig = interruptSignal()) {
      leave("stopped by " + signalText(sig));
      return -1;
    }
    if (now() - lastWord_ > 10.0 * opt_.rankTimeout) {
      session_.abandon();  // rank 0 is gone: nobody to finalize with
      return -1;
    }
    pause(kPollInterval);
  }
}

bool Helper::runTask(int index, TaskOutcome& out) {
  ChildTask child([this, index] { return work_(index); }, opt_.quiet);
  double lastBeat = now();
  while (!child.poll(0.05)) {
    if (const int sig = interruptSignal()) {
      child.kill("interrupted");
      leave("stopped by " + signalText(sig));
      return false;
    }
    if (endReceived()) return false;  // rank 0 stopped: the child is killed with `child`
    if (opt_.timeLimit > 0 && child.elapsed() > opt_.timeLimit) child.kill(timeLimitText(opt_.timeLimit));
    if (!child.ended() && now() - lastBeat >= kHeartbeatInterval) {
      lastBeat = now();
      if (!ranks::send(0, kHeartbeat, "", kSendTimeout)) {
        leave("");
        return false;
      }
    }
    if (child.ended()) break;
  }
  out = childOutcome(index, child, 0);
  return true;
}

}  // namespace

FarmSummary runTaskFarm(RankSession& session, int count, const std::function<std::string(int)>& work,
                        const std::function<void(const TaskOutcome&)>& done, const FarmOptions& options) {
  FarmSummary s;
  s.ranks = session.size();
  if (session.rank() == 0) s = Master(session, count, work, done, options).run();
  else Helper(session, work, options).run();
  ChildTask::reapFinished(true);  // no task's process outlives the farm
  return s;
}

void stopFarmWorkers(const RankSession& session) {
  if (session.rank() != 0) return;
  for (int r = 1; r < session.size(); ++r) ranks::send(r, kEnd, "finalize", 1.0);
}

}  // namespace flexsens
