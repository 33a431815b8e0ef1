// Where the tests find the flexsens executable and the source tree. The paths are compiled
// into tests/TestPaths.cpp alone, so every other test file compiles to the same object in any
// checkout (the compiler cache then serves them to a fresh clone).
#pragma once

namespace flexsens_test_paths {
const char* exe();        ///< the flexsens executable built beside the tests
const char* sourceDir();  ///< the checkout's top folder
}  // namespace flexsens_test_paths
