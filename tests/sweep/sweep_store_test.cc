// Tests of sweep/sweep_store.h on a synthetic record with known answers: a crank turning at
// 5 rev/s sampled at 1 kHz and a slider acceleration A cos θ whose ideal twin is A/2 cos θ, so
// the load amplification is exactly 2, the turning points sit at θ = 0 and π, the spectrum
// has amplitude A in the 5 Hz bin, and the Poincaré points repeat (jitter 0). Then the part
// file and store round trips (bit-identical, units and inputs as attributes, texts beyond
// HDF5's 64 KiB attribute limit), and that
// SameResults sees a one-ulp change.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "sweep/sweep_store.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "tests/test_util.h"

namespace flexrod::study {
namespace {

namespace fs = std::filesystem;
using flexrod::test::kPi;
using flexrod::test::ScratchDir;
constexpr double kRate = 1000.0;        // Hz
constexpr double kRevPerS = 5.0;        // crank speed [rev/s]
constexpr double kA = 100.0;            // m/s^2
constexpr std::size_t kSamples = 1000;  // 1 s: 5 revolutions, 200 samples each

Config RigConfig() {
  Config cfg;
  cfg.Set("rod.material", "steel");
  cfg.Set("rod.height", "12.7 mm");
  cfg.Set("drive.speed", "300 rpm");
  return cfg;
}

TimeSeries Record(double amplitude) {
  TimeSeries ts(kRate, 2.0);
  std::vector<double> theta(kSamples), acc(kSamples), speed(kSamples, 2.0 * kPi * kRevPerS);
  for (std::size_t i = 0; i < kSamples; ++i) {
    theta[i] = 2.0 * kPi * kRevPerS * static_cast<double>(i) / kRate;
    acc[i] = amplitude * std::cos(theta[i]);
  }
  ts.AddChannel("crank_angle", "rad", theta);
  ts.AddChannel("crank_speed", "rad/s", speed);
  ts.AddChannel("slider_acceleration", "m/s^2", acc);
  return ts;
}

RunResult SyntheticRun() {
  RunResult run;
  run.channels = Record(kA);
  TimeSeries ideal = Record(kA);
  for (double& v : ideal.mutable_values("slider_acceleration")) v *= 0.5;  // exact halving
  run.ideal = std::make_shared<const TimeSeries>(std::move(ideal));
  run.summary = {{"wall_time [s]", 0.25}};
  return run;
}

StoreOptions Options() {
  StoreOptions o;
  o.rate = 250.0;  // decimation 4
  o.spectrum_max = 100.0;
  return o;
}

TEST(SweepStore, AmplificationOfADoubledAccelerationIsExactlyTwo) {
  const StoredRun s = AnalyseRun(RigConfig(), SyntheticRun(), Options());
  EXPECT_TRUE(s.ok());
  EXPECT_DOUBLE_EQ(s.Summary("amplification_positive"), 2.0);
  EXPECT_DOUBLE_EQ(s.Summary("amplification_negative"), 2.0);
  EXPECT_NEAR(s.Summary("peak_positive"), kA, 1e-9);
  EXPECT_NEAR(s.Summary("peak_negative"), kA, 1e-9);
  EXPECT_NEAR(s.Summary("ideal_peak_negative"), kA / 2.0, 1e-9);
  EXPECT_NEAR(s.Summary("rms"), kA / std::sqrt(2.0), 1e-9);  // whole revolutions of a cosine
  EXPECT_TRUE(std::isnan(s.Summary("no_such_value")));
  EXPECT_DOUBLE_EQ(s.wall_time, 0.25);
}

TEST(SweepStore, TurningPointsSitAtZeroAndPiOfEveryRevolution) {
  const StoredRun s = AnalyseRun(RigConfig(), SyntheticRun(), Options());
  // Maxima at samples 200, 400, 600, 800 (sample 0 is an end point: never a turning point);
  // minima at 100, 300, ..., 900.
  ASSERT_EQ(s.positive.value.size(), 4u);
  ASSERT_EQ(s.negative.value.size(), 5u);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(s.positive.time[k], 2.0 + 0.2 * static_cast<double>(k + 1), 1e-12);
    EXPECT_NEAR(s.positive.value[k], kA, 1e-9);
    const double wrapped = s.positive.crank_angle[k];  // 2πk wraps to 0 or just below 2π
    EXPECT_NEAR(std::min(wrapped, 2.0 * kPi - wrapped), 0.0, 1e-9);
  }
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_NEAR(s.negative.crank_angle[k], kPi, 1e-9);
    EXPECT_NEAR(s.negative.value[k], -kA, 1e-9);
  }
  EXPECT_DOUBLE_EQ(s.Summary("num_inflection_negative"), 5.0);
}

TEST(SweepStore, SpectrumReadsTheAmplitudeInItsBinAndStopsAtTheStoredMaximum) {
  const StoredRun s = AnalyseRun(RigConfig(), SyntheticRun(), Options());
  EXPECT_EQ(s.spectrum_window, "flat-top");
  EXPECT_DOUBLE_EQ(s.spectrum_resolution, 1.0);  // 1000 samples at 1 kHz
  ASSERT_EQ(s.frequency.size(), 101u);           // bins 0..100 Hz
  EXPECT_DOUBLE_EQ(s.frequency[5], 5.0);
  EXPECT_NEAR(s.amplitude[5], kA, 1e-9 * kA);  // on-bin tone: exact for every window
  EXPECT_LT(s.amplitude[50], 1e-9 * kA);
}

TEST(SweepStore, PoincarePointsOfAPeriodicRecordRepeatWithZeroJitter) {
  const StoredRun s = AnalyseRun(RigConfig(), SyntheticRun(), Options());
  ASSERT_GE(s.poincare.size(), 2u);
  EXPECT_EQ(s.poincare[0].name, "time");
  ASSERT_EQ(s.poincare[0].values.size(), 5u);  // index crossings at samples 0, 200, ..., 800
  for (const StoredSeries& p : s.poincare) {
    if (p.name == "slider_acceleration") {
      for (double v : p.values) EXPECT_NEAR(v, kA, 1e-9);
    }
  }
  bool saw = false;
  for (const StoredScalar& j : s.poincare_jitter) {
    if (j.name == "jitter_slider_acceleration") {
      saw = true;
      EXPECT_NEAR(j.value, 0.0, 1e-9);
      EXPECT_EQ(j.unit, "m/s^2");
    }
  }
  EXPECT_TRUE(saw);
}

TEST(SweepStore, StoredChannelsAreTheRecordDecimatedToTheStoreRate) {
  const RunResult run = SyntheticRun();
  const StoredRun s = AnalyseRun(RigConfig(), run, Options());
  ASSERT_EQ(s.channels.size(), 2u);  // crank_angle, slider_acceleration (the default selection)
  EXPECT_DOUBLE_EQ(s.decimation, 4.0);
  EXPECT_DOUBLE_EQ(s.channel_rate, 250.0);
  EXPECT_DOUBLE_EQ(s.channel_start, 2.0);
  const auto full = run.channels.values("slider_acceleration");
  ASSERT_EQ(s.channels[1].values.size(), kSamples / 4);
  for (std::size_t i = 0; i < s.channels[1].values.size(); ++i)
    EXPECT_EQ(s.channels[1].values[i], full[4 * i]);
  EXPECT_EQ(s.channels[1].unit, "m/s^2");
}

TEST(SweepStore, AFailedRunKeepsItsMessageAndWhatItComputed) {
  RunResult run = SyntheticRun();
  run.status.outcome = multibody::SimulationOutcome::kIntegratorFailure;
  run.status.message = "corrector convergence failed";
  run.status.t_reached = 2.5;
  const StoredRun s = AnalyseRun(RigConfig(), run, Options());
  EXPECT_FALSE(s.ok());
  EXPECT_EQ(s.status, "integrator-failure");
  EXPECT_NE(s.message.find("corrector convergence failed"), std::string::npos);
  EXPECT_NE(s.message.find("t = 2.5 s"), std::string::npos);
  EXPECT_FALSE(s.channels.empty());
}

TEST(SweepStore, PartFileRoundTripIsBitIdenticalWithInputsAsAttributes) {
  const fs::path dir = ScratchDir("sweep_store_part");
  StoredRun s = AnalyseRun(RigConfig(), SyntheticRun(), Options());
  s.id = 7;
  s.label = "drive.speed=300 rpm";
  const std::string path = (dir / "part.h5").string();
  WritePartFile(path, s);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  const StoredRun back = ReadPartFile(path);
  std::string why;
  EXPECT_TRUE(SameResults(s, back, &why)) << why;
  EXPECT_EQ(back.id, 7);
  EXPECT_EQ(back.label, s.label);
  // The stored input reproduces the run's input (same fingerprint).
  EXPECT_EQ(RunFingerprint(back.Input(), Options()), s.fingerprint);
  EXPECT_EQ(back.Input().Text("drive.speed"), "300 rpm");
  // Units of every series.
  for (const StoredSeries& c : back.channels) EXPECT_FALSE(c.unit.empty()) << c.name;
  for (const StoredScalar& c : back.summary) EXPECT_FALSE(c.unit.empty()) << c.name;
  // Inputs as attributes: SI value and unit.
  {
    const h5::Node file = h5::OpenFile(path);
    EXPECT_DOUBLE_EQ(file.GetDouble("rod.height"), 12.7e-3);
    EXPECT_EQ(file.GetString("rod.height.unit"), "m");
    EXPECT_DOUBLE_EQ(file.GetDouble("drive.speed"), 300.0 * 2.0 * kPi / 60.0);
    EXPECT_EQ(file.GetString("drive.speed.unit"), "rad/s");
    EXPECT_EQ(file.GetString("rod.material"), "steel");
  }
  // Without channels, everything else still reads.
  const StoredRun light = ReadPartFile(path, false);
  EXPECT_TRUE(light.channels.empty());
  EXPECT_EQ(light.amplitude, s.amplitude);
  // A file that is not a part is refused.
  std::ofstream(dir / "junk.h5") << "not hdf5";
  EXPECT_THROW(ReadPartFile((dir / "junk.h5").string()), IoError);
  fs::remove_all(dir);
}

TEST(SweepStore, StoreRoundTripKeepsRunOrderAndCountsFailures) {
  const fs::path dir = ScratchDir("sweep_store_store");
  std::vector<StoredRun> runs;
  runs.push_back(AnalyseRun(RigConfig(), SyntheticRun(), Options()));
  // A message longer than an HDF5 object header (64 KiB) is stored in pieces and read back whole.
  const std::string long_message = "no convergence" + std::string(130000, '.') + "end";
  runs.push_back(FailedRun(RigConfig(), Options(), "numerical-error", long_message));
  for (int i = 0; i < 2; ++i) runs[i].id = i;
  StoreHeader header;
  header.name = "synthetic";
  header.matrix_source = "[sweep]\n" + std::string(70000, '#');
  header.axis_keys = {"drive.speed"};
  header.num_runs = 2;
  std::size_t next = 0;
  const std::string path = (dir / "s.h5").string();
  WriteStore(path, header, [&](StoredRun* r) {
    if (next >= runs.size()) return false;
    *r = runs[next++];
    return true;
  });
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  const SweepStore back = ReadStore(path);
  EXPECT_EQ(back.header.name, "synthetic");
  EXPECT_EQ(back.header.axis_keys, header.axis_keys);
  EXPECT_EQ(back.num_failed, 1);
  ASSERT_EQ(back.runs.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    std::string why;
    EXPECT_TRUE(SameResults(runs[i], back.runs[i], &why)) << i << ": " << why;
    EXPECT_EQ(back.runs[i].id, i);
  }
  EXPECT_EQ(back.runs[1].message, long_message);
  EXPECT_EQ(back.header.matrix_source, header.matrix_source);
  // Too few runs delivered: the store is not written.
  header.num_runs = 3;
  next = 0;
  EXPECT_THROW(WriteStore((dir / "short.h5").string(), header,
                          [&](StoredRun* r) {
                            if (next >= runs.size()) return false;
                            *r = runs[next++];
                            return true;
                          }),
               std::logic_error);
  EXPECT_FALSE(fs::exists(dir / "short.h5"));
  EXPECT_THROW(ReadStore((dir / "missing.h5").string()), InputError);
  fs::remove_all(dir);
}

TEST(SweepStore, SameResultsSeesAOneUlpChangeAndIgnoresTimings) {
  const StoredRun a = AnalyseRun(RigConfig(), SyntheticRun(), Options());
  StoredRun b = a;
  b.wall_time = 99.0;
  b.summary_json = "{}";
  EXPECT_TRUE(SameResults(a, b));
  b.channels[1].values[3] = std::nextafter(b.channels[1].values[3], 1e9);
  std::string why;
  EXPECT_FALSE(SameResults(a, b, &why));
  EXPECT_EQ(why, "channels");
}

}  // namespace
}  // namespace flexrod::study
