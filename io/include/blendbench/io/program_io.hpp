#pragma once
// Reading part programs from files (the planner's G-code reader takes text).

#include <string>

#include "blendbench/io/gcode.hpp"

namespace blendbench {

// Reads and parses a G-code file. Throws InputError naming the file when it cannot be read,
// and the parser's InputError (file, line, column, word) when it is not supported.
GcodeResult load_gcode_file(const std::string& path, const GcodeOptions& options);

// Whether a file name looks like a G-code program (.ngc, .nc, .gcode, .tap, .cnc; any case).
bool is_gcode_file(const std::string& path);

}  // namespace blendbench
