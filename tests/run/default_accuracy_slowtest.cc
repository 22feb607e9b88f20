// SPDX-License-Identifier: GPL-3.0-or-later
// Converged by default (issue 24, item 1): for each case the headline figures of a run at the
// default tolerances — peaks and p95 of the per-revolution peak slider acceleration, the load
// amplifications, the peak bearing force, the peak gauge stress — lie within 1 % of the same
// model integrated at sim.rel_tol = 1e-10, sim.abs_tol = 1e-12 (the reference; on the
// exudyn-match ideal joint it differs from rel_tol 1e-9 / abs_tol 1e-11 by 2e-4 %). Measured when
// the default sim.abs_tol went from 1e-8 to 1e-10: the exudyn-match ideal joint's positive peak
// was 17.6 % high at 1e-8 (integration noise on the slider-on-rod axial mode), its clearance
// joint's positive amplification 15.5 % low, the flexible rig at 250 rpm 1.4 % off; at 1e-10 the
// largest difference over these cases is 0.5 % (the exudyn-match clearance joint's amplification).
// The exudyn-match input is benchmarks/exudyn-match.toml, a copy of ../shared/bench/.
//
// Chaotic regimes (issue 24: per-revolution statistics over at least 20 revolutions within 3 %):
// the exudyn-match clearance joint (e = 0.9, μ = 0.01) is one. Its single largest impact is not
// a converged figure at the 1 % level at any tolerance: over 3 s its positive peak slider
// acceleration is 311.1 m/s² at rel_tol 1e-10 / abs_tol 1e-12 and 306.4 at 1e-11 / 1e-13, and a
// round-off-level change of the linear solver (KLU's ordering) moves those to 310.2 and 308.9.
// Its case runs 20 revolutions (6 s at 200 rpm) and its per-revolution statistics are held to
// 3 % (measured: 0.99 % at most, the negative p95 amplification); its single peaks are
// printed, not held.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "input/presets.h"
#include "run/run.h"

namespace flexrod {
namespace {

struct AccuracyCase {
  std::string name;
  std::string input;  // a preset name, or a file below the source tree
  std::vector<std::string> sets;
  bool chaotic{false};  // per-revolution statistics within 3 %, single peaks printed only
};

void PrintTo(const AccuracyCase& c, std::ostream* os) { *os << c.name; }

Config Load(const AccuracyCase& c, const std::vector<std::string>& extra) {
  Config cfg;
  if (const Preset* p = FindPreset(c.input)) {
    cfg.LoadToml(p->toml, c.input);
  } else {
    cfg.LoadTomlFile(std::string(FLEXROD_SOURCE_DIR) + "/" + c.input);
  }
  for (const std::string& s : c.sets) cfg.SetAssignment(s);
  for (const std::string& s : extra) cfg.SetAssignment(s);
  return cfg;
}

class DefaultAccuracy : public ::testing::TestWithParam<AccuracyCase> {};

TEST_P(DefaultAccuracy, HeadlineFiguresWithinOnePercentOfTheTightTolerance) {
  const AccuracyCase& c = GetParam();
  const RunResult run = RunSimulation(Load(c, {}), nullptr, false, RunOutputOptions{});
  ASSERT_TRUE(run.ok()) << run.status.Summary();
  const RunResult ref = RunSimulation(Load(c, {"sim.rel_tol=1e-10", "sim.abs_tol=1e-12"}), nullptr,
                                      false, RunOutputOptions{});
  ASSERT_TRUE(ref.ok()) << ref.status.Summary();
  const nlohmann::json check = CompareHeadlineFigures(run.summary, ref.summary);
  ASSERT_GE(check["figures"].size(), 3u) << check.dump();
  std::printf("%s: %ld steps (reference %ld)\n", c.name.c_str(), run.status.stats.steps,
              ref.status.stats.steps);
  int per_revolution_figures = 0;
  for (const auto& [name, f] : check["figures"].items()) {
    const double diff = f["difference [%]"].get<double>();
    std::printf("  %-52s %12.6g  reference %12.6g  %+8.4f %%\n", name.c_str(),
                f["value"].get<double>(), f["reference"].get<double>(), diff);
    const bool per_revolution = name.find("p95") != std::string::npos;
    per_revolution_figures += per_revolution;
    if (!c.chaotic) {
      EXPECT_LT(std::abs(diff), 1.0) << c.name << ": " << name;
    } else if (per_revolution) {
      EXPECT_LT(std::abs(diff), 3.0) << c.name << ": " << name;
    }
  }
  if (c.chaotic) {
    EXPECT_GE(per_revolution_figures, 3) << check.dump();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, DefaultAccuracy,
    ::testing::Values(
        AccuracyCase{"MainJob", "flexible-rig", {}},
        AccuracyCase{"FlexibleRigIdeal200rpm", "flexible-rig", {"joint.type=ideal"}},
        AccuracyCase{"FlexibleRig1mm100rpm",
                     "flexible-rig",
                     {"joint.clearance=1 mm", "drive.speed=100 rpm"}},
        AccuracyCase{"FlexibleRig0p5mm250rpm", "flexible-rig", {"drive.speed=250 rpm"}},
        AccuracyCase{"FlexibleRig1mm250rpm",
                     "flexible-rig",
                     {"joint.clearance=1 mm", "drive.speed=250 rpm"}},
        AccuracyCase{"ExudynMatchIdeal",
                     "benchmarks/exudyn-match.toml",
                     {"joint.type=ideal", "sim.sample_rate=10 kHz"}},
        AccuracyCase{
            "ExudynMatchClearance", "benchmarks/exudyn-match.toml", {"sim.capture=6 s"}, true},
        AccuracyCase{"RigidRig177rpm", "rigid-rig", {}},
        AccuracyCase{"RigidRigIdeal", "rigid-rig", {"joint.type=ideal"}},
        AccuracyCase{"SimeonCrank", "simeon-crank", {}}),
    [](const ::testing::TestParamInfo<AccuracyCase>& info) { return info.param.name; });

}  // namespace
}  // namespace flexrod
