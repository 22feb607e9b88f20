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

const std::vector<ImpactColumn>& ImpactColumns() {
  static const std::vector<ImpactColumn> kColumns = {
      {"time", "s", [](const Impact& i) { return i.time; }},
      {"crank_angle", "rad", [](const Impact& i) { return i.crank_angle; }},
      {"approach_velocity", "m/s", [](const Impact& i) { return i.approach_velocity; }},
      {"peak_force", "N", [](const Impact& i) { return i.peak_force; }},
      {"time_of_peak_force", "s", [](const Impact& i) { return i.time_of_peak_force; }},
      {"duration", "s", [](const Impact& i) { return i.duration; }},
      {"peak_penetration", "m", [](const Impact& i) { return i.peak_penetration; }},
      {"dissipated_energy", "J", [](const Impact& i) { return i.dissipated_energy; }},
      {"complete", "1", [](const Impact& i) { return i.complete ? 1.0 : 0.0; }},
  };
  return kColumns;
}

void WriteImpactCsv(const std::vector<Impact>& impacts, const std::string& path) {
  std::string text;
  for (const ImpactColumn& c : ImpactColumns()) {
    text += std::string(text.empty() ? "" : ",") + c.name + " [" + c.unit + "]";
  }
  text += '\n';
  char number[32];
  for (const Impact& im : impacts) {
    bool first = true;
    for (const ImpactColumn& c : ImpactColumns()) {
      std::snprintf(number, sizeof(number), "%s%.17g", first ? "" : ",", c.value(im));
      text += number;
      first = false;
    }
    text += '\n';
  }
  try {
    WriteFileAtomic(path, text);
  } catch (const std::runtime_error& e) {
    throw InputError("csv", path, e.what());
  }
}

}  // namespace flexrod::study
