#include "sim/program_io.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace blendbench {

GcodeResult load_gcode_file(const std::string& path, const GcodeOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, 0, "", "cannot open the G-code file");
  std::stringstream text;
  text << in.rdbuf();
  return parse_gcode(text.str(), path, options);
}

bool is_gcode_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".ngc" || ext == ".nc" || ext == ".gcode" || ext == ".tap" || ext == ".cnc";
}

}  // namespace blendbench
