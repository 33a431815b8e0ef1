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

enum Tag { kReady = 1, kResult = 2, kHeartbeat = 3, kLeaving = 4, kTask = 10, kStop = 11 };

constexpr double kHeartbeatInterval = 1.0;  ///< [s] between a busy worker's heartbeats
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
  os << "exceeded the time limit of " << limit << " s per task and was killed";
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
  bool stopped = false;       ///< sent STOP
  bool lost = false;
};

class Master {
 public:
  Master(const RankSession& s, int count, const std::function<std::string(int)>& work,
         const std::function<void(const TaskOutcome&)>& done, const FarmOptions& opt)
      : count_(count), work_(work), done_(done), opt_(opt) {
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
  void stopIdleWorkers();

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
  }
  stopIdleWorkers();
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
    pause(0.002);
    return;
  }
  if (!local_->poll(0.002) && opt_.timeLimit > 0 && local_->elapsed() > opt_.timeLimit)
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
    w.stopped = true;
    ranks::send(w.rank, kStop, "", kSendTimeout);
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

/// STOP to every rank still waiting for word (also those never heard from).
void Master::stopIdleWorkers() {
  for (Worker& w : workers_)
    if (!w.lost && !w.stopped) {
      w.stopped = true;
      ranks::send(w.rank, kStop, "", 1.0);
    }
}

// ------------------------------------------------------------------ ranks 1..P-1
class Helper {
 public:
  Helper(const std::function<std::string(int)>& work, const FarmOptions& opt) : work_(work), opt_(opt) {}
  void run();

 private:
  /// The next task from rank 0; -1 for STOP, an interrupt or rank 0 gone silent.
  int nextTask();
  /// Runs it in a child; false when stopped on the way (nothing more to send).
  bool runTask(int index, TaskOutcome& out);
  /// A word from rank 0 while a task runs: true for STOP.
  bool stopRequested();

  const std::function<std::string(int)>& work_;
  const FarmOptions& opt_;
};

void Helper::run() {
  const std::string me = "host " + ranks::hostName() + ", pid " + std::to_string(::getpid());
  if (!ranks::send(0, kReady, me, kSendTimeout)) return;
  for (int index; (index = nextTask()) >= 0;) {
    TaskOutcome out;
    if (!runTask(index, out)) return;
    if (!ranks::send(0, kResult, packOutcome(out), kSendTimeout)) return;
  }
}

int Helper::nextTask() {
  // Rank 0 answers at once unless it is busy writing results; ten rank timeouts of silence
  // mean it is gone.
  const double deadline = now() + 10.0 * opt_.rankTimeout;
  while (now() < deadline) {
    int from = 0, tag = 0;
    if (ranks::waiting(from, tag)) {
      const std::string bytes = ranks::receive(from, tag);
      if (from != 0) continue;
      if (tag == kStop) return -1;
      if (tag == kTask) return std::stoi(bytes);
    }
    if (interruptSignal()) return -1;
    pause(0.001);
  }
  return -1;
}

bool Helper::stopRequested() {
  int from = 0, tag = 0;
  while (ranks::waiting(from, tag)) {
    ranks::receive(from, tag);
    if (from == 0 && tag == kStop) return true;
  }
  return false;
}

bool Helper::runTask(int index, TaskOutcome& out) {
  ChildTask child([this, index] { return work_(index); }, opt_.quiet);
  double lastBeat = now();
  while (!child.poll(0.05)) {
    if (const int sig = interruptSignal()) {
      child.kill("interrupted");
      ranks::send(0, kLeaving, "stopped by " + signalText(sig), 1.0);
      return false;
    }
    if (stopRequested()) return false;  // the child is killed with `child`
    if (opt_.timeLimit > 0 && child.elapsed() > opt_.timeLimit) child.kill(timeLimitText(opt_.timeLimit));
    if (!child.ended() && now() - lastBeat >= kHeartbeatInterval) {
      lastBeat = now();
      if (!ranks::send(0, kHeartbeat, "", kSendTimeout)) return false;
    }
    if (child.ended()) break;
  }
  out = childOutcome(index, child, 0);
  return true;
}

}  // namespace

FarmSummary runTaskFarm(const RankSession& session, int count, const std::function<std::string(int)>& work,
                        const std::function<void(const TaskOutcome&)>& done, const FarmOptions& options) {
  if (session.rank() == 0) return Master(session, count, work, done, options).run();
  Helper(work, options).run();
  FarmSummary s;
  s.ranks = session.size();
  return s;
}

void stopFarmWorkers(const RankSession& session) {
  if (session.rank() != 0) return;
  for (int r = 1; r < session.size(); ++r) ranks::send(r, kStop, "", 1.0);
}

}  // namespace flexsens
