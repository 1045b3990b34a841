#pragma once
// Reading inputs from files (the planner's G-code reader takes text): every input file is read
// whole by core/input_file.hpp, after checks that bound the work before it is done.

#include <string>

#include "blendbench/core/input_file.hpp"  // read_input_file, kMaxInputBytes: every input file is read through it
#include "blendbench/io/gcode.hpp"

namespace blendbench {

// Reads and parses a G-code file (read_input_file). Unless options.find_subroutine is set, a
// call of a subroutine the program does not define reads <name>.ngc from the program's folder,
// else from the first of options.subroutine_path that has it (LinuxCNC's "Calling Files"), each
// file through read_input_file, all of them together within kMaxInputBytes. Throws InputError
// naming the file when it cannot be read, and the parser's InputError (file, line, column, word)
// when it is not supported.
GcodeResult load_gcode_file(const std::string& path, const GcodeOptions& options);

// Whether a file name looks like a G-code program (.ngc, .nc, .gcode, .tap, .cnc; any case).
bool is_gcode_file(const std::string& path);

}  // namespace blendbench
