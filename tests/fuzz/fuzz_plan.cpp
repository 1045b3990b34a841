// libFuzzer harness: the planner behind the G-code reader, on arbitrary text. The first byte picks
// the transition G64 P maps to, the limits mode and the velocity planner; the rest is a program
// read as `blendbench plan` reads one (the command line's default limits). A program that parses
// is blended and timed. The blender and the planner either return a path and a plan or throw
// InputError (a located refusal: a move too long for the sample bound, a degenerate corner); a
// plan whose outcome is a failure is a refusal too. What is a finding: any other exception, a
// crash, undefined behaviour, a leak, a timeout, an allocation beyond libFuzzer's limit, and a
// plan that claims success with a sample that is not finite, that goes back in time or in arc
// length, that ends anywhere but at the path's end at rest, or a cycle time that is not finite.
//
// The readers' harness (fuzz_gcode) fuzzes the text; this one the geometry the text describes:
// short moves, near-reversing and collinear corners, tiny arcs, feeds at the bounds. The program is
// kept small (kMaxMoves) and the plan short (kMaxSamples) so that one input, planned under the
// sanitizers by the optimal planner's barrier method, stays well inside the per-input timeout.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "blendbench/core/input_error.hpp"
#include "blendbench/corner/blend.hpp"
#include "blendbench/io/gcode.hpp"
#include "blendbench/timing/timing.hpp"
#include "fuzz_setup.hpp"

namespace {

constexpr std::size_t kMaxMoves = 12;
constexpr std::size_t kMaxLines = 2000;
constexpr double kMaxSamples = 2000;  // 2 s at the default 1 ms period

constexpr blendbench::Method kMethods[] = {blendbench::Method::kBiclothoid, blendbench::Method::kClothoid,
                                           blendbench::Method::kBezier, blendbench::Method::kArc};

[[noreturn]] void finding(const char* what, std::size_t k) {
  std::fprintf(stderr, "fuzz_plan: %s (sample %zu)\n", what, k);
  std::abort();
}

// The checks of a plan that claims success.
void check_plan(const blendbench::Path& path, const blendbench::Timing& timing) {
  if (!std::isfinite(timing.cycle_time) || timing.cycle_time < 0) finding("cycle time not finite", 0);
  const auto& samples = timing.samples;
  if (samples.empty()) finding("no samples", 0);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const blendbench::TimedSample& x = samples[k];
    if (!std::isfinite(x.t) || !std::isfinite(x.s) || !std::isfinite(x.v) || !std::isfinite(x.a) || !std::isfinite(x.j)) {
      finding("a sample is not finite", k);
    }
    if (k > 0 && (x.t <= samples[k - 1].t || x.s < samples[k - 1].s)) finding("time or arc length goes back", k);
  }
  const blendbench::TimedSample& last = samples.back();
  const double tol = 1e-9 * std::max(1.0, path.length());
  if (std::abs(last.s - path.length()) > tol || last.v != 0) finding("the plan does not end at rest at the path's end", samples.size() - 1);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t pick = data[0];
  blendbench::GcodeOptions options;
  options.limits.velocity = 1000e-3 / 60.0;
  options.limits.acceleration = 1000e-3;
  options.limits.deceleration = 1000e-3;
  options.limits.jerk = 10000e-3;
  options.tolerance_method = kMethods[pick % 4];
  options.max_moves = kMaxMoves;
  options.max_lines = kMaxLines;
  blendbench::TimingOptions timing;
  timing.limits = (pick / 4) % 2 == 0 ? blendbench::LimitsMode::kCartesian : blendbench::LimitsMode::kPath;
  timing.algorithm = (pick / 8) % 2 == 0 ? blendbench::TimingOptions::Algorithm::kOptimal
                                         : blendbench::TimingOptions::Algorithm::kSeed004;
  timing.max_samples = kMaxSamples;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    const blendbench::GcodeResult parsed = blendbench::parse_gcode(text, "fuzz.ngc", options);
    const blendbench::Path path = blendbench::blend(parsed.program);
    const blendbench::Timing plan = blendbench::plan_timing(path, timing);
    if (plan.outcome.ok()) check_plan(path, plan);
  } catch (const blendbench::InputError&) {
    // a clean refusal
  }
  return 0;
}
