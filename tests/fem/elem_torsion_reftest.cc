// tests/fem/elem_torsion_reftest.cc — Saint-Venant torsion constant of a rectangle against
// published tables and its thin-strip limit.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include "fem/section.h"

namespace flexrod::fem {
namespace {

double Beta(double long_side, double short_side) {
  const RectSection s{.thickness = short_side, .height = long_side};
  return s.torsion_constant() / (long_side * short_side * short_side * short_side);
}

TEST(TorsionConstant, MatchesTimoshenkoGoodierTable) {
  // J = β a b³ (a ≥ b). Timoshenko & Goodier, Theory of Elasticity, 3rd ed. (1970), §109 table
  // (also Roark's Formulas for Stress and Strain, 7th ed., Table 10.7 case 4), three digits:
  // tolerance half a unit in the last digit.
  struct Row {
    double a_over_b, beta;
  };
  const Row table[] = {{1.0, 0.141}, {1.2, 0.166}, {1.5, 0.196}, {2.0, 0.229}, {2.5, 0.249},
                       {3.0, 0.263}, {4.0, 0.281}, {5.0, 0.291}, {10.0, 0.312}};
  const double b = 3.175e-3;
  for (const Row& r : table) EXPECT_NEAR(Beta(r.a_over_b * b, b), r.beta, 5e-4) << r.a_over_b;
}

TEST(TorsionConstant, SquareIsPointOneFourZeroSixASquaredSquared) {
  // Square: J = 0.1406 a⁴ (Roark 7th ed., Table 10.7; 0.140577 from the series to 6 digits).
  const double a = 0.02;
  EXPECT_NEAR(Beta(a, a), 0.1406, 5e-5);
}

TEST(TorsionConstant, ThinStripApproachesOneThirdABCubed) {
  // Thin strip: J → a b³/3 (1 − 0.630 b/a) as a/b → ∞ (Timoshenko & Goodier §109, the
  // exponentially small end terms vanish). The rig rods (a/b = 4, 6, 8) sit in between.
  const double b = 1e-3;
  for (double ratio : {20.0, 50.0, 100.0, 1000.0}) {
    const double a = ratio * b;
    const double J = RectSection{.thickness = b, .height = a}.torsion_constant();
    EXPECT_NEAR(J / (a * b * b * b / 3.0 * (1.0 - 0.630 / ratio)), 1.0, 1e-4) << ratio;
  }
  const double a = 1e4 * b;
  const RectSection strip{.thickness = b, .height = a};
  EXPECT_NEAR(strip.torsion_constant() / (a * b * b * b / 3.0), 1.0, 1e-4);
}

TEST(TorsionConstant, IsIndependentOfOrientationAndBelowPolarMoment) {
  const RectSection s{.thickness = 3.175e-3, .height = 19.05e-3};
  RectSection swapped{.thickness = 19.05e-3, .height = 3.175e-3};
  RectSection strong = s;
  strong.in_plane = BendingAxis::kStrong;
  EXPECT_DOUBLE_EQ(s.torsion_constant(), swapped.torsion_constant());
  EXPECT_DOUBLE_EQ(s.torsion_constant(), strong.torsion_constant());
  // Saint-Venant: J < I_p for every non-circular section (warping relieves the shear).
  EXPECT_LT(s.torsion_constant(), s.inertia_in_plane() + s.inertia_out_of_plane());
}

}  // namespace
}  // namespace flexrod::fem
