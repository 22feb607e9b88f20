// Tests of sweep/sweep_matrix.h: expansion of a matrix file into runs (crossed axes in
// document order, ranges, zipped axes, combinations), the thesis's Table 2 (189 runs with the
// clearance-dependent speed ranges of RIG.md Table 2), run fingerprints and rod keys, and the
// InputError for every kind of bad matrix (naming key, value and rule).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "sweep/sweep_matrix.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <tuple>

#include "common/error.h"

namespace flexrod::study {
namespace {

constexpr double kRpm = 60.0 / (2.0 * std::numbers::pi);

SweepMatrix Parse(const std::string& text, const std::vector<std::string>& sets = {}) {
  return ParseSweepMatrix(text, "test.toml", ".", sets);
}

/// The InputError a matrix raises (fails the test if it raises none).
InputError ErrorOf(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    Parse(text, sets);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for:\n" << text;
  return InputError("", "", "");
}

const char* kRigid = "[sweep]\nbase = \"rigid-rig\"\n";

TEST(SweepMatrix, Table2HasTheSevenRodsAndTheClearanceDependentSpeedRanges) {
  // RIG.md Table 2: 0.5 mm at 100-250 rpm and 1.0 mm at 100-200 rpm in steps of 10, for the 7
  // rods of Table 1: 7 x (16 + 11) = 189 runs, each (rod, clearance, speed) exactly once.
  const SweepMatrix m = LoadSweepMatrix(kDefaultSweepMatrix);
  ASSERT_EQ(m.num_runs(), 189u);
  std::set<std::tuple<std::string, long, long, long>> seen;
  std::map<long, std::set<long>> speeds;  // clearance [µm] -> speeds [rpm]
  std::set<std::pair<std::string, long>> rods;
  for (const SweepRun& r : m.runs) {
    const Config cfg = m.ConfigFor(r.id);
    EXPECT_EQ(cfg.Text("joint.type"), "clearance");
    EXPECT_EQ(cfg.Text("rod.type"), "flexible");
    const long height_um = std::lround(cfg.Quantity("rod.height") * 1e6);
    const long clearance_um = std::lround(cfg.Quantity("joint.clearance") * 1e6);
    const double rpm = cfg.Quantity("drive.speed") * kRpm;
    EXPECT_NEAR(rpm, std::round(rpm), 1e-9);
    const long rpm_i = std::lround(rpm);
    seen.insert({cfg.Text("rod.material"), height_um, clearance_um, rpm_i});
    speeds[clearance_um].insert(rpm_i);
    rods.insert({cfg.Text("rod.material"), height_um});
  }
  EXPECT_EQ(seen.size(), 189u);
  const std::set<std::pair<std::string, long>> table1 = {
      {"brass", 12700}, {"steel", 12700},     {"aluminium", 19050}, {"brass", 19050},
      {"steel", 19050}, {"aluminium", 25400}, {"steel", 25400}};
  EXPECT_EQ(rods, table1);
  ASSERT_EQ(speeds.size(), 2u);
  std::set<long> s05, s10;
  for (long v = 100; v <= 250; v += 10) s05.insert(v);
  for (long v = 100; v <= 200; v += 10) s10.insert(v);
  EXPECT_EQ(speeds[500], s05);
  EXPECT_EQ(speeds[1000], s10);
  // Every run at 1.0 mm stays within the accelerometer limit of 200 rpm.
  for (const auto& [rod_mat, h, c, rpm] : seen) {
    if (c == 1000) {
      EXPECT_LE(rpm, 200);
    }
  }
  EXPECT_EQ(m.axis_keys, (std::vector<std::string>{"rod.material", "rod.height", "joint.clearance",
                                                   "drive.speed"}));
}

TEST(SweepMatrix, AxesCrossInDocumentOrderWithTheLastVaryingFastest) {
  // Keys deliberately not in alphabetical order: document order decides.
  const SweepMatrix m = Parse(std::string(kRigid) +
                              "[axes]\n\"slider.mass\" = [\"1 kg\", \"2 kg\"]\n"
                              "\"drive.speed\" = [\"100 rpm\", \"110 rpm\", \"120 rpm\"]\n"
                              "\"crank.length\" = [\"40 mm\", \"50 mm\"]\n");
  ASSERT_EQ(m.num_runs(), 12u);
  EXPECT_EQ(m.runs[0].Label(), "slider.mass=1 kg, drive.speed=100 rpm, crank.length=40 mm");
  EXPECT_EQ(m.runs[1].Label(), "slider.mass=1 kg, drive.speed=100 rpm, crank.length=50 mm");
  EXPECT_EQ(m.runs[2].Label(), "slider.mass=1 kg, drive.speed=110 rpm, crank.length=40 mm");
  EXPECT_EQ(m.runs[11].Label(), "slider.mass=2 kg, drive.speed=120 rpm, crank.length=50 mm");
  for (std::size_t i = 0; i < m.num_runs(); ++i) EXPECT_EQ(m.runs[i].id, static_cast<int>(i));
  // The base and its overrides reach every run; the run's values win.
  const Config c = m.ConfigFor(5);
  EXPECT_DOUBLE_EQ(c.Quantity("crank.length"), 0.05);
  EXPECT_DOUBLE_EQ(c.Quantity("rod.length"), 0.3);  // rigid-rig preset
}

TEST(SweepMatrix, AnEnsembleCaseIsItsMembersAdjacentEachWithItsStart) {
  const SweepMatrix m = Parse(
      "[set]\n\"ensemble.members\" = \"3\"\n\"joint.type\" = \"clearance\"\n"
      "[axes]\n\"drive.speed\" = [\"100 rpm\", \"200 rpm\"]\n");
  ASSERT_EQ(m.num_runs(), 6u);
  for (int id = 0; id < 6; ++id) {
    const SweepRun& r = m.runs[static_cast<std::size_t>(id)];
    EXPECT_EQ(r.id, id);
    EXPECT_EQ(r.member, id % 3);
    EXPECT_EQ(r.case_id, id - id % 3);
    const Config c = m.ConfigFor(id);
    EXPECT_NEAR(c.Quantity("drive.speed") * kRpm, id < 3 ? 100.0 : 200.0, 1e-9);
    // Member k starts its crank k · 120° on, exactly (the text reads back to the same double).
    EXPECT_NEAR(c.Quantity("drive.initial_angle"), (id % 3) * 2.0 * std::numbers::pi / 3.0, 1e-15);
  }
  EXPECT_EQ(m.runs[0].values.size(), 1u);  // member 0 is the case itself
  EXPECT_EQ(m.runs[1].values.size(), 3u);
  // Sent to other MPI ranks, the members stay members.
  const SweepMatrix back = SweepMatrixFromJson(SweepMatrixToJson(m));
  EXPECT_EQ(back.runs[4].member, 1);
  EXPECT_EQ(back.runs[4].case_id, 3);
  // The keys the members set cannot be axes as well.
  const InputError e = ErrorOf(
      "[set]\n\"ensemble.members\" = \"2\"\n"
      "[axes]\n\"drive.initial_angle\" = [\"0 deg\", \"90 deg\"]\n");
  EXPECT_EQ(e.key(), "drive.initial_angle");
}

TEST(SweepMatrix, RangeIncludesItsEndAndKeepsTheUnit) {
  const SweepMatrix m = Parse(
      std::string(kRigid) +
      "[axes]\n\"drive.speed\" = { from = \"100 rpm\", to = \"130 rpm\", step = \"10 rpm\" }\n"
      "\"crank.length\" = { from = \"0.5 mm\", to = \"1.0 mm\", step = \"0.1 mm\" }\n");
  ASSERT_EQ(m.num_runs(), 4u * 6u);
  EXPECT_EQ(m.runs[0].values[0].value, "100 rpm");
  EXPECT_EQ(m.runs[23].values[0].value, "130 rpm");
  // 0.5 + 5 x 0.1 is 1.0 only to round-off: the end is still included, and written cleanly.
  EXPECT_EQ(m.runs[5].values[1].value, "1 mm");
  EXPECT_EQ(m.runs[3].values[1].value, "0.8 mm");
  EXPECT_NEAR(m.ConfigFor(5).Quantity("crank.length"), 1.0e-3, 1e-15);
}

TEST(SweepMatrix, ZippedAxisVariesItsKeysTogether) {
  const SweepMatrix m =
      Parse(std::string("[sweep]\nbase = \"flexible-rig\"\n") +
            "[axes]\n\"rod.material,rod.height\" = [[\"brass\", \"12.7 mm\"], [\"aluminium\", "
            "\"25.4 mm\"]]\n\"drive.speed\" = [\"100 rpm\", \"200 rpm\"]\n");
  ASSERT_EQ(m.num_runs(), 4u);
  EXPECT_EQ(m.ConfigFor(0).Text("rod.material"), "brass");
  EXPECT_DOUBLE_EQ(m.ConfigFor(0).Quantity("rod.height"), 12.7e-3);
  EXPECT_EQ(m.ConfigFor(3).Text("rod.material"), "aluminium");
  EXPECT_DOUBLE_EQ(m.ConfigFor(3).Quantity("rod.height"), 25.4e-3);
}

TEST(SweepMatrix, CombinationsAreUnitedAndEachIsCrossedWithTheAxes) {
  const SweepMatrix m =
      Parse(std::string(kRigid) +
            "[axes]\n\"slider.mass\" = [\"1 kg\", \"2 kg\", \"3 kg\"]\n"
            "[[combinations]]\n\"crank.length\" = \"40 mm\"\n\"drive.speed\" = [\"100 rpm\", \"110 "
            "rpm\"]\n"
            "[[combinations]]\n\"crank.length\" = \"50 mm\"\n"
            "\"drive.speed\" = { from = \"100 rpm\", to = \"140 rpm\", step = \"10 rpm\" }\n");
  EXPECT_EQ(m.num_runs(), 3u * 2u + 3u * 5u);
  // Combinations are the outer loop: the first 6 runs are the 40 mm crank.
  for (int i = 0; i < 6; ++i) EXPECT_DOUBLE_EQ(m.ConfigFor(i).Quantity("crank.length"), 0.04) << i;
  for (int i = 6; i < 21; ++i) EXPECT_DOUBLE_EQ(m.ConfigFor(i).Quantity("crank.length"), 0.05) << i;
}

TEST(SweepMatrix, CommandLineSetsOverrideTheBaseAndTheStoreOptions) {
  const SweepMatrix m =
      Parse(std::string(kRigid) +
                "[set]\nsim.capture = \"0.5 s\"\n[axes]\n\"drive.speed\" = [100, 200]\n",
            {"sim.capture=0.25 s", "store.rate=5 kHz", "store.channels=crank_angle"});
  EXPECT_DOUBLE_EQ(m.ConfigFor(1).Quantity("sim.capture"), 0.25);
  EXPECT_DOUBLE_EQ(m.ConfigFor(1).Quantity("drive.speed"), 200.0);  // a bare number is SI
  EXPECT_DOUBLE_EQ(m.store.rate, 5000.0);
  EXPECT_EQ(m.store.channels, std::vector<std::string>{"crank_angle"});
}

TEST(SweepMatrix, FingerprintChangesWithEveryInputAndStoreOptionButNotWithTheSpelling) {
  const SweepMatrix m =
      Parse(std::string(kRigid) + "[axes]\n\"drive.speed\" = [\"100 rpm\", \"200 rpm\"]\n");
  const Config a = m.ConfigFor(0);
  const Config b = m.ConfigFor(1);
  EXPECT_EQ(RunFingerprint(a, m.store), RunFingerprint(m.ConfigFor(0), m.store));
  EXPECT_NE(RunFingerprint(a, m.store), RunFingerprint(b, m.store));
  EXPECT_EQ(RunFingerprint(a, m.store).size(), 16u);
  StoreOptions other = m.store;
  other.rate = 20000.0;
  EXPECT_NE(RunFingerprint(a, m.store), RunFingerprint(a, other));
  // The same value written in other units is the same run.
  Config c = a;
  std::ostringstream si;
  si.precision(17);
  si << 100.0 / kRpm;
  c.Set("drive.speed", si.str());
  EXPECT_EQ(RunFingerprint(a, m.store), RunFingerprint(c, m.store));
  // FNV-1a 64 reference values (Fowler-Noll-Vo test vectors): "" and "a".
  EXPECT_EQ(Fnv1aHex(""), "cbf29ce484222325");
  EXPECT_EQ(Fnv1aHex("a"), "af63dc4c8601ec8c");
}

TEST(SweepMatrix, RodKeyChangesWithTheRodOnly) {
  const SweepMatrix m =
      Parse(std::string("[sweep]\nbase = \"flexible-rig\"\n") +
            "[axes]\n\"rod.height\" = [\"12.7 mm\", \"19.05 mm\"]\n\"drive.speed\" = [100, 200]\n"
            "\"reduction.modes\" = [4, 8]\n");
  ASSERT_EQ(m.num_runs(), 8u);
  std::set<std::string> keys;
  for (const SweepRun& r : m.runs) keys.insert(RodKey(m.ConfigFor(r.id)));
  EXPECT_EQ(keys.size(), 4u);  // 2 heights x 2 mode counts; speed does not change the rod
  EXPECT_EQ(RodKey(m.ConfigFor(0)), RodKey(m.ConfigFor(2)));  // runs 0 and 2 differ in speed only
}

TEST(SweepMatrix, JsonRoundTripGivesTheSameRuns) {
  const SweepMatrix m = LoadSweepMatrix(kDefaultSweepMatrix, {"sim.capture=0.5 s"});
  const SweepMatrix back = SweepMatrixFromJson(SweepMatrixToJson(m));
  ASSERT_EQ(back.num_runs(), m.num_runs());
  EXPECT_EQ(back.store.Describe(), m.store.Describe());
  for (int id : {0, 17, 188}) {
    EXPECT_EQ(RunFingerprint(back.ConfigFor(id), back.store),
              RunFingerprint(m.ConfigFor(id), m.store));
    EXPECT_EQ(back.runs[id].Label(), m.runs[id].Label());
  }
}

TEST(SweepMatrix, BadMatricesNameTheKeyTheValueAndTheRule) {
  const std::string base = kRigid;
  InputError e = ErrorOf(base + "[axes]\n\"rod.colour\" = [\"red\"]\n");
  EXPECT_EQ(e.key(), "rod.colour");
  EXPECT_NE(e.rule().find("unknown input key"), std::string::npos);

  e = ErrorOf(base + "[axes]\n\"drive.speed\" = []\n");
  EXPECT_EQ(e.key(), "drive.speed");
  EXPECT_NE(e.rule().find("at least one value"), std::string::npos);

  e = ErrorOf(base + "[axes]\n\"rod.material\" = [\"steel\", \"wood\"]\n");
  EXPECT_EQ(e.key(), "rod.material");
  EXPECT_EQ(e.value(), "wood");

  e = ErrorOf(base + "[axes]\n\"drive.speed\" = [\"100 mm\"]\n");  // wrong dimension
  EXPECT_EQ(e.key(), "drive.speed");

  e = ErrorOf(base + "[axes\n");
  EXPECT_NE(e.rule().find("malformed TOML"), std::string::npos);

  e = ErrorOf(base + "[axis]\n\"drive.speed\" = [100]\n");
  EXPECT_EQ(e.key(), "axis");

  e = ErrorOf(base + "[axes]\n\"drive.speed\" = [100]\n[[combinations]]\n\"drive.speed\" = 200\n");
  EXPECT_EQ(e.key(), "drive.speed");
  EXPECT_NE(e.rule().find("both"), std::string::npos);

  e = ErrorOf(
      base +
      "[axes]\n\"drive.speed\" = [\"100 rpm\", \"10.471975511965976\"]\n");  // same run twice
  EXPECT_NE(e.rule().find("same resolved input"), std::string::npos);

  e = ErrorOf(base + "[axes]\n\"drive.speed\" = { from = 200, to = 100, step = 10 }\n");
  EXPECT_EQ(e.key(), "drive.speed.to");

  e = ErrorOf(base + "[axes]\n\"drive.speed\" = { from = 100, to = 200, step = 0 }\n");
  EXPECT_EQ(e.key(), "drive.speed.step");

  e = ErrorOf(base + "[axes]\n\"rod.material,rod.height\" = [[\"steel\"]]\n");
  EXPECT_EQ(e.key(), "rod.material,rod.height");

  e = ErrorOf(base + "[store]\ncolour = \"red\"\n");
  EXPECT_EQ(e.key(), "store.colour");

  // The rigid rig samples at 100 kHz: 30 kHz does not divide it.
  e = ErrorOf(base + "[store]\nrate = \"30 kHz\"\n");
  EXPECT_EQ(e.key(), "store.rate");

  e = ErrorOf("[sweep]\nbase = \"no-such-preset\"\n");
  EXPECT_EQ(e.key(), "sweep.base");

  e = ErrorOf(base, {"rod.height=-"});
  EXPECT_EQ(e.key(), "rod.height");
}

}  // namespace
}  // namespace flexrod::study
