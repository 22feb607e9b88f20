// SPDX-License-Identifier: GPL-3.0-or-later
// The thesis's comparison groups (RIG.md §4), their tables, and the sweep summary table.
#include "sweep/sweep_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <tuple>
#include <utility>

#include "common/error.h"
#include "common/files.h"
#include "signals/signals.h"

namespace flexrod::study {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRpm = 60.0 / (2.0 * std::numbers::pi);  // (rev/min) per (rad/s)
constexpr double kHeightTolerance = 1e-6;                 // m: Table 1 heights differ by 6.35 mm
constexpr double kClearanceTolerance = 1e-7;              // m: clearances differ by 0.5 mm

// RIG.md Table 1: the seven rods.
const ComparisonItem kAl19{"aluminium 19.05 mm", "aluminium", 19.05e-3, 0.0};
const ComparisonItem kAl25{"aluminium 25.4 mm", "aluminium", 25.4e-3, 0.0};
const ComparisonItem kBr12{"brass 12.7 mm", "brass", 12.7e-3, 0.0};
const ComparisonItem kBr19{"brass 19.05 mm", "brass", 19.05e-3, 0.0};
const ComparisonItem kSt12{"steel 12.7 mm", "steel", 12.7e-3, 0.0};
const ComparisonItem kSt19{"steel 19.05 mm", "steel", 19.05e-3, 0.0};
const ComparisonItem kSt25{"steel 25.4 mm", "steel", 25.4e-3, 0.0};

std::vector<ComparisonItem> AtClearance(std::vector<ComparisonItem> items, double clearance) {
  for (ComparisonItem& i : items) i.clearance = clearance;
  return items;
}

std::string Normalise(const std::string& material) {
  return material == "aluminum" ? "aluminium" : material;
}

/// What a comparison needs to know about a run, read once from its resolved input.
struct RunFacts {
  std::string material;
  double height{0.0}, clearance{0.0}, speed{0.0};
};

RunFacts FactsOf(const StoredRun& run) {
  RunFacts f;
  const Config cfg = run.Input();
  f.material = Normalise(cfg.Text("rod.material"));
  f.height = cfg.Quantity("rod.height");
  f.speed = cfg.Quantity("drive.speed");
  const bool clearance_joint =
      cfg.Text("joint.type") == "clearance" && FindParam("joint.clearance");
  f.clearance = clearance_joint ? cfg.Quantity("joint.clearance") : 0.0;
  return f;
}

bool Matches(const ComparisonItem& item, const RunFacts& f) {
  if (f.clearance <= 0.0) return false;
  if (!item.material.empty() && item.material != f.material) return false;
  if (item.height > 0.0 && std::abs(item.height - f.height) > kHeightTolerance) return false;
  if (item.clearance > 0.0 && std::abs(item.clearance - f.clearance) > kClearanceTolerance)
    return false;
  return true;
}

std::string Num(double v) {
  if (!std::isfinite(v)) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string CsvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string Two(int n) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "%02d", n);
  return buf;
}

std::string Direction(const ComparisonDef& d) { return d.positive ? "positive" : "negative"; }

std::string ClearanceText(const ComparisonDef& d) {
  double c = 0.0;
  for (const ComparisonItem& i : d.items) c = i.clearance;
  if (d.group == "III") return "0.5 vs 1.0 mm";
  return Num(c * 1e3) + " mm";
}

std::string SpeedsText(const std::vector<double>& speeds) {
  std::string s;
  for (double sp : speeds) s += (s.empty() ? "" : ", ") + Num(sp * kRpm);
  return s + " rpm";
}

std::string OrderText(const std::vector<ItemResult>& items, const std::vector<int>& order) {
  std::string s;
  for (int i : order) s += (s.empty() ? "" : " > ") + items[static_cast<std::size_t>(i)].item.label;
  return s;
}

/// Draws of the bootstrap of PairedBootstrap, and its seed (fixed: a store always gives the same
/// intervals).
constexpr int kBootstrapDraws = 1000;
constexpr std::uint64_t kBootstrapSeed = 20261127;

/// The median (= PercentileOfSorted(·, 50) of the sorted values) by selection, reordering
/// `v`: the bootstrap takes a thousand medians per comparison and rod.
double MedianInPlace(std::vector<double>* v) {
  const std::size_t n = v->size(), upper = n / 2;
  std::nth_element(v->begin(), v->begin() + upper, v->end());
  if (n % 2 == 1) return (*v)[upper];
  const double lower = *std::max_element(v->begin(), v->begin() + upper);
  return 0.5 * (lower + (*v)[upper]);
}

/// |acceleration| of one item's turning points, grouped by the speed of their run.
using BySpeed = std::map<double, std::vector<double>>;

struct BootstrapResult {
  std::vector<std::pair<double, double>> item_interval;  ///< per item: 2.5 / 97.5 % of its median
  std::vector<std::pair<double, double>> gap_interval;   ///< per adjacent pair of the ranking
};

/// A bootstrap over the speeds, paired across the rods: each draw takes as many speeds as the
/// comparison has, with replacement, and every rod's points at the drawn speeds; per draw the
/// median of each rod and the difference of the medians of rods adjacent in `ranking`. The
/// speeds are resampled, not the points, because a run's turning points are correlated and the
/// speed moves every rod's accelerations alike: the pairing removes that common part.
BootstrapResult PairedBootstrap(const std::vector<BySpeed>& items,
                                const std::vector<int>& ranking) {
  std::vector<double> speeds;
  for (const BySpeed& item : items) {
    for (const auto& [speed, values] : item) speeds.push_back(speed);
  }
  std::sort(speeds.begin(), speeds.end());
  speeds.erase(std::unique(speeds.begin(), speeds.end()), speeds.end());
  std::mt19937_64 gen(kBootstrapSeed);
  std::uniform_int_distribution<std::size_t> pick(0, speeds.size() - 1);
  std::vector<std::vector<double>> medians(items.size()), gaps(ranking.size() - 1);
  std::vector<double> draw(speeds.size()), sample, med(items.size());
  for (int d = 0; d < kBootstrapDraws; ++d) {
    for (double& sp : draw) sp = speeds[pick(gen)];
    for (std::size_t i = 0; i < items.size(); ++i) {
      sample.clear();
      for (double sp : draw) {
        const auto it = items[i].find(sp);
        if (it != items[i].end()) sample.insert(sample.end(), it->second.begin(), it->second.end());
      }
      med[i] = sample.empty() ? kNaN : MedianInPlace(&sample);
      if (!sample.empty()) medians[i].push_back(med[i]);
    }
    for (std::size_t k = 0; k + 1 < ranking.size(); ++k) {
      const double gap =
          med[static_cast<std::size_t>(ranking[k])] - med[static_cast<std::size_t>(ranking[k + 1])];
      if (std::isfinite(gap)) gaps[k].push_back(gap);
    }
  }
  auto interval = [](std::vector<double>& v) {
    if (v.empty()) return std::pair{kNaN, kNaN};
    std::sort(v.begin(), v.end());
    return std::pair{PercentileOfSorted(v, 2.5), PercentileOfSorted(v, 97.5)};
  };
  BootstrapResult out;
  for (auto& m : medians) out.item_interval.push_back(interval(m));
  for (auto& g : gaps) out.gap_interval.push_back(interval(g));
  return out;
}

std::string Format(const char* format, double a, double b, double c) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), format, a, b, c);
  return buf;
}

std::vector<int> RankBy(const std::vector<ItemResult>& items, double ItemResult::*measure) {
  std::vector<int> idx;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (!items[i].points.empty()) idx.push_back(static_cast<int>(i));
  }
  std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) {
    return items[static_cast<std::size_t>(a)].*measure >
           items[static_cast<std::size_t>(b)].*measure;
  });
  return idx;
}

}  // namespace

const std::vector<ComparisonDef>& ThesisComparisons() {
  static const std::vector<ComparisonDef> defs = [] {
    std::vector<ComparisonDef> d;
    const std::string trend_i = "the more flexible (lower) rod gives larger accelerations";
    const std::string trend_ii = "aluminium highest, steel above brass";
    const std::string trend_iii = "1.0 mm clearance gives larger accelerations than 0.5 mm";
    // Group I (Table 3): same material, different heights; expected order = ascending height.
    const std::vector<std::vector<ComparisonItem>> group_i = {
        {kAl19, kAl25}, {kBr12, kBr19}, {kSt12, kSt19, kSt25}};
    int n = 1;
    for (double c : {0.5e-3, 1.0e-3}) {
      for (bool positive : {false, true}) {
        for (const auto& rods : group_i) {
          ComparisonDef def;
          def.number = n++;
          def.group = "I";
          def.positive = positive;
          def.items = AtClearance(rods, c);
          for (std::size_t i = 0; i < rods.size(); ++i)
            def.expected_order.push_back(static_cast<int>(i));
          def.trend = trend_i;
          const bool observed = def.number == 1 || def.number == 3 || def.number == 4 ||
                                def.number == 6 || def.number == 7 || def.number == 9 ||
                                def.number == 10;
          def.thesis_note =
              observed ? "observed in the experiments, plots 1, 3, 4, 6, 7, 9, 10"
                       : "not reported as holding; weaker with positive points, and the 12.7 mm "
                         "rods were unreliable as the clamp's off-axis weight twisted the rod";
          d.push_back(def);
        }
      }
    }
    // Group II (Table 4): same height, different materials; the thesis found aluminium highest
    // and steel above brass (plot 14).
    struct Set {
      std::vector<ComparisonItem> rods;
      std::vector<int> expected;
    };
    const std::vector<Set> group_ii = {
        {{kBr12, kSt12}, {1, 0}}, {{kAl19, kBr19, kSt19}, {0, 2, 1}}, {{kAl25, kSt25}, {0, 1}}};
    const std::pair<double, bool> blocks[4] = {
        {0.5e-3, false}, {1.0e-3, false}, {0.5e-3, true}, {1.0e-3, true}};
    for (const auto& [c, positive] : blocks) {
      for (const Set& s : group_ii) {
        ComparisonDef def;
        def.number = n++;
        def.group = "II";
        def.positive = positive;
        def.items = AtClearance(s.rods, c);
        def.expected_order = s.expected;
        def.trend = trend_ii;
        def.thesis_note =
            def.number == 14 ? "observed in plot 14; quasi-static stiffness is not the whole story"
            : def.number == 23 ? "differences shrink under high side thrust, plot 23"
                               : "the group II finding, aluminium highest and steel above brass";
        d.push_back(def);
      }
    }
    // Group III (Table 5): clearance, all rods, negative points.
    ComparisonDef def;
    def.number = n++;
    def.group = "III";
    def.positive = false;
    def.items = {{"0.5 mm (all rods)", "", 0.0, 0.5e-3}, {"1.0 mm (all rods)", "", 0.0, 1.0e-3}};
    def.expected_order = {1, 0};
    def.trend = trend_iii;
    def.thesis_note = "observed, 1.0 mm clearly gives larger forces over 81 tests";
    d.push_back(def);
    return d;
  }();
  return defs;
}

namespace {

/// One item of a comparison over the stored runs: its points (turning points of the positive or
/// negative slider acceleration), their median, p95 and maximum |a| [m/s^2], its runs and
/// failures; `by_speed` receives the |a| of its points per crank speed for the bootstrap.
ItemResult CollectItem(const ComparisonItem& item, bool positive,
                       const std::vector<StoredRun>& runs, const std::vector<RunFacts>& facts,
                       const std::set<double>& speeds, BySpeed* by_speed_out) {
  BySpeed& by_speed = *by_speed_out;
  ItemResult ir;
  ir.item = item;
  std::vector<double> magnitudes;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    if (!Matches(item, facts[r])) continue;
    if (!runs[r].ok()) {
      ++ir.num_failed;
      continue;
    }
    if (!speeds.count(facts[r].speed)) continue;  // not a speed every item has
    ++ir.num_runs;
    const StoredPoints& p = positive ? runs[r].positive : runs[r].negative;
    for (std::size_t k = 0; k < p.value.size(); ++k) {
      ir.points.push_back({runs[r].id, facts[r].speed, p.crank_angle[k], p.value[k]});
      magnitudes.push_back(std::abs(p.value[k]));
      by_speed[facts[r].speed].push_back(std::abs(p.value[k]));
    }
  }
  if (magnitudes.empty()) {
    ir.median = ir.median_low = ir.median_high = ir.p95 = ir.max = kNaN;
  } else {
    std::sort(magnitudes.begin(), magnitudes.end());
    ir.median = PercentileOfSorted(magnitudes, 50.0);
    ir.p95 = PercentileOfSorted(magnitudes, 95.0);
    ir.max = magnitudes.back();
  }
  return ir;
}

/// The bootstrap intervals of the items' medians and of each adjacent gap of the ranking;
/// `res.resolved` false where a gap's interval reaches 0, each such gap described in the
/// returned text.
std::string ResolveRanking(const std::vector<BySpeed>& by_speed_of_item, ComparisonResult* result) {
  ComparisonResult& res = *result;
  std::string overlap;
  if (res.evaluable) {
    const BootstrapResult boot = PairedBootstrap(by_speed_of_item, res.ranking);
    for (std::size_t i = 0; i < res.items.size(); ++i) {
      if (res.items[i].points.empty()) continue;
      std::tie(res.items[i].median_low, res.items[i].median_high) = boot.item_interval[i];
    }
    for (std::size_t k = 0; k + 1 < res.ranking.size(); ++k) {
      const ItemResult& hi = res.items[static_cast<std::size_t>(res.ranking[k])];
      const ItemResult& lo = res.items[static_cast<std::size_t>(res.ranking[k + 1])];
      const auto [gap_low, gap_high] = boot.gap_interval[k];
      res.gap_low.push_back(gap_low);
      if (!(gap_low > 0.0)) {
        res.resolved = false;
        overlap += std::string(overlap.empty() ? "" : "; ") + hi.item.label + " − " +
                   lo.item.label +
                   Format(" = %.3g [%.3g, %.3g]", hi.median - lo.median, gap_low, gap_high);
      }
    }
  }
  return overlap;
}

/// The verdict line of a comparison: the thesis's trend and what the model says of it.
std::string VerdictLine(const ComparisonResult& res, const std::vector<int>& expected,
                        const std::string& overlap) {
  const ComparisonDef& def = res.def;
  std::string line = "Thesis trend: " + def.trend + ". Thesis: " + def.thesis_note + ". ";
  line += "Loads at the " + std::to_string(res.common_speeds.size()) +
          " speeds every rod has (two-level bootstrap over speeds and runs): ";
  for (std::size_t k = 0; k < res.loads.size(); ++k) {
    const LoadVerdict& v = res.loads[k];
    line += (k ? "; " : "") + v.metric + " " + v.verdict +
            (v.detail.empty() ? "" : " (" + v.detail + ")");
  }
  if (!res.excluded_speeds.empty())
    line += "; excluded speeds (not run for every rod): " + SpeedsText(res.excluded_speeds);
  line += ". Ripple (median |a| at the turning points, the thesis's metric): ";
  if (!res.evaluable) {
    line += "not evaluable (fewer than two of its rods have turning points in this store).";
  } else if (!res.resolved) {
    line +=
        "not resolved: the 95 % interval of the difference of medians (bootstrap over the "
        "speeds) includes 0: " +
        overlap + " m/s^2; the medians alone would say the trend " +
        (res.trend_holds ? "holds." : "does not hold.");
  } else if (res.trend_holds) {
    line += std::string("holds") +
            (res.trend_holds_p95 ? " (median and 95th percentile)"
                                 : " by the median, not by the 95th percentile") +
            ": " + OrderText(res.items, res.ranking) + ".";
  } else {
    line += "does not hold: " + OrderText(res.items, res.ranking) + " by the median (expected " +
            OrderText(res.items, expected) + ")" +
            (res.trend_holds_p95 ? ", but holds by the 95th percentile." : ".");
  }
  return line;
}

/// The speeds of the completed runs of each item; `common` receives those every item with runs
/// has, `excluded` the others.
void CommonSpeeds(const ComparisonDef& def, const std::vector<StoredRun>& runs,
                  const std::vector<RunFacts>& facts, std::set<double>* common,
                  std::vector<double>* excluded) {
  std::set<double> all;
  bool first = true;
  for (const ComparisonItem& item : def.items) {
    std::set<double> mine;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      if (runs[r].ok() && Matches(item, facts[r])) mine.insert(facts[r].speed);
    }
    if (mine.empty()) continue;  // an item without runs constrains nothing
    all.insert(mine.begin(), mine.end());
    if (first) {
      *common = mine;
      first = false;
    } else {
      std::set<double> both;
      std::set_intersection(common->begin(), common->end(), mine.begin(), mine.end(),
                            std::inserter(both, both.begin()));
      *common = both;
    }
  }
  for (double sp : all) {
    if (!common->count(sp)) excluded->push_back(sp);
  }
}

/// A run's value of a load metric (LoadMetrics()), NaN if it has none.
double MetricOf(const StoredRun& run, const std::string& metric, bool positive) {
  if (metric == "amplification_p95")
    return run.Summary(positive ? "amplification_positive_p95" : "amplification_negative_p95");
  return run.Summary(metric);
}

constexpr int kLoadDraws = 2000;

/// The load metric `metric` of a comparison's items at the common speeds (LoadVerdict).
LoadVerdict JudgeLoad(const ComparisonResult& res, const std::string& metric,
                      const std::vector<StoredRun>& runs, const std::vector<RunFacts>& facts,
                      const std::set<double>& common) {
  LoadVerdict v;
  v.metric = metric;
  v.unit = metric == "gauge_stress_p95" ? "Pa" : "1";
  const std::size_t n = res.def.items.size();
  const std::vector<double> speeds(common.begin(), common.end());
  // values[i][s]: the metric of item i's runs at speed s.
  std::vector<std::vector<std::vector<double>>> values(
      n, std::vector<std::vector<double>>(speeds.size()));
  std::vector<bool> has(n, !speeds.empty());
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t r = 0; r < runs.size(); ++r) {
      if (!runs[r].ok() || !Matches(res.def.items[i], facts[r])) continue;
      const auto it = std::find(speeds.begin(), speeds.end(), facts[r].speed);
      const double x = MetricOf(runs[r], metric, res.def.positive);
      if (it != speeds.end() && std::isfinite(x))
        values[i][static_cast<std::size_t>(it - speeds.begin())].push_back(x);
    }
    for (const std::vector<double>& at : values[i]) has[i] = has[i] && !at.empty();
  }
  auto mean = [](const std::vector<double>& x) {
    double s = 0.0;
    for (double e : x) s += e;
    return s / static_cast<double>(x.size());
  };
  v.value.assign(n, kNaN);
  v.low.assign(n, kNaN);
  v.high.assign(n, kNaN);
  for (std::size_t i = 0; i < n; ++i) {
    if (!has[i]) continue;
    std::vector<double> per_speed;
    for (const std::vector<double>& at : values[i]) per_speed.push_back(mean(at));
    v.value[i] = mean(per_speed);
    v.ranking.push_back(static_cast<int>(i));
  }
  std::stable_sort(v.ranking.begin(), v.ranking.end(), [&](int a, int b) {
    return v.value[static_cast<std::size_t>(a)] > v.value[static_cast<std::size_t>(b)];
  });
  std::vector<int> expected;
  for (int i : res.def.expected_order) {
    if (has[static_cast<std::size_t>(i)]) expected.push_back(i);
  }
  if (expected.size() < 2) {
    v.verdict = "not evaluable";
    return v;
  }
  std::mt19937_64 gen(kBootstrapSeed);
  std::uniform_int_distribution<std::size_t> pick(0, speeds.size() - 1);
  std::vector<std::vector<double>> draws(n), gaps(expected.size() - 1);
  std::vector<double> item(n);
  for (int d = 0; d < kLoadDraws; ++d) {
    std::vector<std::size_t> drawn(speeds.size());
    for (std::size_t& s : drawn) s = pick(gen);
    for (std::size_t i = 0; i < n; ++i) {
      if (!has[i]) continue;
      double total = 0.0;
      for (std::size_t s : drawn) {
        const std::vector<double>& at = values[i][s];
        std::uniform_int_distribution<std::size_t> member(0, at.size() - 1);
        double m = 0.0;
        for (std::size_t k = 0; k < at.size(); ++k) m += at[member(gen)];
        total += m / static_cast<double>(at.size());
      }
      item[i] = total / static_cast<double>(drawn.size());
      draws[i].push_back(item[i]);
    }
    for (std::size_t k = 0; k + 1 < expected.size(); ++k)
      gaps[k].push_back(item[static_cast<std::size_t>(expected[k])] -
                        item[static_cast<std::size_t>(expected[k + 1])]);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!has[i]) continue;
    std::sort(draws[i].begin(), draws[i].end());
    v.low[i] = PercentileOfSorted(draws[i], 2.5);
    v.high[i] = PercentileOfSorted(draws[i], 97.5);
  }
  bool all_above = true, any_below = false;
  for (std::size_t k = 0; k < gaps.size(); ++k) {
    std::sort(gaps[k].begin(), gaps[k].end());
    const double lo = PercentileOfSorted(gaps[k], 2.5), hi = PercentileOfSorted(gaps[k], 97.5);
    all_above = all_above && lo > 0.0;
    any_below = any_below || hi < 0.0;
    const std::size_t a = static_cast<std::size_t>(expected[k]),
                      b = static_cast<std::size_t>(expected[k + 1]);
    v.detail += std::string(v.detail.empty() ? "" : "; ") + res.def.items[a].label + " − " +
                res.def.items[b].label +
                Format(" = %.3g [%.3g, %.3g]", v.value[a] - v.value[b], lo, hi);
  }
  v.verdict = all_above ? "holds" : any_below ? "reversed" : "not resolved";
  return v;
}

}  // namespace

const std::vector<std::string>& LoadMetrics() {
  static const std::vector<std::string> metrics = {
      "amplification_p95", "amplification_bearing_force_p95", "gauge_stress_p95"};
  return metrics;
}

std::vector<ComparisonResult> RunComparisons(const std::vector<ComparisonDef>& defs,
                                             const std::vector<StoredRun>& runs) {
  std::vector<RunFacts> facts;
  facts.reserve(runs.size());
  for (const StoredRun& r : runs) facts.push_back(FactsOf(r));
  std::vector<ComparisonResult> results;
  for (const ComparisonDef& def : defs) {
    ComparisonResult res;
    res.def = def;
    std::set<double> common;
    CommonSpeeds(def, runs, facts, &common, &res.excluded_speeds);
    res.common_speeds.assign(common.begin(), common.end());
    std::vector<BySpeed> by_speed_of_item;
    for (const ComparisonItem& item : def.items) {
      res.items.push_back(
          CollectItem(item, def.positive, runs, facts, common, &by_speed_of_item.emplace_back()));
    }
    for (const std::string& metric : LoadMetrics())
      res.loads.push_back(JudgeLoad(res, metric, runs, facts, common));
    res.ranking = RankBy(res.items, &ItemResult::median);
    const std::vector<int> by_p95 = RankBy(res.items, &ItemResult::p95);
    std::vector<int> expected;
    for (int i : def.expected_order) {
      if (!res.items[static_cast<std::size_t>(i)].points.empty()) expected.push_back(i);
    }
    res.evaluable = res.ranking.size() >= 2;
    res.trend_holds = res.evaluable && res.ranking == expected;
    res.trend_holds_p95 = res.evaluable && by_p95 == expected;
    res.resolved = res.evaluable;
    const std::string overlap = ResolveRanking(by_speed_of_item, &res);
    res.verdict = VerdictLine(res, expected, overlap);
    results.push_back(std::move(res));
  }
  return results;
}

void WriteComparisonFiles(const ComparisonResult& res, const std::string& dir) {
  const ComparisonDef& d = res.def;
  const std::string stem = dir + "/comparison_" + Two(d.number);
  auto rank_of = [](const std::vector<int>& ranking, int i) {
    for (std::size_t k = 0; k < ranking.size(); ++k) {
      if (ranking[k] == i) return std::to_string(k + 1);
    }
    return std::string("-");
  };
  const std::vector<int> by_p95 = RankBy(res.items, &ItemResult::p95);
  const std::vector<int> by_max = RankBy(res.items, &ItemResult::max);
  // Rows: ranked items first, then those without points.
  std::vector<int> rows = res.ranking;
  for (std::size_t i = 0; i < res.items.size(); ++i) {
    if (res.items[i].points.empty()) rows.push_back(static_cast<int>(i));
  }
  std::ostringstream md, csv, pts;
  md << "# Comparison " << d.number << " — group " << d.group << ", clearance " << ClearanceText(d)
     << ", " << Direction(d) << " points\n\n";
  md << "Rods ranked by their loads at the speeds every rod was run at ("
     << SpeedsText(res.common_speeds)
     << "): the load amplification (95th percentile of the per-revolution peaks, " << Direction(d)
     << " direction), the bearing-force amplification and the gauge stress (95th percentiles of "
        "the per-revolution peaks), each the mean over those speeds of the mean over the runs "
        "(ensemble members) at a speed, with a 95 % interval from a two-level bootstrap (speeds, "
        "then runs). The thesis's measure, the median |acceleration| at the turning points "
        "beyond the noise floor, follows as the ripple of the acceleration.\n\n";
  md << res.verdict << "\n\n";
  md << "| rod |";
  for (const LoadVerdict& v : res.loads) md << " " << v.metric << " [" << v.unit << "] |";
  md << "\n|---|";
  for (std::size_t k = 0; k < res.loads.size(); ++k) md << "---|";
  md << "\n";
  for (std::size_t i = 0; i < res.items.size(); ++i) {
    md << "| " << res.items[i].item.label << " |";
    for (const LoadVerdict& v : res.loads)
      md << " " << Num(v.value[i]) << " [" << Num(v.low[i]) << ", " << Num(v.high[i]) << "] |";
    md << "\n";
  }
  md << "\n| verdict |";
  for (const LoadVerdict& v : res.loads) md << " " << v.verdict << " |";
  md << "\n|---|";
  for (std::size_t k = 0; k < res.loads.size(); ++k) md << "---|";
  md << "\n\nRipple: turning points at the common speeds.\n\n";
  md << "| rank | rod | runs | failed | points | median \\|a\\| [m/s^2] | its 95 % interval "
        "[m/s^2] | p95 \\|a\\| [m/s^2] | max \\|a\\| [m/s^2] | "
        "rank by p95 | rank by max |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  csv << "rank,item,runs,failed,points,median [m/s^2],median_low [m/s^2],median_high [m/s^2],"
         "p95 [m/s^2],max [m/s^2],rank_p95,rank_max";
  for (const LoadVerdict& v : res.loads) {
    csv << "," << v.metric << " [" << v.unit << "]," << v.metric << "_low [" << v.unit << "],"
        << v.metric << "_high [" << v.unit << "]";
  }
  csv << "\n";
  for (int i : rows) {
    const ItemResult& it = res.items[static_cast<std::size_t>(i)];
    const std::string rank = rank_of(res.ranking, i);
    md << "| " << rank << " | " << it.item.label << " | " << it.num_runs << " | " << it.num_failed
       << " | " << it.points.size() << " | " << Num(it.median) << " | " << Num(it.median_low)
       << " – " << Num(it.median_high) << " | " << Num(it.p95) << " | " << Num(it.max) << " | "
       << rank_of(by_p95, i) << " | " << rank_of(by_max, i) << " |\n";
    csv << rank << "," << CsvField(it.item.label) << "," << it.num_runs << "," << it.num_failed
        << "," << it.points.size() << "," << Num(it.median) << "," << Num(it.median_low) << ","
        << Num(it.median_high) << "," << Num(it.p95) << "," << Num(it.max) << ","
        << rank_of(by_p95, i) << "," << rank_of(by_max, i);
    const std::size_t ui = static_cast<std::size_t>(i);
    for (const LoadVerdict& v : res.loads)
      csv << "," << Num(v.value[ui]) << "," << Num(v.low[ui]) << "," << Num(v.high[ui]);
    csv << "\n";
  }
  pts << "item,run_id,speed [rpm],crank_angle [deg],acceleration [m/s^2]\n";
  pts.precision(10);
  for (const ItemResult& it : res.items) {
    for (const AgglomeratedPoint& p : it.points) {
      pts << CsvField(it.item.label) << "," << p.run_id << "," << p.speed * kRpm << ","
          << p.crank_angle * 180.0 / std::numbers::pi << "," << p.acceleration << "\n";
    }
  }
  WriteFileAtomic(stem + ".md", md.str());
  WriteFileAtomic(stem + ".csv", csv.str());
  WriteFileAtomic(stem + "_points.csv", pts.str());
}

void WriteComparisonIndex(const std::vector<ComparisonResult>& results, const std::string& store,
                          const std::string& dir) {
  std::ostringstream md;
  md << "# Comparisons of " << store
     << "\n\nThe thesis's comparison groups (RIG.md §4, Tables 3–5). "
     << "Each line: the trend the thesis reports and whether the model shows it, by each load "
        "metric at the speeds every rod was run at (holds / reversed / not resolved: the 95 % "
        "interval of every difference in the expected order is above 0, one is below 0, or "
        "neither; two-level bootstrap over speeds and runs), and by the thesis's ripple measure "
        "(median |acceleration| at the turning points).\n\n| # | group | clearance | points | "
        "rods |";
  for (const std::string& m : LoadMetrics()) md << " " << m << " |";
  md << " ripple |\n|---|---|---|---|---|";
  for (std::size_t k = 0; k < LoadMetrics().size(); ++k) md << "---|";
  md << "---|\n";
  int holds = 0, evaluable = 0, resolved = 0;
  std::map<std::string, std::map<std::string, int>> load_counts;  // metric → verdict → count
  for (const ComparisonResult& r : results) {
    std::string rods;
    for (const ComparisonItem& i : r.def.items) rods += (rods.empty() ? "" : ", ") + i.label;
    const std::string model = !r.evaluable    ? "not evaluable"
                              : !r.resolved   ? "not resolved"
                              : r.trend_holds ? "trend holds"
                                              : "trend does not hold";
    md << "| [" << r.def.number << "](comparison_" << Two(r.def.number) << ".md) | " << r.def.group
       << " | " << ClearanceText(r.def) << " | " << Direction(r.def) << " | " << rods << " |";
    for (const LoadVerdict& v : r.loads) {
      md << " " << v.verdict << " |";
      ++load_counts[v.metric][v.verdict];
    }
    md << " " << model << " |\n";
    evaluable += r.evaluable ? 1 : 0;
    resolved += r.resolved ? 1 : 0;
    holds += r.resolved && r.trend_holds ? 1 : 0;
  }
  md << "\n";
  for (const std::string& m : LoadMetrics()) {
    std::string counts;
    for (const char* verdict : {"holds", "reversed", "not resolved", "not evaluable"})
      counts += (counts.empty() ? "" : ", ") + std::string(verdict) + " " +
                std::to_string(load_counts[m][verdict]);
    md << "- " << m << ": " << counts << "\n";
  }
  md << "\nRipple: the trend holds in " << holds << " of " << resolved << " resolved comparisons; "
     << evaluable - resolved << " of the " << evaluable
     << " evaluable ones are not resolved (the 95 % interval of a difference of medians "
        "includes 0: the runs cannot order those rods).\n\n";
  for (const ComparisonResult& r : results)
    md << "- **" << r.def.number << "**: " << r.verdict << "\n";
  WriteFileAtomic(dir + "/comparisons.md", md.str());
}

void WriteSweepSummaryCsv(const SweepStore& store, const std::string& path) {
  std::ostringstream csv;
  csv << "run_id,status,speed [rpm],clearance [mm],line,peak_positive [m/s^2],peak_negative "
         "[m/s^2],"
         "ideal_peak_positive [m/s^2],ideal_peak_negative [m/s^2],amplification_positive [1],"
         "amplification_negative [1],amplification_positive_p95 [1],amplification_negative_p95 [1],"
         "num_inflection_positive [1],num_inflection_negative [1],message\n";
  for (const StoredRun& r : store.runs) {
    const Config cfg = r.Input();
    const bool clearance = cfg.Text("joint.type") == "clearance" && FindParam("joint.clearance");
    // The line of the plot: every varying value except speed and clearance.
    std::string line;
    std::stringstream ss(r.label);
    std::string item;
    while (std::getline(ss, item, ',')) {
      const std::size_t b = item.find_first_not_of(' ');
      if (b == std::string::npos) continue;
      item = item.substr(b);
      const std::size_t eq = item.find('=');
      const std::string key = item.substr(0, eq);
      if (eq == std::string::npos || key == "drive.speed" || key == "joint.clearance") continue;
      line += (line.empty() ? "" : " ") + item.substr(eq + 1);
    }
    csv << r.id << "," << r.status << "," << Num(cfg.Quantity("drive.speed") * kRpm) << ","
        << (clearance ? Num(cfg.Quantity("joint.clearance") * 1e3) : std::string()) << ","
        << CsvField(line.empty() ? "all" : line);
    for (const char* s :
         {"peak_positive", "peak_negative", "ideal_peak_positive", "ideal_peak_negative",
          "amplification_positive", "amplification_negative", "amplification_positive_p95",
          "amplification_negative_p95", "num_inflection_positive", "num_inflection_negative"}) {
      csv << "," << Num(r.Summary(s));
    }
    csv << "," << CsvField(r.message) << "\n";
  }
  WriteFileAtomic(path, csv.str());
}

}  // namespace flexrod::study
