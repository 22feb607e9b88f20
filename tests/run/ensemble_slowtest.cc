// tests/run/ensemble_slowtest.cc — answers that hold on the flexible rig (DESIGN.md, "A run's
// answer is a distribution, not a number"), on Table 2 cases whose behaviour was measured with
// flexrod itself before these checks existed:
// - steel 12.7 mm, 0.5 mm, 200 rpm carries its start-up into a capture after the fixed 1 s settle
//   (its first captured revolution peaks at +105.8 m/s^2, the next ones at 100 ± 0.6): the steady
//   window must catch it and capture the next window;
// - aluminium 25.4 mm, 0.5 mm, 240 rpm settles into a steady state with a positive amplification
//   of 12.8 from a 0° crank start and 22.8 from 90° (20.8 while the rod's damping was referred
//   to the mechanism at the start's crank angle; an ensemble of 8 starts finds four states: 7.5,
//   12.8, 13.6 and 22.8): an ensemble of the two starts must report two steady states with those
//   figures, and an interval that spans both;
// - aluminium 19.05 mm, 0.5 mm, 200 rpm is intermittent (a revolution far above the rest);
// - member 0 of an ensemble is the single run, bit for bit.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <numbers>
#include <string>
#include <vector>

#include "input/presets.h"
#include "run/ensemble.h"
#include "run/run.h"

namespace flexrod {
namespace {

Config Rig(const std::string& material, const std::string& height, const std::string& rpm) {
  Config cfg;
  cfg.LoadToml(FindPreset("flexible-rig")->toml, "flexible-rig");
  cfg.Set("rod.material", material);
  cfg.Set("rod.height", height);
  cfg.Set("drive.speed", rpm);
  return cfg;
}

double Figure(const nlohmann::json& s, const char* name) {
  return s["load_amplification"][name].get<double>();
}

TEST(SteadyWindow, AStartUpLeftInTheCaptureIsSettledAway) {
  Config cfg = Rig("steel", "12.7 mm", "200 rpm");
  cfg.Set("ensemble.members", "1");
  const RunResult steady = RunSimulation(cfg);
  ASSERT_TRUE(steady.ok()) << steady.status.Summary();
  const nlohmann::json& w = steady.summary["steady_window"];
  EXPECT_EQ(w["windows"].get<int>(), 2) << w.dump(1);
  EXPECT_TRUE(w["stationary"].get<bool>());
  EXPECT_NEAR(w["capture_start [s]"].get<double>(), 4.2, 1e-9);
  cfg.Set("sim.steady_window", "false");
  const RunResult fixed = RunSimulation(cfg);
  ASSERT_TRUE(fixed.ok());
  EXPECT_FALSE(fixed.summary.contains("steady_window"));
  // The fixed settle's window peaks on its first revolution, 5 % above the steady one.
  const double biased = Figure(fixed.summary, "slider_acceleration_positive");
  const double settled = Figure(steady.summary, "slider_acceleration_positive");
  EXPECT_GT(biased, 1.03 * settled) << biased << " " << settled;
  // The biased window itself fails the test that the steady one passes.
  const auto series = PerRevolutionSeries(fixed);
  std::vector<std::vector<double>> values;
  for (const auto& [name, x] : series) values.push_back(x);
  EXPECT_FALSE(study::TestStationarity(values).stationary);
}

TEST(Ensemble, ABistableCaseReportsBothSteadyStates) {
  Config cfg = Rig("aluminium", "25.4 mm", "240 rpm");
  cfg.Set("ensemble.members", "2");
  cfg.Set("ensemble.angle_step", "90 deg");
  const RunResult run = RunEnsemble(cfg, {});
  ASSERT_TRUE(run.ok()) << run.status.Summary();
  const nlohmann::json& e = run.summary["ensemble"];
  ASSERT_EQ(e["regime"]["steady_states"].get<int>(), 2) << e.dump(1);
  ASSERT_EQ(e["states"].size(), 2u);
  const double low =
      e["states"][0]["figures"]["slider_acceleration_positive_p95"]["centre"].get<double>();
  const double high =
      e["states"][1]["figures"]["slider_acceleration_positive_p95"]["centre"].get<double>();
  EXPECT_NEAR(low, 12.8, 0.05 * 12.8);
  EXPECT_NEAR(high, 22.8, 0.05 * 22.8);
  // The ensemble's interval spans both states: the answer depends on the start, and says so.
  const nlohmann::json& f = e["figures"]["slider_acceleration_positive_p95"];
  EXPECT_LE(f["interval"][0].get<double>(), low * 1.01);
  EXPECT_GE(f["interval"][1].get<double>(), high * 0.99);
  // The second member started where it was asked to.
  EXPECT_NEAR(e["member_runs"][1]["drive.initial_angle [rad]"].get<double>(),
              std::numbers::pi / 2.0, 1e-12);
}

TEST(Ensemble, AnIntermittentWindowIsNamed) {
  Config cfg = Rig("aluminium", "19.05 mm", "200 rpm");
  cfg.Set("ensemble.members", "1");
  const RunResult run = RunSimulation(cfg);
  ASSERT_TRUE(run.ok()) << run.status.Summary();
  EXPECT_EQ(run.summary["regime"]["window"], "intermittent") << run.summary["regime"].dump(1);
  EXPECT_GE(run.summary["regime"]["outlier_revolutions"].get<int>(), 1);
}

TEST(Ensemble, MemberZeroIsTheSingleRunAndThePeriodicMainJobHasATightInterval) {
  Config cfg;
  cfg.LoadToml(FindPreset("flexible-rig")->toml, "flexible-rig");
  cfg.Set("ensemble.members", "2");
  const RunResult ensemble = RunEnsemble(cfg, {});
  const RunResult single = RunSimulation(cfg);
  ASSERT_TRUE(ensemble.ok() && single.ok());
  for (const char* name :
       {"slider_acceleration_positive", "slider_acceleration_negative_p95", "bearing_force_p95"}) {
    EXPECT_EQ(Figure(ensemble.summary, name), Figure(single.summary, name)) << name;
  }
  const nlohmann::json& e = ensemble.summary["ensemble"];
  EXPECT_EQ(e["regime"]["steady_states"].get<int>(), 1);
  EXPECT_EQ(e["regime"]["windows"]["periodic"].get<int>(), 2);
  // A periodic case: the interval is as narrow as the integration error (below 0.5 %).
  const nlohmann::json& f = e["figures"]["slider_acceleration_positive_p95"];
  const double c = f["centre"].get<double>();
  EXPECT_LT(f["interval"][1].get<double>() - f["interval"][0].get<double>(), 5e-3 * c);
  EXPECT_NEAR(c, Figure(single.summary, "slider_acceleration_positive_p95"), 5e-3 * c);
}

}  // namespace
}  // namespace flexrod
