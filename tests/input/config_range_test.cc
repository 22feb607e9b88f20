// Tests of the schema's value ranges (input/config.h ValueRange): every default lies in its
// key's range; a value outside is refused when it is set, naming the user's key, the SI value
// and the rule, whether or not the configuration will read the key; the rule's text for open,
// closed and two-sided intervals.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "common/error.h"
#include "input/config.h"

namespace flexrod {
namespace {

TEST(ConfigRange, EveryDefaultLiesInItsRange) {
  int ranged = 0;
  for (const ParamDef& p : Schema()) {
    if (p.kind != ParamKind::kQuantity && p.kind != ParamKind::kInteger) continue;
    const double v = ParseQuantity(p.key, p.default_text, p.dim);
    EXPECT_TRUE(p.range.Contains(v)) << p.key << " = " << p.default_text;
    ranged += std::isinf(p.range.low) && std::isinf(p.range.high) ? 0 : 1;
  }
  EXPECT_GE(ranged, 50);  // the plain rules of the schema's docs
}

TEST(ConfigRange, AValueOutsideIsRefusedWhenSetEvenIfTheRunWouldNotReadIt) {
  struct Case {
    const char* key;
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {"damping.alpha", "-1", "damping.alpha = -1: must be >= 0"},  // damping.type is band
      {"joint.clearance", "-1 mm", "joint.clearance = -0.001: must be > 0"},
      {"joint.restitution", "0", "joint.restitution = 0: must lie in (0, 1]"},
      {"joint.restitution", "1.5", "joint.restitution = 1.5: must lie in (0, 1]"},
      {"rod.elements", "0", "rod.elements = 0: must lie in [1, 100000]"},
      {"sim.steady_revolutions", "1", "sim.steady_revolutions = 1: must be >= 2"},
      {"motor.belt_ratio", "0", "motor.belt_ratio = 0: must be > 0"},  // drive.type is constant
  };
  for (const Case& c : cases) {
    Config cfg;
    try {
      cfg.Set(c.key, c.text);
      ADD_FAILURE() << c.key << " = " << c.text << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
    EXPECT_FALSE(cfg.IsSet(c.key));
  }
  Config cfg;
  EXPECT_NO_THROW(cfg.Set("joint.restitution", "1"));  // the closed end
  EXPECT_NO_THROW(cfg.Set("damping.alpha", "0"));
}

TEST(ConfigRange, RuleTextNamesTheInterval) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ((ValueRange{0.0, true, inf, false}).Rule(), "must be > 0");
  EXPECT_EQ((ValueRange{0.0, false, inf, false}).Rule(), "must be >= 0");
  EXPECT_EQ((ValueRange{-inf, false, 5.0, true}).Rule(), "must be < 5");
  EXPECT_EQ((ValueRange{0.0, true, 1.0, false}).Rule(), "must lie in (0, 1]");
  EXPECT_FALSE((ValueRange{0.0, false, 1.0, false}).Contains(std::nan("")));
  EXPECT_TRUE(ValueRange{}.Contains(-1e300));
}

}  // namespace
}  // namespace flexrod
