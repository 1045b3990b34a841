#include "blendbench/io/program_io.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <fstream>

namespace blendbench {

GcodeResult load_gcode_file(const std::string& path, const GcodeOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, 0, "", "cannot open the G-code file");
  // read it all; istream::read turns a read error (a directory, an I/O error part way) into
  // badbit, where `out << in.rdbuf()` would swallow it and parse a shorter text
  std::string text;
  std::array<char, 1 << 14> buffer;
  while (in.read(buffer.data(), static_cast<std::streamsize>(buffer.size())) || in.gcount() > 0) {
    text.append(buffer.data(), static_cast<std::size_t>(in.gcount()));
  }
  if (in.bad()) throw InputError(path, 0, 0, "", "cannot read the G-code file");
  return parse_gcode(text, path, options);
}

bool is_gcode_file(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".ngc" || ext == ".nc" || ext == ".gcode" || ext == ".tap" || ext == ".cnc";
}

}  // namespace blendbench
