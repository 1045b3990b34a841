// libFuzzer harness: the sweep file reader on arbitrary text, relative to scenarios/sweeps/ (so
// `scenario: ../three_corners.yaml` names a real base scenario). parse_sweep either returns a
// sweep or throws InputError; then the sweep is expanded (every point's scenario text) and its
// first point validated by the scenario loader, as `blendbench sweep` does next. Any exception
// other than InputError, a crash, a leak, undefined behaviour, an allocation beyond libFuzzer's
// limit or a timeout is a finding (tests/fuzz/run_fuzzers.sh).

#include <cstddef>
#include <cstdint>
#include <string>

#include "blendbench/core/input_error.hpp"
#include "blendbench/io/sweep_spec.hpp"
#include "fuzz_setup.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const blendbench::SweepSpec spec =
        blendbench::parse_sweep(text, "fuzz_sweep.yaml", BLENDBENCH_FUZZ_BASE_DIR "/scenarios/sweeps");
    const blendbench::SweepPlan plan = blendbench::expand_sweep(spec);
    if (!plan.points.empty()) blendbench::validate_point(plan, plan.points.front(), "fuzz_sweep.yaml");
  } catch (const blendbench::InputError&) {
    // a clean refusal
  }
  return 0;
}
