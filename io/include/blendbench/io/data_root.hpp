#pragma once
// Where the program finds its data: the arm model (models/), the scenarios (scenarios/), the
// plot scripts (report/scripts/, papers/scripts/) and the regression baselines
// (results/baselines/). The layout below the data root is the same in the source tree and in an
// install prefix (<prefix>/share/blendbench/), so one relative name works in both.

#include <filesystem>
#include <stdexcept>
#include <string>

namespace blendbench {

// The data root could not be found; what() names every place that was tried.
class DataRootError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The name of the environment variable that overrides the lookup.
inline constexpr const char* kDataDirVariable = "BLENDBENCH_DATA_DIR";
// The file CMake writes into the build tree; it holds the source tree's path on one line.
inline constexpr const char* kDataRootFile = "blendbench-data-root";

// The data root, looked up in this order (the first that applies wins):
//   1. `env_value` (the environment variable BLENDBENCH_DATA_DIR) when not null and not empty;
//      it must name a folder, else DataRootError (an explicit choice is not silently skipped);
//   2. <folder of `executable`>/../share/blendbench when that is a folder (an installed program:
//      <prefix>/bin/blendbench finds <prefix>/share/blendbench; the relative path follows
//      CMAKE_INSTALL_BINDIR and CMAKE_INSTALL_DATADIR);
//   3. the folder named in the file blendbench-data-root beside `executable` or in its parent
//      folder (the build tree: build/blendbench and build/tests/x_test find build/blendbench-data-root).
// `executable` may be empty (unknown), which skips 2 and 3. Returns an absolute, normalised path.
// Throws DataRootError naming each place tried when none applies.
std::filesystem::path find_data_root(const char* env_value, const std::filesystem::path& executable);

// find_data_root for this process: getenv("BLENDBENCH_DATA_DIR") and /proc/self/exe.
std::filesystem::path data_root();

// data_root() / relative, as a string (for example data_file("models/ur5e_like.urdf")).
std::string data_file(const std::string& relative);

}  // namespace blendbench
