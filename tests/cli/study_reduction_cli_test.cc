// SPDX-License-Identifier: GPL-3.0-or-later
// `flexrod study reduction`: every variant runs and is compared with the exact rod; the table,
// the verdict and each variant's summary are written; bad input is refused before any work.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/test_util.h"

namespace {

namespace fs = std::filesystem;
using flexrod::test::Flexrod;
using flexrod::test::ScratchPath;

// The Simeon crank from rest for 10 ms, Rayleigh damping on every variant (β = 1e-5 s): the
// exact rod and the full FE rod agree on the peak deflection-driven figures, every row is there.
TEST(StudyReductionCli, EveryVariantIsComparedWithTheExactRod) {
  const fs::path out = ScratchPath("cli_reduction");
  const int rc = Flexrod(
                     "study reduction simeon-crank --no-plot --set damping.type=rayleigh "
                     "--set damping.beta=1e-5 --set sim.capture=0.01s --out " +
                     out.string())
                     .exit_code;
  ASSERT_EQ(rc, 0);
  std::ifstream csv(out / "table.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_NE(line.find("diff. to exact [%]"), std::string::npos);
  int rows = 0;
  bool exact_first = false;
  while (std::getline(csv, line)) {
    if (rows == 0) exact_first = line.rfind("exact,completed", 0) == 0;
    ++rows;
  }
  EXPECT_EQ(rows, 10);  // exact, full, cb-0 … cb-16, orthonormal-cb-8, free-free-8
  EXPECT_TRUE(exact_first);
  EXPECT_TRUE(fs::exists(out / "verdict.txt"));
  for (const char* v : {"exact", "full", "cb-8"}) {
    std::ifstream in(out / v / "summary.json");
    const nlohmann::json s = nlohmann::json::parse(in);
    EXPECT_EQ(s["integrator"]["outcome"], "completed") << v;
    EXPECT_EQ(s["rod"]["model"], std::string(v) == "exact" ? "exact" : "reduced") << v;
  }
  fs::remove_all(out);
}

TEST(StudyReductionCli, BadInputIsRefusedBeforeAnyWork) {
  const fs::path out = ScratchPath("cli_reduction_bad");
  EXPECT_EQ(Flexrod("study reduction --within 0 --out " + out.string()).exit_code, 2);
  EXPECT_EQ(Flexrod("study reduction --set rod.height=-3mm --out " + out.string()).exit_code, 2);
  EXPECT_EQ(Flexrod("study reduction no-such-preset.toml --out " + out.string()).exit_code, 2);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
