// tests/mechanisms/mechanism_recipe_test.cc — the mechanism recipes
// (mechanisms/mechanism_recipe.h): the schema offers exactly the recipes; every recipe, with every
// rod model and with or without a small-end clamp body, starts on its constraints: its rigid-motion
// coordinates p0 satisfy g(p0) = 0 and its velocities v0 satisfy G v0 + g_t = 0 (the slider-crank's
// closed-form pose; v0 by a central difference, error ~1e-12 relative). SPDX-License-Identifier:
// GPL-3.0-or-later
#include "mechanisms/mechanism_recipe.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "input/config.h"
#include "input/presets.h"
#include "mechanisms/mechanism_model.h"
#include "multibody/dae.h"
#include "multibody/run_data.h"

namespace flexrod {
namespace {

TEST(MechanismRecipe, SchemaOffersExactlyTheRecipes) {
  const ParamDef* type = FindParam("mechanism.type");
  ASSERT_NE(type, nullptr);
  EXPECT_EQ(type->choices, RecipeNames());
  for (const std::string& name : RecipeNames()) EXPECT_EQ(FindRecipe(name).name(), name);
}

TEST(MechanismRecipe, EveryRecipeStartsOnItsConstraintsWithEveryRod) {
  struct Case {
    const char* preset;
    const char* type;  ///< mechanism.type set on the preset, or null
  };
  std::vector<std::string> covered;
  for (const Case& c : {Case{"flexible-rig", nullptr}, Case{"flexible-pendulum", nullptr},
                        Case{"flexible-rig", "four-bar"}}) {
    const char* preset = c.preset;
    for (const char* rod : {"rigid", "flexible", "exact"}) {
      for (const char* small_mass : {"0 kg", "0.15 kg"}) {
        SCOPED_TRACE(std::string(preset) + (c.type ? std::string(" as ") + c.type : "") +
                     ", rod.type = " + rod + ", clamp.small_mass = " + small_mass);
        Config cfg;
        cfg.LoadToml(FindPreset(preset)->toml, preset);
        if (c.type) {
          cfg.Set("mechanism.type", c.type);
          cfg.Set("joint.type", "ideal");
        }
        cfg.Set("rod.type", rod);
        cfg.Set("rod.elements", "6");
        cfg.Set("reduction.modes", "2");
        cfg.Set("clamp.small_mass", small_mass);
        cfg.Set("drive.initial_angle", "0.7");  // a general crank angle (rad)
        const MechanismModel mm = BuildMechanism(cfg, nullptr);
        ASSERT_NE(mm.recipe, nullptr);
        covered.emplace_back(mm.recipe->name());
        EXPECT_EQ(mm.recipe->name(), cfg.Text("mechanism.type"));
        EXPECT_EQ(mm.small_clamp.index >= 0,
                  std::string(rod) == "flexible" && std::string(small_mass) != "0 kg");
        const multibody::Mechanism& m = mm.mechanism;
        multibody::RunData data(m);
        Vec g;
        multibody::CalcConstraints(m, &data, 0.0, mm.p0, &g);
        EXPECT_LT(g.lpNorm<Eigen::Infinity>(), 1e-12) << "g(p0) = " << g.transpose();
        Mat G;
        Vec g_t;
        multibody::CalcConstraintJacobian(m, &data, 0.0, mm.p0, &G, &g_t);
        const Vec gv = G * mm.v0 + g_t;
        EXPECT_LT(gv.lpNorm<Eigen::Infinity>(), 1e-8 * (1.0 + mm.v0.lpNorm<Eigen::Infinity>()))
            << "G v0 + g_t = " << gv.transpose();
      }
    }
  }
  for (const std::string& name : RecipeNames()) {  // a new recipe needs its case above
    EXPECT_NE(std::find(covered.begin(), covered.end(), name), covered.end()) << name;
  }
}

}  // namespace
}  // namespace flexrod
