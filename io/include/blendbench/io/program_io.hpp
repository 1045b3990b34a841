#pragma once
// Reading inputs from files (the planner's G-code reader takes text): every input file is read
// whole, after checks that bound the work before it is done.

#include <cstdint>
#include <string>

#include "blendbench/io/gcode.hpp"

namespace blendbench {

// The largest input file (scenario or G-code) read, in bytes: 64 MiB, twenty times a scenario of
// 10^5 moves (about 3 MB). Larger files are refused before a byte is read.
inline constexpr std::uintmax_t kMaxInputBytes = std::uintmax_t{64} << 20;

// The whole content of the input file `path`; `what` names it in messages ("scenario file",
// "G-code file"). Throws InputError(path, 0, 0, "", message) when the file does not exist or
// cannot be opened, is not a regular file (a folder, a FIFO, a device such as /dev/zero: none is
// opened for reading, so a FIFO never blocks), is larger than `max_bytes`, or a read fails.
std::string read_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes = kMaxInputBytes);

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
