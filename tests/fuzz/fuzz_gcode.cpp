// libFuzzer harness: the G-code reader on arbitrary text, with the command line's default limits
// (1000 mm/min, 1000 mm/s^2, 10000 mm/s^3) and smaller bounds on the work of one program. parse_gcode either returns a program or throws
// InputError; any other exception, a crash, a leak, undefined behaviour, an allocation beyond
// libFuzzer's limit or a timeout is a finding (tests/fuzz/run_fuzzers.sh).

#include <cstddef>
#include <cstdint>
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
  try {
    (void)blendbench::parse_gcode(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.ngc", options);
  } catch (const blendbench::InputError&) {
    // a clean refusal
  }
  return 0;
}
