// tests/fem/elem_material_section_test.cc — built-in materials, rectangular section
// properties and every Validate path of Material and RectSection.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fem/material.h"
#include "fem/section.h"
#include "mesh_test_util.h"

namespace flexrod::fem {
namespace {

using testing::ExpectInputError;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(Material, BuiltInMaterialsAreValidCitedAndPhysicallyOrdered) {
  ASSERT_EQ(MaterialNames(), (std::vector<std::string>{"steel", "brass", "aluminium"}));
  for (const std::string& name : MaterialNames()) {
    const Material m = MaterialByName(name);
    EXPECT_EQ(m.name, name);
    EXPECT_NO_THROW(m.Validate());
    EXPECT_FALSE(m.source.empty()) << name;
  }
  const Material steel = MaterialByName("steel");
  const Material brass = MaterialByName("brass");
  const Material al = MaterialByName("aluminium");
  // Handbook ordering (ASM): E_steel > E_brass > E_al, ρ_brass > ρ_steel > ρ_al.
  EXPECT_GT(steel.youngs_modulus, brass.youngs_modulus);
  EXPECT_GT(brass.youngs_modulus, al.youngs_modulus);
  EXPECT_GT(brass.density, steel.density);
  EXPECT_GT(steel.density, al.density);
  // Specific stiffness E/ρ of steel and aluminium agree within 5 % (a classic sanity check:
  // 25.4 vs 25.5 MJ/kg), brass is well below.
  EXPECT_NEAR(steel.youngs_modulus / steel.density / (al.youngs_modulus / al.density), 1.0, 0.05);
  EXPECT_LT(brass.youngs_modulus / brass.density, 0.5 * al.youngs_modulus / al.density);
}

TEST(Material, AmericanSpellingSelectsAluminium) {
  const Material a = MaterialByName("aluminum");
  EXPECT_EQ(a.name, "aluminium");
  EXPECT_EQ(a.youngs_modulus, MaterialByName("aluminium").youngs_modulus);
}

TEST(Material, UnknownNameIsRejectedNamingKeyAndValue) {
  ExpectInputError([] { MaterialByName("unobtainium"); }, "material", "unobtainium");
}

TEST(Material, ShearModulusIsEOverTwoOnePlusNu) {
  const Material s = MaterialByName("steel");
  EXPECT_DOUBLE_EQ(s.shear_modulus(), s.youngs_modulus / (2.0 * (1.0 + s.poisson_ratio)));
}

TEST(Material, ValidateRejectsEveryInvalidField) {
  const Material good = MaterialByName("brass");
  struct Case {
    void (*mutate)(Material*);
    const char* key;
    const char* value;
  };
  const Case cases[] = {
      {[](Material* m) { m->youngs_modulus = 0.0; }, "rod.E", "0"},
      {[](Material* m) { m->youngs_modulus = -2.0e9; }, "rod.E", "-2000000000"},
      {[](Material* m) { m->youngs_modulus = kNaN; }, "rod.E", "nan"},
      {[](Material* m) { m->youngs_modulus = kInf; }, "rod.E", "inf"},
      {[](Material* m) { m->poisson_ratio = 0.5; }, "rod.nu", "0.5"},
      {[](Material* m) { m->poisson_ratio = -1.0; }, "rod.nu", "-1"},
      {[](Material* m) { m->poisson_ratio = kNaN; }, "rod.nu", "nan"},
      {[](Material* m) { m->density = 0.0; }, "rod.rho", "0"},
      {[](Material* m) { m->density = -7800.0; }, "rod.rho", "-7800"},
      {[](Material* m) { m->yield_strength = -1.0; }, "rod.yield", "-1"},
      {[](Material* m) { m->yield_strength = kInf; }, "rod.yield", "inf"},
  };
  for (const Case& c : cases) {
    Material m = good;
    c.mutate(&m);
    ExpectInputError([&] { m.Validate("rod"); }, c.key, c.value);
  }
  // The default prefix is "material".
  Material m = good;
  m.density = -1.0;
  ExpectInputError([&] { m.Validate(); }, "material.rho", "-1");
}

TEST(Material, PoissonRatioInsideOpenIntervalIsAccepted) {
  Material m = MaterialByName("steel");
  m.poisson_ratio = 0.4999;
  EXPECT_NO_THROW(m.Validate());
  m.poisson_ratio = -0.9999;
  EXPECT_NO_THROW(m.Validate());
}

TEST(Section, SecondMomentsFollowTheNamedBendingAxis) {
  const double t = 3.175e-3, h = 19.05e-3;
  RectSection weak{.thickness = t, .height = h};
  EXPECT_EQ(weak.in_plane, BendingAxis::kWeak);  // DESIGN.md default
  EXPECT_DOUBLE_EQ(weak.area(), t * h);
  EXPECT_DOUBLE_EQ(weak.inertia_in_plane(), h * t * t * t / 12.0);
  EXPECT_DOUBLE_EQ(weak.inertia_out_of_plane(), t * h * h * h / 12.0);
  EXPECT_DOUBLE_EQ(weak.half_depth_in_plane(), t / 2.0);
  RectSection strong = weak;
  strong.in_plane = BendingAxis::kStrong;
  EXPECT_DOUBLE_EQ(strong.inertia_in_plane(), t * h * h * h / 12.0);
  EXPECT_DOUBLE_EQ(strong.inertia_out_of_plane(), h * t * t * t / 12.0);
  EXPECT_DOUBLE_EQ(strong.half_depth_in_plane(), h / 2.0);
  // Standing on edge is (h/t)² = 36 times stiffer in the plane.
  EXPECT_NEAR(strong.inertia_in_plane() / weak.inertia_in_plane(), (h / t) * (h / t), 1e-12);
}

TEST(Section, BendingAxisParsesWeakAndStrongOnly) {
  EXPECT_EQ(BendingAxisFromString("rod.in_plane_bending", "weak"), BendingAxis::kWeak);
  EXPECT_EQ(BendingAxisFromString("rod.in_plane_bending", "strong"), BendingAxis::kStrong);
  EXPECT_STREQ(ToString(BendingAxis::kWeak), "weak");
  EXPECT_STREQ(ToString(BendingAxis::kStrong), "strong");
  ExpectInputError([] { BendingAxisFromString("rod.in_plane_bending", "sideways"); },
                   "rod.in_plane_bending", "sideways");
}

TEST(Section, CowperShearFactorMatchesPublishedRectangleValues) {
  // Cowper (1966), J. Appl. Mech. 33:335, Table 1, rectangle: κ = 10(1+ν)/(12+11ν);
  // ν = 0 → 0.833, ν = 0.3 → 0.850, ν = 0.5 → 0.857 (three digits as tabulated).
  EXPECT_NEAR(RectSection::CowperShearFactor(0.0), 0.833, 5e-4);
  EXPECT_NEAR(RectSection::CowperShearFactor(0.3), 0.850, 5e-4);
  EXPECT_NEAR(RectSection::CowperShearFactor(0.5), 0.857, 5e-4);
}

TEST(Section, ValidateRejectsNonPositiveOrNonFiniteDimensions) {
  const RectSection good{.thickness = 3e-3, .height = 20e-3};
  EXPECT_NO_THROW(good.Validate());
  RectSection s = good;
  s.thickness = 0.0;
  ExpectInputError([&] { s.Validate(); }, "rod.thickness", "0");
  s = good;
  s.thickness = -3e-3;
  ExpectInputError([&] { s.Validate("link"); }, "link.thickness", "-0.003");
  s = good;
  s.height = kNaN;
  ExpectInputError([&] { s.Validate(); }, "rod.height", "nan");
  s = good;
  s.height = kInf;
  ExpectInputError([&] { s.Validate(); }, "rod.height", "inf");
}

}  // namespace
}  // namespace flexrod::fem
