#pragma once
// Files in tests: the whole content of one, read back.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace blendbench::test {

// The bytes of `file`; empty when it cannot be read.
inline std::string read_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace blendbench::test
