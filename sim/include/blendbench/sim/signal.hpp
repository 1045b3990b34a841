#pragma once
// Signal processing for the metrics of a sampled run: zero-phase Butterworth filters and the
// dominant frequency of a window. Plain values; uniform sampling at rate fs (Hz).

#include <vector>

namespace blendbench {

// A second-order Butterworth filter (bilinear transform, cut-off prewarped) applied forward and
// then backward, so the result has no phase lag and the magnitude response is squared (-6 dB at
// the cut-off fc, 4th order roll-off). The signal is extended at both ends by its odd reflection
// over 3 fs / fc samples (at most n - 1), and each pass starts from the steady state of the first
// sample it sees, so a signal that starts or ends at rest, in a ramp or in a sine gives no edge
// transient. fc is clamped to 0.45 fs. Empty in, empty out. Throws std::invalid_argument unless
// fs > 0 and fc > 0.
std::vector<double> lowpass_zero_phase(const std::vector<double>& x, double fs, double fc);
std::vector<double> highpass_zero_phase(const std::vector<double>& x, double fs, double fc);

// The frequency (Hz) of the largest peak of the Hann-windowed spectrum of x (its mean removed)
// between f_min and fs / 2, scanned every `resolution` Hz and refined by a parabola through the
// peak and its neighbours. A peak is a local maximum inside the band; a spectrum without one
// (falling from f_min on: a transient, not a vibration) gives the frequency of its largest value.
// 0 when x has fewer than 8 samples or no energy.
double dominant_frequency(const std::vector<double>& x, double fs, double f_min, double resolution = 0.25);

}  // namespace blendbench
