#include "blendbench/io/program_io.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace blendbench {

GcodeResult load_gcode_file(const std::string& path, const GcodeOptions& options) {
  return parse_gcode(read_input_file(path, "G-code file"), path, options);
}

bool is_gcode_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".ngc" || ext == ".nc" || ext == ".gcode" || ext == ".tap" || ext == ".cnc";
}

}  // namespace blendbench
