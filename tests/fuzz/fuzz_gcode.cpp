// libFuzzer harness: the G-code reader on arbitrary text, with the command line's default limits
// (1000 mm/min, 1000 mm/s^2, 10000 mm/s^3), smaller bounds on the work of one program, and the
// input standing for every subroutine file it calls. parse_gcode either returns a program or throws
// InputError; any other exception, a crash, a leak, undefined behaviour, an allocation beyond
// libFuzzer's limit or a timeout is a finding (tests/fuzz/run_fuzzers.sh).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "blendbench/core/input_error.hpp"
#include "blendbench/io/gcode.hpp"
#include "fuzz_setup.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  blendbench::GcodeOptions options;
  options.limits.velocity = 1000e-3 / 60.0;
  options.limits.acceleration = 1000e-3;
  options.limits.deceleration = 1000e-3;
  options.limits.jerk = 10000e-3;
  // loops and calls can expand a short input without end: smaller bounds than a real run keeps
  // each input fast under the sanitizers (the bounds themselves are tested in gcode_rs274_test)
  options.max_moves = 20000;
  options.max_lines = 200000;
  // subroutine files: the input up to a line ";;file" is the program, what follows it the file
  // of every subroutine the program calls but does not define (the whole input when there is no
  // such line), so reading subroutine files, their O-word structure and calls between files are
  // fuzzed too
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view kSeparator = "\n;;file\n";
  const std::size_t split = input.find(kSeparator);
  const std::string_view program = split == std::string_view::npos ? input : input.substr(0, split + 1);
  const std::string_view file = split == std::string_view::npos ? input : input.substr(split + kSeparator.size());
  options.find_subroutine = [file](const std::string& name) {
    blendbench::GcodeSubroutineLookup found;
    found.searched = "the fuzz input";
    found.file = blendbench::GcodeSubroutineFile{name + ".ngc", std::string(file)};
    return found;
  };
  try {
    (void)blendbench::parse_gcode(program, "fuzz.ngc", options);
  } catch (const blendbench::InputError&) {
    // a clean refusal
  }
  return 0;
}
