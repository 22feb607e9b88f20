// SPDX-License-Identifier: GPL-3.0-or-later
#include "signals/signals.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/error.h"
#include "common/units.h"

namespace flexrod::study {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Number of the revolution the crank is in: floor((θ − index) / 2π). Crossing of level L_k
// ⇔ this number reaches k.
double RevolutionNumber(double angle, double index_angle) {
  return std::floor((angle - index_angle) / kTwoPi);
}

// x[i − 1]; before the first sample, the record's linear extension x[−1] = 2x[0] − x[1]
// (x.size() >= 2).
double ValueBefore(std::span<const double> x, std::size_t i) {
  return i > 0 ? x[i - 1] : 2.0 * x[0] - x[1];
}

// Calls f(IndexCrossing) for every crossing whose sample lies in [first, last), in time order,
// until f returns false. Sample 0 has no predecessor: the record is extended linearly,
// θ[−1] = 2θ[0] − θ[1], so a record that starts on the index (a triggered capture: θ[0] = L up
// to round-off) has its crossing at sample 0 whichever side of L the round-off puts θ[0].
template <typename F>
void ScanCrossings(std::span<const double> crank_angle, double index_angle, double sample_rate,
                   double start_time, std::size_t first, std::size_t last, F f) {
  last = std::min(last, crank_angle.size());
  if (crank_angle.size() < 2) first = std::max<std::size_t>(first, 1);
  if (first >= last) return;
  double prev_rev = RevolutionNumber(ValueBefore(crank_angle, first), index_angle);
  for (std::size_t i = first; i < last; ++i) {
    const double rev = RevolutionNumber(crank_angle[i], index_angle);
    for (double k = prev_rev + 1.0; k <= rev; k += 1.0) {
      const double level = index_angle + kTwoPi * k;
      const double a = ValueBefore(crank_angle, i);
      const double b = crank_angle[i];
      // a < level ≤ b in exact arithmetic; clamp round-off of the quotient into (0, 1].
      double s = (level - a) / (b - a);
      s = std::clamp(s, std::numeric_limits<double>::min(), 1.0);
      const IndexCrossing c{i, s, start_time + (static_cast<double>(i) - 1.0 + s) / sample_rate};
      if (!f(c)) return;
    }
    prev_rev = rev;
  }
}

void RequireSameLength(std::size_t a, std::size_t b, const std::string& what) {
  if (a != b) {
    throw InputError(what, std::to_string(a) + " vs " + std::to_string(b) + " samples",
                     "the signal and the crank angle must have the same length");
  }
}

PeakStatistics StatisticsOf(std::vector<double>* peaks) {
  PeakStatistics s;
  s.num_revolutions = peaks->size();
  if (peaks->empty()) {
    s.median = s.p95 = s.max = kNaN;
    return s;
  }
  std::sort(peaks->begin(), peaks->end());
  s.median = PercentileOfSorted(*peaks, 50.0);
  s.p95 = PercentileOfSorted(*peaks, 95.0);
  s.max = peaks->back();
  return s;
}

double Ratio(double real, double ideal) { return ideal == 0.0 ? kNaN : real / ideal; }

}  // namespace

std::vector<IndexCrossing> FindIndexCrossings(std::span<const double> crank_angle,
                                              double index_angle, double sample_rate,
                                              double start_time, SampleRange range) {
  ValidateRange("crossings.range", range, crank_angle.size());
  std::vector<IndexCrossing> out;
  ScanCrossings(crank_angle, index_angle, sample_rate, start_time, range.begin, range.end,
                [&out](const IndexCrossing& c) {
                  out.push_back(c);
                  return true;
                });
  return out;
}

std::vector<SampleRange> SplitRevolutions(std::span<const double> crank_angle, double index_angle,
                                          SampleRange range) {
  ValidateRange("revolutions.range", range, crank_angle.size());
  std::vector<SampleRange> revolutions;
  std::size_t previous = 0;
  bool have_previous = false;
  // Crossing samples in [begin, end]: a crossing at sample `end` closes the last revolution.
  // Rates and times do not matter here.
  ScanCrossings(crank_angle, index_angle, 1.0, 0.0, range.begin, range.end + 1,
                [&](const IndexCrossing& c) {
                  if (have_previous && c.sample != previous) {
                    revolutions.push_back({previous, c.sample});
                  }
                  previous = c.sample;
                  have_previous = true;
                  return true;
                });
  return revolutions;
}

void CaptureOptions::Validate() const {
  Require(std::isfinite(settling_time) && settling_time >= 0.0, "capture.settling_time",
          settling_time, "must be finite and >= 0 [s]");
  Require(std::isfinite(duration) && duration > 0.0, "capture.duration", duration,
          "must be finite and > 0 [s]");
  Require(std::isfinite(index_angle), "capture.index_angle", index_angle, "must be finite [rad]");
}

SampleRange FindCaptureWindow(std::span<const double> crank_angle, double sample_rate,
                              double start_time, const CaptureOptions& options) {
  options.Validate();
  Require(std::isfinite(sample_rate) && sample_rate > 0.0, "sample_rate", sample_rate,
          "must be finite and > 0 [Hz]");
  const double count_real = std::round(options.duration * sample_rate);
  Require(count_real >= 1.0, "capture.duration", options.duration,
          "must hold at least one sample at " + FormatValue(sample_rate) + " Hz");
  // No crossing belonging to a sample before floor(settling · rate) can be at or after the
  // settling time; start the scan there and test each crossing's instant.
  const auto first = static_cast<std::size_t>(std::min(
      std::floor(options.settling_time * sample_rate), static_cast<double>(crank_angle.size())));
  bool found = false;
  IndexCrossing trigger;
  ScanCrossings(crank_angle, options.index_angle, sample_rate, start_time, first,
                crank_angle.size(), [&](const IndexCrossing& c) {
                  const double since_start =
                      (static_cast<double>(c.sample) - 1.0 + c.fraction) / sample_rate;
                  // (a crossing on the settling instant up to round-off of θ counts)
                  if (since_start < options.settling_time - 1e-9 / sample_rate) return true;
                  trigger = c;
                  found = true;
                  return false;
                });
  if (!found) {
    throw InputError(
        "capture.settling_time", FormatValue(options.settling_time) + " s",
        "the crank does not pass the index angle " + FormatValue(options.index_angle) +
            " rad after it (record ends at " +
            FormatValue(start_time + static_cast<double>(crank_angle.size()) / sample_rate) +
            " s)");
  }
  const auto remaining = static_cast<double>(crank_angle.size() - trigger.sample);
  if (count_real > remaining) {  // compared as doubles: count_real may exceed size_t
    throw InputError("capture.duration", FormatValue(options.duration) + " s",
                     "the record holds only " + FormatValue(remaining / sample_rate) +
                         " s after the trigger at t = " + FormatValue(trigger.time) + " s");
  }
  return {trigger.sample, trigger.sample + static_cast<std::size_t>(count_real)};
}

SampleRange FindCaptureWindow(const TimeSeries& series, std::string_view crank_channel,
                              const CaptureOptions& options) {
  return FindCaptureWindow(series.values(crank_channel), series.sample_rate(), series.start_time(),
                           options);
}

void InterpolateAtCrossings(std::span<const double> x, std::span<const IndexCrossing> crossings,
                            std::span<double> out) {
  FLEXROD_ASSERT(out.size() == crossings.size());
  for (std::size_t j = 0; j < crossings.size(); ++j) {
    const IndexCrossing& c = crossings[j];
    FLEXROD_ASSERT(c.sample < x.size() && x.size() >= 2);
    out[j] = (1.0 - c.fraction) * ValueBefore(x, c.sample) + c.fraction * x[c.sample];
  }
}

PoincareMap CalcPoincareMap(const TimeSeries& series, std::string_view crank_channel,
                            double index_angle, const std::vector<std::string>& channels,
                            SampleRange range) {
  const std::vector<IndexCrossing> crossings = FindIndexCrossings(
      series.values(crank_channel), index_angle, series.sample_rate(), series.start_time(), range);
  PoincareMap map;
  map.time.reserve(crossings.size());
  for (const IndexCrossing& c : crossings) map.time.push_back(c.time);
  map.points.resize(static_cast<Eigen::Index>(crossings.size()),
                    static_cast<Eigen::Index>(channels.size()));
  for (std::size_t col = 0; col < channels.size(); ++col) {
    const Channel& ch = series.channel(channels[col]);
    map.channels.push_back(ch.name);
    map.units.push_back(ch.unit);
    InterpolateAtCrossings(
        ch.values, crossings,
        std::span<double>(map.points.col(static_cast<Eigen::Index>(col)).data(), crossings.size()));
  }
  return map;
}

PoincareJitter CalcPoincareJitter(std::span<const double> points) {
  Require(points.size() >= 4, "poincare.points", static_cast<double>(points.size()),
          "jitter needs at least 4 Poincaré points");
  PoincareJitter j;
  for (std::size_t n = 0; n + 3 < points.size(); ++n) {
    j.total += std::abs(points[n + 3] - 3.0 * points[n + 2] + 3.0 * points[n + 1] - points[n]);
  }
  j.count = points.size() - 3;
  j.normalised = j.total / static_cast<double>(j.count);
  return j;
}

PoincareJitter CalcPoincareJitter(const Eigen::Ref<const Mat>& points) {
  const Eigen::Index num = points.rows();
  Require(num >= 4, "poincare.points", static_cast<double>(num),
          "jitter needs at least 4 Poincaré points");
  PoincareJitter j;
  for (Eigen::Index n = 0; n + 3 < num; ++n) {
    j.total +=
        (points.row(n + 3) - 3.0 * points.row(n + 2) + 3.0 * points.row(n + 1) - points.row(n))
            .norm();
  }
  j.count = static_cast<std::size_t>(num - 3);
  j.normalised = j.total / static_cast<double>(j.count);
  return j;
}

InflectionPoints FindInflectionPoints(std::span<const double> x,
                                      std::span<const double> crank_angle, double sample_rate,
                                      double start_time, SampleRange range, double floor) {
  RequireSameLength(x.size(), crank_angle.size(), "inflection.samples");
  ValidateRange("inflection.range", range, x.size());
  Require(std::isfinite(floor) && floor >= 0.0, "inflection.floor", floor,
          "must be finite and >= 0");
  const std::span<const double> window = x.subspan(range.begin, range.size());
  InflectionPoints out;
  out.floor = floor;
  std::vector<std::size_t> found;
  const auto store = [&](std::vector<TurningPoint>* dest) {
    dest->reserve(found.size());
    for (std::size_t local : found) {
      const std::size_t i = range.begin + local;
      dest->push_back(TurningPoint{i, start_time + static_cast<double>(i) / sample_rate,
                                   WrapToTwoPi(crank_angle[i]), x[i]});
    }
  };
  FindLocalMaxima(window, floor, &found);
  store(&out.positive);
  FindLocalMinima(window, -floor, &found);
  store(&out.negative);
  return out;
}

InflectionPoints FindInflectionPoints(const TimeSeries& series, std::string_view channel,
                                      std::string_view crank_channel, SampleRange range,
                                      double floor) {
  return FindInflectionPoints(series.values(channel), series.values(crank_channel),
                              series.sample_rate(), series.start_time(), range, floor);
}

double PercentileOfSorted(std::span<const double> sorted, double percent) {
  if (sorted.empty()) throw InputError("percentile.values", "0 values", "needs at least 1 value");
  Require(percent >= 0.0 && percent <= 100.0, "percentile", percent, "must lie in [0, 100]");
  FLEXROD_ASSERT(std::is_sorted(sorted.begin(), sorted.end()));
  const double h = static_cast<double>(sorted.size() - 1) * percent / 100.0;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  if (lo + 1 >= sorted.size()) return sorted.back();
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[lo + 1] - sorted[lo]);
}

double Percentile(std::span<const double> values, double percent) {
  std::vector<double> sorted(values.begin(), values.end());
  std::sort(sorted.begin(), sorted.end());
  return PercentileOfSorted(sorted, percent);
}

double Rms(std::span<const double> x) {
  if (x.empty()) throw InputError("rms.samples", "0 samples", "needs at least 1 sample");
  double sum_sq = 0.0;
  for (double v : x) sum_sq += v * v;
  return std::sqrt(sum_sq / static_cast<double>(x.size()));
}

SignalSummary CalcSignalSummary(std::span<const double> x, std::span<const double> crank_angle,
                                double index_angle, SampleRange range) {
  RequireSameLength(x.size(), crank_angle.size(), "summary.samples");
  ValidateRange("summary.range", range, x.size());
  return CalcSignalSummary(x, range, SplitRevolutions(crank_angle, index_angle, range));
}

SignalSummary CalcSignalSummary(std::span<const double> x, SampleRange range,
                                std::span<const SampleRange> revolutions) {
  ValidateRange("summary.range", range, x.size());
  SignalSummary s;
  const auto peaks_of = [&x](SampleRange r, double* pos, double* neg) {
    *pos = 0.0;
    *neg = 0.0;
    for (std::size_t i = r.begin; i < r.end; ++i) {
      *pos = std::max(*pos, x[i]);
      *neg = std::max(*neg, -x[i]);
    }
  };
  peaks_of(range, &s.peak_positive, &s.peak_negative);
  s.rms = Rms(x.subspan(range.begin, range.size()));
  std::vector<double> pos(revolutions.size()), neg(revolutions.size()), mag(revolutions.size());
  for (std::size_t k = 0; k < revolutions.size(); ++k) {
    ValidateRange("summary.revolutions", revolutions[k], x.size());
    peaks_of(revolutions[k], &pos[k], &neg[k]);
    mag[k] = std::max(pos[k], neg[k]);
  }
  s.positive_peaks = pos;
  s.negative_peaks = neg;
  s.magnitude = StatisticsOf(&mag);
  s.positive = StatisticsOf(&pos);
  s.negative = StatisticsOf(&neg);
  return s;
}

SignalSummary CalcSignalSummary(const TimeSeries& series, std::string_view channel,
                                std::string_view crank_channel, double index_angle,
                                SampleRange range) {
  return CalcSignalSummary(series.values(channel), series.values(crank_channel), index_angle,
                           range);
}

LoadAmplification CalcLoadAmplification(const SignalSummary& real, const SignalSummary& ideal) {
  return LoadAmplification{Ratio(real.peak_positive, ideal.peak_positive),
                           Ratio(real.peak_negative, ideal.peak_negative),
                           Ratio(real.positive.p95, ideal.positive.p95),
                           Ratio(real.negative.p95, ideal.negative.p95)};
}

}  // namespace flexrod::study
