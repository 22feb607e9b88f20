// tests/run/clearance_trends_slowtest.cc — the thesis's friction × clearance study on the rigid
// rig (RIG.md §1, section 3.4, Fig. 39): preset rigid-rig with joint.type = clearance (hybrid
// law, restitution 0.9, Coulomb friction), clearance 0.5 vs 1.0 mm × joint friction 0.2 vs 0.6,
// at 101 and 177 rpm, 0.5 s settling then 4 revolutions, integrator tolerances 1e-8/1e-10. Per
// revolution the peak |slider acceleration| is taken (signals/signals.h SplitRevolutions), and its
// median over the revolutions is the measure (the thesis judged single peaks too scattered). Trends
// to reproduce (RIG.md §1 conclusions): the amplification grows with clearance and with joint
// friction. The test asserts both orders at both speeds, checks the impact log of each run is
// consistent with its channels, and prints every number (median, max, amplification over the
// ideal twin, impacts per revolution, wall time) for the lead to quote.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "input/presets.h"
#include "mechanisms/impact_log.h"
#include "run/run.h"
#include "signals/signals.h"

namespace flexrod {
namespace {

struct TrendPoint {
  double median_peak{0.0};  // median over revolutions of the per-revolution peak |a| [m/s²]
  double max_peak{0.0};     // [m/s²]
  double ideal_peak{0.0};   // ideal twin, max |a| [m/s²]
  double impacts_per_rev{0.0};
  double wall{0.0};  // [s]
  std::size_t revolutions{0};
};

TrendPoint RunPoint(const std::string& rpm, const std::string& clearance, const std::string& mu) {
  Config cfg;
  cfg.LoadToml(FindPreset("rigid-rig")->toml, "rigid-rig");
  cfg.Set("joint.type", "clearance");
  cfg.Set("joint.clearance", clearance);
  cfg.Set("joint.friction", mu);
  cfg.Set("drive.speed", rpm);
  cfg.Set("sim.settle", "0.5 s");
  // Impact peaks need tighter tolerances than the rig default (1e-6/1e-8): measured at 177 rpm,
  // 1 mm, μ = 0.2, the largest peak moves by ≈ 20 % between 1e-6/1e-8 and 1e-8/1e-10.
  cfg.Set("sim.rel_tol", "1e-8");
  cfg.Set("sim.abs_tol", "1e-10");
  // 4 revolutions (+ a little so the 4th closes at the next index crossing).
  cfg.Set("sim.capture",
          std::to_string(4.02 * 2.0 * std::numbers::pi / cfg.Quantity("drive.speed")) + " s");
  const auto t0 = std::chrono::steady_clock::now();
  const RunResult run = RunSimulation(cfg);
  TrendPoint p;
  p.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(run.ok()) << run.status.Summary();
  const study::PeakStatistics peaks =
      study::CalcSignalSummary(run.channels, "slider_acceleration", "crank_angle", 0.0,
                               run.channels.all())
          .magnitude;  // per-revolution peaks of |a|
  p.revolutions = peaks.num_revolutions;
  if (p.revolutions == 0) return p;
  p.median_peak = peaks.median;
  p.max_peak = peaks.max;
  if (run.ideal) {
    for (double v : run.ideal->values("slider_acceleration"))
      p.ideal_peak = std::max(p.ideal_peak, std::abs(v));
  }
  // The impact log sees every sample as well as the integrator's points between them.
  const std::vector<study::Impact>& log = run.impacts;
  const study::ImpactStatistics st = study::CalcImpactStatistics(log);
  double channel_peak = 0.0;
  for (double f : run.channels.values("contact_normal_force"))
    channel_peak = std::max(channel_peak, f);
  EXPECT_FALSE(log.empty());  // a run-long sliding contact is one incomplete entry
  double log_peak = 0.0;
  for (const study::Impact& im : log) log_peak = std::max(log_peak, im.peak_force);
  EXPECT_GE(log_peak, channel_peak);
  for (const study::Impact& im : log) {
    if (im.complete) {
      EXPECT_GT(im.duration, 0.0);
    }
  }
  p.impacts_per_rev = static_cast<double>(st.count) / static_cast<double>(p.revolutions);
  return p;
}

TEST(ClearanceTrends, AmplificationGrowsWithClearanceAndWithJointFriction) {
  std::printf("rigid rig, hybrid law, e = 0.9, Coulomb friction; per-revolution peak |a_slider|\n");
  std::printf("%8s %10s %6s %12s %12s %12s %10s %9s %8s\n", "speed", "clearance", "mu",
              "median [m/s2]", "max [m/s2]", "ideal [m/s2]", "ampl(med)", "imp/rev", "wall[s]");
  for (const std::string rpm : {"101 rpm", "177 rpm"}) {
    std::map<std::string, TrendPoint> r;
    for (const std::string c : {"0.5 mm", "1.0 mm"}) {
      for (const std::string mu : {"0.2", "0.6"}) {
        const TrendPoint p = RunPoint(rpm, c, mu);
        r[c + "/" + mu] = p;
        std::printf("%8s %10s %6s %12.1f %12.1f %12.2f %10.1f %9.1f %8.2f\n", rpm.c_str(),
                    c.c_str(), mu.c_str(), p.median_peak, p.max_peak, p.ideal_peak,
                    p.ideal_peak > 0 ? p.median_peak / p.ideal_peak : NAN, p.impacts_per_rev,
                    p.wall);
        EXPECT_GE(p.revolutions, 3u);
      }
    }
    SCOPED_TRACE(rpm);
    // Clearance: 1.0 mm above 0.5 mm at both frictions and both speeds.
    EXPECT_GT(r["1.0 mm/0.2"].median_peak, r["0.5 mm/0.2"].median_peak);
    EXPECT_GT(r["1.0 mm/0.6"].median_peak, r["0.5 mm/0.6"].median_peak);
    // Clearance at μ = 0.6, 177 rpm is the thinnest margin: 1251 vs 1190 m/s² with the calibrated
    // guide (examples/rigid-rig.toml); other guides that also give the thesis's 40× at 101 rpm
    // reverse it there.
    // Friction: 0.6 above 0.2 at both clearances and both speeds. (With the earlier guide,
    // 2 N Coulomb, the order reversed at 101 rpm, 1.0 mm: 1.83e3 vs 1.47e3 m/s².)
    EXPECT_GT(r["0.5 mm/0.6"].median_peak, r["0.5 mm/0.2"].median_peak);
    EXPECT_GT(r["1.0 mm/0.6"].median_peak, r["1.0 mm/0.2"].median_peak);
  }
}

}  // namespace
}  // namespace flexrod
