// Tests of signals/signals.h: the triggered capture window, index crossings and revolutions,
// the Poincaré map and its jitter, turning ("inflection") points above the noise floor,
// percentiles, per-revolution peak statistics and load amplification.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "signals/signals.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "common/error.h"
#include "tests/test_util.h"

namespace flexrod::study {
namespace {

using flexrod::test::kPi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Crank turning at a constant rate: θ_i = theta0 + omega · i / rate (unwrapped) [rad].
std::vector<double> UniformCrank(std::size_t n, double rate, double omega, double theta0) {
  std::vector<double> theta(n);
  for (std::size_t i = 0; i < n; ++i) theta[i] = theta0 + omega * static_cast<double>(i) / rate;
  return theta;
}

// ---- capture window -------------------------------------------------------------------------

TEST(CaptureWindow, StartsAtTheFirstIndexCrossingAfterSettling) {
  const double rate = 1000.0, start = 10.0;
  const double omega = kTwoPi * 2.3, theta0 = 0.4, index = 1.0;
  const std::vector<double> theta = UniformCrank(4000, rate, omega, theta0);
  CaptureOptions options;
  options.settling_time = 0.5;
  options.duration = 1.25;
  options.index_angle = index;
  // Analytic crossing instants (relative to the record's start): (index + 2πk − θ0) / ω.
  int k = 0;
  while ((index + kTwoPi * k - theta0) / omega < options.settling_time) ++k;
  const double t_cross = (index + kTwoPi * k - theta0) / omega;
  const auto expected_begin = static_cast<std::size_t>(std::ceil(t_cross * rate));

  const SampleRange window = FindCaptureWindow(theta, rate, start, options);
  EXPECT_EQ(window.begin, expected_begin);
  EXPECT_EQ(window.size(), 1250u);
  const double level = index + kTwoPi * k;
  EXPECT_LT(theta[window.begin - 1], level);
  EXPECT_GE(theta[window.begin], level);

  TimeSeries ts(rate, start);
  ts.AddChannel("crank_angle", "rad", theta);
  EXPECT_EQ(FindCaptureWindow(ts, "crank_angle", options), window);
}

TEST(CaptureWindow, CrossingJustBeforeSettlingDoesNotTrigger) {
  // 2 rev/s, θ_i = 4π (i − 0.5) / 1000: index 0 is crossed half-way between samples, at
  // t = 0.5 k + 0.0005 s, and the crossing belongs to sample 500 k + 1.
  const double rate = 1000.0, omega = kTwoPi * 2.0, theta0 = -0.5 * omega / rate;
  const std::vector<double> theta = UniformCrank(3000, rate, omega, theta0);
  CaptureOptions options;
  options.duration = 1.0;
  // Crossing k = 1 (0.5005 s) comes 0.2 ms before the settling time: k = 2 triggers.
  options.settling_time = 0.5007;
  EXPECT_EQ(FindCaptureWindow(theta, rate, 0.0, options).begin, 1001u);
  // Settling 0.2 ms before crossing k = 1 — and after sample 500 — lets k = 1 trigger.
  options.settling_time = 0.5003;
  EXPECT_EQ(FindCaptureWindow(theta, rate, 0.0, options).begin, 501u);
}

TEST(CaptureWindow, RigCaptureHoldsThreeHundredThousandSamples) {
  // RIG.md Table 2: 3 s at 100 kHz = 300 000 points.
  const std::vector<double> theta = UniformCrank(360000, kRigSampleRate, kTwoPi * 2.0, 0.1);
  CaptureOptions options;  // default duration 3 s, index angle 0, no settling
  const SampleRange window = FindCaptureWindow(theta, kRigSampleRate, 0.0, options);
  EXPECT_EQ(window.size(), 300000u);
  // θ = 0.1 + 4π t starts past level 0 and reaches 2π at t = (2π − 0.1) / 4π = 0.4920423 s,
  // between samples 49204 and 49205.
  EXPECT_EQ(window.begin, 49205u);
}

TEST(CaptureWindow, ImpossibleCapturesAreRejectedNamingTheKey) {
  const std::vector<double> theta = UniformCrank(1000, 1000.0, kTwoPi, 0.5);  // 1 rev/s, 1 s
  CaptureOptions options;
  options.duration = 0.8;
  options.settling_time = 0.0;
  try {  // crossing at t ≈ 0.92 s leaves 0.08 s
    FindCaptureWindow(theta, 1000.0, 0.0, options);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "capture.duration");
  }
  options.settling_time = 0.95;  // no crossing after it
  try {
    FindCaptureWindow(theta, 1000.0, 0.0, options);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "capture.settling_time");
  }
  options.settling_time = -1.0;
  EXPECT_THROW(FindCaptureWindow(theta, 1000.0, 0.0, options), InputError);
}

// ---- crossings and revolutions ---------------------------------------------------------------

TEST(IndexCrossings, AreInterpolatedToTheExactInstant) {
  // θ linear in t, x = a + b t: linear interpolation is exact, so the crossing instants and the
  // Poincaré values must match the analytic ones to round-off.
  const double rate = 997.0, start = 0.3, omega = 7.1, theta0 = -0.2, index = 0.6;
  const std::size_t n = 5000;
  const std::vector<double> theta = UniformCrank(n, rate, omega, theta0);
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = 4.0 - 2.5 * (start + static_cast<double>(i) / rate);
  TimeSeries ts(rate, start);
  ts.AddChannel("crank_angle", "rad", theta);
  ts.AddChannel("x", "m", x);
  const PoincareMap map = CalcPoincareMap(ts, "crank_angle", index, {"x"}, ts.all());
  // Levels passed: θ from −0.2 to −0.2 + 7.1·5000/997 ≈ 35.4 rad → k = 0..5.
  ASSERT_EQ(map.num_points(), 6u);
  EXPECT_EQ(map.units[0], "m");
  for (std::size_t k = 0; k < map.num_points(); ++k) {
    const double t = start + (index + kTwoPi * static_cast<double>(k) - theta0) / omega;
    EXPECT_NEAR(map.time[k], t, 1e-12);
    EXPECT_NEAR(map.points(static_cast<Eigen::Index>(k), 0), 4.0 - 2.5 * t, 1e-11);
  }
}

TEST(Revolutions, OnlyCompleteRevolutionsInsideTheRangeAreKept) {
  // 100 samples per revolution, θ_i = 2π (i − 30.5) / 100: index 0 is crossed at samples 31,
  // 131, 231, 331, 431, 531.
  std::vector<double> theta(560);
  for (std::size_t i = 0; i < theta.size(); ++i) {
    theta[i] = kTwoPi * (static_cast<double>(i) - 30.5) / 100.0;
  }
  const std::vector<SampleRange> all = SplitRevolutions(theta, 0.0, {0, 560});
  ASSERT_EQ(all.size(), 5u);
  EXPECT_EQ(all.front(), (SampleRange{31, 131}));
  EXPECT_EQ(all.back(), (SampleRange{431, 531}));
  // A range starting at a crossing sample keeps that revolution; one ending on the next
  // crossing sample (exclusive end) keeps the last.
  const std::vector<SampleRange> inner = SplitRevolutions(theta, 0.0, {32, 531});
  ASSERT_EQ(inner.size(), 4u);
  EXPECT_EQ(inner.front(), (SampleRange{131, 231}));
  EXPECT_EQ(inner.back(), (SampleRange{431, 531}));
  EXPECT_EQ(SplitRevolutions(theta, 0.0, {31, 530}).size(), 4u);
  EXPECT_EQ(SplitRevolutions(theta, 0.0, {40, 130}).size(), 0u);
}

TEST(Revolutions, ACaptureStartingOnTheIndexCountsItsFirstRevolution) {
  // A capture triggered at the index angle: θ_0 = L up to round-off. Whichever side of L the
  // round-off puts θ_0, five revolutions are complete in 560 samples (crossings at 0 or 1,
  // 100 or 101, ..., 500 or 501).
  for (const double offset : {0.0, 1e-9, -1e-9}) {
    std::vector<double> theta(560);
    for (std::size_t i = 0; i < theta.size(); ++i) {
      theta[i] = 0.3 + kTwoPi * (static_cast<double>(i) + offset) / 100.0;
    }
    const std::vector<SampleRange> revs = SplitRevolutions(theta, 0.3, {0, 560});
    ASSERT_EQ(revs.size(), 5u) << offset;
    EXPECT_EQ(revs.front().begin, offset < 0.0 ? 1u : 0u) << offset;
    // 100 samples each, ±1 where round-off moves a later crossing by one sample (offset 0).
    for (const SampleRange& r : revs) EXPECT_NEAR(double(r.end - r.begin), 100.0, 1.0) << offset;
  }
}

TEST(IndexCrossings, ARecordStartingOnTheIndexHasItsFirstCrossingAtTheStart) {
  // θ_i = L + 2π (i + offset)/100, x_i = 5 + 2 (i + offset): the crossings lie at i = 100k −
  // offset and x there is 5 + 200k exactly. The first one is at the record's start (offset 0),
  // a round-off before it (offset > 0: the linear extension θ[−1] = 2θ[0] − θ[1] finds it) or
  // just after it (offset < 0): six crossings in 560 samples in every case.
  const double rate = 1000.0, start = 2.0, index = 0.3;
  for (const double offset : {0.0, 1e-9, -1e-9}) {
    std::vector<double> theta(560), x(560);
    for (std::size_t i = 0; i < theta.size(); ++i) {
      const double u = static_cast<double>(i) + offset;
      theta[i] = index + kTwoPi * u / 100.0;
      x[i] = 5.0 + 2.0 * u;
    }
    TimeSeries ts(rate, start);
    ts.AddChannel("crank_angle", "rad", theta);
    ts.AddChannel("x", "m", x);
    const PoincareMap map = CalcPoincareMap(ts, "crank_angle", index, {"x"}, ts.all());
    ASSERT_EQ(map.num_points(), 6u) << offset;
    for (std::size_t k = 0; k < map.num_points(); ++k) {
      EXPECT_NEAR(map.time[k], start + (100.0 * static_cast<double>(k) - offset) / rate, 1e-12)
          << offset;
      EXPECT_NEAR(map.points(static_cast<Eigen::Index>(k), 0), 5.0 + 200.0 * static_cast<double>(k),
                  1e-9)
          << offset;
    }
  }
}

// ---- Poincaré map and jitter ------------------------------------------------------------------

// Record of x = f(θ, revolution) with the crank at 2 rev/s sampled at `rate`.
template <typename F>
TimeSeries CrankRecord(double rate, std::size_t n, F f) {
  const std::vector<double> theta = UniformCrank(n, rate, kTwoPi * 2.0, 0.05);
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = f(theta[i]);
  TimeSeries ts(rate, 0.0);
  ts.AddChannel("crank_angle", "rad", theta);
  ts.AddChannel("slider_acceleration", "m/s^2", x);
  return ts;
}

double PeriodicAcceleration(double theta) {
  return 300.0 * std::cos(theta) + 80.0 * std::cos(2.0 * theta + 0.3) +
         25.0 * std::sin(7.0 * theta);
}

TEST(Poincare, PeriodicSignalCollapsesToOnePointWithZeroJitter) {
  // Sampling commensurate with the revolution (500 samples per rev): every crossing falls at
  // the same sub-sample position, so the points agree to round-off.
  const TimeSeries ts = CrankRecord(1000.0, 20000, PeriodicAcceleration);
  const PoincareMap map =
      CalcPoincareMap(ts, "crank_angle", kPi, {"slider_acceleration"}, ts.all());
  ASSERT_EQ(map.num_points(), 40u);
  const double first = map.points(0, 0);
  EXPECT_NEAR(first, PeriodicAcceleration(kPi), 0.5);  // interpolation error O(dt²)
  for (Eigen::Index k = 1; k < map.points.rows(); ++k) {
    EXPECT_NEAR(map.points(k, 0), first, 1e-9) << "point " << k;
  }
  const PoincareJitter jitter = CalcPoincareJitter(map.points);
  EXPECT_EQ(jitter.count, 37u);
  EXPECT_LT(jitter.total, 1e-7);  // round-off of θ and x: ~1e-11 per point
}

TEST(Poincare, InterpolationErrorIsSecondOrderInTheSamplePeriod) {
  // Linear interpolation at the crossing errs by ½ s(1−s) h² x''(θ) + O(h³) for a step h in θ.
  // With the crossing mid-way between samples (s = ½) the odd terms cancel: the error is
  // h² x''/8 + O(h⁴), so halving h quarters it and error·8/h² → x''(θ_index).
  const double index = 1.0;
  const double curvature = -300.0 * std::cos(index) - 320.0 * std::cos(2.0 * index + 0.3) -
                           1225.0 * std::sin(7.0 * index);  // x''(θ) of PeriodicAcceleration
  double previous = 0.0;
  for (std::size_t per_rev : {100u, 200u, 400u}) {
    const double h = kTwoPi / static_cast<double>(per_rev);
    std::vector<double> theta(5 * per_rev), x(5 * per_rev);
    for (std::size_t i = 0; i < theta.size(); ++i) {
      theta[i] = index + (static_cast<double>(i) - 0.5) * h;  // crossings at i = k·per_rev + ½
      x[i] = PeriodicAcceleration(theta[i]);
    }
    TimeSeries ts(static_cast<double>(per_rev), 0.0);  // 1 rev/s
    ts.AddChannel("crank_angle", "rad", theta);
    ts.AddChannel("slider_acceleration", "m/s^2", x);
    const PoincareMap map =
        CalcPoincareMap(ts, "crank_angle", index, {"slider_acceleration"}, ts.all());
    ASSERT_EQ(map.num_points(), 5u);
    const double error = map.points(2, 0) - PeriodicAcceleration(index);
    EXPECT_NEAR(error * 8.0 / (h * h), curvature, 0.02 * std::abs(curvature)) << per_rev;
    if (previous != 0.0) {
      EXPECT_NEAR(std::log2(previous / error), 2.0, 0.02) << per_rev << " samples per rev";
    }
    previous = error;
  }
}

TEST(PoincareJitter, IsZeroForAQuadraticTrend) {
  std::vector<double> p(25);
  for (std::size_t n = 0; n < p.size(); ++n) {
    const double m = static_cast<double>(n);
    p[n] = 2.0 + 0.5 * m - 0.3 * m * m;
  }
  const PoincareJitter j = CalcPoincareJitter(p);
  EXPECT_EQ(j.count, 22u);
  EXPECT_LT(j.total, 1e-12 * 0.3 * 24.0 * 24.0 * 22.0);
}

TEST(PoincareJitter, CubicTrendGivesSixTimesItsCoefficientPerPoint) {
  // Δ³(c n³) = 6c for every n (RIG.md §3 predictor: the quadratic misses the cubic term).
  const double c = 0.125;
  std::vector<double> p(10);
  for (std::size_t n = 0; n < p.size(); ++n) {
    const double m = static_cast<double>(n);
    p[n] = c * m * m * m - 4.0 * m * m + 1.0;
  }
  const PoincareJitter j = CalcPoincareJitter(p);
  EXPECT_EQ(j.count, 7u);
  EXPECT_NEAR(j.total, 6.0 * c * 7.0, 1e-12);
  EXPECT_NEAR(j.normalised, 6.0 * c, 1e-13);
}

TEST(PoincareJitter, TwoDimensionalPointsUseTheEuclideanDistance) {
  // x: cubic (Δ³ = 6a), y: cubic (Δ³ = 6b) ⇒ every residual has length 6·sqrt(a² + b²).
  const double a = 0.3, b = -0.4;
  Mat p(8, 2);
  for (Eigen::Index n = 0; n < 8; ++n) {
    const double m = static_cast<double>(n);
    p(n, 0) = a * m * m * m + m;
    p(n, 1) = b * m * m * m - 2.0 * m * m;
  }
  const PoincareJitter j = CalcPoincareJitter(p);
  EXPECT_EQ(j.count, 5u);
  EXPECT_NEAR(j.normalised, 6.0 * 0.5, 1e-12);
  // A single column gives the scalar result.
  const Vec x = p.col(0);
  EXPECT_NEAR(CalcPoincareJitter(Mat(p.col(0))).total,
              CalcPoincareJitter(std::span<const double>(x.data(), 8)).total, 1e-14);
  EXPECT_NEAR(CalcPoincareJitter(std::span<const double>(x.data(), 8)).normalised, 6.0 * a, 1e-12);
}

TEST(PoincareJitter, RandomPhaseSignalJittersFarMoreThanAPeriodicOne) {
  // Revolution r carries A sin(3θ + φ_r) with a random φ_r; the Poincaré section at θ = π
  // (mid-revolution, away from the phase jumps at θ = 0 mod 2π) samples −A sin(φ_r).
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> phase(0.0, kTwoPi);
  std::vector<double> phases(64);
  for (double& p : phases) p = phase(rng);
  const double amplitude = 50.0;
  const auto random_phase = [&](double theta) {
    const auto r = static_cast<std::size_t>(std::floor(theta / kTwoPi));
    return amplitude * std::sin(3.0 * theta + phases[r]);
  };
  const auto fixed_phase = [&](double theta) {
    return amplitude * std::sin(3.0 * theta + phases[0]);
  };
  const TimeSeries noisy = CrankRecord(1000.0, 30000, random_phase);
  const TimeSeries smooth = CrankRecord(1000.0, 30000, fixed_phase);
  const auto jitter_of = [](const TimeSeries& ts) {
    const PoincareMap map =
        CalcPoincareMap(ts, "crank_angle", kPi, {"slider_acceleration"}, ts.all());
    return CalcPoincareJitter(map.points);
  };
  const PoincareJitter j_noisy = jitter_of(noisy);
  const PoincareJitter j_smooth = jitter_of(smooth);
  EXPECT_EQ(j_noisy.count, 57u);  // 60 crossings of θ = π in 30 s at 2 rev/s
  EXPECT_GT(j_noisy.normalised, 0.5 * amplitude);
  EXPECT_LT(j_smooth.normalised, 1e-9 * amplitude);
}

TEST(PoincareJitter, NeedsFourPoints) {
  EXPECT_THROW(CalcPoincareJitter(std::vector<double>{1.0, 2.0, 3.0}), InputError);
  EXPECT_NO_THROW(CalcPoincareJitter(std::vector<double>{1.0, 2.0, 3.0, 4.0}));
}

// ---- inflection (turning) points --------------------------------------------------------------

struct Expected {
  std::size_t sample;
  double value;
};

void ExpectPoints(const std::vector<TurningPoint>& got, const std::vector<Expected>& want,
                  const char* what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t j = 0; j < want.size(); ++j) {
    EXPECT_EQ(got[j].sample, want[j].sample) << what << " #" << j;
    EXPECT_EQ(got[j].value, want[j].value) << what << " #" << j;
  }
}

TEST(InflectionPoints, HandBuiltSequenceGivesExactlyTheTurningPointsBeyondTheFloor) {
  //                               0   1   2   3   4   5   6   7   8   9  10  11   12   13
  const std::vector<double> x = {0, 25, 30, 25, 10, 50, 50, 40, 15, 21, 18, -5, -30, -22,
                                 //  14   15   16   17  18  19
                                 -40, -40, -19, -25, 0, 60};
  std::vector<double> theta(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) theta[i] = 0.5 * static_cast<double>(i);
  const double rate = 100.0, start = 1.0;
  const SampleRange all{0, x.size()};
  // Floor 20: maxima 30 (2), 50 (plateau 5–6, reported at 5), 21 (9); minima −30 (12),
  // −40 (plateau 14–15 at 14), −25 (17). −22 (13) and −19 (16) are local maxima below the
  // floor; 60 (19) is the last sample and 0 (0) the first.
  InflectionPoints p = FindInflectionPoints(x, theta, rate, start, all, 20.0);
  ExpectPoints(p.positive, {{2, 30}, {5, 50}, {9, 21}}, "positive, floor 20");
  ExpectPoints(p.negative, {{12, -30}, {14, -40}, {17, -25}}, "negative, floor 20");
  EXPECT_DOUBLE_EQ(p.positive[1].time, 1.05);
  EXPECT_DOUBLE_EQ(p.positive[1].crank_angle, 2.5);
  EXPECT_NEAR(p.negative[1].crank_angle, 7.0 - kTwoPi, 1e-15);  // wrapped into [0, 2π)
  // Raising the floor removes the points it covers, in each direction.
  p = FindInflectionPoints(x, theta, rate, start, all, 22.0);
  ExpectPoints(p.positive, {{2, 30}, {5, 50}}, "positive, floor 22");
  ExpectPoints(p.negative, {{12, -30}, {14, -40}, {17, -25}}, "negative, floor 22");
  p = FindInflectionPoints(x, theta, rate, start, all, 30.0);  // strict: 30 is not beyond 30
  ExpectPoints(p.positive, {{5, 50}}, "positive, floor 30");
  ExpectPoints(p.negative, {{14, -40}}, "negative, floor 30");
  // The default floor is the rig's 20 m/s² (thesis §5.3.6).
  EXPECT_EQ(FindInflectionPoints(x, theta, rate, start, all).positive.size(), 3u);
  // A sub-range sees only its own samples: sample 5 needs sample 4 as left neighbour.
  p = FindInflectionPoints(x, theta, rate, start, {5, 20}, 20.0);
  ExpectPoints(p.positive, {{9, 21}}, "positive, range [5, 20)");
}

TEST(InflectionPoints, StaircasePlateausAreNotTurningPoints) {
  const std::vector<double> x = {0, 30,  30,  40,  40,  50,  45,  45,  35,  35,
                                 0, -30, -30, -40, -40, -50, -45, -45, -35, 0};
  const std::vector<double> theta(x.size(), 0.0);
  const InflectionPoints p = FindInflectionPoints(x, theta, 1.0, 0.0, {0, x.size()}, 20.0);
  ExpectPoints(p.positive, {{5, 50}}, "positive");
  ExpectPoints(p.negative, {{15, -50}}, "negative");
}

TEST(InflectionPoints, SumOfCosinesHasItsAnalyticExtrema) {
  // x = 100 cos 2πt + 10 cos 4πt: x' = −200π sin 2πt (1 + 0.4 cos 2πt) vanishes only where
  // sin 2πt = 0, so the maxima are x = 110 at integer t and the minima x = −90 at half-integer
  // t. Sampled at 1 kHz from t = 0.1 s for 3 s, with the crank at 1 rev/s (θ = 2πt).
  const double rate = 1000.0, start = 0.1;
  std::vector<double> x(3000), theta(3000);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double t = start + static_cast<double>(i) / rate;
    x[i] = 100.0 * std::cos(kTwoPi * t) + 10.0 * std::cos(2.0 * kTwoPi * t);
    theta[i] = kTwoPi * t;
  }
  TimeSeries ts(rate, start);
  ts.AddChannel("slider_acceleration", "m/s^2", x);
  ts.AddChannel("crank_angle", "rad", theta);
  InflectionPoints p = FindInflectionPoints(ts, "slider_acceleration", "crank_angle", ts.all());
  ASSERT_EQ(p.positive.size(), 3u);
  ASSERT_EQ(p.negative.size(), 3u);
  for (std::size_t j = 0; j < 3; ++j) {
    EXPECT_EQ(p.positive[j].sample, 900u + 1000u * j);
    EXPECT_NEAR(p.positive[j].value, 110.0, 1e-9);
    EXPECT_NEAR(p.positive[j].time, 1.0 + static_cast<double>(j), 1e-12);
    const double a = p.positive[j].crank_angle;  // 0 or just below 2π
    EXPECT_LT(std::min(a, kTwoPi - a), 1e-9);
    EXPECT_EQ(p.negative[j].sample, 400u + 1000u * j);
    EXPECT_NEAR(p.negative[j].value, -90.0, 1e-9);
    EXPECT_NEAR(p.negative[j].crank_angle, kPi, 1e-9);
  }
  // A floor of 95 m/s² keeps the +110 maxima and removes the −90 minima.
  p = FindInflectionPoints(ts, "slider_acceleration", "crank_angle", ts.all(), 95.0);
  EXPECT_EQ(p.positive.size(), 3u);
  EXPECT_EQ(p.negative.size(), 0u);
  EXPECT_THROW(FindInflectionPoints(ts, "slider_acceleration", "crank_angle", ts.all(), -1.0),
               InputError);
}

// ---- statistics --------------------------------------------------------------------------------

TEST(Percentile, MatchesHandComputedType7Values) {
  // Sorted: 15 20 35 40 50. p40: h = 1.6 → 20 + 0.6·15 = 29; p95: h = 3.8 → 40 + 0.8·10 = 48.
  const std::vector<double> v = {50, 15, 40, 20, 35};
  EXPECT_DOUBLE_EQ(Percentile(v, 0.0), 15.0);
  EXPECT_DOUBLE_EQ(Percentile(v, 40.0), 29.0);
  EXPECT_DOUBLE_EQ(Percentile(v, 50.0), 35.0);
  EXPECT_DOUBLE_EQ(Percentile(v, 95.0), 48.0);
  EXPECT_DOUBLE_EQ(Percentile(v, 100.0), 50.0);
  EXPECT_DOUBLE_EQ(Percentile(std::vector<double>{4, 1, 3, 2}, 50.0), 2.5);  // even count
  EXPECT_DOUBLE_EQ(Percentile(std::vector<double>{7}, 95.0), 7.0);
  EXPECT_THROW(Percentile(std::vector<double>{}, 50.0), InputError);
  EXPECT_THROW(Percentile(v, 101.0), InputError);
}

TEST(Rms, OfASineOverWholePeriodsIsAmplitudeOverRootTwo) {
  std::vector<double> x(1000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = 3.0 * std::sin(kTwoPi * 5.0 * i / 1000.0 + 0.2);
  EXPECT_NEAR(Rms(x), 3.0 / std::sqrt(2.0), 1e-12);
}

TEST(SignalSummary, PerRevolutionPeaksIgnorePartialRevolutions) {
  // 100 samples per revolution, crossings at 31, 131, ..., 531 (see Revolutions test).
  std::vector<double> theta(560), x(560, 0.0);
  for (std::size_t i = 0; i < theta.size(); ++i) {
    theta[i] = kTwoPi * (static_cast<double>(i) - 30.5) / 100.0;
  }
  x[10] = 1000.0;  // in the leading partial revolution
  x[11] = -1000.0;
  x[545] = 7777.0;  // in the trailing partial revolution
  const double pos[5] = {10, 30, 20, 50, 40};
  const double neg[5] = {-5, -1, -4, -3, -2};
  for (std::size_t r = 0; r < 5; ++r) {
    x[31 + 100 * r + 7] = pos[r];
    x[31 + 100 * r + 50] = neg[r];
  }
  const SignalSummary s = CalcSignalSummary(x, theta, 0.0, {0, 560});
  EXPECT_EQ(s.peak_positive, 7777.0);  // whole-range peaks see everything
  EXPECT_EQ(s.peak_negative, 1000.0);
  EXPECT_EQ(s.positive.num_revolutions, 5u);
  EXPECT_DOUBLE_EQ(s.positive.median, 30.0);  // sorted 10 20 30 40 50
  EXPECT_DOUBLE_EQ(s.positive.p95, 48.0);     // h = 3.8
  EXPECT_DOUBLE_EQ(s.positive.max, 50.0);
  EXPECT_DOUBLE_EQ(s.negative.median, 3.0);  // magnitudes 1 2 3 4 5
  EXPECT_DOUBLE_EQ(s.negative.p95, 4.8);
  EXPECT_DOUBLE_EQ(s.negative.max, 5.0);
  EXPECT_DOUBLE_EQ(s.magnitude.median, 30.0);  // every revolution's larger peak is its positive one
  // A revolution whose negative peak is the larger: |x| peaks 10 60 20 50 40.
  std::vector<double> y = x;
  y[31 + 100 + 50] = -60.0;
  const SignalSummary m = CalcSignalSummary(y, theta, 0.0, {0, 560});
  EXPECT_DOUBLE_EQ(m.magnitude.median, 40.0);
  EXPECT_DOUBLE_EQ(m.magnitude.max, 60.0);
  EXPECT_DOUBLE_EQ(m.positive.median, 30.0);
  double sum_sq = 0.0;
  for (double v : x) sum_sq += v * v;
  EXPECT_NEAR(s.rms, std::sqrt(sum_sq / 560.0), 1e-12);
  // No complete revolution: statistics are NaN, not zero.
  const SignalSummary none = CalcSignalSummary(x, theta, 0.0, {40, 120});
  EXPECT_EQ(none.positive.num_revolutions, 0u);
  EXPECT_TRUE(std::isnan(none.positive.p95));
}

TEST(LoadAmplification, OfAScaledSignalEqualsTheScale) {
  const TimeSeries ideal = CrankRecord(1000.0, 10000, PeriodicAcceleration);
  const SampleRange window = FindCaptureWindow(ideal, "crank_angle", CaptureOptions{0.2, 4.0, 0.0});
  const SignalSummary s_ideal =
      CalcSignalSummary(ideal, "slider_acceleration", "crank_angle", 0.0, window);
  const std::span<const double> a = ideal.values("slider_acceleration");

  std::vector<double> scaled(a.begin(), a.end());
  for (double& v : scaled) v *= 3.7;
  const SignalSummary s_scaled =
      CalcSignalSummary(scaled, ideal.values("crank_angle"), 0.0, window);
  const LoadAmplification la = CalcLoadAmplification(s_scaled, s_ideal);
  EXPECT_NEAR(la.positive, 3.7, 1e-14);
  EXPECT_NEAR(la.negative, 3.7, 1e-14);
  EXPECT_NEAR(la.positive_p95, 3.7, 1e-14);
  EXPECT_NEAR(la.negative_p95, 3.7, 1e-14);

  // Different scales per direction come back in the right direction.
  std::vector<double> skewed(a.begin(), a.end());
  for (double& v : skewed) v *= (v > 0.0 ? 2.0 : 5.0);
  const LoadAmplification lb = CalcLoadAmplification(
      CalcSignalSummary(skewed, ideal.values("crank_angle"), 0.0, window), s_ideal);
  EXPECT_NEAR(lb.positive, 2.0, 1e-14);
  EXPECT_NEAR(lb.negative, 5.0, 1e-14);
  EXPECT_NEAR(lb.positive_p95, 2.0, 1e-14);
  EXPECT_NEAR(lb.negative_p95, 5.0, 1e-14);

  // An ideal record that never goes negative leaves the negative ratio undefined.
  std::vector<double> positive_only(a.size(), 1.0);
  const SignalSummary s_pos =
      CalcSignalSummary(positive_only, ideal.values("crank_angle"), 0.0, window);
  EXPECT_TRUE(std::isnan(CalcLoadAmplification(s_scaled, s_pos).negative));
}

}  // namespace
}  // namespace flexrod::study
