// Tests of the typed options (input/options.h): every choice the schema offers for sim.start,
// sim.linear_solver, drive.type and damping.type reads as the enumerator of its position; the
// quantities arrive in SI; drive.profile is read in rpm and stored in rad/s, and a malformed
// profile is refused naming the key whatever drive.type is.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "input/options.h"

#include <gtest/gtest.h>

#include <functional>
#include <numbers>
#include <string>

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

/// Each choice of `key`, set, reads as the enumerator of its position in the schema.
void ExpectChoicesInSchemaOrder(const std::string& key,
                                const std::function<int(const Config&)>& read) {
  const std::vector<std::string>& choices = Def(key).choices;
  ASSERT_GE(choices.size(), 2u) << key;
  for (size_t i = 0; i < choices.size(); ++i) {
    Config cfg;
    cfg.Set(key, choices[i]);
    EXPECT_EQ(read(cfg), static_cast<int>(i)) << key << " = " << choices[i];
  }
}

TEST(Options, EveryChoiceOfTheSchemaReadsAsItsEnumerator) {
  ExpectChoicesInSchemaOrder(
      "sim.start", [](const Config& c) { return static_cast<int>(ReadSimOptions(c).start); });
  ExpectChoicesInSchemaOrder("sim.linear_solver", [](const Config& c) {
    return static_cast<int>(ReadSimOptions(c).linear_solver);
  });
  ExpectChoicesInSchemaOrder(
      "damping.type", [](const Config& c) { return static_cast<int>(ReadDampingOptions(c).type); });
  ExpectChoicesInSchemaOrder("drive.type", [&](const Config& c) {
    Config both = c;
    both.Set("drive.profile", "0 s:0, 1 s:60");
    return static_cast<int>(ReadDriveOptions(both).type);
  });
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
