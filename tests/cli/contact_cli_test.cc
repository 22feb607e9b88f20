// tests/cli/contact_cli_test.cc — `flexrod contact` end to end: the JSON keys and values of one
// impact, units on the command line, the exit code 2 and no output file for bad input, and the
// PNG of the force–penetration loop.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/test_util.h"

namespace {

namespace fs = std::filesystem;

using flexrod::test::CommandResult;
using flexrod::test::Flexrod;
using flexrod::test::ScratchPath;

TEST(ContactCli, JsonHasTheResultKeysAndTheResolvedParameters) {
  const fs::path json = ScratchPath("contact_cli_flores.json");
  const CommandResult run = Flexrod(
      "contact --law flores --restitution 0.8 --mass \"2.71 kg\" "
      "--velocity \"500 mm/s\" --pin-radius \"9.025 mm\" --json " +
      json.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("achieved restitution"), std::string::npos);
  std::ifstream in(json);
  const nlohmann::json j = nlohmann::json::parse(in);
  fs::remove(json);
  for (const char* key : {"achieved_restitution", "peak_force", "peak_penetration",
                          "contact_duration", "law", "parameters", "units"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["law"], "flores");
  // Flores reaches the input restitution within 0.05 (tests/contact/impact_reftest.cc).
  EXPECT_NEAR(j["achieved_restitution"].get<double>(), 0.8, 0.05);
  EXPECT_GT(j["peak_force"].get<double>(), 0.0);
  EXPECT_GT(j["peak_penetration"].get<double>(), 0.0);
  EXPECT_LT(j["peak_penetration"].get<double>(), 1e-4);  // micrometres for steel on steel
  EXPECT_GT(j["contact_duration"].get<double>(), 0.0);
  EXPECT_EQ(j["units"]["peak_force"], "N");
  bool saw_stiffness = false;
  for (const auto& p : j["parameters"]) {
    if (p["name"] == "stiffness") {
      saw_stiffness = true;
      EXPECT_EQ(p["unit"], "N/m^1.5");
    }
    EXPECT_TRUE(p.contains("value") && p.contains("unit") && p.contains("source"));
  }
  EXPECT_TRUE(saw_stiffness);
  EXPECT_NEAR(j["inputs"]["velocity"]["value"].get<double>(), 0.5, 1e-15);
}

TEST(ContactCli, AnApproachBelowTheDampingFloorIsWarnedAbout) {
  // Hysteresis damping ∝ 1/v₀ uses max(v₀, min-approach-velocity = 1e-3 m/s): at 1e-4 m/s the
  // floor decides the restitution (Flores, input 0.5: 0.90) unless the user lowers it, and then
  // the achieved restitution is the speed-independent one of 0.5 m/s.
  auto achieved = [](const std::string& extra, bool* warned) {
    const fs::path json = ScratchPath("contact_cli_floor.json");
    const CommandResult run = Flexrod("contact --law flores --restitution 0.5 --mass \"2.71 kg\" " +
                                      extra + " --json " + json.string());
    EXPECT_EQ(run.exit_code, 0) << run.output;
    std::ifstream in(json);
    const nlohmann::json j = nlohmann::json::parse(in);
    fs::remove(json);
    *warned = j.contains("warnings");
    EXPECT_EQ(*warned, run.output.find("min-approach-velocity = 0.001 m/s") != std::string::npos)
        << run.output;
    return j["achieved_restitution"].get<double>();
  };
  bool warned = false;
  const double reference = achieved("--velocity \"0.5 m/s\"", &warned);
  EXPECT_FALSE(warned);
  const double floored = achieved("--velocity \"1e-4 m/s\"", &warned);
  EXPECT_TRUE(warned);
  EXPECT_GT(floored, reference + 0.3);
  const double lowered =
      achieved("--velocity \"1e-4 m/s\" --min-approach-velocity \"1e-5 m/s\"", &warned);
  EXPECT_FALSE(warned);
  EXPECT_NEAR(lowered, reference, 1e-5);
}

TEST(ContactCli, UnknownLawExitsWithCode2AndWritesNothing) {
  const fs::path json = ScratchPath("contact_cli_unknown.json");
  const fs::path png = ScratchPath("contact_cli_unknown.png");
  fs::remove(json);
  const CommandResult run = Flexrod("contact --law hertzian --mass 1 --velocity 1 --json " +
                                    json.string() + " --plot " + png.string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("hertzian"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(json));
  EXPECT_FALSE(fs::exists(png));
}

TEST(ContactCli, ParameterTheLawDoesNotTakeExitsWithCode2) {
  const fs::path json = ScratchPath("contact_cli_badparam.json");
  const CommandResult run = Flexrod(
      "contact --law hertz --restitution 0.5 --mass 1 --velocity 1 --json " + json.string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("restitution = 0.5"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(json));
  const CommandResult bad_e =
      Flexrod("contact --law flores --restitution 1.5 --mass 1 --velocity 1");
  EXPECT_EQ(bad_e.exit_code, 2) << bad_e.output;
  // A pin larger than its bush: the error names the flag.
  const CommandResult big_pin =
      Flexrod("contact --law hertz --mass 1 --velocity 1 --pin-radius \"10 mm\"");
  EXPECT_EQ(big_pin.exit_code, 2) << big_pin.output;
  EXPECT_NE(big_pin.output.find("pin-radius = 0.01 m: must be < bush_radius"), std::string::npos)
      << big_pin.output;
  const CommandResult soft_bush =
      Flexrod("contact --law hertz --mass 1 --velocity 1 --bush-E \"-3 GPa\"");
  EXPECT_EQ(soft_bush.exit_code, 2) << soft_bush.output;
  EXPECT_NE(soft_bush.output.find("bush-E = "), std::string::npos) << soft_bush.output;
}

TEST(ContactCli, PlotWritesAPng) {
  const fs::path png = ScratchPath("contact_cli_loop.png");
  fs::remove(png);
  const CommandResult run = Flexrod(
      "contact --law hybrid --restitution 0.9 --mass 1 --velocity 0.3 --plot " + png.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream in(png, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  fs::remove(png);
  // Nothing half-written is left beside it.
  for (const auto& entry : fs::directory_iterator(png.parent_path())) {
    EXPECT_EQ(entry.path().filename().string().find(".flexrod_contact_cli_" +
                                                    std::to_string(getpid()) + "_loop.png.tmp"),
              std::string::npos);
  }
}

}  // namespace
