// Tests of signals/signals_spectrum.h: amplitude calibration (bin-centred tones exact, off-bin
// tones within the flat-top window's flatness), special bins, Parseval, agreement with a
// direct DFT for odd lengths, and resolution of two tones by the peak finder.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "signals/signals_spectrum.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include "common/error.h"
#include "tests/test_util.h"

namespace flexrod::study {
namespace {

using flexrod::test::kPi;
constexpr Window kAllWindows[] = {Window::kRectangular, Window::kHann, Window::kHamming,
                                  Window::kBlackmanHarris, Window::kFlatTop};

// A sin(2π f t + phase) + offset sampled at rate for n samples, t_j = j / rate.
std::vector<double> Sine(std::size_t n, double rate, double amplitude, double frequency,
                         double phase = 0.7, double offset = 0.0) {
  std::vector<double> x(n);
  for (std::size_t j = 0; j < n; ++j) {
    x[j] = offset +
           amplitude * std::sin(2.0 * kPi * frequency * static_cast<double>(j) / rate + phase);
  }
  return x;
}

std::size_t ArgMax(const std::vector<double>& v) {
  return static_cast<std::size_t>(std::max_element(v.begin(), v.end()) - v.begin());
}

TEST(Spectrum, BinCentredSineReadsItsAmplitudeExactlyWithRectangularWindow) {
  // N = 1000 at 1 kHz: 1 Hz bins; 50 Hz lies on bin 50.
  const Spectrum s =
      CalcAmplitudeSpectrum(Sine(1000, 1000.0, 2.5, 50.0), 1000.0, Window::kRectangular);
  ASSERT_EQ(s.num_bins(), 501u);
  EXPECT_DOUBLE_EQ(s.resolution, 1.0);
  EXPECT_DOUBLE_EQ(s.frequency[50], 50.0);
  EXPECT_NEAR(s.amplitude[50], 2.5, 1e-10);
  for (std::size_t k = 0; k < s.num_bins(); ++k) {
    if (k != 50) {
      EXPECT_LT(s.amplitude[k], 1e-10) << "bin " << k;
    }
  }
}

TEST(Spectrum, BinCentredSineReadsItsAmplitudeWithEveryWindow) {
  // Periodic cosine-sum windows put exactly S/2 of a bin-centred tone into its bin, so the
  // amplitude correction 2|X|/S is exact for all of them.
  for (Window w : kAllWindows) {
    const Spectrum s = CalcAmplitudeSpectrum(Sine(2048, 2048.0, 0.75, 300.0), 2048.0, w);
    EXPECT_EQ(ArgMax(s.amplitude), 300u) << ToString(w);
    EXPECT_NEAR(s.amplitude[300], 0.75, 1e-10) << ToString(w);
  }
}

TEST(Spectrum, AnyLengthWorksIncludingPrimes) {
  // 997 is prime: Bluestein's transform handles it (no zero padding, no radix-2 demand).
  const Spectrum s =
      CalcAmplitudeSpectrum(Sine(997, 997.0, 1.25, 31.0), 997.0, Window::kRectangular);
  ASSERT_EQ(s.num_bins(), 499u);  // odd N: bins 0..498, no Nyquist bin
  EXPECT_NEAR(s.amplitude[31], 1.25, 1e-10);
  EXPECT_NEAR(s.frequency[31], 31.0, 1e-12);
}

TEST(Spectrum, OffBinSineWithFlatTopIsWithinOneThousandth) {
  // Worst case is half a bin off (scallop loss). HFT90D's flatness is 0.0039 dB ≈ 4.5e-4
  // (Heinzel et al. 2002); the Hann window loses 1.42 dB ≈ 15 % there, which shows the test
  // can tell a flat-top from an ordinary window.
  const double amplitude = 3.0;
  for (double offset : {0.1, 0.25, 0.5, 0.75, 0.9}) {
    const std::vector<double> x = Sine(4000, 4000.0, amplitude, 400.0 + offset, 1.1);
    const Spectrum flat = CalcAmplitudeSpectrum(x, 4000.0, Window::kFlatTop);
    const double peak = *std::max_element(flat.amplitude.begin(), flat.amplitude.end());
    EXPECT_NEAR(peak, amplitude, 1e-3 * amplitude) << "offset " << offset << " bin";
    if (offset == 0.5) {
      const Spectrum hann = CalcAmplitudeSpectrum(x, 4000.0, Window::kHann);
      const double hann_peak = *std::max_element(hann.amplitude.begin(), hann.amplitude.end());
      EXPECT_GT(amplitude - hann_peak, 0.1 * amplitude);
    }
  }
}

TEST(Spectrum, DcAndNyquistBinsAreNotDoubled) {
  const std::size_t n = 64;
  std::vector<double> x(n);
  for (std::size_t j = 0; j < n; ++j) x[j] = 1.5 + 0.25 * ((j % 2 == 0) ? 1.0 : -1.0);
  const Spectrum s = CalcAmplitudeSpectrum(x, 64.0, Window::kRectangular);
  ASSERT_EQ(s.num_bins(), 33u);
  EXPECT_NEAR(s.amplitude[0], 1.5, 1e-12);
  EXPECT_NEAR(s.amplitude[32], 0.25, 1e-12);
  EXPECT_DOUBLE_EQ(s.frequency[32], 32.0);
}

TEST(Spectrum, ParsevalHoldsWithRectangularWindow) {
  // mean(x²) = a_0² + a_{N/2}² + Σ_{0<k<N/2} a_k² / 2 for the single-sided amplitudes.
  std::mt19937 rng(12345);
  std::normal_distribution<double> gauss(0.3, 2.0);
  std::vector<double> x(1024);
  double mean_square = 0.0;
  for (double& v : x) {
    v = gauss(rng);
    mean_square += v * v / 1024.0;
  }
  const Spectrum s = CalcAmplitudeSpectrum(x, 1.0, Window::kRectangular);
  double sum = s.amplitude[0] * s.amplitude[0] + s.amplitude[512] * s.amplitude[512];
  for (std::size_t k = 1; k < 512; ++k) sum += 0.5 * s.amplitude[k] * s.amplitude[k];
  EXPECT_NEAR(sum, mean_square, 1e-12 * mean_square);
}

TEST(Spectrum, MatchesDirectDftForOddAndEvenLengthsWithWindow) {
  // Independent formulation: the O(N²) DFT sum of the windowed data, single-sided and
  // normalised by Σw. 15, 16, 105, 211 (prime): GSL's mixed-radix transform; 614 = 2 · 307,
  // 401 (prime), 2018 = 2 · 1009: a prime factor above 300, Bluestein's chirp-z transform.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (std::size_t n : {15u, 16u, 105u, 211u, 614u, 401u, 2018u}) {
    std::vector<double> x(n), w(n);
    for (double& v : x) v = uni(rng);
    FillWindow(Window::kBlackmanHarris, w);
    double sum_w = 0.0;
    for (double v : w) sum_w += v;
    const Spectrum s = CalcAmplitudeSpectrum(x, 10.0, Window::kBlackmanHarris);
    ASSERT_EQ(s.num_bins(), n / 2 + 1);
    for (std::size_t k = 0; k < s.num_bins(); ++k) {
      std::complex<double> X = 0.0;
      for (std::size_t j = 0; j < n; ++j) {
        X += w[j] * x[j] *
             std::polar(1.0, -2.0 * kPi * static_cast<double>(j * k) / static_cast<double>(n));
      }
      const double factor = (k == 0 || 2 * k == n) ? 1.0 : 2.0;
      EXPECT_NEAR(s.amplitude[k], factor * std::abs(X) / sum_w, 1e-12) << "N=" << n << " k=" << k;
      EXPECT_NEAR(s.frequency[k], 10.0 * static_cast<double>(k) / static_cast<double>(n), 1e-12);
    }
  }
}

TEST(Spectrum, WindowsHaveTheirPublishedShapes) {
  std::vector<double> w(8);
  FillWindow(Window::kHann, w);
  EXPECT_NEAR(w[0], 0.0, 1e-15);  // periodic Hann starts at 0 and peaks at 1 at N/2
  EXPECT_NEAR(w[4], 1.0, 1e-15);
  FillWindow(Window::kHamming, w);
  EXPECT_NEAR(w[0], 0.08, 1e-15);
  FillWindow(Window::kBlackmanHarris, w);
  EXPECT_NEAR(w[0], 0.35875 - 0.48829 + 0.14128 - 0.01168, 1e-15);  // 6e-5 (Harris 1978)
  FillWindow(Window::kFlatTop, w);
  EXPECT_NEAR(w[4], 1.0 + 1.942604 + 1.340318 + 0.440811 + 0.043097, 1e-12);  // HFT90D peak
  FillWindow(Window::kRectangular, w);
  EXPECT_EQ(w[3], 1.0);
}

TEST(Spectrum, TwoCloseTonesAreResolvedWithHann) {
  // Hann: a bin-centred tone occupies its bin and the two neighbours only, so tones 4 bins
  // apart stay separate (nothing between them) and read their exact amplitudes.
  std::vector<double> x = Sine(2000, 2000.0, 1.0, 100.0, 0.3);
  const std::vector<double> y = Sine(2000, 2000.0, 0.25, 104.0, 2.0);
  for (std::size_t j = 0; j < x.size(); ++j) x[j] += y[j];
  const Spectrum s = CalcAmplitudeSpectrum(x, 2000.0, Window::kHann);
  EXPECT_DOUBLE_EQ(s.frequency[100], 100.0);
  EXPECT_NEAR(s.amplitude[100], 1.0, 1e-10);
  EXPECT_NEAR(s.amplitude[104], 0.25, 1e-10);
  EXPECT_NEAR(s.amplitude[102], 0.0, 1e-10);
  for (std::size_t k : {99u, 101u}) EXPECT_NEAR(s.amplitude[k], 0.5, 1e-10);  // Hann's ½
  for (std::size_t k : {103u, 105u}) EXPECT_NEAR(s.amplitude[k], 0.125, 1e-10);
}

TEST(Spectrum, OffBinTonesWithFlatTopGiveTheirAmplitudes) {
  // The flat-top window's scalloping loss is below 1e-3 anywhere between bins (HFT90D).
  std::vector<double> x = Sine(5000, 5000.0, 40.0, 120.3, 0.1);
  const std::vector<double> y = Sine(5000, 5000.0, 15.0, 151.6, 1.3);
  for (std::size_t j = 0; j < x.size(); ++j) x[j] += y[j];
  const Spectrum s = CalcAmplitudeSpectrum(x, 5000.0, Window::kFlatTop);
  EXPECT_NEAR(s.amplitude[120], 40.0, 40.0 * 1e-3);
  EXPECT_NEAR(s.amplitude[152], 15.0, 15.0 * 1e-3);
}

TEST(Spectrum, BadInputIsRejectedNamingTheKey) {
  EXPECT_THROW(CalcAmplitudeSpectrum(std::vector<double>{1.0}, 10.0, Window::kHann), InputError);
  EXPECT_THROW(CalcAmplitudeSpectrum(std::vector<double>{1.0, 2.0}, 0.0, Window::kHann),
               InputError);
  SpectrumAnalyzer analyzer(16, 1.0, Window::kHann);
  EXPECT_THROW(analyzer.Calc(std::vector<double>(15, 0.0)), InputError);
  EXPECT_EQ(WindowFromString("fft.window", "blackman-harris"), Window::kBlackmanHarris);
  for (Window w : kAllWindows) EXPECT_EQ(WindowFromString("k", ToString(w)), w);
  try {
    WindowFromString("fft.window", "kaiser");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "fft.window");
    EXPECT_EQ(e.value(), "kaiser");
  }
}

TEST(Spectrum, AnalyzerIsReusableAcrossChannels) {
  SpectrumAnalyzer analyzer(512, 512.0, Window::kHann);
  Spectrum s;
  analyzer.Calc(Sine(512, 512.0, 1.0, 20.0), &s);
  EXPECT_NEAR(s.amplitude[20], 1.0, 1e-10);
  analyzer.Calc(Sine(512, 512.0, 2.0, 40.0), &s);
  EXPECT_NEAR(s.amplitude[40], 2.0, 1e-10);
  EXPECT_LT(s.amplitude[20], 1e-10);
}

}  // namespace
}  // namespace flexrod::study
