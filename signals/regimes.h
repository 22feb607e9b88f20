// signals/regimes.h — what a run's per-revolution statistics can and cannot say (DESIGN.md, "A
// run's answer is a distribution, not a number"): whether a window of revolutions is stationary,
// the confidence interval of a statistic pooled over revolutions and over ensemble members (a
// two-level moving-block bootstrap), and the regime a window or an ensemble is in (periodic,
// quasi-periodic, chaotic, intermittent; one or several steady states).
// Inputs are plain per-revolution series (one value per complete crank revolution, in time
// order); nothing here knows about the solver.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace flexrod::study {

// ---- stationarity ---------------------------------------------------------------------------

/// Relative difference of the two half-window means that is always accepted: below it a
/// difference is no bias a user would quote (integration error alone moves the per-revolution
/// peaks of the rig's runs by up to a few 0.1 %).
inline constexpr double kStationarityFloor = 0.01;

/// The stationarity test of one per-revolution series x_0 … x_{n−1} (n ≥ 4): no leading block
/// of revolutions differs from the rest, and the window has no trend.
/// - Blocks: for each j = 1 … ⌊n/2⌋, the mean m₁ of the first j revolutions and the mean m₂ of
///   the other n − j agree if |m₁ − m₂| ≤ max(t · s₂ · sqrt(1/j + 1/(n − j)), floor · |m₂|), with
///   s₂ the sample standard deviation of the n − j (a start-up transient would inflate the first
///   block's) and t the two-sided Student quantile for n − j − 1 degrees of freedom. j = ⌊n/2⌋
///   compares the two halves ("the means of the last two blocks agree"); j = 1 catches a single
///   revolution of start-up (a first impact), which halves average away.
/// - Trend: the least-squares line through (r, x_r) changes by (n − 1)|b| over the window; it
///   must stay within max(t · (n − 1) se(b), floor · |mean|), t for n − 2 degrees of freedom. A
///   drift inflates s₂ above; the line's residual does not carry it.
/// Each of the ⌊n/2⌋ + 1 comparisons is at level alpha / (⌊n/2⌋ + 1). With several series
/// (TestStationarity of many) alpha is divided among them too (Bonferroni). A series shorter
/// than 4 revolutions cannot be tested and counts as stationary, with `tested` false.
struct StationarityResult {
  bool stationary{true};
  bool tested{false};  ///< false: fewer than 4 revolutions
  /// The comparison reported (the failing one, else the closest to its limit): j of a block
  /// comparison, 0 for the trend.
  int leading{0};
  double first_mean{0.0};   ///< m₁ of the first j revolutions; the line at r = 0 [unit]
  double second_mean{0.0};  ///< m₂ of the others; the line at r = n − 1 [unit]
  double limit{0.0};        ///< the bound |m₁ − m₂| was held to [unit of the series]
};
StationarityResult TestStationarity(std::span<const double> series, double alpha = 0.01,
                                    double floor = kStationarityFloor);

/// All series together (Bonferroni: each at alpha / count); `worst` is the index of the series
/// whose |m₂ − m₁| / limit is largest (−1 if none was tested).
struct StationarityVerdict {
  bool stationary{true};
  int worst{-1};
  std::vector<StationarityResult> series;
};
StationarityVerdict TestStationarity(const std::vector<std::vector<double>>& series,
                                     double alpha = 0.01, double floor = kStationarityFloor);

// ---- bootstrap intervals --------------------------------------------------------------------

/// A statistic of a pooled sample (the values of all revolutions of all members, in any order).
using PooledStatistic = std::function<double(std::span<const double>)>;

struct BootstrapOptions {
  double confidence{0.95};  ///< two-sided coverage of the percentile interval, in (0, 1)
  int resamples{2000};      ///< >= 100
  /// Moving-block length [revolutions]; 0: ⌈n^(1/3)⌉ for a member of n revolutions (Künsch
  /// 1989; Hall, Horowitz & Jing 1995 give n^(1/3) as the order for a variance or interval).
  int block_length{0};
  std::uint64_t seed{20261206};  ///< the same seed gives the same interval
};

struct Interval {
  double centre{0.0};  ///< the statistic of the whole pooled sample [unit]
  double low{0.0};     ///< lower percentile bound [unit]
  double high{0.0};    ///< upper percentile bound [unit]
};

/// The two-level bootstrap of DESIGN.md: each resample draws as many members as there are, with
/// replacement (one member: that member), and each drawn member's revolutions by the moving-block
/// bootstrap (overlapping blocks of consecutive revolutions, drawn with replacement, until the
/// member's length is filled); the statistic of the pooled resample is one replicate. The
/// interval is the replicates' (1 ± confidence)/2 percentiles (type 7); the centre is the
/// statistic of the original pool. InputError if there is no member, a member is empty or the
/// options are out of range.
Interval BootstrapInterval(const std::vector<std::vector<double>>& members,
                           const PooledStatistic& statistic, const BootstrapOptions& options = {});

/// Statistics for BootstrapInterval: the mean, and the type-7 percentile p (0 … 100).
double PooledMean(std::span<const double> values);
PooledStatistic PooledPercentile(double percent);

// ---- regimes --------------------------------------------------------------------------------

/// The 0–1 test for chaos (Gottwald & Melbourne 2004, in the modified, regression-free form of
/// Gottwald & Melbourne 2009, "On the implementation of the 0–1 test for chaos", SIAM J. Appl.
/// Dyn. Syst. 8, 129–145): for c ∈ (π/5, 4π/5) the translation variables
/// p_c(n) = Σ_{j≤n} φ_j cos(jc), q_c(n) = Σ_{j≤n} φ_j sin(jc), their mean square displacement
/// M_c(n) (n ≤ N/10) less the oscillatory term (E φ)² (1 − cos nc)/(1 − cos c), and K_c, the
/// correlation of that with n; K is the median of K_c over `num_c` values of c drawn uniformly
/// (fixed seed). K ≈ 0 for regular (periodic, quasi-periodic) dynamics, ≈ 1 for chaotic ones.
/// InputError if the series has fewer than 50 values.
double ZeroOneTestK(std::span<const double> phi, int num_c = 100, std::uint64_t seed = 1);

/// The fewest revolutions the 0–1 test is run on: on a quasi-periodic sequence it gives K = 0.10
/// at 300 values but 0.80 at 160 (tests/signals/regimes_test.cc), so a shorter window cannot
/// tell quasi-periodic from chaotic motion.
inline constexpr std::size_t kZeroOneMinRevolutions = 300;

enum class WindowRegime {
  kPeriodic,       ///< the per-revolution figures repeat (with a period of 1 to 4 revolutions)
  kQuasiPeriodic,  ///< they do not repeat, and the 0–1 test says regular
  kChaotic,        ///< they do not repeat, and the 0–1 test says chaotic
  kIntermittent,   ///< a few revolutions (at most a quarter) far above the rest
  kAperiodic,      ///< they do not repeat; too few revolutions for the 0–1 test
  kUndetermined,   ///< too few revolutions to tell anything (fewer than 4)
};
const char* ToString(WindowRegime r);

/// The limits behind ClassifyWindow.
struct RegimeOptions {
  /// A per-revolution series repeats with period p if |x_{r+p} − x_r| ≤ this · median|x|.
  double repeat_tolerance{0.01};
  /// A revolution is an outlier if x_r > outlier_ratio · median and x_r − median > outlier_mads
  /// robust standard deviations (1.4826 · median absolute deviation).
  double outlier_ratio{1.5};
  double outlier_mads{5.0};
  double max_outlier_share{0.25};  ///< more outliers than this share: not intermittency
  double chaos_k{0.5};             ///< K of the 0–1 test above which a window is chaotic
};

struct WindowClassification {
  WindowRegime regime{WindowRegime::kUndetermined};
  int period{0};              ///< revolutions, for kPeriodic
  int outliers{0};            ///< revolutions far above the rest (kIntermittent)
  double relative_spread{0};  ///< (max − min) / median of the per-revolution series, largest
  double zero_one_k{-1.0};    ///< K of the 0–1 test, −1 where not computed
  std::string reason;         ///< one sentence: why this label
};

/// The regime of one window, from one or more per-revolution series of magnitudes (peaks) of
/// the same revolutions, in time order. Rules, in order: fewer than 4 revolutions →
/// undetermined; every series repeats with one period p ≤ 4 → periodic; any series has between 1
/// and max_outlier_share · n outliers → intermittent; fewer than kZeroOneMinRevolutions →
/// aperiodic; else the 0–1 test on the first series → chaotic (K > chaos_k) or quasi-periodic.
/// The test runs on one value per revolution (a stroboscopic section, as Gottwald & Melbourne
/// advise for a forced system): a record sampled many times per revolution is oversampled, and
/// a periodic one then gives K near 1.
WindowClassification ClassifyWindow(const std::vector<std::vector<double>>& per_revolution,
                                    const RegimeOptions& options = {});

/// Members of an ensemble grouped into steady states by their figures (each a per-member value
/// and its interval): two members are alike if, in every figure, their intervals overlap or
/// their values differ by less than `tolerance` (relative to the larger); the states are the
/// groups members are joined into through chains of alike pairs (single linkage), numbered in
/// the order of their first member. `figures[f][m]`: figure f of member m.
struct SteadyStates {
  std::vector<int> state;  ///< per member, in the members' order
  int count{0};
};
SteadyStates GroupSteadyStates(const std::vector<std::vector<Interval>>& figures,
                               double tolerance = 0.2);

}  // namespace flexrod::study
