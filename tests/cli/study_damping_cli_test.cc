// SPDX-License-Identifier: GPL-3.0-or-later
// `flexrod study damping`: the case runs under every damping model, each model's figures are
// tabulated against the band default, every model's damping is the one asked (its mechanism
// modes' ratios in summary.json), and a bad input is refused before any work.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/test_util.h"

namespace {

namespace fs = std::filesystem;
using flexrod::test::Flexrod;
using flexrod::test::ScratchPath;

// The main job on a short window, one member per model.
TEST(StudyDampingCli, EveryDampingModelIsTabulatedAgainstTheBand) {
  const fs::path out = ScratchPath("cli_damping");
  const auto r = Flexrod(
      "study damping --no-plot --set ensemble.members=1 --set sim.settle=0.1s "
      "--set sim.capture=0.7s --out " +
      out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream csv(out / "table.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line.rfind("damping,outcome,steady states,amplification + (p95)", 0), 0u) << line;
  std::vector<std::string> names;
  while (std::getline(csv, line)) {
    names.push_back(line.substr(0, line.find(',')));
    if (names.back() == "band") {
      EXPECT_NE(line.find(",+0.0,"), std::string::npos) << line;
    }
  }
  EXPECT_EQ(names, (std::vector<std::string>{"band", "material", "ratio-1%", "ratio-2%", "ratio-5%",
                                             "rayleigh-2e-5"}));
  auto ratios = [&](const char* model) {
    std::ifstream f(out / model / "summary.json");
    return nlohmann::json::parse(f)["rod"]["mechanism_damping_ratios"];
  };
  EXPECT_EQ(ratios("material")[0].get<double>(), 2e-4);  // steel: η / 2 = 4e-4 / 2
  EXPECT_EQ(ratios("ratio-5%")[3].get<double>(), 0.05);
  EXPECT_EQ(ratios("band")[0].get<double>(), 0.01);  // the first mode, 51 Hz
}

TEST(StudyDampingCli, ABadKeyIsRefusedBeforeAnyRun) {
  const fs::path out = ScratchPath("cli_damping_bad");
  const auto r = Flexrod("study damping --no-plot --set rod.loss_factor=-1 --out " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("rod.loss_factor"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out / "table.csv"));
}

}  // namespace
