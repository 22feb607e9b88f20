// signals/signals.h — time-domain analysis of a sampled record, keyed to the crank's index
// angle as on the rig (RIG.md §3): the triggered capture window, the split into crank
// revolutions, the Poincaré map and its "jitter", the turning points above a noise floor (the
// thesis's "inflection points"), RMS, percentiles, per-revolution peak statistics and the load
// amplification of a real-joint record over its ideal-joint twin. It includes
// signals/signals_spectrum.h, so this one header gives the whole signal toolbox.
// What does not live here: anything about the solver. Inputs are plain sample spans or a
// TimeSeries with named channels; the crank angle is an ordinary channel, unwrapped, in rad.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/eigen.h"
#include "signals/signals_extrema.h"
#include "signals/signals_spectrum.h"
#include "signals/timeseries.h"

namespace flexrod::study {

inline constexpr double kInflectionFloor = 20.0;    // m/s², noise floor, thesis §5.3.6
inline constexpr double kRigCaptureDuration = 3.0;  // s, RIG.md Table 2
inline constexpr double kRigSampleRate = 100000.0;  // Hz, RIG.md Table 2

// ---- index crossings and revolutions ------------------------------------------------------

/// The index levels are L_k = index_angle + 2πk for every integer k. The crank passes a level L
/// between samples i−1 and i when θ[i−1] < L ≤ θ[i] (upward only: the crank turns forward and
/// its angle channel is unwrapped). The crossing belongs to sample i, the first sample at or
/// past the index. Sample 0's predecessor is the linear extension θ[−1] = 2θ[0] − θ[1] (and
/// x[−1] = 2x[0] − x[1] for interpolated channels): a record that starts on the index has its
/// crossing at sample 0, whichever side of the index round-off puts θ[0].
struct IndexCrossing {
  std::size_t sample{0};  ///< i: first sample at or past the index level
  double fraction{0.0};   ///< s ∈ (0, 1]: the crossing lies at sample position (i − 1) + s,
                          ///< by linear interpolation of θ between samples i−1 and i
  double time{0.0};       ///< start_time + (i − 1 + s) / sample_rate [s]
};

/// The crossings whose sample i lies in `range`, in time order (sample i−1 may lie just before
/// range.begin). If one sample step passes several levels, each gives a crossing.
std::vector<IndexCrossing> FindIndexCrossings(std::span<const double> crank_angle,
                                              double index_angle, double sample_rate,
                                              double start_time, SampleRange range);

/// The complete crank revolutions inside `range`: [c_j, c_{j+1}) between consecutive crossing
/// samples c_j (as above) with range.begin ≤ c_j and c_{j+1} ≤ range.end (c_{j+1} may be the
/// sample just past the range). The partial revolutions before the first and after the last
/// crossing are left out.
std::vector<SampleRange> SplitRevolutions(std::span<const double> crank_angle, double index_angle,
                                          SampleRange range);

// ---- capture window -------------------------------------------------------------------------

struct CaptureOptions {
  double settling_time{0.0};             ///< wait after the record's start time before the
                                         ///< trigger is armed [s], >= 0
  double duration{kRigCaptureDuration};  ///< length of the capture [s], > 0
  double index_angle{0.0};               ///< crank angle of the encoder's index pulse [rad]
  /// Throws InputError naming capture.<field>.
  void Validate() const;
};

/// The rig's triggered capture (RIG.md Table 2): the first index crossing whose interpolated
/// instant is ≥ start_time + settling_time triggers it; the window starts at that crossing's
/// sample (the first sample at or past the index) and holds round(duration · sample_rate)
/// samples. Throws InputError if no crossing follows the settling time or the record ends
/// before the window does.
SampleRange FindCaptureWindow(std::span<const double> crank_angle, double sample_rate,
                              double start_time, const CaptureOptions& options);
SampleRange FindCaptureWindow(const TimeSeries& series, std::string_view crank_channel,
                              const CaptureOptions& options);

// ---- Poincaré map and jitter ----------------------------------------------------------------

/// One point per index crossing: every channel interpolated linearly at the crossing,
/// p = (1 − s) x[i−1] + s x[i] (IndexCrossing's i and s).
struct PoincareMap {
  std::vector<std::string> channels;  ///< channel names, one per column
  std::vector<std::string> units;     ///< their units
  std::vector<double> time;           ///< crossing instants [s]
  Mat points;  ///< rows: crossings in time order; columns: channels [channel units]
  std::size_t num_points() const { return time.size(); }
};

/// Poincaré map of `channels` at the crossings of `range` (FindIndexCrossings). InputError on an
/// unknown channel or a bad range.
PoincareMap CalcPoincareMap(const TimeSeries& series, std::string_view crank_channel,
                            double index_angle, const std::vector<std::string>& channels,
                            SampleRange range);
/// Writes x at each crossing into out (out.size() == crossings.size()).
void InterpolateAtCrossings(std::span<const double> x, std::span<const IndexCrossing> crossings,
                            std::span<double> out);

/// Poincaré "jitter" (thesis §5.3.5, RIG.md §3). The parabola through (0, p_n), (1, p_{n+1}),
/// (2, p_{n+2}) extrapolates to p̂_{n+3} = p_n − 3 p_{n+1} + 3 p_{n+2} (Lagrange), so the
/// residual p_{n+3} − p̂_{n+3} is the third forward difference Δ³p_n. Over N points:
///   total = Σ_{n=0}^{N−4} ‖Δ³p_n‖,  count = N − 3,  normalised = total / count,
/// with ‖·‖ the absolute value for a scalar map and the Euclidean norm of a row for a
/// multi-column map (give its columns one unit). It is 0 for points on any quadratic in n and
/// 6|c|(N − 3) for p_n = c n³ + (any quadratic).
struct PoincareJitter {
  double total{0.0};       ///< Σ |actual − predicted| [unit of the points]
  double normalised{0.0};  ///< total / count [unit of the points]
  std::size_t count{0};    ///< number of predictions, N − 3
};
/// InputError("poincare.points", N, ...) if N < 4.
PoincareJitter CalcPoincareJitter(std::span<const double> points);
/// Rows are points, columns coordinates.
PoincareJitter CalcPoincareJitter(const Eigen::Ref<const Mat>& points);

// ---- turning ("inflection") points ----------------------------------------------------------

struct TurningPoint {
  std::size_t sample{0};    ///< index in the record
  double time{0.0};         ///< [s]
  double crank_angle{0.0};  ///< crank angle wrapped to [0, 2π) [rad]
  double value{0.0};        ///< [unit of the channel]
};

struct InflectionPoints {
  std::vector<TurningPoint> positive;  ///< local maxima with value > floor, in time order
  std::vector<TurningPoint> negative;  ///< local minima with value < −floor, in time order
  double floor{kInflectionFloor};      ///< [unit of the channel]
};

/// The thesis's "inflection points" (§5.3.6) are the turning points of the acceleration record
/// beyond a noise floor. Rule (signals/signals_extrema.h), applied to the samples of `range`
/// only: a plateau x[a] = ... = x[b] (often a = b) with x[a−1] < x[a] and x[b+1] < x[b] is a
/// positive point if x[a] > floor; with x[a−1] > x[a] and x[b+1] > x[b] it is a negative point
/// if x[a] < −floor. Each plateau is reported once, at a. The range's first and last samples
/// are never turning points. floor ≥ 0 (InputError otherwise).
InflectionPoints FindInflectionPoints(std::span<const double> x,
                                      std::span<const double> crank_angle, double sample_rate,
                                      double start_time, SampleRange range,
                                      double floor = kInflectionFloor);
InflectionPoints FindInflectionPoints(const TimeSeries& series, std::string_view channel,
                                      std::string_view crank_channel, SampleRange range,
                                      double floor = kInflectionFloor);

// ---- statistics and load amplification ------------------------------------------------------

/// Percentile by linear interpolation between order statistics (Hyndman & Fan 1996, type 7;
/// the default of R and NumPy): with the values sorted y_0 ≤ ... ≤ y_{N−1},
///   h = (N − 1) · percent / 100,  P = y_⌊h⌋ + (h − ⌊h⌋) (y_{⌊h⌋+1} − y_⌊h⌋).
/// The median is Percentile(v, 50). InputError if values is empty or percent ∉ [0, 100].
double Percentile(std::span<const double> values, double percent);
/// Same, for values already sorted ascending (no copy).
double PercentileOfSorted(std::span<const double> sorted, double percent);
/// sqrt(mean(x²)); InputError if x is empty.
double Rms(std::span<const double> x);

/// Statistics of the per-revolution peaks of one direction.
struct PeakStatistics {
  std::size_t num_revolutions{0};  ///< complete revolutions (SplitRevolutions)
  double median{0.0};              ///< type-7 50th percentile [unit]; NaN if no revolution
  double p95{0.0};                 ///< type-7 95th percentile [unit]; NaN if no revolution
  double max{0.0};                 ///< [unit]; NaN if no revolution
};

/// Peak measures of one channel over a range. Peaks of each direction are magnitudes ≥ 0:
/// positive = max(0, max x), negative = max(0, max(−x)); a direction the signal never enters
/// has peak 0.
struct SignalSummary {
  double peak_positive{0.0};  ///< over the whole range [unit]
  double peak_negative{0.0};  ///< over the whole range, a magnitude [unit]
  double rms{0.0};            ///< over the whole range [unit]
  PeakStatistics positive;    ///< of the per-revolution positive peaks
  PeakStatistics negative;    ///< of the per-revolution negative peaks (magnitudes)
  PeakStatistics magnitude;   ///< of the per-revolution peaks of |x| (the larger of the two)
  /// The per-revolution peaks themselves, in time order (one per complete revolution) [unit].
  std::vector<double> positive_peaks, negative_peaks;
};

/// InputError if the spans differ in length or the range is bad.
SignalSummary CalcSignalSummary(std::span<const double> x, std::span<const double> crank_angle,
                                double index_angle, SampleRange range);
/// Same, with the range's revolutions already split (SplitRevolutions of the same crank angle
/// and range; each must lie inside the range): a record's channels share one split.
SignalSummary CalcSignalSummary(std::span<const double> x, SampleRange range,
                                std::span<const SampleRange> revolutions);
SignalSummary CalcSignalSummary(const TimeSeries& series, std::string_view channel,
                                std::string_view crank_channel, double index_angle,
                                SampleRange range);

/// Load amplification of a real-joint record over its ideal-joint twin (DESIGN.md, "The study
/// layer"), per direction. Both summaries must come from windows of the same length started at
/// the same index crossing (FindCaptureWindow with the same options) — the caller's duty.
/// A ratio whose ideal value is 0 is undefined and reported as NaN.
struct LoadAmplification {
  double positive{0.0};      ///< real.peak_positive / ideal.peak_positive [-]
  double negative{0.0};      ///< real.peak_negative / ideal.peak_negative [-]
  double positive_p95{0.0};  ///< real.positive.p95 / ideal.positive.p95 (robust variant) [-]
  double negative_p95{0.0};  ///< real.negative.p95 / ideal.negative.p95 (robust variant) [-]
};
LoadAmplification CalcLoadAmplification(const SignalSummary& real, const SignalSummary& ideal);

}  // namespace flexrod::study
