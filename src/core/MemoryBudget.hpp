// The memory a run may plan to use for one large structure (a dense matrix, the nodes of a
// geometry). Dense linear algebra on a model that is legal but large (modes of a fine solid
// mesh: an n x n eigenproblem, 4.8 GB per matrix at n = 24603) would otherwise end in
// std::bad_alloc or the OOM killer after minutes. Callers estimate the bytes before they
// allocate and call requireMemory, which refuses with the estimate, the budget and how to
// change either. Default budget 4 GiB; the CLI's --max-memory GIB sets it.
#pragma once

#include <string>

namespace flexsens {

/// The budget [bytes] (default 4 GiB).
double memoryBudget();
void setMemoryBudget(double bytes);

/// Throws InputError "<what> needs an estimated X GiB ...; the memory budget is Y GiB: <remedy>,
/// or raise the budget with --max-memory GIB" when `bytes` exceeds the budget.
void requireMemory(double bytes, const std::string& what, const std::string& remedy);

/// Bytes of `count` doubles (as a double: products of sizes overflow 64-bit integers sooner).
inline double doubles(double count) { return 8.0 * count; }

}  // namespace flexsens
