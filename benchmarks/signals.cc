// Benchmarks of the signal analysis (signals/signals.h) on a rig-sized record: 3 s at 100 kHz
// (300 000 samples, RIG.md Table 2) of a slider-crank-like acceleration with impact ringing.
// Measures only; correctness lives in tests/signals/signals_*_test.cc.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "signals/signals.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace flexrod::study {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr std::size_t kRigSamples = 300000;

// 200 rpm crank; 2nd-order slider acceleration plus a decaying 900 Hz ring once per revolution.
TimeSeries RigRecord() {
  const double omega = 200.0 * kTwoPi / 60.0;  // rad/s
  std::vector<double> theta(kRigSamples), accel(kRigSamples);
  for (std::size_t i = 0; i < kRigSamples; ++i) {
    const double t = static_cast<double>(i) / kRigSampleRate;
    theta[i] = omega * t;
    const double since_impact = std::fmod(theta[i], kTwoPi) / omega;
    accel[i] = 0.03 * omega * omega * (std::cos(theta[i]) + 0.2 * std::cos(2.0 * theta[i])) +
               400.0 * std::exp(-60.0 * since_impact) * std::sin(kTwoPi * 900.0 * since_impact);
  }
  TimeSeries ts(kRigSampleRate, 0.0);
  ts.AddChannel("crank_angle", "rad", std::move(theta));
  ts.AddChannel("slider_acceleration", "m/s^2", std::move(accel));
  return ts;
}

const TimeSeries& Record() {
  static const TimeSeries record = RigRecord();
  return record;
}

void SpectrumLoop(benchmark::State& state, std::span<const double> x) {
  SpectrumAnalyzer analyzer(x.size(), kRigSampleRate, Window::kFlatTop);
  Spectrum spectrum;
  for (auto _ : state) {
    analyzer.Calc(x, &spectrum);
    benchmark::DoNotOptimize(spectrum.amplitude.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(x.size()));
}

void BM_SpectrumFlatTop300k(benchmark::State& state) {
  SpectrumLoop(state, Record().values("slider_acceleration"));
}
BENCHMARK(BM_SpectrumFlatTop300k)->Unit(benchmark::kMillisecond);

// Record lengths with a prime factor above GSL's radices take Bluestein's transform: 33 898 =
// 2 · 17 · 997 (a 3.3898 s capture at 10 kHz), 299 999 = 7 · 17 · 2521.
void BM_SpectrumFlatTopLargePrimeFactor(benchmark::State& state) {
  SpectrumLoop(
      state,
      Record().values("slider_acceleration").first(static_cast<std::size_t>(state.range(0))));
}
BENCHMARK(BM_SpectrumFlatTopLargePrimeFactor)
    ->Arg(33898)
    ->Arg(299999)
    ->Unit(benchmark::kMillisecond);

void BM_InflectionPoints300k(benchmark::State& state) {
  const TimeSeries& ts = Record();
  for (auto _ : state) {
    InflectionPoints p = FindInflectionPoints(ts, "slider_acceleration", "crank_angle", ts.all());
    benchmark::DoNotOptimize(p.positive.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(ts.num_samples()));
}
BENCHMARK(BM_InflectionPoints300k)->Unit(benchmark::kMillisecond);

void BM_PoincareMapAndJitter300k(benchmark::State& state) {
  const TimeSeries& ts = Record();
  for (auto _ : state) {
    const PoincareMap map =
        CalcPoincareMap(ts, "crank_angle", 0.0, {"slider_acceleration"}, ts.all());
    benchmark::DoNotOptimize(CalcPoincareJitter(map.points).total);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(ts.num_samples()));
}
BENCHMARK(BM_PoincareMapAndJitter300k)->Unit(benchmark::kMillisecond);

void BM_SignalSummary300k(benchmark::State& state) {
  const TimeSeries& ts = Record();
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        CalcSignalSummary(ts, "slider_acceleration", "crank_angle", 0.0, ts.all()).positive.p95);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(ts.num_samples()));
}
BENCHMARK(BM_SignalSummary300k)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace flexrod::study

BENCHMARK_MAIN();
