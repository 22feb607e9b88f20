// SPDX-License-Identifier: GPL-3.0-or-later
// The analysis of a run for the sweep store (AnalyseRun, FailedRun): the slider acceleration's
// peaks, per-revolution statistics and load amplification, its inflection points, the Poincaré
// section, the spectrum and the decimated channels. A record too short for a revolution gives
// NaN statistics and empty point sets; anything the analyses throw stops the run's analysis
// (ComputeSweepRun records it as failed, with the message).
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "common/error.h"
#include "signals/signals.h"
#include "sweep/sweep_store.h"

namespace flexrod::study {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kAcc = "slider_acceleration";
constexpr const char* kCrank = "crank_angle";

StoredRun Base(const Config& cfg, const StoreOptions& store) {
  StoredRun out;
  out.fingerprint = RunFingerprint(cfg, store);
  out.input_toml = InputToml(cfg);
  return out;
}

StoredPoints ToStored(const std::vector<TurningPoint>& points) {
  StoredPoints p;
  for (const TurningPoint& t : points) {
    p.time.push_back(t.time);
    p.crank_angle.push_back(t.crank_angle);
    p.value.push_back(t.value);
  }
  return p;
}

void Add(StoredRun* out, const std::string& name, double v, const std::string& unit) {
  out->summary.push_back({name, v, unit});
}

/// Peaks, per-revolution statistics and the load amplification over the ideal twin; a record
/// too short for a revolution gives NaNs.
void AddAccelerationSummary(const RunResult& run, double index_angle, StoredRun* out) {
  const TimeSeries& ts = run.channels;
  const SignalSummary s = CalcSignalSummary(ts, kAcc, kCrank, index_angle, ts.all());
  Add(out, "peak_positive", s.peak_positive, "m/s^2");
  Add(out, "peak_negative", s.peak_negative, "m/s^2");
  Add(out, "rms", s.rms, "m/s^2");
  Add(out, "revolutions", static_cast<double>(s.positive.num_revolutions), "1");
  Add(out, "positive_median", s.positive.median, "m/s^2");
  Add(out, "positive_p95", s.positive.p95, "m/s^2");
  Add(out, "positive_max", s.positive.max, "m/s^2");
  Add(out, "negative_median", s.negative.median, "m/s^2");
  Add(out, "negative_p95", s.negative.p95, "m/s^2");
  Add(out, "negative_max", s.negative.max, "m/s^2");
  LoadAmplification amp{kNaN, kNaN, kNaN, kNaN};
  double ideal_pos = kNaN, ideal_neg = kNaN;
  if (run.ideal && run.ideal->num_samples() == ts.num_samples() && run.ideal->HasChannel(kAcc)) {
    const SignalSummary i =
        CalcSignalSummary(*run.ideal, kAcc, kCrank, index_angle, run.ideal->all());
    amp = CalcLoadAmplification(s, i);
    ideal_pos = i.peak_positive;
    ideal_neg = i.peak_negative;
  }
  Add(out, "ideal_peak_positive", ideal_pos, "m/s^2");
  Add(out, "ideal_peak_negative", ideal_neg, "m/s^2");
  Add(out, "amplification_positive", amp.positive, "1");
  Add(out, "amplification_negative", amp.negative, "1");
  Add(out, "amplification_positive_p95", amp.positive_p95, "1");
  Add(out, "amplification_negative_p95", amp.negative_p95, "1");
  const auto& la = run.summary.contains("load_amplification") ? run.summary["load_amplification"]
                                                              : nlohmann::json();
  auto ratio = [&la](const char* key) {
    return la.is_object() && la.contains(key) && la[key].is_number() ? la[key].get<double>() : kNaN;
  };
  Add(out, "amplification_bearing_force", ratio("bearing_force"), "1");
  Add(out, "amplification_bearing_force_p95", ratio("bearing_force_p95"), "1");
  // The gauge stress's per-revolution peaks (the run's largest |stress| over its gauges).
  Add(out, "gauge_stress_p95",
      run.gauge_stress_peaks.empty() ? kNaN : Percentile(run.gauge_stress_peaks, 95.0), "Pa");
}

/// The Poincaré section at the crank index of store.poincare_channels, with each channel's
/// jitter (NaN below 4 points).
void AddPoincare(const TimeSeries& ts, double index_angle, const StoreOptions& store,
                 StoredRun* out) {
  std::vector<std::string> names;
  for (const std::string& c : store.poincare_channels) {
    if (ts.HasChannel(c)) names.push_back(c);
  }
  const PoincareMap map = CalcPoincareMap(ts, kCrank, index_angle, names, ts.all());
  out->poincare.push_back({"time", "s", map.time});
  for (std::size_t c = 0; c < names.size(); ++c) {
    const Vec col = map.points.col(static_cast<Eigen::Index>(c));
    out->poincare.push_back(
        {names[c], map.units[c], std::vector<double>(col.data(), col.data() + col.size())});
    PoincareJitter j{kNaN, kNaN, 0};
    if (map.num_points() >= 4)
      j = CalcPoincareJitter(std::span<const double>(col.data(), col.size()));
    out->poincare_jitter.push_back({"jitter_" + names[c], j.total, map.units[c]});
    out->poincare_jitter.push_back({"jitter_normalised_" + names[c], j.normalised, map.units[c]});
  }
}

/// The slider acceleration's amplitude spectrum up to store.spectrum_max.
void AddSpectrum(const TimeSeries& ts, const StoreOptions& store, StoredRun* out) {
  const Spectrum sp = CalcAmplitudeSpectrum(ts, kAcc, ts.all(), store.spectrum_window);
  out->spectrum_channel = kAcc;
  out->spectrum_window = ToString(sp.window);
  out->spectrum_resolution = sp.resolution;
  out->spectrum_num_samples = static_cast<double>(sp.num_samples);
  out->amplitude_unit = ts.channel(kAcc).unit;
  for (std::size_t k = 0; k < sp.num_bins() && sp.frequency[k] <= store.spectrum_max; ++k) {
    out->frequency.push_back(sp.frequency[k]);
    out->amplitude.push_back(sp.amplitude[k]);
  }
}

/// store.channels, decimated to store.rate (plain subsampling: the analyses used every sample).
void AddStoredChannels(const TimeSeries& ts, const StoreOptions& store, StoredRun* out) {
  const double rate = ts.sample_rate();
  const std::size_t decimation =
      store.rate < rate ? static_cast<std::size_t>(std::lround(rate / store.rate)) : 1;
  out->decimation = static_cast<double>(decimation);
  out->channel_rate = rate / static_cast<double>(decimation);
  out->channel_start = ts.start_time();
  for (const std::string& name : store.channels) {
    if (!ts.HasChannel(name)) continue;
    const Channel& c = ts.channel(name);
    StoredSeries s{c.name, c.unit, {}};
    s.values.reserve(c.values.size() / decimation + 1);
    for (std::size_t i = 0; i < c.values.size(); i += decimation) s.values.push_back(c.values[i]);
    out->channels.push_back(std::move(s));
  }
}

}  // namespace

StoredRun FailedRun(const Config& cfg, const StoreOptions& store, const std::string& status,
                    const std::string& message) {
  StoredRun out = Base(cfg, store);
  out.status = status;
  out.message = message;
  out.summary_json = "{}";
  return out;
}

StoredRun AnalyseRun(const Config& cfg, const RunResult& run, const StoreOptions& store) {
  StoredRun out = Base(cfg, store);
  out.status = run.ok() ? "completed" : multibody::ToString(run.status.outcome);
  if (!run.ok()) {
    out.message = "t = " + FormatValue(run.status.t_reached) + " s: " + run.status.message;
    if (!run.status.hint.empty()) out.message += " (hint: " + run.status.hint + ")";
  }
  out.summary_json = run.summary.dump();
  if (run.summary.contains("wall_time [s]") && run.summary["wall_time [s]"].is_number()) {
    out.wall_time = run.summary["wall_time [s]"].get<double>();
  }
  const TimeSeries& ts = run.channels;
  const double index_angle = cfg.Quantity("sim.index_angle");
  Add(&out, "num_samples", static_cast<double>(ts.num_samples()), "1");
  if (ts.num_samples() >= 3 && ts.HasChannel(kAcc) && ts.HasChannel(kCrank)) {
    AddAccelerationSummary(run, index_angle, &out);
    const InflectionPoints p =
        FindInflectionPoints(ts, kAcc, kCrank, ts.all(), store.inflection_floor);
    out.positive = ToStored(p.positive);
    out.negative = ToStored(p.negative);
    Add(&out, "num_inflection_positive", static_cast<double>(out.positive.time.size()), "1");
    Add(&out, "num_inflection_negative", static_cast<double>(out.negative.time.size()), "1");
    Add(&out, "inflection_floor", store.inflection_floor, "m/s^2");
    AddPoincare(ts, index_angle, store, &out);
    AddSpectrum(ts, store, &out);
  }
  if (ts.num_samples() > 0) AddStoredChannels(ts, store, &out);
  return out;
}

}  // namespace flexrod::study
