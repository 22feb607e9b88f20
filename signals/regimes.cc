// SPDX-License-Identifier: GPL-3.0-or-later
#include "signals/regimes.h"

#include <gsl/gsl_cdf.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "common/error.h"
#include "signals/signals.h"

namespace flexrod::study {
namespace {

double Mean(std::span<const double> x) {
  double s = 0.0;
  for (double v : x) s += v;
  return s / static_cast<double>(x.size());
}

/// Sample variance (n − 1 in the denominator); 0 for fewer than 2 values.
double Variance(std::span<const double> x) {
  if (x.size() < 2) return 0.0;
  const double m = Mean(x);
  double s = 0.0;
  for (double v : x) s += (v - m) * (v - m);
  return s / static_cast<double>(x.size() - 1);
}

double Median(std::span<const double> x) { return Percentile(x, 50.0); }

}  // namespace

StationarityResult TestStationarity(std::span<const double> series, double alpha, double floor) {
  StationarityResult r;
  const std::size_t n = series.size();
  if (n < 4) return r;
  r.tested = true;
  const std::size_t blocks = n / 2;
  double closest = -1.0;  // largest |m₁ − m₂| / limit so far
  for (std::size_t j = 1; j <= blocks; ++j) {
    const std::span<const double> a = series.first(j), b = series.last(n - j);
    const double m1 = Mean(a), m2 = Mean(b);
    const double se =
        std::sqrt(Variance(b) * (1.0 / static_cast<double>(j) + 1.0 / static_cast<double>(n - j)));
    const double t = gsl_cdf_tdist_Qinv(alpha / (2.0 * static_cast<double>(blocks)),
                                        static_cast<double>(n - j - 1));
    const double limit = std::max(t * se, floor * std::abs(m2));
    const double d = std::abs(m1 - m2);
    const double ratio = limit > 0.0 ? d / limit : (d > 0.0 ? INFINITY : 0.0);
    if (ratio > closest) {
      closest = ratio;
      r.leading = static_cast<int>(j);
      r.first_mean = m1;
      r.second_mean = m2;
      r.limit = limit;
    }
  }
  // The trend: x_r = a + b r by least squares; its change over the window (n − 1) b against
  // t · se(b) (n − 2 degrees of freedom) and the floor. A drift inflates the variance the block
  // comparisons use; the fit's residual does not carry it.
  const double nd = static_cast<double>(n), rm = 0.5 * (nd - 1.0), xm = Mean(series);
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (static_cast<double>(i) - rm) * (static_cast<double>(i) - rm);
    sxy += (static_cast<double>(i) - rm) * (series[i] - xm);
  }
  const double slope = sxy / sxx;
  double ssr = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double e = series[i] - xm - slope * (static_cast<double>(i) - rm);
    ssr += e * e;
  }
  const double se = std::sqrt(ssr / (nd - 2.0) / sxx) * (nd - 1.0);
  const double t = gsl_cdf_tdist_Qinv(alpha / (2.0 * static_cast<double>(blocks + 1)), nd - 2.0);
  const double limit = std::max(t * se, floor * std::abs(xm));
  const double change = std::abs(slope) * (nd - 1.0);
  const double ratio = limit > 0.0 ? change / limit : (change > 0.0 ? INFINITY : 0.0);
  if (ratio > closest) {
    closest = ratio;
    r.leading = 0;
    r.first_mean = xm - slope * rm;
    r.second_mean = xm + slope * rm;
    r.limit = limit;
  }
  r.stationary = closest <= 1.0;
  return r;
}

StationarityVerdict TestStationarity(const std::vector<std::vector<double>>& series, double alpha,
                                     double floor) {
  StationarityVerdict v;
  const double each = alpha / static_cast<double>(std::max<std::size_t>(series.size(), 1));
  double worst = -1.0;
  for (std::size_t k = 0; k < series.size(); ++k) {
    const StationarityResult r = TestStationarity(series[k], each, floor);
    v.series.push_back(r);
    v.stationary = v.stationary && r.stationary;
    if (!r.tested) continue;
    const double d = std::abs(r.second_mean - r.first_mean);
    const double ratio = r.limit > 0.0 ? d / r.limit : (d > 0.0 ? INFINITY : 0.0);
    if (ratio > worst) {
      worst = ratio;
      v.worst = static_cast<int>(k);
    }
  }
  return v;
}

double PooledMean(std::span<const double> values) { return Mean(values); }

PooledStatistic PooledPercentile(double percent) {
  return [percent](std::span<const double> values) { return Percentile(values, percent); };
}

Interval BootstrapInterval(const std::vector<std::vector<double>>& members,
                           const PooledStatistic& statistic, const BootstrapOptions& options) {
  Require(!members.empty(), "bootstrap.members", static_cast<double>(members.size()),
          "an ensemble needs at least one member");
  for (const std::vector<double>& m : members) {
    Require(!m.empty(), "bootstrap.member", 0.0, "every member needs at least one revolution");
  }
  Require(options.confidence > 0.0 && options.confidence < 1.0, "bootstrap.confidence",
          options.confidence, "must lie in (0, 1)");
  Require(options.resamples >= 100, "bootstrap.resamples", options.resamples, "must be >= 100");
  Require(options.block_length >= 0, "bootstrap.block_length", options.block_length,
          "must be >= 0 (0: automatic)");
  std::vector<double> pool;
  for (const std::vector<double>& m : members) pool.insert(pool.end(), m.begin(), m.end());
  Interval out;
  out.centre = statistic(pool);
  std::mt19937_64 rng(options.seed);
  const std::size_t k = members.size();
  std::vector<double> replicates(static_cast<std::size_t>(options.resamples));
  std::vector<double> resample;
  resample.reserve(pool.size() * 2);
  for (double& rep : replicates) {
    resample.clear();
    for (std::size_t j = 0; j < k; ++j) {
      const std::vector<double>& m =
          k == 1 ? members[0] : members[std::uniform_int_distribution<std::size_t>(0, k - 1)(rng)];
      const std::size_t n = m.size();
      const std::size_t l =
          options.block_length > 0
              ? std::min<std::size_t>(static_cast<std::size_t>(options.block_length), n)
              : std::min<std::size_t>(
                    n, static_cast<std::size_t>(std::ceil(std::cbrt(static_cast<double>(n)))));
      std::uniform_int_distribution<std::size_t> start(0, n - l);
      for (std::size_t filled = 0; filled < n;) {
        const std::size_t s = start(rng);
        for (std::size_t i = 0; i < l && filled < n; ++i, ++filled) resample.push_back(m[s + i]);
      }
    }
    rep = statistic(resample);
  }
  std::sort(replicates.begin(), replicates.end());
  const double tail = 50.0 * (1.0 - options.confidence);
  out.low = PercentileOfSorted(replicates, tail);
  out.high = PercentileOfSorted(replicates, 100.0 - tail);
  return out;
}

double ZeroOneTestK(std::span<const double> phi, int num_c, std::uint64_t seed) {
  const std::size_t n = phi.size();
  Require(n >= 50, "zero_one_test.values", static_cast<double>(n),
          "the 0-1 test needs at least 50 values");
  const std::size_t ncut = n / 10;
  const double mean = Mean(phi);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> draw(std::numbers::pi / 5.0, 4.0 * std::numbers::pi / 5.0);
  std::vector<double> p(n), q(n), ks;
  std::vector<double> nn(ncut), d(ncut);
  for (std::size_t k = 0; k < ncut; ++k) nn[k] = static_cast<double>(k + 1);
  for (int ci = 0; ci < num_c; ++ci) {
    const double c = draw(rng);
    double ps = 0.0, qs = 0.0;
    for (std::size_t j = 0; j < n; ++j) {
      ps += phi[j] * std::cos(static_cast<double>(j + 1) * c);
      qs += phi[j] * std::sin(static_cast<double>(j + 1) * c);
      p[j] = ps;
      q[j] = qs;
    }
    for (std::size_t k = 1; k <= ncut; ++k) {
      double m = 0.0;
      for (std::size_t j = 0; j + k < n; ++j) {
        const double dp = p[j + k] - p[j], dq = q[j + k] - q[j];
        m += dp * dp + dq * dq;
      }
      m /= static_cast<double>(n - k);
      const double osc =
          mean * mean * (1.0 - std::cos(static_cast<double>(k) * c)) / (1.0 - std::cos(c));
      d[k - 1] = m - osc;
    }
    // Correlation coefficient of (k, D_c(k)).
    const double mk = Mean(nn), md = Mean(d);
    double sxy = 0.0, sxx = 0.0, syy = 0.0;
    for (std::size_t k = 0; k < ncut; ++k) {
      sxy += (nn[k] - mk) * (d[k] - md);
      sxx += (nn[k] - mk) * (nn[k] - mk);
      syy += (d[k] - md) * (d[k] - md);
    }
    ks.push_back(syy > 0.0 ? sxy / std::sqrt(sxx * syy) : 0.0);
  }
  return Median(ks);
}

const char* ToString(WindowRegime r) {
  switch (r) {
    case WindowRegime::kPeriodic:
      return "periodic";
    case WindowRegime::kQuasiPeriodic:
      return "quasi-periodic";
    case WindowRegime::kChaotic:
      return "chaotic";
    case WindowRegime::kIntermittent:
      return "intermittent";
    case WindowRegime::kAperiodic:
      return "aperiodic";
    case WindowRegime::kUndetermined:
      break;
  }
  return "undetermined";
}

WindowClassification ClassifyWindow(const std::vector<std::vector<double>>& per_revolution,
                                    const RegimeOptions& options) {
  WindowClassification w;
  std::size_t n = per_revolution.empty() ? 0 : per_revolution.front().size();
  for (const std::vector<double>& x : per_revolution) n = std::min(n, x.size());
  if (n < 4) {
    w.reason = "fewer than 4 complete revolutions";
    return w;
  }
  std::vector<double> medians;
  for (const std::vector<double>& x : per_revolution) {
    const std::span<const double> s(x.data(), n);
    const double med = Median(s);
    medians.push_back(med);
    const auto [lo, hi] = std::minmax_element(s.begin(), s.end());
    if (med > 0.0) w.relative_spread = std::max(w.relative_spread, (*hi - *lo) / med);
  }
  // Periodic: one period p that every series repeats with.
  for (int p = 1; p <= 4 && static_cast<std::size_t>(p) + 2 <= n; ++p) {
    bool repeats = true;
    for (std::size_t k = 0; k < per_revolution.size() && repeats; ++k) {
      const double tol = options.repeat_tolerance * std::abs(medians[k]);
      for (std::size_t r = 0; r + static_cast<std::size_t>(p) < n && repeats; ++r)
        repeats = std::abs(per_revolution[k][r + static_cast<std::size_t>(p)] -
                           per_revolution[k][r]) <= tol;
    }
    if (repeats) {
      w.regime = WindowRegime::kPeriodic;
      w.period = p;
      w.reason = "the per-revolution peaks repeat every " + std::to_string(p) +
                 (p == 1 ? " revolution" : " revolutions");
      return w;
    }
  }
  // Intermittent: a few revolutions far above the rest.
  for (std::size_t k = 0; k < per_revolution.size(); ++k) {
    const std::span<const double> s(per_revolution[k].data(), n);
    std::vector<double> dev(n);
    for (std::size_t r = 0; r < n; ++r) dev[r] = std::abs(s[r] - medians[k]);
    const double sigma = 1.4826 * Median(dev);
    int outliers = 0;
    for (double v : s) {
      if (v > options.outlier_ratio * medians[k] && v - medians[k] > options.outlier_mads * sigma)
        ++outliers;
    }
    if (outliers > 0 && outliers <= options.max_outlier_share * static_cast<double>(n))
      w.outliers = std::max(w.outliers, outliers);
  }
  if (w.outliers > 0) {
    w.regime = WindowRegime::kIntermittent;
    w.reason = std::to_string(w.outliers) + " of " + std::to_string(n) +
               " revolutions peak far above the rest";
    return w;
  }
  if (n < kZeroOneMinRevolutions) {
    w.regime = WindowRegime::kAperiodic;
    w.reason = "the per-revolution peaks do not repeat; " + std::to_string(n) +
               " revolutions are too few for the 0-1 test to tell quasi-periodic from chaotic (" +
               std::to_string(kZeroOneMinRevolutions) + " needed)";
    return w;
  }
  w.zero_one_k = ZeroOneTestK(std::span<const double>(per_revolution.front().data(), n));
  w.regime = w.zero_one_k > options.chaos_k ? WindowRegime::kChaotic : WindowRegime::kQuasiPeriodic;
  w.reason = "the per-revolution peaks do not repeat; 0-1 test K = " + FormatValue(w.zero_one_k);
  return w;
}

SteadyStates GroupSteadyStates(const std::vector<std::vector<Interval>>& figures,
                               double tolerance) {
  SteadyStates out;
  const std::size_t k = figures.empty() ? 0 : figures.front().size();
  for (const std::vector<Interval>& f : figures) {
    FLEXROD_ASSERT(f.size() == k);
    (void)f;
  }
  auto alike = [&](std::size_t a, std::size_t b) {
    for (const std::vector<Interval>& f : figures) {
      const Interval& x = f[a];
      const Interval& y = f[b];
      const bool overlap = x.low <= y.high && y.low <= x.high;
      const double larger = std::max(std::abs(x.centre), std::abs(y.centre));
      if (!overlap && std::abs(x.centre - y.centre) > tolerance * larger) return false;
    }
    return true;
  };
  out.state.assign(k, -1);
  for (std::size_t m = 0; m < k; ++m) {
    if (out.state[m] >= 0) continue;
    // A new state: every member reachable from m through alike pairs.
    const int st = out.count++;
    std::vector<std::size_t> stack = {m};  // members joined, not yet searched from
    out.state[m] = st;
    while (!stack.empty()) {
      const std::size_t a = stack.back();
      stack.pop_back();
      for (std::size_t b = 0; b < k; ++b) {
        if (out.state[b] < 0 && alike(a, b)) {
          out.state[b] = st;
          stack.push_back(b);
        }
      }
    }
  }
  return out;
}

}  // namespace flexrod::study
