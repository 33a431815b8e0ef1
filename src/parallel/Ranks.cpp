#include "parallel/Ranks.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <thread>

#include "core/Types.hpp"

#ifdef FLEXSENS_WITH_MPI
#include <mpi.h>
#endif

namespace flexsens {

namespace {

/// A launcher's variable as a number, -1 when it is not set.
long launcherNumber(const char* name) {
  const char* v = std::getenv(name);
  if (!v || !*v) return -1;
  char* end = nullptr;
  const long n = std::strtol(v, &end, 10);
  return *end ? -1 : n;
}

}  // namespace

#ifdef FLEXSENS_WITH_MPI

namespace {
bool gInitialized = false;  ///< a RankSession called MPI_Init (messages need it)

/// Set by mpirun (OMPI_COMM_WORLD_SIZE), srun --mpi=pmix (PMIX_RANK) or a PMI launcher.
bool launched() {
  return launcherNumber("OMPI_COMM_WORLD_SIZE") >= 0 || launcherNumber("PMIX_RANK") >= 0 ||
         launcherNumber("PMI_RANK") >= 0 || launcherNumber("PMI_SIZE") >= 0;
}
}  // namespace

bool mpiBuilt() { return true; }

RankSession::RankSession(const std::string&) {
  int already = 0;
  MPI_Initialized(&already);
  if (!already && !launched()) return;
  // The ranks exchange a few hundred bytes per task and fork a process per task: OpenMPI's
  // plain point-to-point layer (ob1 over shared memory and TCP) is safe with fork, where the
  // RDMA transports (UCX, verbs) are not, and MPI_Init takes 0.03 s instead of the 0.23 s of
  // probing them (measured here). The user's own choice (OMPI_MCA_pml, OMPI_MCA_btl, mpirun
  // --mca) wins.
  ::setenv("OMPI_MCA_pml", "ob1", 0);
  ::setenv("OMPI_MCA_btl", "self,vader,tcp", 0);
  // MPI started by the caller (a Python program with mpi4py): used as it is, not finalized.
  if (!already && MPI_Init(nullptr, nullptr) != MPI_SUCCESS) throw std::runtime_error("MPI_Init failed");
  initialized_ = !already;
  gInitialized = true;
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

RankSession::~RankSession() {
  if (!initialized_ || abandoned_) return;  // not ours to finalize, or a rank is gone
  MPI_Finalize();
  gInitialized = false;
}

namespace ranks {

bool send(int to, int tag, const std::string& bytes, double timeout) {
  if (bytes.size() > static_cast<size_t>(INT_MAX)) throw std::runtime_error("a result over 2 GiB cannot be sent");
  // The buffer outlives a send that never completes (a dead rank): MPI may still read it.
  auto buffer = std::make_unique<std::string>(bytes);
  MPI_Request req;
  if (MPI_Isend(buffer->data(), static_cast<int>(buffer->size()), MPI_BYTE, to, tag, MPI_COMM_WORLD, &req) !=
      MPI_SUCCESS)
    return false;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  for (;;) {
    int done = 0;
    if (MPI_Test(&req, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS) return false;
    if (done) return true;
    if (std::chrono::steady_clock::now() > end) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  MPI_Request_free(&req);
  buffer.release();  // deliberately kept: the request may still read it
  return false;
}

bool waiting(int& from, int& tag) {
  if (!gInitialized) return false;  // one rank: nobody to hear from
  int flag = 0;
  MPI_Status st;
  if (MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st) != MPI_SUCCESS || !flag) return false;
  from = st.MPI_SOURCE;
  tag = st.MPI_TAG;
  return true;
}

std::string receive(int from, int tag) {
  MPI_Status st;
  MPI_Probe(from, tag, MPI_COMM_WORLD, &st);
  int count = 0;
  MPI_Get_count(&st, MPI_BYTE, &count);
  std::string bytes(static_cast<size_t>(count), '\0');
  MPI_Recv(bytes.data(), count, MPI_BYTE, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return bytes;
}

}  // namespace ranks

#else  // a build without MPI: one rank

bool mpiBuilt() { return false; }

RankSession::RankSession(const std::string& command) {
  const long size = std::max(launcherNumber("OMPI_COMM_WORLD_SIZE"), launcherNumber("PMI_SIZE"));
  if (size > 1 || launcherNumber("PMIX_RANK") > 0 || launcherNumber("PMI_RANK") > 0)
    throw InputError("flexsens " + command + " was started by an MPI launcher" +
                     (size > 1 ? " with " + std::to_string(size) + " ranks" : "") +
                     ", but this flexsens was built without MPI (CMake option FLEXSENS_MPI off, or OpenMPI not "
                     "found: install libopenmpi-dev and rebuild); run it without mpirun or srun");
}

RankSession::~RankSession() = default;

namespace ranks {
bool send(int, int, const std::string&, double) { throw std::logic_error("ranks::send without MPI"); }
bool waiting(int&, int&) { return false; }
std::string receive(int, int) { throw std::logic_error("ranks::receive without MPI"); }
}  // namespace ranks

#endif

std::string ranks::hostName() {
  char buf[256] = {0};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "?";
  return buf;
}

}  // namespace flexsens
