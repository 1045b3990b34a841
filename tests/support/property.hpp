#pragma once
// Helpers for seeded property tests: the case count comes from BLENDBENCH_PROPERTY_CASES or
// BLENDBENCH_PROPERTY_SCALE and the seeds from BLENDBENCH_PROPERTY_SEED (so CI and a developer can
// run more cases, and other ones), and every failure message carries the seed to replay it.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include "support/source_tree.hpp"

namespace blendbench::test {

// Number of random cases: BLENDBENCH_PROPERTY_CASES if set and positive, else `fallback` times
// BLENDBENCH_PROPERTY_SCALE when that is set to a positive factor (at least one case). The
// sanitizer build runs the suite at a quarter of the cases (tests/CMakeLists.txt): the Release
// build runs them all, the sanitizers check the code paths, at 10-30x the cost per case.
inline int property_cases(int fallback) {
  if (const char* env = std::getenv("BLENDBENCH_PROPERTY_CASES")) {
    const int n = std::atoi(env);
    if (n > 0) return n;
  }
  if (const char* env = std::getenv("BLENDBENCH_PROPERTY_SCALE")) {
    const double scale = std::atof(env);
    if (scale > 0) return std::max(1, static_cast<int>(std::lround(fallback * scale)));
  }
  return fallback;
}

// The offset added to every seed a test asks for: BLENDBENCH_PROPERTY_SEED, a whole number (0,
// the default, when unset, empty or not a number). Each test numbers its cases from a base of its
// own (seed = base + case), so an offset of 10^7 or more moves every test onto cases that no
// default run has drawn; bad text is not a silent 0 but a loud failure, so a typo cannot rerun
// the default cases under another name.
inline std::uint64_t seed_offset() {
  const char* env = std::getenv("BLENDBENCH_PROPERTY_SEED");
  if (env == nullptr || *env == '\0') return 0;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(env, &end, 10);
  if (*end != '\0' || *env == '-') {
    std::fprintf(stderr, "BLENDBENCH_PROPERTY_SEED=%s is not a whole number\n", env);
    std::abort();
  }
  return value;
}

// Whether a test that walks a fixed list (every shipped scenario's variants, a set of reference
// paths) checks its `index`-th item: every item in a normal run; when BLENDBENCH_PROPERTY_SCALE is
// a factor below 1 (the sanitizer build sets 0.25), every k-th, k = round(cost / scale), starting
// at the seed offset modulo k, so that runs with BLENDBENCH_PROPERTY_SEED = 0 .. k-1 cover the
// whole list between them. `cost` (>= 1) is how many ordinary items one of this list costs: the
// optimal planner's walks pass more, and check a proportionally smaller share there. The Release
// build checks every item every run.
inline bool property_sample(std::size_t index, int cost = 1) {
  const char* env = std::getenv("BLENDBENCH_PROPERTY_SCALE");
  if (env == nullptr) return true;
  const double scale = std::atof(env);
  if (!(scale > 0) || scale >= 1) return true;
  const auto stride = static_cast<std::uint64_t>(std::max(1L, std::lround(std::max(cost, 1) / scale)));
  return (index + seed_offset()) % stride == 0;
}

// A generator seeded per case (the test's seed plus the offset above); `seed_text(seed)` goes into
// failure messages and names the offset when one is set, so the line alone replays the case.
inline std::mt19937_64 make_rng(std::uint64_t seed) { return std::mt19937_64(seed + seed_offset()); }
inline std::string seed_text(std::uint64_t seed) {
  const std::uint64_t offset = seed_offset();
  std::string text = "seed=" + std::to_string(seed);
  if (offset != 0) text += " (BLENDBENCH_PROPERTY_SEED=" + std::to_string(offset) + ")";
  return text;
}

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// Log-uniform in [lo, hi], 0 < lo <= hi: every decade as likely.
inline double log_uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::exp(uniform(rng, std::log(lo), std::log(hi)));
}

}  // namespace blendbench::test
