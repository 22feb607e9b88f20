// mechanisms/mechanism_damping.h — the flexible rod's modal damping referred to the rod's modes in
// the assembled mechanism: damping.type = ratio | band sets the ratios of the mechanism's
// modes (crank held, at the initial crank angle), not of the rod clamped to its floating frame
// (DESIGN.md, "The rod must be right under axial load"). BuildMechanism
// (mechanisms/mechanism_model.h) builds the mechanism once without rod damping, calls
// ReferDampingToMechanism, and builds it again with the returned damping matrix. What does not live
// here: the modal analysis and the matrix (multibody/mechanism_modes.h), the damping kinds
// (multibody::DampingSpec).
//
// Rayleigh damping (damping.type = rayleigh) is left as it is, D = α M_ff + β K on the rod's
// elastic coordinates: its stiffness part acts on the strain rate only, which no frame choice
// changes, and gives every mechanism mode ζ_i = β ω_i / 2 exactly (the rod's K is the
// mechanism's only stiffness); its mass part damps the elastic velocities relative to the
// rod's floating frame.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <vector>

#include "common/eigen.h"
#include "input/config.h"
#include "mechanisms/mechanism_model.h"
#include "multibody/mechanism.h"

namespace flexrod {

/// The exact rod's mechanism modes up to this frequency, and below the first mode asked to be
/// critically damped (damping.type = band: about 1.4 kHz), get exactly the ratios damping.*
/// asks (FitCorotatedModalDamping, multibody/mechanism_modes.h); the modes above get β ω / 2
/// continuing from the first of them, which gets its ratio. 20 kHz
/// lies above the reduced rod's highest mechanism mode on the rigs (18.8 kHz, flexible rig, default
/// Craig–Bampton basis). Why stop at critical: the modal ratios of the constrained mechanism do not
/// fix the damping once the small end flies free in its clearance (its free shapes mix every
/// mechanism mode), and the reduced rod has no modes above its basis at all (they are rigid);
/// measured on the main job (band), the exact rod gives +7.94 / -6.70 / bearing 8.13 with
/// Kelvin-Voigt from the first critical mode, +6.45 / -5.52 / 5.75 with every mode to 3 kHz
/// exact and +3.80 / -5.19 / 4.58 with every mode to 20 kHz exact, against the reduced rod's
/// +7.67 / -6.00 / 7.63, which does not move with its basis (20 Craig-Bampton modes:
/// +7.665 / -6.004 / 7.623).
inline constexpr double kExactRodModalLimitHz = 20000.0;

/// The rod damping referred to the mechanism's modes.
struct MechanismDamping {
  multibody::DampingSpec spec;  ///< DampingKind::kMatrix, for the rod's FlexibleBodySpec
  Vec frequencies_hz;           ///< the rod's modes in the assembled mechanism, ascending [Hz]
  Vec ratios;                   ///< ζ_i given to each of them [-]
};

/// True for an elastic rod (flexible or exact) with damping.type = band, or ratio with
/// damping.ratio > 0: the cases whose ratios refer to the mechanism's modes (the reduced rod's
/// through ReferDampingToMechanism, the exact rod's through its fitted β). Throws InputError for
/// damping.ratio < 0.
bool DampingRefersToMechanism(const Config& cfg);

/// Coordinates held in the modal analysis: the crank's angle (the slider-crank), the rod
/// frame's angle (the pendulum, whose rod frame sits on the pivot node: its modes are then
/// those of the rod clamped at the pivot).
std::vector<int> HeldForMechanismModes(const MechanismModel& model);

/// The ratio ζ [-] damping.* asks of each mode of frequency frequencies_hz [Hz]: damping.ratio
/// for every mode (type ratio), or by the frequency band (type band).
Vec DampingRatiosFor(const DampingOptions& damping, const Vec& frequencies_hz);

/// Modes of `undamped` — the mechanism built with the rod undamped and an ideal
/// small-end joint — at its initial configuration p0 at rest with HeldForMechanismModes held;
/// ratios per mode from its damping.* (ratio: damping.ratio for every mode; band: by each mode's
/// frequency with the limits and ratios of multibody::DampingSpec::FrequencyBand()); and the
/// rod damping matrix that gives the modes exactly those ratios
/// (multibody::ModalDampingForBody). The ideal joint is the reference also for clearance runs:
/// the clearance joint is open at the concentric start and would leave the small end free,
/// while in contact the pin carries the small end as the ideal joint does; a clearance run and
/// its ideal twin thus share one D. Other damping (the slider guide's) adds to these ratios.
MechanismDamping ReferDampingToMechanism(const MechanismModel& undamped);

}  // namespace flexrod
