// `flexsens run` over several PIM cases under mpirun: the cases spread over the ranks (one
// task each, parallel/TaskFarm.hpp); each rank runs its case into a private scratch folder
// and sends the files to rank 0, which alone writes the output folder: each case's folder
// committed as it arrives, as a serial run commits it. Every case runs: a failed case does
// not stop the others (the first failure, in case order, is thrown at the end).
#pragma once

#include <functional>
#include <vector>

#include "app/Commands.hpp"
#include "parallel/Ranks.hpp"

namespace flexsens {

/// Runs `cases` (prepared by prepareRun, moved from) over the ranks of `session`. On rank 0,
/// `caseDone` sees each case that ended complete or suspect, in the order they end; the
/// result lists them. Other ranks return an empty result.
RunCommandResult runCasesOnRanks(RankSession& session, std::vector<RunCase>& cases,
                                 const std::function<void(const RunCase&, const RunResult&)>& caseDone);

}  // namespace flexsens
