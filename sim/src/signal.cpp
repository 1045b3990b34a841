#include "blendbench/sim/signal.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace blendbench {
namespace {

// Coefficients of y[n] = b0 x[n] + b1 x[n-1] + b2 x[n-2] - a1 y[n-1] - a2 y[n-2].
struct Biquad {
  double b0, b1, b2, a1, a2;
};

// Second-order Butterworth, bilinear transform with the cut-off prewarped: K = tan(pi fc / fs).
Biquad butterworth(double fs, double fc, bool highpass) {
  if (!(fs > 0) || !(fc > 0)) throw std::invalid_argument("filter: the sample rate and the cut-off must be positive");
  const double k = std::tan(std::numbers::pi * std::min(fc, 0.45 * fs) / fs);
  const double norm = 1 / (1 + std::numbers::sqrt2 * k + k * k);
  Biquad f{};
  f.a1 = 2 * (k * k - 1) * norm;
  f.a2 = (1 - std::numbers::sqrt2 * k + k * k) * norm;
  if (highpass) {
    f.b0 = norm;
    f.b1 = -2 * norm;
    f.b2 = norm;
  } else {
    f.b0 = k * k * norm;
    f.b1 = 2 * f.b0;
    f.b2 = f.b0;
  }
  return f;
}

// One pass in place, forward or backward. The low-pass starts at rest at the first value (its
// DC gain is 1); the high-pass filters the signal minus its first value (its DC gain is 0).
void pass(const Biquad& f, std::vector<double>& x, bool forward, bool highpass) {
  const std::size_t n = x.size();
  if (n == 0) return;
  const double x0 = forward ? x.front() : x.back();
  double x1 = 0, x2 = 0, y1 = 0, y2 = 0;
  for (std::size_t k = 0; k < n; ++k) {
    double& v = x[forward ? k : n - 1 - k];
    const double in = v - x0;
    const double out = f.b0 * in + f.b1 * x1 + f.b2 * x2 - f.a1 * y1 - f.a2 * y2;
    x2 = x1;
    x1 = in;
    y2 = y1;
    y1 = out;
    v = highpass ? out : out + x0;
  }
}

std::vector<double> zero_phase(const std::vector<double>& x, double fs, double fc, bool highpass) {
  const Biquad f = butterworth(fs, fc, highpass);
  const std::size_t n = x.size();
  if (n < 2) return highpass ? std::vector<double>(n, 0.0) : x;
  // odd reflection about each end over three time constants of the cut-off (as filtfilt pads),
  // so a signal that starts or ends in a ramp or a sine continues smoothly into the pad
  const auto pad = std::min<std::size_t>(n - 1, static_cast<std::size_t>(std::ceil(3 * fs / std::min(fc, 0.45 * fs))));
  std::vector<double> y(n + 2 * pad);
  for (std::size_t k = 0; k < pad; ++k) {
    y[k] = 2 * x.front() - x[pad - k];
    y[n + pad + k] = 2 * x.back() - x[n - 2 - k];
  }
  std::copy(x.begin(), x.end(), y.begin() + static_cast<std::ptrdiff_t>(pad));
  pass(f, y, true, highpass);
  pass(f, y, false, highpass);
  return {y.begin() + static_cast<std::ptrdiff_t>(pad), y.begin() + static_cast<std::ptrdiff_t>(pad + n)};
}

}  // namespace

std::vector<double> lowpass_zero_phase(const std::vector<double>& x, double fs, double fc) {
  return zero_phase(x, fs, fc, false);
}

std::vector<double> highpass_zero_phase(const std::vector<double>& x, double fs, double fc) {
  return zero_phase(x, fs, fc, true);
}

double dominant_frequency(const std::vector<double>& x, double fs, double f_min, double resolution) {
  const std::size_t n = x.size();
  if (n < 8 || !(fs > 0) || !(resolution > 0)) return 0;
  double mean = 0;
  for (const double v : x) mean += v;
  mean /= static_cast<double>(n);
  // Hann-windowed samples
  std::vector<double> w(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double hann = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(n - 1));
    w[k] = (x[k] - mean) * hann;
  }
  // |X(f)|^2 on a grid from f_min to fs / 2
  const auto power = [&](double f) {
    // the phasor exp(-i 2 pi f k / fs) by recurrence (a rotation per sample)
    const double step = 2 * std::numbers::pi * f / fs;
    const double c = std::cos(step), s = -std::sin(step);
    double pr = 1, pi = 0, re = 0, im = 0;
    for (std::size_t k = 0; k < n; ++k) {
      re += w[k] * pr;
      im += w[k] * pi;
      const double next = pr * c - pi * s;
      pi = pr * s + pi * c;
      pr = next;
    }
    return re * re + im * im;
  };
  const double f_lo = std::max(f_min, resolution);
  const double f_hi = 0.5 * fs;
  std::vector<double> f, p;
  for (double g = f_lo; g <= f_hi; g += resolution) {
    f.push_back(g);
    p.push_back(power(g));
  }
  // the largest spectral peak (a local maximum inside the band); a spectrum that only falls
  // from f_min (a transient's, not a vibration's) gives its largest value
  std::size_t best = 0;
  bool peak = false;
  for (std::size_t k = 1; k + 1 < p.size(); ++k) {
    if (p[k] > p[k - 1] && p[k] >= p[k + 1] && (!peak || p[k] > p[best])) {
      best = k;
      peak = true;
    }
  }
  if (!peak) best = static_cast<std::size_t>(std::max_element(p.begin(), p.end()) - p.begin());
  const double best_p = p.empty() ? 0.0 : p[best];
  const double best_f = p.empty() ? 0.0 : f[best];
  const double before = best > 0 ? p[best - 1] : best_p;
  const double after = best + 1 < p.size() ? p[best + 1] : best_p;
  if (!(best_p > 0)) return 0;
  // parabola through the peak and its neighbours
  const double denominator = before - 2 * best_p + after;
  const double shift = denominator < 0 ? 0.5 * (before - after) / denominator : 0.0;
  return best_f + std::clamp(shift, -0.5, 0.5) * resolution;
}

}  // namespace blendbench
