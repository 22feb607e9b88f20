// tests/run/law_matrix_slowtest.cc — every normal law with every friction law on both rigs, as
// a user picks them from `flexrod keys`: each run completes, keeps the pin outside the bush wall
// but for micrometres, closes its energy balance, and needs a bounded number of steps. Two
// regressions it guards: LuGre friction let the pin pass through the bush on both rigs (every
// normal law; multibody/clearance_joint.h, event band), and Stribeck's sign(v) took 10 min of
// wall time for 0.02 s of the flexible rig (contact/friction_law.h, tanh regularisation).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "contact/friction_law.h"
#include "contact/normal_law.h"
#include "input/presets.h"
#include "run/run.h"

namespace flexrod {
namespace {

TEST(LawMatrix, EveryLawPairOnBothRigsKeepsThePinOutOfTheBushAndClosesItsEnergyBalance) {
  std::vector<std::string> frictions = contact::FrictionLawNames();
  frictions.push_back("none");
  for (const char* rig : {"flexible-rig", "rigid-rig"}) {
    for (const std::string& law : contact::NormalLawNames()) {
      for (const std::string& friction : frictions) {
        SCOPED_TRACE(std::string(rig) + ", " + law + ", " + friction);
        Config cfg;
        cfg.LoadToml(FindPreset(rig)->toml, rig);
        cfg.Set("joint.type", "clearance");
        cfg.Set("joint.law", law);
        cfg.Set("joint.friction_law", friction);
        cfg.Set("sim.settle", "0 s");
        cfg.Set("sim.capture", "0.15 s");  // the first impacts (from t = 8 ms) and some sliding
        cfg.Set("sim.sample_rate", "20 kHz");
        const RunResult r = RunSimulation(cfg);
        ASSERT_TRUE(r.ok()) << r.status.Summary();
        double deepest = 0.0;
        for (double d : r.channels.values("penetration")) deepest = std::max(deepest, d);
        EXPECT_LT(deepest, 5e-5);  // loaded contacts: micrometres; through the bush: millimetres
        EXPECT_GE(r.summary["impacts"]["count"].get<int>() +
                      r.summary["impacts"]["incomplete"].get<int>(),
                  1);
        // Standard linear solid: the free wall's relaxation energy leaves the balance at each
        // onset (multibody/clearance_joint.h), so its bound is looser.
        const double balance = r.summary["energy"]["relative_balance_error"].get<double>();
        EXPECT_LT(balance, law == "standard-linear-solid" ? 1e-2 : 1e-3);
        EXPECT_LT(r.status.stats.steps, 60000);  // 0.15 s; Stribeck's sign(v) needed millions
      }
    }
  }
}

}  // namespace
}  // namespace flexrod
