// fem/section.h — rectangular beam cross-sections (thickness × height) with an explicit
// in-plane bending axis. Value type shared by every element formulation.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>

namespace flexrod::fem {

/// Which principal axis of the flat bar bends in the mechanism plane (DESIGN.md).
/// kWeak: the bar stands on edge, in-plane second moment = height·thickness³/12 (default).
/// kStrong: in-plane second moment = thickness·height³/12.
enum class BendingAxis { kWeak, kStrong };
BendingAxis BendingAxisFromString(const std::string& key, const std::string& value);
const char* ToString(BendingAxis axis);

struct RectSection {
  double thickness;  ///< t [m], > 0
  double height;     ///< h [m], > 0
  BendingAxis in_plane{BendingAxis::kWeak};

  double area() const { return thickness * height; }  ///< A [m^2]
  /// Second moment for bending in the mechanism plane (local y-deflection) [m^4].
  double inertia_in_plane() const;
  /// Second moment for bending out of the plane (local z-deflection) [m^4].
  double inertia_out_of_plane() const;
  /// Saint-Venant torsion constant of a rectangle [m^4] (series solution, not the polar J).
  double torsion_constant() const;
  /// Cowper (1966) shear coefficient of a rectangle: 10(1+ν)/(12+11ν) [-].
  static double CowperShearFactor(double poisson_ratio);
  /// Distance from the neutral axis to the surface that bends in-plane [m] (the gauge face).
  double half_depth_in_plane() const;
  void Validate(const std::string& prefix = "rod") const;
};

}  // namespace flexrod::fem
