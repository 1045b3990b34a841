#pragma once
// Helpers for seeded property tests: the case count comes from BLENDBENCH_PROPERTY_CASES (so CI
// and a developer can run more), and every failure message carries the seed to replay it.

#include <algorithm>
#include <cmath>
#include <cstdint>
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

// A generator seeded per case; `seed_text(seed)` goes into failure messages.
inline std::mt19937_64 make_rng(std::uint64_t seed) { return std::mt19937_64(seed); }
inline std::string seed_text(std::uint64_t seed) { return "seed=" + std::to_string(seed); }

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// Log-uniform in [lo, hi], 0 < lo <= hi: every decade as likely.
inline double log_uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::exp(uniform(rng, std::log(lo), std::log(hi)));
}

}  // namespace blendbench::test
