#pragma once
// The scenario library (scenarios/) as the tests that walk all of it see it, in one order.

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "support/source_tree.hpp"

namespace blendbench::test {

// Every scenario file of the library, sorted by path (a directory's order is the file system's,
// and a sample of the list must be the same on every machine); the sweep files of
// scenarios/sweeps/ are not scenarios and are left out.
inline std::vector<std::filesystem::path> shipped_scenarios() {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(source_path("scenarios"))) {
    if (entry.path().extension() != ".yaml") continue;
    if (entry.path().parent_path().filename() == "sweeps") continue;
    files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The scenarios a test plans every variant of in this build: all of them, but where
// BLENDBENCH_PROPERTY_SCALE is below 1 (the sanitizer build, support/property.hpp) the long part
// programs of scenarios/process/ are left to the Release build, as the regression gate leaves
// them there (tests/CMakeLists.txt): their thousands of moves exercise the code the short
// scenarios do, at 20-40x the cost under the sanitizers (cam_contour's clothoid_points variant
// plans in about a minute in Release).
inline std::vector<std::filesystem::path> scenarios_to_plan() {
  std::vector<std::filesystem::path> files = shipped_scenarios();
  const char* scale = std::getenv("BLENDBENCH_PROPERTY_SCALE");
  if (scale != nullptr && std::atof(scale) > 0 && std::atof(scale) < 1) {
    std::erase_if(files, [](const std::filesystem::path& f) { return f.parent_path().filename() == "process"; });
  }
  return files;
}

}  // namespace blendbench::test
