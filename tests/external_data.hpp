#pragma once
// Data the project does not ship, for the tests that check barnbench against the originals:
//   BARN_DATASET_DIR     a copy of the original BARN dataset (grid_files/, path_files/, ...)
//   BARN_GAZEBO_DWA_OUT  the official harness's results file of its DWA baseline in Gazebo
//                        (run.py's out.txt lines: world_idx success collided timeout time metric)
// A test that needs one skips, naming the variable, when it is not set.

#include <cstdlib>
#include <filesystem>

namespace barn::test {

/// The path in environment variable `variable`, or empty.
inline std::filesystem::path externalData(const char* variable) {
  const char* value = std::getenv(variable);
  return value ? std::filesystem::path(value) : std::filesystem::path();
}

}  // namespace barn::test
