// mechanisms/impact_log.h — the per-run log of clearance-joint impacts, built while the run
// proceeds from the joint's located events. The integrator's root functions locate every contact
// onset (δ = +b crossed upwards) and separation (δ = −b crossed downwards, b = ClearanceJoint::
// EventBand(), 1e-6 of the clearance); the joint counts the onsets and keeps the last onset time
// in its run memory (multibody/clearance_joint.h). An impact runs from a located onset to the
// next located separation, so an impact shorter than a sample period is logged as well as a
// long one, and a persistent contact (the pin sliding or rolling on the bush wall) is one long
// impact. Onset time, crank angle and approach velocity are the values at the located onset;
// the duration is separation − onset. The dissipated energy is integrated over every solution
// point the run offers inside the impact: the integrator's accepted steps, its located events
// and the output samples (the steps are sub-microsecond inside an impact); the peak force and
// penetration are located inside each step (LocateImpactPeaks). Nothing is
// filtered: every located onset is logged. The joint's coordinates carry their relative
// tolerance on the clearance (ForceElement::ResolvedLength), so the onsets are contact, not
// position error (tests/run/clearance_tolerance_reftest.cc). Near-separations of a riding
// pin (the contact force passing close to zero once a revolution) are genuinely sensitive:
// rigid rig, 177 rpm, 10 revolutions, 6.5 impacts per revolution at rel_tol 1e-6, 2.5 at 1e-7.
// What does not live here: the contact model (multibody/clearance_joint.h, contact/), channel
// recording (run/run.cc).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "multibody/clearance_joint.h"
#include "multibody/simulate.h"
#include "signals/timeseries.h"

namespace flexrod::study {

/// The clearance joint at one solution point of a run.
struct ContactPoint {
  double time{0.0};         ///< [s]
  double crank_angle{0.0};  ///< unwrapped [rad]
  /// The joint's contact flag: on from a located onset to the located separation.
  bool contact{false};
  long onsets{0};                ///< onsets located so far in the run
  double onset_time{0.0};        ///< time of the last located onset [s]
  double penetration{0.0};       ///< δ [m]
  double penetration_rate{0.0};  ///< δ̇ [m/s]
  double normal_force{0.0};      ///< F_n [N]
  double dissipation{0.0};       ///< power the contact removes (normal damping + friction) [W]
};
ContactPoint MakeContactPoint(double time, double crank_angle,
                              const multibody::ClearanceResponse& r);

/// One impact.
struct Impact {
  double time{0.0};         ///< located onset (or the start of the log, if already in contact) [s]
  double crank_angle{0.0};  ///< at `time`, wrapped to [0, 2π) [rad]
  double approach_velocity{0.0};  ///< δ̇ at `time`: the located onset, or the start of the log [m/s]
  double peak_force{0.0};  ///< max F_n: solution points and located peaks (LocateImpactPeaks) [N]
  double time_of_peak_force{0.0};  ///< [s]
  double duration{0.0};            ///< located separation (or the end of the log) − time [s]
  double peak_penetration{0.0};    ///< max δ, as peak_force [m]
  /// Energy the contact removed from the mechanism, ∫ dissipation dt over the impact (normal
  /// damping and friction), trapezoidal rule over its solution points [J].
  double dissipated_energy{0.0};
  bool complete{true};  ///< false if the log starts or ends inside the impact
};

/// The largest value of f over [a, b] when it lies inside the interval — f rises from a and
/// falls into b, or the midpoint beats both ends — by Brent's parabolic and golden-section search
/// to a bracket of 1e-9 (b − a) (or of t's own resolution; at most 64 steps). Returns {t, f(t)}, or
/// {a, −inf} when no interior point beats both ends (the ends are solution points the log sees
/// anyway), or when f cannot reach above `wanted_above` inside: the largest of f(a), f(b) and
/// the midpoint's f, plus f's variation over the two half-intervals, stays at or below it. (A
/// step resolves its force: to rise above that bound, f would have to climb more within the
/// step than it moves across both of its halves.)
struct LocatedMaximum {
  double t{0.0};
  double value{0.0};
};
LocatedMaximum LocateInteriorMaximum(
    const std::function<double(double)>& f, double a, double b,
    double wanted_above = -std::numeric_limits<double>::infinity());

/// Inside an open impact of `log`, locates the peak normal force and penetration of the
/// clearance joint `joint` within the integrator's step (LocateInteriorMaximum on its
/// interpolating polynomial) and offers them (ObservePeak): the solution points alone gave
/// peaks up to 5e-4 low. Only a peak above the open impact's peak so far is searched for. The
/// step's start is a solution point the log has seen (ImpactLogger::RecentPoint), whose force
/// and penetration it takes from there. Returns the joint's response at the step's end, which
/// the search evaluates: the solution point the caller offers next (Observe it from this, not
/// from a second evaluation). Outside an impact: does nothing and returns nullopt.
class ImpactLogger;
std::optional<multibody::ClearanceResponse> LocateImpactPeaks(
    const multibody::StepInterpolant& step, multibody::ElementId joint, ImpactLogger* log);

/// Builds the log from the solution points of a run, offered in time order (steps, located
/// events and samples; any window of the run: the first point opens the log, the last closes it).
class ImpactLogger {
 public:
  void Observe(const ContactPoint& p);
  /// True between a located onset and its separation.
  bool in_impact() const { return is_open_; }
  /// The last point offered (meaningful once one has been).
  const ContactPoint& last_point() const {
    return recent_[(num_offered_ + recent_.size() - 1) % recent_.size()];
  }
  /// The point at time t among the last four offered (the start of the step a peak search
  /// covers, with at most the samples inside that step offered after it); nullptr if none.
  const ContactPoint* RecentPoint(double t) const;
  /// The open impact's peak force [N] and penetration [m] so far (in_impact()).
  double open_peak_force() const { return open_.peak_force; }
  double open_peak_penetration() const { return open_.peak_penetration; }
  /// A peak located between solution points (LocateImpactPeaks): raises the open impact's
  /// peak force and penetration if it is later than its onset and higher.
  void ObservePeak(double time, double normal_force, double penetration);
  /// Every impact in time order; one still open is closed at the last point, incomplete.
  std::vector<Impact> Finish();

 private:
  void Close(double t, bool complete);
  std::vector<Impact> log_;
  Impact open_;
  bool is_open_{false};
  bool started_{false};
  long onsets_seen_{0};
  std::array<ContactPoint, 4> recent_;  // the last points offered, a ring (last_point, RecentPoint)
  std::size_t num_offered_{0};
};

/// Summary numbers of a log (complete impacts only; zeros if there are none).
struct ImpactStatistics {
  std::size_t count{0};                 ///< complete impacts
  std::size_t incomplete{0};            ///< cut by the start or end of the record
  double max_peak_force{0.0};           ///< [N]
  double median_peak_force{0.0};        ///< [N]
  double max_approach_velocity{0.0};    ///< [m/s]
  double max_peak_penetration{0.0};     ///< [m]
  double mean_duration{0.0};            ///< [s]
  double total_dissipated_energy{0.0};  ///< [J]
};
ImpactStatistics CalcImpactStatistics(const std::vector<Impact>& impacts);

/// The log as columns, one value per impact: time [s], crank_angle [rad], approach_velocity
/// [m/s], peak_force [N], time_of_peak_force [s], duration [s], peak_penetration [m],
/// dissipated_energy [J], complete [1] (1 or 0).
std::vector<Channel> ImpactColumns(const std::vector<Impact>& impacts);

/// The columns as CSV ("time [s],crank_angle [rad],...", %.17g), written whole (path + ".tmp", then
/// rename). IoError naming the file if it cannot be written.
void WriteImpactCsv(const std::vector<Impact>& impacts, const std::string& path);

}  // namespace flexrod::study
