// fem/material.cc — the built-in material library and Material::Validate.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "fem/material.h"

#include <cmath>

#include "common/error.h"

namespace flexrod::fem {
namespace {

// Typical room-temperature values. The thesis does not give grades or properties (RIG.md §2:
// "grades assumed"); these grades are the common bar stocks for each metal. Loss factors: L.
// Cremer, M. Heckl, B. A. T. Petersson, Structure-Borne Sound, 3rd ed., Springer 2005, the table
// of loss factors of materials (bending waves, room temperature): steel and iron 2-6e-4 (middle
// taken), aluminium 1e-4, brass < 1e-3 (the bound taken). Small: the metal alone damps little;
// the rig's joints, clamps and guide damp more, which is what the band default stands for.
Material Steel() {
  return Material{.name = "steel",
                  .youngs_modulus = 200.0e9,
                  .poisson_ratio = 0.29,
                  .density = 7870.0,
                  .yield_strength = 310.0e6,
                  .loss_factor = 4e-4,
                  .source =
                      "AISI 1045 carbon steel, hot rolled: MatWeb typical values (E 200 GPa, "
                      "nu 0.29, rho 7.87 g/cm^3, yield 310 MPa); ASM Handbook Vol. 1; loss "
                      "factor 4e-4 (2-6e-4): Cremer, Heckl & Petersson, Structure-Borne Sound"};
}

Material Brass() {
  return Material{
      .name = "brass",
      .youngs_modulus = 97.0e9,
      .poisson_ratio = 0.31,
      .density = 8500.0,
      .yield_strength = 310.0e6,
      .loss_factor = 1e-3,
      .source =
          "C36000 free-cutting brass, half-hard (H02) bar: MatWeb typical values (E 97 GPa, "
          "nu 0.31, rho 8.50 g/cm^3, yield 310 MPa); ASM Handbook Vol. 2; loss factor 1e-3 "
          "(< 1e-3): Cremer, Heckl & Petersson, Structure-Borne Sound"};
}

Material Aluminium() {
  return Material{.name = "aluminium",
                  .youngs_modulus = 68.9e9,
                  .poisson_ratio = 0.33,
                  .density = 2700.0,
                  .yield_strength = 276.0e6,
                  .loss_factor = 1e-4,
                  .source =
                      "6061-T6 aluminium alloy: MatWeb / ASM Aerospace typical values (E 68.9 GPa, "
                      "nu 0.33, rho 2.70 g/cm^3, yield 276 MPa); ASM Handbook Vol. 2; loss "
                      "factor 1e-4: Cremer, Heckl & Petersson, Structure-Borne Sound"};
}

}  // namespace

void Material::Validate(const std::string& prefix) const {
  auto finite_positive = [&](const std::string& field, double value, const char* unit) {
    if (!(std::isfinite(value) && value > 0.0)) {
      throw InputError(prefix + "." + field, FormatValue(value) + " " + unit,
                       "must be finite and > 0");
    }
  };
  finite_positive("E", youngs_modulus, "Pa");
  if (!(std::isfinite(poisson_ratio) && poisson_ratio > -1.0 && poisson_ratio < 0.5)) {
    throw InputError(prefix + ".nu", FormatValue(poisson_ratio),
                     "Poisson ratio must lie in (-1, 0.5) for an isotropic solid");
  }
  finite_positive("rho", density, "kg/m^3");
  finite_positive("yield", yield_strength, "Pa");
  if (!(std::isfinite(loss_factor) && loss_factor >= 0.0 && loss_factor < 2.0)) {
    throw InputError(prefix + ".loss_factor", FormatValue(loss_factor),
                     "a loss factor must lie in [0, 2) (its modes get zeta = eta / 2 < 1)");
  }
}

Material MaterialByName(const std::string& name) {
  if (name == "steel") return Steel();
  if (name == "brass") return Brass();
  if (name == "aluminium" || name == "aluminum") return Aluminium();
  std::string list;
  for (const std::string& n : MaterialNames()) list += (list.empty() ? "" : ", ") + n;
  throw InputError("material", name, "must be one of " + list + " (or \"aluminum\")");
}

std::vector<std::string> MaterialNames() { return {"steel", "brass", "aluminium"}; }

}  // namespace flexrod::fem
