// study/impact_log.h — the per-run log of clearance-joint contact events, recovered after the
// run from the sampled channels (penetration, contact normal force, penetration rate, crank
// angle, and the contact dissipation when recorded), so the mechanism model carries no mutable
// log. An impact is a maximal run of samples with penetration δ > 0; its onset and exit are the
// zero crossings of δ interpolated linearly between samples. Resolution is the sample period:
// impacts shorter than one sample can be missed, and peaks are sampled values. A persistent
// contact (the pin sliding or rolling on the bush wall) is one long "impact".
// What does not live here: the contact model (multibody/clearance_joint.h, contact/), channel
// recording (study/run.cc).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "study/timeseries.h"

namespace flexrod::study {

/// Names of the channels the log reads (defaults: those study/run.cc records).
struct ImpactLogChannels {
  std::string penetration{"penetration"};             ///< δ [m]
  std::string normal_force{"contact_normal_force"};   ///< F_n [N]
  std::string penetration_rate{"penetration_rate"};   ///< δ̇ [m/s]
  std::string crank_angle{"crank_angle"};             ///< unwrapped [rad]; optional
  std::string dissipation{"contact_dissipation"};     ///< [W]; optional
};

/// One contact event.
struct Impact {
  double time{0.0};               ///< onset: δ crosses 0 upwards (interpolated) [s]
  double crank_angle{0.0};        ///< at onset, wrapped to [0, 2π) [rad]; 0 if no channel
  double approach_velocity{0.0};  ///< δ̇ at onset (interpolated) [m/s]
  double peak_force{0.0};         ///< max sampled F_n [N]
  double time_of_peak_force{0.0}; ///< [s]
  double duration{0.0};           ///< onset to exit (δ back through 0, interpolated) [s]
  double peak_penetration{0.0};   ///< max sampled δ [m]
  /// Energy the contact removed from the mechanism [J]: ∫ (contact dissipation) dt if that
  /// channel is recorded (normal damping + friction), else the normal hysteresis ∫ F_n δ̇ dt
  /// (the stored elastic energy is zero at both ends). Trapezoidal rule over the samples,
  /// closed by the interpolated crossings.
  double dissipated_energy{0.0};
  bool complete{true};            ///< false if the record starts or ends inside the contact
  std::size_t first_sample{0};    ///< first sample with δ > 0
  std::size_t end_sample{0};      ///< one past the last sample with δ > 0
};

/// Every impact of the record, in time order. InputError if a required channel is missing.
std::vector<Impact> FindImpacts(const TimeSeries& series, const ImpactLogChannels& channels = {});

/// Summary numbers of a log (complete impacts only; zeros if there are none).
struct ImpactStatistics {
  std::size_t count{0};                ///< complete impacts
  std::size_t incomplete{0};           ///< cut by the start or end of the record
  double max_peak_force{0.0};          ///< [N]
  double median_peak_force{0.0};       ///< [N]
  double max_approach_velocity{0.0};   ///< [m/s]
  double max_peak_penetration{0.0};    ///< [m]
  double mean_duration{0.0};           ///< [s]
  double total_dissipated_energy{0.0}; ///< [J]
};
ImpactStatistics CalcImpactStatistics(const std::vector<Impact>& impacts);

/// The log as a TimeSeries-independent CSV ("time [s],crank_angle [rad],..."), written whole
/// (path + ".tmp", then rename). InputError("csv", path, ...) if it cannot be written.
void WriteImpactCsv(const std::vector<Impact>& impacts, const std::string& path);

}  // namespace flexrod::study
