#include "TestPaths.hpp"

namespace flexsens_test_paths {
const char* exe() { return FLEXSENS_EXE_PATH; }
const char* sourceDir() { return FLEXSENS_SOURCE_PATH; }
}  // namespace flexsens_test_paths
