// SPDX-License-Identifier: GPL-3.0-or-later
#include "mechanisms/mechanism_damping.h"

#include "common/error.h"
#include "mechanisms/mechanism_recipe.h"
#include "multibody/mechanism_modes.h"

namespace flexrod {

bool DampingRefersToMechanism(const Config& cfg) {
  if (ReadRodModel(cfg) == RodModel::kRigid) return false;
  const DampingOptions d = ReadDampingOptions(cfg);
  if (d.type == DampingOptions::Type::kBand || d.type == DampingOptions::Type::kMaterial)
    return true;
  if (d.type != DampingOptions::Type::kRatio) return false;
  RequireNonNegative("damping.ratio", d.ratio);
  return d.ratio > 0.0;
}

std::vector<int> HeldForMechanismModes(const MechanismModel& model) {
  return model.recipe->HeldForModes(model);
}

Vec DampingRatiosFor(const DampingOptions& damping, const Vec& frequencies_hz) {
  if (damping.type == DampingOptions::Type::kBand) {
    const multibody::DampingSpec band = multibody::DampingSpec::FrequencyBand();
    return frequencies_hz.unaryExpr([&](double f) { return band.BandRatio(f); });
  }
  if (damping.type == DampingOptions::Type::kMaterial)
    return Vec::Constant(frequencies_hz.size(), 0.5 * damping.loss_factor);
  RequireNonNegative("damping.ratio", damping.ratio);
  return Vec::Constant(frequencies_hz.size(), damping.ratio);
}

MechanismDamping ReferDampingToMechanism(const MechanismModel& undamped) {
  const multibody::Mechanism& m = undamped.mechanism;
  const multibody::MechanismModes modes =
      multibody::CalcMechanismModes(m, undamped.p0, HeldForMechanismModes(undamped));
  MechanismDamping out;
  out.frequencies_hz = modes.frequencies_hz;
  out.ratios = DampingRatiosFor(undamped.damping, modes.frequencies_hz);
  out.spec = multibody::DampingSpec::Matrix(
      multibody::ModalDampingForBody(m, modes, undamped.conrod, out.ratios));
  return out;
}

}  // namespace flexrod
