#include "blendbench/io/data_root.hpp"

#include <cstdlib>
#include <system_error>
#include <vector>

#include "blendbench/core/input_error.hpp"
#include "blendbench/core/input_file.hpp"

namespace blendbench {

namespace fs = std::filesystem;

namespace {

// The data relative to an installed program's folder (io/CMakeLists.txt: from
// CMAKE_INSTALL_BINDIR to CMAKE_INSTALL_DATADIR/blendbench).
constexpr const char* kBinToData = BLENDBENCH_BIN_TO_DATA;

fs::path normalised(const fs::path& p) { return fs::absolute(p).lexically_normal(); }

bool is_folder(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

// The first line of `file` without trailing blanks; empty when the file cannot be read (read as
// every input is: a regular file, bounded, core/input_file.hpp).
std::string first_line(const fs::path& file) {
  std::string text;
  try {
    text = read_input_file(file.string(), "data-root file", 1 << 16);
  } catch (const InputError&) {
    return {};
  }
  std::string line = text.substr(0, text.find('\n'));
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) line.pop_back();
  return line;
}

}  // namespace

fs::path find_data_root(const char* env_value, const fs::path& executable) {
  std::vector<std::string> tried;

  // 1. the environment variable, an explicit choice
  if (env_value != nullptr && *env_value != '\0') {
    if (is_folder(env_value)) return normalised(env_value);
    throw DataRootError(std::string(kDataDirVariable) + "=" + env_value + " is not a folder");
  }
  tried.push_back(std::string(kDataDirVariable) + " (not set)");

  if (executable.empty()) {
    tried.emplace_back("the running program's folder (unknown)");
  } else {
    const fs::path bin = normalised(executable).parent_path();

    // 2. an installed program: <prefix>/bin/../share/blendbench
    const fs::path installed = (bin / kBinToData).lexically_normal();
    if (is_folder(installed)) return installed;
    tried.push_back(installed.string() + " (no such folder)");

    // 3. the build tree: a file naming the source tree, beside the program or one folder up
    for (const fs::path& dir : {bin, bin.parent_path()}) {
      const fs::path marker = dir / kDataRootFile;
      std::error_code ec;
      if (!fs::exists(marker, ec)) {
        tried.push_back(marker.string() + " (no such file)");
        continue;
      }
      const std::string named = first_line(marker);
      if (!named.empty() && is_folder(named)) return normalised(named);
      tried.push_back(marker.string() + " (names '" + named + "', not a folder)");
    }
  }

  std::string message = "cannot find BlendBench's data (models/, scenarios/, ...); tried:";
  // one line (messages are printed escaped, so a newline would show as \n)
  for (std::size_t i = 0; i < tried.size(); ++i) message += (i == 0 ? " " : "; ") + tried[i];
  message += "; set " + std::string(kDataDirVariable) + " to the folder that holds models/ and scenarios/";
  throw DataRootError(message);
}

fs::path data_root() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return find_data_root(std::getenv(kDataDirVariable), ec ? fs::path() : exe);
}

std::string data_file(const std::string& relative) { return (data_root() / relative).string(); }

}  // namespace blendbench
