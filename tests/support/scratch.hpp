#pragma once
// A directory of its own for the files a test writes: created fresh (mkdtemp, so no two test
// processes share it, whether ctest runs them side by side or two builds run their suites at
// once) and removed with everything in it when the object goes.

#include <stdlib.h>  // mkdtemp

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace blendbench::test {

class ScratchDir {
 public:
  // `label` names the directory (blendbench-<label>-XXXXXX under the system's temporary folder).
  explicit ScratchDir(const std::string& label) {
    std::string pattern = (std::filesystem::temp_directory_path() / ("blendbench-" + label + "-XXXXXX")).string();
    if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("cannot create a scratch directory " + pattern);
    dir_ = pattern;
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  [[nodiscard]] const std::filesystem::path& path() const { return dir_; }
  // `name` inside the directory
  [[nodiscard]] std::filesystem::path operator/(const std::string& name) const { return dir_ / name; }
  // Writes `text` to `name` inside the directory and returns its path.
  [[nodiscard]] std::string write(const std::string& name, const std::string& text) const {
    const std::filesystem::path file = dir_ / name;
    std::ofstream(file, std::ios::binary) << text;
    return file.string();
  }

 private:
  std::filesystem::path dir_;
};

}  // namespace blendbench::test
