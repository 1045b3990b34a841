// libFuzzer harness: the sweep file reader on arbitrary text, relative to scenarios/sweeps/ (so
// `scenario: ../three_corners.yaml` names a real base scenario). parse_sweep either returns a
// sweep or throws InputError; then the sweep is expanded with its first point validated by the
// scenario loader as soon as it exists, as `blendbench sweep` does. Any exception other than
// InputError, a crash, a leak, undefined behaviour, an allocation beyond libFuzzer's limit or a
// timeout is a finding (tests/fuzz/run_fuzzers.sh).
//
// Expansion costs a scenario's copy and emission per point (about 0.25 ms in Release, several
// times that under the sanitizers), so a valid sweep at the reader's limit of kMaxSweepPoints would
// take longer than the per-input timeout while exercising nothing a small one does not. The
// harness keeps the first values of each axis, up to kFuzzPoints points: the first point, which
// the check validates, is unchanged.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "blendbench/core/input_error.hpp"
#include "blendbench/io/sweep_spec.hpp"
#include "fuzz_setup.hpp"

namespace {

constexpr std::size_t kFuzzPoints = 256;

// Keeps each axis' first values while the product stays within kFuzzPoints.
void bound_points(blendbench::SweepSpec& spec) {
  std::size_t product = 1;
  for (blendbench::SweepAxis& axis : spec.axes) {
    // an axis has at least one value (parse_sweep), and its labels match its values
    const std::size_t keep = std::max<std::size_t>(1, std::min(axis.values.size(), kFuzzPoints / product));
    axis.values.resize(keep);
    axis.labels.resize(keep);
    product *= keep;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    blendbench::SweepSpec spec =
        blendbench::parse_sweep(text, "fuzz_sweep.yaml", BLENDBENCH_FUZZ_BASE_DIR "/scenarios/sweeps");
    bound_points(spec);
    (void)blendbench::expand_sweep(spec, [](const blendbench::SweepPlan& plan, const blendbench::SweepPoint& point) {
      blendbench::validate_point(plan, point, "fuzz_sweep.yaml");
    });
  } catch (const blendbench::InputError&) {
    // a clean refusal
  }
  return 0;
}
