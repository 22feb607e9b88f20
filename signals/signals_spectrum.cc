// SPDX-License-Identifier: GPL-3.0-or-later
#include "signals/signals_spectrum.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_fft_complex.h>
#include <gsl/gsl_fft_real.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <vector>

#include "common/error.h"

namespace flexrod::study {
namespace {

// Cosine-sum coefficients a_k of w[j] = Σ_k (−1)^k a_k cos(2π k j / N).
// Blackman–Harris: F. J. Harris, "On the use of windows for harmonic analysis with the discrete
// Fourier transform", Proc. IEEE 66(1):51–83, 1978, 4-term −92 dB window.
// Flat-top HFT90D: G. Heinzel, A. Rüdiger, R. Schilling, "Spectrum and spectral density
// estimation by the Discrete Fourier transform (DFT), including a comprehensive list of window
// functions and some new flat-top windows", MPI für Gravitationsphysik, 2002, §D (HFT90D:
// sidelobes −90.2 dB, maximum amplitude flatness 0.0039 dB).
constexpr std::array<double, 1> kCoeffRectangular = {1.0};
constexpr std::array<double, 2> kCoeffHann = {0.5, 0.5};
constexpr std::array<double, 2> kCoeffHamming = {0.54, 0.46};
constexpr std::array<double, 4> kCoeffBlackmanHarris = {0.35875, 0.48829, 0.14128, 0.01168};
constexpr std::array<double, 5> kCoeffFlatTopHft90d = {1.0, 1.942604, 1.340318, 0.440811, 0.043097};

std::span<const double> Coefficients(Window window) {
  switch (window) {
    case Window::kRectangular:
      return kCoeffRectangular;
    case Window::kHann:
      return kCoeffHann;
    case Window::kHamming:
      return kCoeffHamming;
    case Window::kBlackmanHarris:
      return kCoeffBlackmanHarris;
    case Window::kFlatTop:
      return kCoeffFlatTopHft90d;
  }
  FLEXROD_ASSERT(false);
  return kCoeffRectangular;
}

struct WavetableDeleter {
  void operator()(gsl_fft_real_wavetable* p) const { gsl_fft_real_wavetable_free(p); }
};
struct WorkspaceDeleter {
  void operator()(gsl_fft_real_workspace* p) const { gsl_fft_real_workspace_free(p); }
};

// GSL's mixed-radix FFT costs O(n p) for a length with a prime factor p beyond its radices (a
// prime length: n²; 299 999 = 7 · 17 · 2521 samples, about 1.6 s). Above this factor the DFT is
// taken by Bluestein's chirp-z algorithm instead: O(m log m) with m >= 2n − 1 a power of two,
// the same DFT to round-off. Measured (bench_signals, flat-top, ~3·10⁴ samples): p = 101 mixed
// radix 6.8 ms, Bluestein 12.6 ms; p = 997 mixed radix 72 ms, Bluestein 29 ms.
constexpr std::size_t kMaxMixedRadixFactor = 300;

std::size_t LargestPrimeFactor(std::size_t n) {
  std::size_t largest = 1;
  for (std::size_t f = 2; f * f <= n; ++f) {
    while (n % f == 0) {
      largest = f;
      n /= f;
    }
  }
  return n > 1 ? std::max(largest, n) : largest;
}

void CheckGsl(int status, const char* what) {
  if (status != GSL_SUCCESS) {
    throw NumericalError(std::string(what) + " failed: " + gsl_strerror(status));
  }
}

// Bluestein (L. I. Bluestein, "A linear filtering approach to the computation of discrete
// Fourier transform", IEEE Trans. Audio Electroacoust. 18(4):451–455, 1970): with
// jk = (j² + k² − (k − j)²)/2 and w_j = exp(iπ j²/n), X_k = w̄_k Σ_j (x_j w̄_j) w_(k−j), a
// convolution, done cyclically over m >= 2n − 1 points by radix-2 FFTs.
struct Chirp {
  using C = std::complex<double>;  // layout-compatible with GSL's packed complex arrays
  std::size_t n{0}, m{1};
  std::vector<C> w;   // w_j, j < n
  std::vector<C> bf;  // FFT of b: b_j = w_|j| for |j| < n, cyclic over m
  std::vector<C> a;   // work

  static void Fft(std::vector<C>* v, bool inverse) {
    double* d = reinterpret_cast<double*>(v->data());
    CheckGsl(inverse ? gsl_fft_complex_radix2_inverse(d, 1, v->size())
                     : gsl_fft_complex_radix2_forward(d, 1, v->size()),
             "gsl_fft_complex_radix2");
  }

  explicit Chirp(std::size_t num_samples) : n(num_samples), w(num_samples) {
    while (m < 2 * n - 1) m *= 2;
    const auto two_n = static_cast<std::uint64_t>(2 * n);
    for (std::size_t j = 0; j < n; ++j) {
      // j² mod 2n keeps the angle exact for long records.
      const std::uint64_t r = (static_cast<std::uint64_t>(j) * j) % two_n;
      w[j] = std::polar(1.0, std::numbers::pi * static_cast<double>(r) / static_cast<double>(n));
    }
    bf.assign(m, 0.0);
    for (std::size_t j = 0; j < n; ++j) bf[j] = bf[(m - j) % m] = w[j];
    Fft(&bf, false);
    a.resize(m);
  }

  // The DFT of the real x (n values) into GSL's half-complex layout (gsl_fft_real_transform's).
  void Transform(const double* x, double* halfcomplex) {
    std::fill(a.begin(), a.end(), 0.0);
    for (std::size_t j = 0; j < n; ++j) a[j] = x[j] * std::conj(w[j]);
    Fft(&a, false);
    for (std::size_t k = 0; k < m; ++k) a[k] *= bf[k];
    Fft(&a, true);
    for (std::size_t k = 0; 2 * k <= n; ++k) {
      const C X = std::conj(w[k]) * a[k];
      if (k == 0) {
        halfcomplex[0] = X.real();
      } else if (2 * k == n) {
        halfcomplex[n - 1] = X.real();
      } else {
        halfcomplex[2 * k - 1] = X.real();
        halfcomplex[2 * k] = X.imag();
      }
    }
  }
};

}  // namespace

Window WindowFromString(const std::string& key, const std::string& value) {
  for (Window w : {Window::kRectangular, Window::kHann, Window::kHamming, Window::kBlackmanHarris,
                   Window::kFlatTop}) {
    if (value == ToString(w)) return w;
  }
  throw InputError(key, value,
                   "must be one of rectangular, hann, hamming, blackman-harris, flat-top");
}

const char* ToString(Window window) {
  switch (window) {
    case Window::kRectangular:
      return "rectangular";
    case Window::kHann:
      return "hann";
    case Window::kHamming:
      return "hamming";
    case Window::kBlackmanHarris:
      return "blackman-harris";
    case Window::kFlatTop:
      return "flat-top";
  }
  return "?";
}

void FillWindow(Window window, std::span<double> w) {
  const std::span<const double> a = Coefficients(window);
  // Periodic: w_j = w_{n−j}, so the second half mirrors the first (half the cosines: a long
  // capture's window has millions of samples).
  const std::size_t size = w.size();
  if (size == 0) return;
  const double n = static_cast<double>(size);
  for (std::size_t j = 0; j <= size / 2; ++j) {
    const double z = 2.0 * std::numbers::pi * static_cast<double>(j) / n;
    double sum = a[0];
    double sign = -1.0;
    for (std::size_t k = 1; k < a.size(); ++k, sign = -sign) {
      sum += sign * a[k] * std::cos(static_cast<double>(k) * z);
    }
    w[j] = sum;
    if (j > 0) w[size - j] = sum;
  }
}

// ---- the GSL wrapper: the only place flexrod calls gsl_fft_* --------------------------------

struct SpectrumAnalyzer::Impl {
  std::size_t n;
  double sample_rate;
  Window window;
  std::vector<double> weights;  // window samples
  double weight_sum;            // S = Σ w
  std::vector<double> scratch;  // windowed data, transformed in place (half-complex)
  std::unique_ptr<gsl_fft_real_wavetable, WavetableDeleter> wavetable;
  std::unique_ptr<gsl_fft_real_workspace, WorkspaceDeleter> workspace;
  std::unique_ptr<Chirp> chirp;  // lengths with a large prime factor (kMaxMixedRadixFactor)
};

SpectrumAnalyzer::SpectrumAnalyzer(std::size_t num_samples, double sample_rate, Window window) {
  Require(num_samples >= 2, "spectrum.num_samples", static_cast<double>(num_samples),
          "must be >= 2");
  Require(std::isfinite(sample_rate) && sample_rate > 0.0, "spectrum.sample_rate", sample_rate,
          "must be finite and > 0 [Hz]");
  impl_ = std::make_unique<Impl>();
  Impl& p = *impl_;
  p.n = num_samples;
  p.sample_rate = sample_rate;
  p.window = window;
  p.weights.resize(num_samples);
  FillWindow(window, p.weights);
  p.weight_sum = 0.0;
  for (double w : p.weights) p.weight_sum += w;
  p.scratch.resize(num_samples);
  if (LargestPrimeFactor(num_samples) > kMaxMixedRadixFactor) {
    p.chirp = std::make_unique<Chirp>(num_samples);
    return;
  }
  p.wavetable.reset(gsl_fft_real_wavetable_alloc(num_samples));
  p.workspace.reset(gsl_fft_real_workspace_alloc(num_samples));
  if (!p.wavetable || !p.workspace) {
    throw NumericalError("GSL could not allocate an FFT plan for " + std::to_string(num_samples) +
                         " samples");
  }
}

SpectrumAnalyzer::~SpectrumAnalyzer() = default;
SpectrumAnalyzer::SpectrumAnalyzer(SpectrumAnalyzer&&) noexcept = default;
SpectrumAnalyzer& SpectrumAnalyzer::operator=(SpectrumAnalyzer&&) noexcept = default;

std::size_t SpectrumAnalyzer::num_samples() const { return impl_->n; }
double SpectrumAnalyzer::sample_rate() const { return impl_->sample_rate; }
Window SpectrumAnalyzer::window() const { return impl_->window; }

void SpectrumAnalyzer::Calc(std::span<const double> x, Spectrum* out) {
  Impl& p = *impl_;
  if (x.size() != p.n) {
    throw InputError("spectrum.samples", std::to_string(x.size()),
                     "the analyzer was planned for " + std::to_string(p.n) + " samples");
  }
  for (std::size_t j = 0; j < p.n; ++j) p.scratch[j] = p.weights[j] * x[j];
  if (p.chirp) {
    p.chirp->Transform(p.scratch.data(), p.scratch.data());
  } else {
    CheckGsl(gsl_fft_real_transform(p.scratch.data(), 1, p.n, p.wavetable.get(), p.workspace.get()),
             "gsl_fft_real_transform");
  }
  // Half-complex layout (GSL manual, "Mixed-radix FFT routines for real data"):
  // data[0] = Re X_0; data[2k−1], data[2k] = Re, Im X_k for 0 < k < N − k; data[N−1] = Re X_{N/2}
  // when N is even.
  const std::size_t num_bins = p.n / 2 + 1;
  out->frequency.resize(num_bins);
  out->amplitude.resize(num_bins);
  out->resolution = p.sample_rate / static_cast<double>(p.n);
  out->num_samples = p.n;
  out->window = p.window;
  const double scale = 1.0 / p.weight_sum;
  for (std::size_t k = 0; k < num_bins; ++k) {
    out->frequency[k] = static_cast<double>(k) * p.sample_rate / static_cast<double>(p.n);
    if (k == 0) {
      out->amplitude[k] = std::abs(p.scratch[0]) * scale;
    } else if (2 * k == p.n) {
      out->amplitude[k] = std::abs(p.scratch[p.n - 1]) * scale;
    } else {
      out->amplitude[k] = 2.0 * std::hypot(p.scratch[2 * k - 1], p.scratch[2 * k]) * scale;
    }
  }
}

Spectrum SpectrumAnalyzer::Calc(std::span<const double> x) {
  Spectrum s;
  Calc(x, &s);
  return s;
}

Spectrum CalcAmplitudeSpectrum(std::span<const double> x, double sample_rate, Window window) {
  SpectrumAnalyzer analyzer(x.size(), sample_rate, window);
  return analyzer.Calc(x);
}

Spectrum CalcAmplitudeSpectrum(const TimeSeries& series, std::string_view channel,
                               SampleRange range, Window window) {
  const std::span<const double> x = series.values(channel);
  ValidateRange("spectrum.range", range, x.size());
  return CalcAmplitudeSpectrum(x.subspan(range.begin, range.size()), series.sample_rate(), window);
}

}  // namespace flexrod::study
