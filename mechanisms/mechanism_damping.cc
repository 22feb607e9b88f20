// SPDX-License-Identifier: GPL-3.0-or-later
#include "mechanisms/mechanism_damping.h"

#include "common/error.h"
#include "mechanisms/mechanism_recipe.h"
#include "multibody/mechanism_modes.h"

namespace flexrod {

bool DampingRefersToMechanism(const Config& cfg) {
  if (cfg.Text("rod.type") == "rigid") return false;
  const std::string type = cfg.Text("damping.type");
  if (type == "band") return true;
  if (type != "ratio") return false;
  const double zeta = cfg.Quantity("damping.ratio");
  RequireNonNegative("damping.ratio", zeta);
  return zeta > 0.0;
}

std::vector<int> HeldForMechanismModes(const MechanismModel& model) {
  return model.recipe->HeldForModes(model);
}

Vec DampingRatiosFor(const Config& cfg, const Vec& frequencies_hz) {
  if (cfg.Text("damping.type") == "band") {
    const multibody::DampingSpec band = multibody::DampingSpec::FrequencyBand();
    return frequencies_hz.unaryExpr([&](double f) { return band.BandRatio(f); });
  }
  const double zeta = cfg.Quantity("damping.ratio");
  RequireNonNegative("damping.ratio", zeta);
  return Vec::Constant(frequencies_hz.size(), zeta);
}

MechanismDamping ReferDampingToMechanism(const Config& cfg, const MechanismModel& undamped) {
  const multibody::Mechanism& m = undamped.mechanism;
  const multibody::MechanismModes modes =
      multibody::CalcMechanismModes(m, undamped.p0, HeldForMechanismModes(undamped));
  MechanismDamping out;
  out.frequencies_hz = modes.frequencies_hz;
  out.ratios = DampingRatiosFor(cfg, modes.frequencies_hz);
  out.spec = multibody::DampingSpec::Matrix(
      multibody::ModalDampingForBody(m, modes, undamped.conrod, out.ratios));
  return out;
}

}  // namespace flexrod
