#include "core/MemoryBudget.hpp"

#include <sstream>

#include "core/Types.hpp"

namespace flexsens {

namespace {
double& budget() {
  static double bytes = 4.0 * (1ull << 30);
  return bytes;
}
}  // namespace

double memoryBudget() { return budget(); }
void setMemoryBudget(double bytes) { budget() = bytes; }

void requireMemory(double bytes, const std::string& what, const std::string& remedy) {
  if (bytes <= budget()) return;
  constexpr double GiB = 1ull << 30;
  std::ostringstream os;
  os.precision(3);
  os << what << " needs an estimated " << bytes / GiB << " GiB, more than the memory budget of " << budget() / GiB
     << " GiB: " << remedy << ", or raise the budget with --max-memory GIB (e.g. --max-memory "
     << static_cast<long long>(bytes / GiB + 1.0) << ") on a machine that has that much";
  throw InputError(os.str());
}

}  // namespace flexsens
