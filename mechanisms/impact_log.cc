// mechanisms/impact_log.cc — the impact log built from the located contact events (see
// impact_log.h). SPDX-License-Identifier: GPL-3.0-or-later
#include "mechanisms/impact_log.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <utility>

#include "common/error.h"
#include "common/files.h"
#include "common/units.h"
#include "signals/signals.h"

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
  const ContactPoint& last = last_point();
  if (!started_ || p.onsets != onsets_seen_) {
    // The first point, or the point of a located onset (the joint's count moved).
    if (is_open_) Close(last.time, false);  // its separation was not offered
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
    open_.dissipated_energy += 0.5 * (last.dissipation + p.dissipation) * (p.time - last.time);
  }
  if (is_open_) {
    if (p.normal_force > open_.peak_force) {
      open_.peak_force = p.normal_force;
      open_.time_of_peak_force = p.time;
    }
    open_.peak_penetration = std::max(open_.peak_penetration, p.penetration);
    if (!p.contact) Close(p.time, open_.complete);  // the located separation
  }
  recent_[num_offered_++ % recent_.size()] = p;
}

const ContactPoint* ImpactLogger::RecentPoint(double t) const {
  for (std::size_t k = 0; k < std::min(num_offered_, recent_.size()); ++k) {
    const ContactPoint& p = recent_[(num_offered_ - 1 - k) % recent_.size()];
    if (p.time == t) return &p;
  }
  return nullptr;
}

void ImpactLogger::ObservePeak(double time, double normal_force, double penetration) {
  if (!is_open_ || time < open_.time) return;
  if (normal_force > open_.peak_force) {
    open_.peak_force = normal_force;
    open_.time_of_peak_force = time;
  }
  open_.peak_penetration = std::max(open_.peak_penetration, penetration);
}

LocatedMaximum LocateInteriorMaximum(const std::function<double(double)>& f, double a, double b,
                                     double wanted_above) {
  const double width = b - a, d = 1e-4 * width;
  const double fa = f(a), fb = f(b), m = 0.5 * (a + b), fm = f(m);
  const LocatedMaximum none{a, -std::numeric_limits<double>::infinity()};
  // Out of reach of `wanted_above`: inside an impact most steps are, once its peak has passed.
  if (std::max({fa, fm, fb}) + std::abs(fm - fa) + std::abs(fb - fm) <= wanted_above) return none;
  // A maximum lies inside if the midpoint beats both ends, or if f rises from a and falls into b
  // (one-sided differences over 1e-4 of the step), each difference evaluated only when needed:
  // inside an impact this runs at every step, and most steps rise or fall throughout. The end
  // the step climbs to is tested first (a step that rises throughout does not fall into b, one
  // that falls throughout does not rise from a), so such a step costs one difference.
  auto rises_then_falls = [&] {
    return fb > fa ? f(b - d) > fb && f(a + d) > fa : f(a + d) > fa && f(b - d) > fb;
  };
  const bool inside = fm > std::max(fa, fb) || rises_then_falls();
  if (!inside) return none;
  // Brent's method (R. P. Brent, Algorithms for Minimization without Derivatives, 1973, ch. 5)
  // on −f: a parabola through the three best points x (best), w (second), v (third) gives the
  // next point when it falls inside the bracket and moves less than half the step before last;
  // otherwise a golden-section step into the larger part. A smooth peak then takes a handful of
  // parabolic steps where golden section alone took ~45 evaluations to the same bracket.
  // To 1e-9 of the step, or the resolution of t itself (a step can be a few ulp of t long).
  const double resolution =
      std::max(1e-9 * width, 8.0 * std::numeric_limits<double>::epsilon() * std::abs(b));
  const double golden = 0.5 * (3.0 - std::sqrt(5.0));
  double lo = a, hi = b;
  double x = m, w = m, v = m, fx = fm, fw = fm, fv = fm;
  double step = 0.0, step_before_last = 0.0;
  for (int it = 0; it < 64; ++it) {
    const double mid = 0.5 * (lo + hi), tol = 0.5 * resolution;
    if (std::abs(x - mid) <= 2.0 * tol - 0.5 * (hi - lo)) break;  // bracket within resolution
    bool parabolic = false;
    if (std::abs(step_before_last) > tol) {
      // Vertex of the parabola through (x, fx), (w, fw), (v, fv): x + p / q.
      const double r = (x - w) * (fv - fx), s = (x - v) * (fw - fx);
      double p = (x - v) * s - (x - w) * r, q = 2.0 * (s - r);
      if (q > 0.0) p = -p;
      q = std::abs(q);
      if (std::abs(p) < std::abs(0.5 * q * step_before_last) && p > q * (lo - x) &&
          p < q * (hi - x)) {
        step_before_last = step;
        step = p / q;
        const double u = x + step;
        if (u - lo < 2.0 * tol || hi - u < 2.0 * tol) step = std::copysign(tol, mid - x);
        parabolic = true;
      }
    }
    if (!parabolic) {
      step_before_last = x >= mid ? lo - x : hi - x;
      step = golden * step_before_last;
    }
    const double u = std::abs(step) >= tol ? x + step : x + std::copysign(tol, step);
    const double fu = f(u);
    if (fu >= fx) {
      (u >= x ? lo : hi) = x;
      v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
    } else {
      (u < x ? lo : hi) = u;
      if (fu >= fw || w == x) {
        v = w, fv = fw, w = u, fw = fu;
      } else if (fu >= fv || v == x || v == w) {
        v = u, fv = fu;
      }
    }
  }
  return {x, fx};
}

std::optional<multibody::ClearanceResponse> LocateImpactPeaks(
    const multibody::StepInterpolant& step, multibody::ElementId joint, ImpactLogger* log) {
  if (!log->in_impact()) return std::nullopt;
  // Both searches test the same points (ends, midpoint, the one-sided differences they need):
  // the second reads the first's values instead of evaluating the joint again. The step starts
  // at a solution point the log has seen; its end is evaluated here once, for the searches and
  // for the caller, whose next point it is.
  struct Point {
    double t, force, depth;
  };
  std::array<Point, 6> seen;
  std::size_t num_seen = 0;
  if (const ContactPoint* start = log->RecentPoint(step.t_begin()))
    seen[num_seen++] = {start->time, start->normal_force, start->penetration};
  const multibody::ClearanceResponse end =
      multibody::CalcClearanceResponse(step.ElementAt(step.t_end(), joint), joint);
  seen[num_seen++] = {step.t_end(), end.normal_force, end.kinematics.penetration};
  auto at = [&](double t) {
    for (std::size_t i = 0; i < num_seen; ++i) {
      if (seen[i].t == t) return seen[i];
    }
    const multibody::ClearanceResponse r =
        multibody::CalcClearanceResponse(step.ElementAt(t, joint), joint);
    const Point p{t, r.normal_force, r.kinematics.penetration};
    if (num_seen < seen.size()) seen[num_seen++] = p;
    return p;
  };
  const LocatedMaximum force = LocateInteriorMaximum(
      [&](double t) { return at(t).force; }, step.t_begin(), step.t_end(), log->open_peak_force());
  const LocatedMaximum depth =
      LocateInteriorMaximum([&](double t) { return at(t).depth; }, step.t_begin(), step.t_end(),
                            log->open_peak_penetration());
  if (force.value > 0.0) log->ObservePeak(force.t, force.value, 0.0);
  if (depth.value > 0.0) log->ObservePeak(depth.t, 0.0, depth.value);
  return end;
}

void ImpactLogger::Close(double t, bool complete) {
  open_.duration = t - open_.time;
  open_.complete = complete;
  log_.push_back(open_);
  is_open_ = false;
}

std::vector<Impact> ImpactLogger::Finish() {
  if (is_open_) Close(last_point().time, false);
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
