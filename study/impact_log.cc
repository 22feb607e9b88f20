// study/impact_log.cc — the impact log built from the located contact events (see impact_log.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "study/impact_log.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "common/error.h"
#include "common/files.h"
#include "common/units.h"
#include "study/signals.h"

namespace flexrod::study {

ContactPoint MakeContactPoint(double time, double crank_angle,
                              const multibody::ClearanceResponse& r) {
  ContactPoint p;
  p.time = time;
  p.crank_angle = crank_angle;
  p.contact = r.contact_flag;
  p.onsets = r.onsets;
  p.onset_time = r.onset_time;
  p.penetration = r.kinematics.penetration;
  p.penetration_rate = r.kinematics.penetration_rate;
  p.normal_force = r.normal_force;
  p.dissipation = r.dissipation();
  return p;
}

void ImpactLogger::Observe(const ContactPoint& p) {
  if (!started_ || p.onsets != onsets_seen_) {
    // The first point, or the point of a located onset (the joint's count moved).
    if (is_open_) Close(last_.time, false);  // its separation was not offered
    if (p.contact) {
      open_ = Impact{};
      open_.complete = started_;
      open_.time = started_ ? p.onset_time : p.time;
      open_.crank_angle = WrapToTwoPi(p.crank_angle);
      open_.approach_velocity = p.penetration_rate;
      // Zero at the onset's own point; the onset's share if only later points are offered.
      open_.dissipated_energy = 0.5 * p.dissipation * (p.time - open_.time);
      is_open_ = true;
    }
    started_ = true;
    onsets_seen_ = p.onsets;
  } else if (is_open_) {
    open_.dissipated_energy += 0.5 * (last_.dissipation + p.dissipation) * (p.time - last_.time);
  }
  if (is_open_) {
    if (p.normal_force > open_.peak_force) {
      open_.peak_force = p.normal_force;
      open_.time_of_peak_force = p.time;
    }
    open_.peak_penetration = std::max(open_.peak_penetration, p.penetration);
    if (!p.contact) Close(p.time, open_.complete);  // the located separation
  }
  last_ = p;
}

void ImpactLogger::Close(double t, bool complete) {
  open_.duration = t - open_.time;
  open_.complete = complete;
  log_.push_back(open_);
  is_open_ = false;
}

std::vector<Impact> ImpactLogger::Finish() {
  if (is_open_) Close(last_.time, false);
  return std::move(log_);
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

std::vector<Channel> ImpactColumns(const std::vector<Impact>& impacts) {
  std::vector<Channel> c = {{"time", "s", {}},
                            {"crank_angle", "rad", {}},
                            {"approach_velocity", "m/s", {}},
                            {"peak_force", "N", {}},
                            {"time_of_peak_force", "s", {}},
                            {"duration", "s", {}},
                            {"peak_penetration", "m", {}},
                            {"dissipated_energy", "J", {}},
                            {"complete", "1", {}}};
  for (const Impact& im : impacts) {
    const double row[] = {im.time,
                          im.crank_angle,
                          im.approach_velocity,
                          im.peak_force,
                          im.time_of_peak_force,
                          im.duration,
                          im.peak_penetration,
                          im.dissipated_energy,
                          im.complete ? 1.0 : 0.0};
    for (std::size_t k = 0; k < c.size(); ++k) c[k].values.push_back(row[k]);
  }
  return c;
}

void WriteImpactCsv(const std::vector<Impact>& impacts, const std::string& path) {
  const std::vector<Channel> columns = ImpactColumns(impacts);
  std::string text;
  for (const Channel& c : columns) text += (text.empty() ? "" : ",") + c.name + " [" + c.unit + "]";
  text += "\n";
  char cell[32];
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    for (std::size_t k = 0; k < columns.size(); ++k) {
      std::snprintf(cell, sizeof cell, k == 0 ? "%.17g" : ",%.17g", columns[k].values[i]);
      text += cell;
    }
    text += "\n";
  }
  WriteFileAtomic(path, text);
}

}  // namespace flexrod::study
