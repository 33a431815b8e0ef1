// Counts the calls of malloc, calloc and realloc in this process (the bench's executable
// defines them over glibc's, so Eigen's dynamic matrices and std::string's buffers are seen
// as well as operator new). Not thread-safe; the bench runs on one thread.
#pragma once

#include <cstddef>

namespace bench {
/// Allocations since the start of the process.
std::size_t allocations();
}  // namespace bench
