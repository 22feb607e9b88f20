// signals/signals_spectrum.h — single-sided amplitude spectra of sampled records: the window
// functions, the FFT (GSL mixed-radix real transform, any length, wrapped here and nowhere
// else), and the spectrum peaks (the rig's "FFT inflection points"). What does not live here:
// time-domain measures (signals/signals.h) and the record type (signals/timeseries.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "signals/timeseries.h"

namespace flexrod::study {

/// Data windows, all in the periodic (DFT-even) form w[j] = Σ_k (−1)^k a_k cos(2π k j / N),
/// j = 0..N−1, which is what spectral analysis wants (Harris 1978, §II).
enum class Window {
  kRectangular,     ///< a = {1}
  kHann,            ///< a = {0.5, 0.5}
  kHamming,         ///< a = {0.54, 0.46}
  kBlackmanHarris,  ///< 4-term, −92 dB: a = {0.35875, 0.48829, 0.14128, 0.01168} (Harris 1978)
  kFlatTop,         ///< HFT90D (Heinzel et al. 2002): amplitude error < 5e-4 anywhere in a bin
};
/// "rectangular", "hann", "hamming", "blackman-harris", "flat-top"; InputError(key, value, ...)
/// otherwise.
Window WindowFromString(const std::string& key, const std::string& value);
const char* ToString(Window window);
/// Fills w (its size is N) with the window's samples.
void FillWindow(Window window, std::span<double> w);

/// Single-sided amplitude spectrum of N samples: bins k = 0 .. floor(N/2).
/// With X_k = Σ_j w_j x_j e^{−2πi jk/N} and S = Σ_j w_j (the coherent gain × N):
///   amplitude_k = |X_k| / S for k = 0 and (N even) k = N/2,  2 |X_k| / S otherwise,
/// so a sine A sin(2π f t + φ) with f on a bin reads exactly A there (to round-off) with every
/// window, a constant c reads c in bin 0, and A cos(π j) reads A in the Nyquist bin. Off-bin
/// tones read low by the window's scallop loss (flat-top: < 5e-4 relative).
struct Spectrum {
  std::vector<double> frequency;  ///< bin frequencies k · sample_rate / N [Hz]
  std::vector<double> amplitude;  ///< [unit of the signal]
  double resolution{0.0};         ///< bin spacing sample_rate / N [Hz]
  std::size_t num_samples{0};     ///< N
  Window window{Window::kRectangular};
  std::size_t num_bins() const { return amplitude.size(); }
};

/// Reusable plan for spectra of N samples: owns the GSL wavetable and workspace, the window
/// and the scratch buffer, so Calc() on a Spectrum of the right size allocates nothing. One
/// analyzer per thread (Calc writes its scratch).
class SpectrumAnalyzer {
 public:
  /// Throws InputError unless num_samples ≥ 2 and sample_rate > 0.
  SpectrumAnalyzer(std::size_t num_samples, double sample_rate, Window window);
  ~SpectrumAnalyzer();
  SpectrumAnalyzer(SpectrumAnalyzer&&) noexcept;
  SpectrumAnalyzer& operator=(SpectrumAnalyzer&&) noexcept;
  SpectrumAnalyzer(const SpectrumAnalyzer&) = delete;
  SpectrumAnalyzer& operator=(const SpectrumAnalyzer&) = delete;

  std::size_t num_samples() const;
  double sample_rate() const;  ///< [Hz]
  Window window() const;

  /// Spectrum of x (x.size() must equal num_samples(), else InputError). Throws
  /// NumericalError if GSL reports a failure.
  void Calc(std::span<const double> x, Spectrum* out);
  Spectrum Calc(std::span<const double> x);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot spectrum (builds a SpectrumAnalyzer).
Spectrum CalcAmplitudeSpectrum(std::span<const double> x, double sample_rate, Window window);
/// Spectrum of one channel over `range` (InputError on an unknown channel or a bad range).
Spectrum CalcAmplitudeSpectrum(const TimeSeries& series, std::string_view channel,
                               SampleRange range, Window window);

}  // namespace flexrod::study
