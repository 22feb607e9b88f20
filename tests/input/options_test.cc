// Tests of the typed options (input/options.h): every choice the schema offers for sim.start,
// sim.linear_solver, drive.type, damping.type and rod.type reads as its named enumerator; the
// quantities arrive in SI; drive.profile is read in rpm and stored in rad/s, and a malformed
// profile is refused naming the key whatever drive.type is.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "input/options.h"

#include <gtest/gtest.h>

#include <functional>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "input/config.h"

namespace flexrod {
namespace {

const ParamDef& Def(const std::string& key) {
  for (const ParamDef& p : Schema()) {
    if (p.key == key) return p;
  }
  throw std::logic_error("no key " + key);
}

/// The schema's choices for `key` are exactly the names listed, each read (by `read`) as the
/// enumerator listed beside it: an enumerator declared out of the schema's order, or a choice
/// added to the schema without its enumerator, fails.
template <class E>
void ExpectChoices(const std::string& key, const std::vector<std::pair<std::string, E>>& named,
                   const std::function<E(const Config&)>& read) {
  std::vector<std::string> names;
  for (const auto& [name, e] : named) {
    names.push_back(name);
    Config cfg;
    cfg.Set(key, name);
    EXPECT_EQ(static_cast<int>(read(cfg)), static_cast<int>(e)) << key << " = " << name;
  }
  EXPECT_EQ(Def(key).choices, names) << key;
}

TEST(Options, EveryChoiceOfTheSchemaReadsAsItsNamedEnumerator) {
  using Start = SimOptions::Start;
  ExpectChoices<Start>(
      "sim.start",
      {{"rigid", Start::kRigid}, {"static", Start::kStatic}, {"steady", Start::kSteady}},
      [](const Config& c) { return ReadSimOptions(c).start; });
  using Solver = SimOptions::LinearSolver;
  ExpectChoices<Solver>("sim.linear_solver",
                        {{"auto", Solver::kAuto}, {"dense", Solver::kDense}, {"klu", Solver::kKlu}},
                        [](const Config& c) { return ReadSimOptions(c).linear_solver; });
  using Damping = DampingOptions::Type;
  ExpectChoices<Damping>("damping.type",
                         {{"band", Damping::kBand},
                          {"ratio", Damping::kRatio},
                          {"rayleigh", Damping::kRayleigh},
                          {"material", Damping::kMaterial}},
                         [](const Config& c) { return ReadDampingOptions(c).type; });
  using Drive = DriveOptions::Type;
  ExpectChoices<Drive>(
      "drive.type",
      {{"constant", Drive::kConstant}, {"profile", Drive::kProfile}, {"motor", Drive::kMotor}},
      [](const Config& c) {
        Config both = c;
        both.Set("drive.profile", "0 s:0, 1 s:60");
        return ReadDriveOptions(both).type;
      });
  ExpectChoices<RodModel>(
      "rod.type",
      {{"flexible", RodModel::kFlexible}, {"exact", RodModel::kExact}, {"rigid", RodModel::kRigid}},
      ReadRodModel);
}

TEST(Options, AKeyThatIsNotAChoiceHasNoChoiceIndex) {
  Config cfg;
  EXPECT_THROW((void)ChoiceIndex(cfg, "sim.capture"), std::logic_error);
}

TEST(Options, QuantitiesArriveInSI) {
  Config cfg;
  cfg.Set("sim.capture", "250 ms");
  cfg.Set("sim.sample_rate", "20 kHz");
  cfg.Set("sim.index_angle", "90 deg");
  cfg.Set("drive.speed", "60 rpm");
  const SimOptions sim = ReadSimOptions(cfg);
  EXPECT_DOUBLE_EQ(sim.capture, 0.25);
  EXPECT_DOUBLE_EQ(sim.sample_rate, 2e4);
  EXPECT_DOUBLE_EQ(sim.index_angle, 0.5 * std::numbers::pi);
  EXPECT_DOUBLE_EQ(ReadDriveOptions(cfg).speed, 2.0 * std::numbers::pi);
}

TEST(Options, ProfileIsReadInRpmAndRefusedWhenMalformedWhateverTheDrive) {
  Config cfg;
  cfg.Set("drive.profile", "0 s:0, 0.5 s:120");
  const DriveOptions d = ReadDriveOptions(cfg);  // drive.type = constant: still read
  ASSERT_EQ(d.profile.size(), 2u);
  EXPECT_DOUBLE_EQ(d.profile[1].first, 0.5);
  EXPECT_DOUBLE_EQ(d.profile[1].second, 4.0 * std::numbers::pi);
  for (const char* bad : {"0 s:0", "1 s:0, 0.5 s:10", "garbage"}) {
    Config c;
    c.Set("drive.profile", bad);
    try {
      (void)ReadDriveOptions(c);
      ADD_FAILURE() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), "drive.profile") << bad;
    }
  }
  Config empty;
  empty.Set("drive.type", "profile");
  EXPECT_THROW((void)ReadDriveOptions(empty), InputError);
}

}  // namespace
}  // namespace flexrod
