// `flexsens study` under mpirun: its sections spread over the ranks (one task each,
// parallel/TaskFarm.hpp) and rank 0 writes the report as a serial study writes it. The CPU
// times inside each section are its own process's; the report's total adds them up.
#pragma once

#include <string>

#include "app/Study.hpp"
#include "parallel/Ranks.hpp"

namespace flexsens {

/// Returns the report's path on rank 0, "" on the other ranks.
std::string runStudyOnRanks(RankSession& session, const StudyOptions& options);

}  // namespace flexsens
