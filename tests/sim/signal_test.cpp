// The zero-phase Butterworth filters and the dominant-frequency estimate the metrics use.

#include "blendbench/sim/signal.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kFs = 1000;  // Hz

std::vector<double> sine(double f, double amplitude, std::size_t n, double phase = 0) {
  std::vector<double> x(n);
  for (std::size_t k = 0; k < n; ++k) x[k] = amplitude * std::sin(2 * kPi * f * static_cast<double>(k) / kFs + phase);
  return x;
}

// Largest |value| away from the ends (a tenth of the samples on each side).
double middle_peak(const std::vector<double>& x) {
  double peak = 0;
  for (std::size_t k = x.size() / 10; k < x.size() - x.size() / 10; ++k) peak = std::max(peak, std::abs(x[k]));
  return peak;
}

// The forward-backward 2nd-order Butterworth has the squared magnitude response: 1 / (1 + (f/fc)^4)
// for the low-pass, (f/fc)^4 / (1 + (f/fc)^4) for the high-pass (prewarped, so exact at fc).
TEST(Signal, MagnitudeResponseIsTheSquaredButterworth) {
  constexpr double kFc = 40;
  for (const double f : {5.0, 20.0, 40.0, 80.0, 160.0}) {
    const double r = std::pow(std::tan(kPi * f / kFs) / std::tan(kPi * kFc / kFs), 4);
    const std::vector<double> x = sine(f, 1.0, 4000);
    EXPECT_NEAR(middle_peak(lowpass_zero_phase(x, kFs, kFc)), 1 / (1 + r), 0.01) << f << " Hz";
    EXPECT_NEAR(middle_peak(highpass_zero_phase(x, kFs, kFc)), r / (1 + r), 0.01) << f << " Hz";
  }
}

// Zero phase: a filtered sine crosses zero where the input does.
TEST(Signal, NoPhaseLag) {
  const std::vector<double> x = sine(10, 1.0, 2000);
  const std::vector<double> y = lowpass_zero_phase(x, kFs, 30);
  for (std::size_t k = 200; k < 1800; ++k) {
    if (std::abs(x[k]) < 1e-12) {
      EXPECT_LT(std::abs(y[k]), 1e-3) << k;
    }
  }
  // a sample where the input is at its peak is the filtered signal's peak too
  EXPECT_NEAR(y[525], middle_peak(y), 1e-3);
}

// Constants, ramps and sines at the ends give no edge transient: the low-pass returns a line as
// it is and the high-pass removes it.
TEST(Signal, LinesPassWithoutEdgeTransients) {
  std::vector<double> line(500);
  for (std::size_t k = 0; k < line.size(); ++k) line[k] = 0.3 + 2e-3 * static_cast<double>(k);
  const std::vector<double> low = lowpass_zero_phase(line, kFs, 20);
  const std::vector<double> high = highpass_zero_phase(line, kFs, 20);
  // (what is left of the start-up of each pass after the pad: below 1e-6 of a ramp that climbs
  // by 1 over the signal)
  for (std::size_t k = 0; k < line.size(); ++k) {
    EXPECT_NEAR(low[k], line[k], 1e-6) << k;
    EXPECT_NEAR(high[k], 0.0, 1e-6) << k;
  }
  EXPECT_TRUE(lowpass_zero_phase({}, kFs, 10).empty());
  EXPECT_EQ(highpass_zero_phase({2.0}, kFs, 10), std::vector<double>{0.0});
  EXPECT_THROW((void)lowpass_zero_phase(line, 0, 10), std::invalid_argument);
}

// Property: the dominant frequency of a sine (random frequency, phase, window length) plus a
// weaker one is the stronger sine's, to a fraction of a Hz.
TEST(Signal, DominantFrequencyOfRandomSines) {
  const int cases = test::property_cases(40);
  for (int c = 0; c < cases; ++c) {
    const auto seed = static_cast<std::uint64_t>(300 + c);
    auto rng = test::make_rng(seed);
    const double f = test::uniform(rng, 10, 200);
    const auto n = static_cast<std::size_t>(test::uniform(rng, 200, 800));
    std::vector<double> x = sine(f, 1.0, n, test::uniform(rng, 0, 2 * kPi));
    const std::vector<double> weak = sine(test::uniform(rng, 250, 450), 0.3, n);
    for (std::size_t k = 0; k < n; ++k) x[k] += weak[k] + 5.0;
    EXPECT_NEAR(dominant_frequency(x, kFs, 5), f, 0.3) << test::seed_text(seed);
  }
  EXPECT_EQ(dominant_frequency(std::vector<double>(5, 1.0), kFs, 5), 0.0);
  EXPECT_EQ(dominant_frequency(std::vector<double>(100, 1.0), kFs, 5), 0.0) << "a constant has no frequency";
}

}  // namespace
}  // namespace blendbench
