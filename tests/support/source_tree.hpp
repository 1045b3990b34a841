#pragma once
// Where the source tree is, for tests and benchmarks that read shipped files (models, scenarios).

#include <cctype>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace blendbench::test {

// The build tree of a test or benchmark program: they live one folder below it
// (build/tests/x_test, build/bench/bench_x). Found from /proc/self/exe at run time rather than
// compiled in, so the objects do not depend on where the checkout is and ccache shares them
// between clones.
inline std::filesystem::path build_root() {
  std::error_code error;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) throw std::runtime_error("test support: /proc/self/exe: " + error.message());
  return exe.parent_path().parent_path();
}

// The program under test, build/blendbench.
inline std::string blendbench_binary() { return (build_root() / "blendbench").string(); }

// The source tree, named by the build tree's file blendbench-data-root (io/CMakeLists.txt writes
// it). Throws when the file is missing (a program moved out of its build tree).
inline const std::string& source_root() {
  static const std::string root = [] {
    const std::filesystem::path marker = build_root() / "blendbench-data-root";
    std::ifstream in(marker);
    std::string line;
    if (!std::getline(in, line))
      throw std::runtime_error("test support: cannot read the source tree from " + marker.string());
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    return line;
  }();
  return root;
}

// A path to a source-tree file (models, scenarios) from a test.
inline std::string source_path(const std::string& relative) { return source_root() + "/" + relative; }

}  // namespace blendbench::test
