// sweep/sweep_compare.h — what is read out of a sweep store: the thesis's 25 comparisons
// (RIG.md §4, Tables 3–5: group I same material / different heights, group II same height /
// different materials, group III clearance), each agglomerating the turning ("inflection")
// points of its rods' runs into (speed, crank angle, acceleration) points, ranking the rods by
// the median, 95th percentile and maximum of |acceleration| at those points and checking the
// thesis's trend for that comparison; and the per-run summary table of a sweep (the data of
// the amplification-vs-speed plot). Files are written whole (temporary + rename).
// What does not live here: the store's layout (sweep/sweep_store.h), the PNG plots
// (scripts/flexrod_plots.py, called by the app).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "sweep/sweep_store.h"

namespace flexrod::study {

/// One side of a comparison: the runs of one rod at one clearance, or (group III) of every
/// rod at one clearance. Zero means "any".
struct ComparisonItem {
  std::string label;      ///< "steel 19.05 mm", "0.5 mm"
  std::string material;   ///< rod.material ("aluminium", "brass", "steel"); empty: any
  double height{0.0};     ///< rod.height [m]; 0: any
  double clearance{0.0};  ///< joint.clearance [m]; 0: any
};

struct ComparisonDef {
  int number{0};         ///< 1..25 (RIG.md Tables 3–5)
  std::string group;     ///< "I", "II", "III"
  bool positive{false};  ///< direction of the turning points
  std::vector<ComparisonItem> items;
  /// Item indices in the order the thesis's trend expects, largest |acceleration| first.
  std::vector<int> expected_order;
  std::string trend;        ///< the trend in words
  std::string thesis_note;  ///< what the thesis observed for this plot
};

/// The 25 comparisons of the thesis.
const std::vector<ComparisonDef>& ThesisComparisons();

/// A turning point of a run, placed for the 3-D scatter plot.
struct AgglomeratedPoint {
  int run_id{0};
  double speed{0.0};         ///< drive.speed [rad/s]
  double crank_angle{0.0};   ///< [rad], in [0, 2π)
  double acceleration{0.0};  ///< [m/s^2], signed
};

struct ItemResult {
  ComparisonItem item;
  int num_runs{0};    ///< completed runs matched
  int num_failed{0};  ///< failed runs matched (left out)
  std::vector<AgglomeratedPoint> points;
  double median{0.0};  ///< of |acceleration| [m/s^2]; NaN without points
  /// 95 % interval of the median [m/s^2] from the comparison's bootstrap over the speeds
  /// (ComparisonResult::resolved); NaN without points or in a comparison that is not evaluable.
  double median_low{std::numeric_limits<double>::quiet_NaN()};
  double median_high{std::numeric_limits<double>::quiet_NaN()};
  double p95{0.0};  ///< type-7 95th percentile of |acceleration| [m/s^2]; NaN without points
  double max{0.0};  ///< [m/s^2]; NaN without points
};

/// One load metric of a comparison (what the trend is about: the loads, DESIGN.md), at the
/// speeds every item of the comparison has completed runs at. A run's metric is a figure of its
/// summary: "amplification_p95" (amplification_positive_p95 or amplification_negative_p95, the
/// comparison's direction), "amplification_bearing_force_p95", "gauge_stress_p95" [Pa]. An
/// item's value is the mean over the common speeds of the mean over its runs at that speed (an
/// ensemble's members; group III: every rod's). Its interval and the verdict come from a
/// two-level bootstrap (2000 draws, fixed seed): the speeds drawn with replacement (paired
/// across the items: a speed moves every rod alike), then, for each item and drawn speed, its
/// runs there drawn with replacement.
struct LoadVerdict {
  std::string metric;                    ///< the summary figure, as above
  std::string unit;                      ///< "1" or "Pa"
  std::vector<double> value, low, high;  ///< per item [unit]; NaN without runs
  std::vector<int> ranking;              ///< items with a value, by value descending
  /// "holds": the 95 % interval of every difference of items adjacent in the expected order
  /// lies above 0; "reversed": one lies below 0; "not resolved": otherwise; "not evaluable":
  /// fewer than two items with a value.
  std::string verdict;
  std::string detail;  ///< the differences with their intervals, in the expected order
};

/// The load metrics, in the order a comparison reports them.
const std::vector<std::string>& LoadMetrics();

struct ComparisonResult {
  ComparisonDef def;
  /// Speeds [rad/s] at which every item with runs has a completed run: the only ones compared
  /// (turning points included); the others, excluded.
  std::vector<double> common_speeds, excluded_speeds;
  std::vector<LoadVerdict> loads;  ///< one per LoadMetrics(), in that order
  std::vector<ItemResult> items;
  std::vector<int> ranking;  ///< item indices with points, by median descending
  bool evaluable{false};     ///< at least two items have points
  bool trend_holds{false};   ///< the median ranking equals the expected order (items with points)
  /// For every two rods adjacent in the median ranking, the 95 % interval of the difference
  /// of their medians excludes 0. The interval comes from a bootstrap over the speeds, paired
  /// across the rods (1000 draws, fixed seed): each draw takes as many speeds as there are,
  /// with replacement, and every rod's turning points at them. An unresolved comparison
  /// decides nothing: the speeds' scatter is larger than the rods' difference.
  bool resolved{false};
  std::vector<double> gap_low;  ///< per adjacent pair of `ranking`: 2.5 % of the difference [m/s^2]
  bool trend_holds_p95{false};  ///< same with the 95th percentiles
  /// "Thesis trend: ... Loads: ... Ripple (turning points): ..." — one line for the report.
  std::string verdict;
};

/// Agglomerates the store's completed runs for each comparison, at the speeds common to its
/// items (ComparisonResult::common_speeds), and ranks its items by the load metrics (LoadVerdict)
/// and by the thesis's turning-point median (the ripple of the acceleration, kept as one column).
/// A run matches an item by rod.material, rod.height (within 1 µm) and joint.clearance (within
/// 0.1 µm) of its resolved input; a run without a clearance joint matches no item.
std::vector<ComparisonResult> RunComparisons(const std::vector<ComparisonDef>& defs,
                                             const std::vector<StoredRun>& runs);

/// Writes comparison_NN.md, comparison_NN.csv (the ranking table) and comparison_NN_points.csv
/// (item, run, speed [rpm], crank angle [deg], acceleration [m/s^2]) into dir.
void WriteComparisonFiles(const ComparisonResult& result, const std::string& dir);
/// Writes dir/comparisons.md: one line per comparison with its verdict.
void WriteComparisonIndex(const std::vector<ComparisonResult>& results, const std::string& store,
                          const std::string& dir);

/// One row per run: id, status, speed [rpm], clearance [mm], line (the varying keys other
/// than speed and clearance), peaks, ideal peaks, amplification per direction, message.
void WriteSweepSummaryCsv(const SweepStore& store, const std::string& path);

}  // namespace flexrod::study
