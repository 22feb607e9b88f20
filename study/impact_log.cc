// study/impact_log.cc — contact events recovered from the sampled channels (see impact_log.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "study/impact_log.h"

#include <algorithm>
#include <cstdio>
#include <span>
#include <stdexcept>

#include "common/error.h"
#include "common/files.h"
#include "study/signals.h"

namespace flexrod::study {
namespace {

double Lerp(double a, double b, double s) { return a + s * (b - a); }

}  // namespace

std::vector<Impact> FindImpacts(const TimeSeries& series, const ImpactLogChannels& channels) {
  const std::span<const double> d = series.values(channels.penetration);
  const std::span<const double> f = series.values(channels.normal_force);
  const std::span<const double> rate = series.values(channels.penetration_rate);
  const bool has_angle = series.HasChannel(channels.crank_angle);
  const bool has_dissipation = series.HasChannel(channels.dissipation);
  const std::span<const double> angle =
      has_angle ? series.values(channels.crank_angle) : std::span<const double>();
  const std::span<const double> dissipation =
      has_dissipation ? series.values(channels.dissipation) : std::span<const double>();
  const std::size_t n = series.num_samples();
  const double dt = series.sample_period();
  // Power removed by the contact at sample i [W].
  auto power = [&](std::size_t i) { return has_dissipation ? dissipation[i] : f[i] * rate[i]; };

  std::vector<Impact> out;
  std::size_t i = 0;
  while (i < n) {
    if (!(d[i] > 0.0)) {
      ++i;
      continue;
    }
    const std::size_t a = i;
    while (i < n && d[i] > 0.0) ++i;
    const std::size_t b = i;  // contact samples [a, b)
    Impact im;
    im.first_sample = a;
    im.end_sample = b;
    im.complete = a > 0 && b < n;

    // Onset: δ crosses 0 between samples a−1 and a.
    double power_on = power(a);
    if (a > 0) {
      const double s = -d[a - 1] / (d[a] - d[a - 1]);
      im.time = series.time(a - 1) + s * dt;
      im.approach_velocity = Lerp(rate[a - 1], rate[a], s);
      if (has_angle) im.crank_angle = WrapToTwoPi(Lerp(angle[a - 1], angle[a], s));
      power_on = Lerp(power(a - 1), power(a), s);
    } else {
      im.time = series.time(0);
      im.approach_velocity = rate[0];
      if (has_angle) im.crank_angle = WrapToTwoPi(angle[0]);
    }
    // Exit: δ crosses 0 between samples b−1 and b.
    double t_exit = series.time(b - 1), power_exit = power(b - 1);
    if (b < n) {
      const double s = d[b - 1] / (d[b - 1] - d[b]);
      t_exit = series.time(b - 1) + s * dt;
      power_exit = Lerp(power(b - 1), power(b), s);
    }
    im.duration = t_exit - im.time;

    for (std::size_t k = a; k < b; ++k) {
      if (f[k] > im.peak_force) {
        im.peak_force = f[k];
        im.time_of_peak_force = series.time(k);
      }
      im.peak_penetration = std::max(im.peak_penetration, d[k]);
    }
    // Trapezoidal rule over (t_on, samples a..b−1, t_exit).
    double energy = 0.5 * (power_on + power(a)) * (series.time(a) - im.time);
    for (std::size_t k = a + 1; k < b; ++k) energy += 0.5 * (power(k - 1) + power(k)) * dt;
    energy += 0.5 * (power(b - 1) + power_exit) * (t_exit - series.time(b - 1));
    im.dissipated_energy = energy;
    out.push_back(im);
  }
  return out;
}

ImpactStatistics CalcImpactStatistics(const std::vector<Impact>& impacts) {
  ImpactStatistics s;
  std::vector<double> peaks;
  double duration = 0.0;
  for (const Impact& im : impacts) {
    if (!im.complete) {
      ++s.incomplete;
      continue;
    }
    ++s.count;
    peaks.push_back(im.peak_force);
    s.max_peak_force = std::max(s.max_peak_force, im.peak_force);
    s.max_approach_velocity = std::max(s.max_approach_velocity, im.approach_velocity);
    s.max_peak_penetration = std::max(s.max_peak_penetration, im.peak_penetration);
    duration += im.duration;
    s.total_dissipated_energy += im.dissipated_energy;
  }
  if (s.count > 0) {
    s.median_peak_force = Percentile(peaks, 50.0);
    s.mean_duration = duration / static_cast<double>(s.count);
  }
  return s;
}

void WriteImpactCsv(const std::vector<Impact>& impacts, const std::string& path) {
  std::string text =
      "time [s],crank_angle [rad],approach_velocity [m/s],peak_force [N],time_of_peak_force "
      "[s],duration [s],peak_penetration [m],dissipated_energy [J],complete [1]\n";
  char row[512];
  for (const Impact& im : impacts) {
    std::snprintf(row, sizeof(row), "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d\n",
                  im.time, im.crank_angle, im.approach_velocity, im.peak_force,
                  im.time_of_peak_force, im.duration, im.peak_penetration,
                  im.dissipated_energy, im.complete ? 1 : 0);
    text += row;
  }
  try {
    WriteFileAtomic(path, text);
  } catch (const std::runtime_error& e) {
    throw InputError("csv", path, e.what());
  }
}

}  // namespace flexrod::study
