// mechanisms/mechanism_model.h — the mechanism of a run, built from the input keys: the connecting
// rod (rigid, flexible = reduced, or geometrically exact, with its clamps and joint offsets) and,
// around it, what the recipe of mechanism.type adds (mechanisms/mechanism_recipe.h: the
// slider-crank, the pendulum). It owns the world layout and the initial configuration guess; the
// multibody engine knows none of it.
//
// World frame W: crank axis (pendulum: pivot) at the origin; slider-crank: the slider guide
// along +x at y = slider.offset, positive slider acceleration = away from the crank (RIG.md sign
// convention). Rod frame B: origin at the big-end clamp node (FE node 0), x along the undeformed
// rod. Points: p_WO crank axis; p_WC crank pin; p_WJ journal (pin) centre on the slider;
// p_WK bush centre on the small-end clamp. q_f: the rod's elastic coordinates.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <memory>
#include <vector>

#include "fem/reduced_rod.h"
#include "input/config.h"
#include "input/options.h"
#include "multibody/clearance_joint.h"
#include "multibody/exact_rod.h"
#include "multibody/mechanism.h"

namespace flexrod {

class MechanismRecipe;

struct MechanismModel {
  /// The recipe of mechanism.type that built it (mechanisms/mechanism_recipe.h).
  const MechanismRecipe* recipe{nullptr};
  DriveOptions drive;      ///< drive.*, motor.* (a recipe with a crank drives it so)
  DampingOptions damping;  ///< damping.*: what the user asked of the rod
  multibody::Mechanism mechanism;
  std::shared_ptr<const fem::ReducedRod> rod;  ///< rod.type = flexible (null otherwise)
  /// rod.type = exact: the geometrically exact rod's node bodies and elements (null otherwise);
  /// `conrod` is then its node-0 body.
  std::shared_ptr<const multibody::ExactRod> exact;
  /// The rod's body (the exact rod's node-0 body), and the crank and slider of a slider-crank
  /// (ground, index −1, where the mechanism has none).
  multibody::BodyId crank, conrod, slider;
  /// The small-end clamp welded to the reduced rod's last node (SmallClampIsABody), or −1.
  multibody::BodyId small_clamp{-1};
  multibody::MarkerId crank_pin, big_end, small_end, journal;
  multibody::JointId crank_pivot_joint, big_end_joint, small_end_joint, guide_joint;
  multibody::DriverId driver;
  /// The clearance small-end joint (force element between small_end = bush and journal = pin);
  /// index −1 with an ideal joint.
  multibody::ElementId clearance;
  /// Resolved clearance-joint parameters (SI; mechanisms/joint_config.h), empty with an ideal
  /// joint.
  std::vector<contact::ResolvedParameter> joint_parameters;
  Vec p0;                          ///< initial coordinates of the rigid motion (q = 0)
  Vec v0;                          ///< initial velocities of the rigid motion (q̇ = 0)
  double crank_length{0.0};        ///< [m] (0 without a crank)
  double rod_length{0.0};          ///< rod.length, big-end node to small-end node [m]
  Vec2 big_end_point{0.0, 0.0};    ///< big-end joint point in the rod frame [m]
  Vec2 small_end_point{0.0, 0.0};  ///< small-end joint point in the rod frame, undeformed [m]
  double effective_length{0.0};    ///< |small_end_point − big_end_point| [m]
  /// damping.type = ratio | band with a flexible rod: the rod's modes in the assembled
  /// mechanism (crank held, initial crank angle, ideal small-end joint) and the damping ratios
  /// given to them (mechanisms/mechanism_damping.h); empty otherwise.
  Vec mechanism_frequencies_hz;  ///< [Hz], ascending
  Vec mechanism_damping_ratios;  ///< [-]
  /// Where the rod cannot realise the damping.* asked of it exactly (the exact rod's fitted
  /// Kelvin–Voigt damping): what it realises instead, one sentence for the run's warnings;
  /// empty otherwise.
  std::string damping_warning;
};

/// [[cos θ, −sin θ], [sin θ, cos θ]]: a planar rotation by θ [rad].
Mat2 Rotation(double angle);

/// Writes into `p` the coordinates of the rod's bodies (the rod frame, the exact rod's node
/// bodies, a small-end clamp body) for the undeformed rod with its frame at R [m], angle θ
/// [rad]. The recipes place the rod with it.
void PlaceRod(const MechanismModel& mm, const Vec2& R, double theta, Vec* p);

/// Reduced rod for the run (flexible rod only): rod.*, reduction.*, clamps as attachments.
std::shared_ptr<const fem::ReducedRod> BuildReducedRod(const Config& cfg);
/// Whether the reduced rod's small-end clamp (clamp.small_mass > 0) is a rigid body welded to
/// its last node, carrying the bush, rather than an attachment in the rod's basis: a rigid
/// body turns the bush's offset exactly with the node.
bool SmallClampIsABody(const Config& cfg);

/// The mechanism for the input. `rod` from BuildReducedRod (null: built here, or rigid rod).
/// `ideal_joint` forces an ideal small-end joint (the ideal twin of a clearance run).
/// damping.type = ratio | band with a flexible rod: the rod's damping refers to its modes in the
/// assembled mechanism (mechanisms/mechanism_damping.h; the mechanism is built twice).
MechanismModel BuildMechanism(const Config& cfg, std::shared_ptr<const fem::ReducedRod> rod,
                              bool ideal_joint = false);

/// BuildMechanism with the flexible (reduced) rod's damping `rod_damping` as given instead of
/// from damping.* (no referral to the mechanism's modes): BuildMechanism's two passes, and
/// checks against other damping (e.g. the clamped-frame DampingSpec::ModalRatio).
MechanismModel BuildMechanismWithRodDamping(const Config& cfg,
                                            std::shared_ptr<const fem::ReducedRod> rod,
                                            bool ideal_joint,
                                            const multibody::DampingSpec& rod_damping);

}  // namespace flexrod
