// SPDX-License-Identifier: GPL-3.0-or-later
#include "mechanisms/mechanism_model.h"

#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.h"
#include "mechanisms/joint_config.h"
#include "mechanisms/mechanism_damping.h"
#include "mechanisms/mechanism_recipe.h"
#include "mechanisms/rod_config.h"
#include "multibody/mechanism_modes.h"

namespace flexrod {
namespace {

using multibody::BodyId;
using multibody::MarkerId;

/// The rod's damping as damping.* gives it, in the rod's own (clamped-frame) modes.
multibody::DampingSpec DampingSpecOf(const DampingOptions& o) {
  multibody::DampingSpec d;
  if (o.type == DampingOptions::Type::kBand) {
    d = multibody::DampingSpec::FrequencyBand();
  } else if (o.type == DampingOptions::Type::kRatio || o.type == DampingOptions::Type::kMaterial) {
    const double ratio = o.type == DampingOptions::Type::kRatio ? o.ratio : 0.5 * o.loss_factor;
    d = ratio > 0.0 ? multibody::DampingSpec::ModalRatio({ratio}) : multibody::DampingSpec::None();
  } else {
    d = multibody::DampingSpec::Rayleigh(o.alpha, o.beta);
  }
  return d;
}

}  // namespace

Mat2 Rotation(double angle) {
  Mat2 A;
  A << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return A;
}

void PlaceRod(const MechanismModel& mm, const Vec2& R, double theta, Vec* p) {
  const multibody::Mechanism& m = mm.mechanism;
  (*p)[m.coordinate(mm.conrod, multibody::kX)] = R.x();
  (*p)[m.coordinate(mm.conrod, multibody::kY)] = R.y();
  (*p)[m.coordinate(mm.conrod, multibody::kTheta)] = theta;
  if (mm.exact) multibody::SetExactRodPose(m, *mm.exact, R, theta, p);
  if (mm.small_clamp.index >= 0) {
    const Vec2 C = R + Rotation(theta) * Vec2(mm.rod_length, 0.0);
    (*p)[m.coordinate(mm.small_clamp, multibody::kX)] = C.x();
    (*p)[m.coordinate(mm.small_clamp, multibody::kY)] = C.y();
    (*p)[m.coordinate(mm.small_clamp, multibody::kTheta)] = theta;
  }
}

/// The rod of the input with its clamps as rigid attachments (flexible and exact rods); the
/// small-end clamp only if `small_clamp`.
static fem::RodSpec RodWithClamps(const Config& cfg, bool small_clamp) {
  fem::RodSpec rod = RodFromConfig(cfg);
  const double big_mass = cfg.Quantity("clamp.big_mass");
  const double small_mass = cfg.Quantity("clamp.small_mass");
  if (big_mass > 0.0 || cfg.Quantity("clamp.big_inertia") > 0.0) {
    rod.attachments.push_back(
        {"big-end clamp", 0, big_mass, cfg.Quantity("clamp.big_inertia"), Vec2::Zero()});
  }
  if (small_clamp && (small_mass > 0.0 || cfg.Quantity("clamp.small_inertia") > 0.0)) {
    rod.attachments.push_back(
        {"small-end clamp", rod.num_elements, small_mass, cfg.Quantity("clamp.small_inertia"),
         Vec2(cfg.Quantity("clamp.small_com_x"), cfg.Quantity("clamp.small_com_y"))});
  }
  rod.Validate();
  return rod;
}

bool SmallClampIsABody(const Config& cfg) {
  return ReadRodModel(cfg) == RodModel::kFlexible && cfg.Quantity("clamp.small_mass") > 0.0;
}

std::shared_ptr<const fem::ReducedRod> BuildReducedRod(const Config& cfg) {
  if (ReadRodModel(cfg) != RodModel::kFlexible) return nullptr;
  const fem::RodSpec rod = RodWithClamps(cfg, !SmallClampIsABody(cfg));
  const fem::ReductionSpec spec = MechanismReductionFromConfig(cfg, rod);
  return std::make_shared<const fem::ReducedRod>(fem::Reduce(rod, spec));
}

namespace {

/// The reduced rod's floating-frame body, its big-end node marker and its small-end marker
/// (on the small-end clamp body where SmallClampIsABody), `small_offset` [m] from the last node.
void AddReducedRodBody(const Config& cfg, const multibody::DampingSpec& damping,
                       const Vec2& small_offset, multibody::MechanismBuilder* builder,
                       MechanismModel* model) {
  multibody::MechanismBuilder& b = *builder;
  MechanismModel& out = *model;
  const Vec2 big_offset = out.big_end_point;
  const int last_node = out.rod->rod.num_nodes() - 1;
  multibody::FlexibleBodySpec fs;
  fs.name = "rod";
  fs.rod = out.rod;
  fs.damping = damping;
  fs.geometric_stiffening = cfg.Bool("rod.geometric_stiffening");
  out.conrod = b.AddFlexibleBody(fs);
  out.big_end = b.AddNodeMarker(out.conrod, "big-end", 0, big_offset);
  if (SmallClampIsABody(cfg)) {
    // The small-end clamp is a rigid body welded to the last node: the bush, 17 mm off the
    // node on the rig, then turns with the node's rotation exactly. A node marker's offset
    // turns with it only to first order (S_u + J d S_φ), which misplaced the bush by
    // ½ |d| φ² and dropped the offset's second-order stiffness: 8 % on the flexible rig's
    // peak slider acceleration against the exact rod (tests/run/exact_rod_slowtest.cc).
    out.small_clamp = b.AddRigidBody(
        {"small-end clamp", cfg.Quantity("clamp.small_mass"), cfg.Quantity("clamp.small_inertia"),
         Vec2(cfg.Quantity("clamp.small_com_x"), cfg.Quantity("clamp.small_com_y"))});
    b.AddWeld("small-end clamp", b.AddNodeMarker(out.conrod, "small-end node", last_node),
              b.AddBodyMarker(out.small_clamp, "small-end clamp origin", Vec2::Zero()));
    out.small_end = b.AddBodyMarker(out.small_clamp, "small-end", small_offset);
  } else {
    out.small_end = b.AddNodeMarker(out.conrod, "small-end", last_node, small_offset);
  }
}

/// The geometrically exact rod's node bodies and elements (multibody/exact_rod.h), with
/// Kelvin–Voigt damping β from the Rayleigh stiffness factor, or the modal damping `modal`
/// (non-null for the modal damping types: BuildExactRodMechanism), and its end markers
/// (`small_offset` [m] from the last node).
void AddExactRodBodies(const Config& cfg, const multibody::DampingSpec& damping,
                       const multibody::CorotatedModalFit* modal, const Vec2& small_offset,
                       multibody::MechanismBuilder* b, MechanismModel* model) {
  MechanismModel& out = *model;
  const Vec2 big_offset = out.big_end_point;
  if (damping.kind == multibody::DampingKind::kRayleigh && damping.rayleigh_alpha != 0.0) {
    throw InputError("damping.alpha", FormatValue(damping.rayleigh_alpha) + " 1/s",
                     "must be 0 with rod.type = exact: mass-proportional damping would damp the "
                     "rod's rigid motion");
  }
  multibody::ExactRodSpec es;
  es.name = "rod";
  es.rod = RodWithClamps(cfg, true);
  es.beta = damping.kind == multibody::DampingKind::kRayleigh ? damping.rayleigh_beta : 0.0;
  if (modal != nullptr) {
    es.beta = modal->beta;
    es.modal_damping_modes = modal->modes;
    es.modal_damping_coefficients = modal->coefficients;
  }
  out.exact = std::make_shared<const multibody::ExactRod>(multibody::AddExactRod(b, es));
  out.conrod = out.exact->nodes.front();
  out.big_end = b->AddBodyMarker(out.exact->nodes.front(), "big-end", big_offset);
  out.small_end = b->AddBodyMarker(out.exact->nodes.back(), "small-end", small_offset);
}

/// The rigid rod: rod.rigid_mass and rod.rigid_inertia, or those of the rod's section and
/// material (a slender bar) where they are 0.
void AddRigidRodBody(const Config& cfg, multibody::MechanismBuilder* b, MechanismModel* model) {
  MechanismModel& out = *model;
  const double length = out.rod_length;
  double mass = cfg.Quantity("rod.rigid_mass");
  double inertia = cfg.Quantity("rod.rigid_inertia");
  if (mass == 0.0) {
    const fem::RodSpec spec = RodFromConfig(cfg);
    mass = spec.material.density * spec.section.area() * length;
  }
  if (inertia == 0.0) inertia = mass * length * length / 12.0;
  RequirePositive("rod.rigid_mass", mass);
  out.conrod = b->AddRigidBody({"rod", mass, inertia, Vec2(0.5 * length, 0.0)});
  out.big_end = b->AddBodyMarker(out.conrod, "big-end", out.big_end_point);
  out.small_end = b->AddBodyMarker(out.conrod, "small-end", out.small_end_point);
}

}  // namespace

/// One build of the mechanism; `rod_damping` (may be null: damping.* as is) is the flexible
/// rod's damping, `exact_modal` (may be null) the exact rod's modal damping. BuildMechanism
/// below decides which.
static MechanismModel BuildMechanismPass(
    const Config& cfg, std::shared_ptr<const fem::ReducedRod> rod, bool ideal_joint,
    const multibody::DampingSpec* rod_damping,
    const multibody::CorotatedModalFit* exact_modal = nullptr) {
  MechanismModel out;
  out.drive = ReadDriveOptions(cfg);
  out.damping = ReadDampingOptions(cfg);
  if (out.damping.type == DampingOptions::Type::kMaterial && ReadRodModel(cfg) != RodModel::kRigid)
    out.damping.loss_factor = RodFromConfig(cfg).material.loss_factor;
  multibody::MechanismBuilder b;
  const bool flexible = ReadRodModel(cfg) == RodModel::kFlexible;
  if (flexible && !rod) rod = BuildReducedRod(cfg);
  out.rod = rod;
  const double length = cfg.Quantity("rod.length");
  const Vec2 big_offset(cfg.Quantity("rod.big_end_x"), cfg.Quantity("rod.big_end_y"));
  const Vec2 small_offset(cfg.Quantity("rod.small_end_x"), cfg.Quantity("rod.small_end_y"));
  const bool exact = ReadRodModel(cfg) == RodModel::kExact;
  // The joint points in the rod frame (undeformed).
  const Vec2 small_point = Vec2(length, 0.0) + small_offset;
  out.rod_length = length;
  out.big_end_point = big_offset;
  out.small_end_point = small_point;
  out.effective_length = (small_point - big_offset).norm();

  // ---- the connecting rod ----
  const multibody::DampingSpec damping =
      rod_damping != nullptr ? *rod_damping : DampingSpecOf(out.damping);
  if (flexible) {
    AddReducedRodBody(cfg, damping, small_offset, &b, &out);
  } else if (exact) {
    AddExactRodBodies(cfg, damping, exact_modal, small_offset, &b, &out);
  } else {
    AddRigidRodBody(cfg, &b, &out);
  }

  if (cfg.Bool("gravity.enabled"))
    b.SetGravity(Vec2(cfg.Quantity("gravity.x"), cfg.Quantity("gravity.y")));

  out.recipe = &FindRecipe(cfg.Text("mechanism.type"));
  out.recipe->Build(cfg, ideal_joint, &b, &out);
  return out;
}

MechanismModel BuildMechanismWithRodDamping(const Config& cfg,
                                            std::shared_ptr<const fem::ReducedRod> rod,
                                            bool ideal_joint,
                                            const multibody::DampingSpec& rod_damping) {
  return BuildMechanismPass(cfg, std::move(rod), ideal_joint, &rod_damping);
}

namespace {

/// The input whose assembled mechanism the rod's modal damping refers to: `cfg` with the crank
/// at 0 (drive.initial_angle = 0). The damping is a property of the rod, so it must not depend
/// on where a run starts: the members of an ensemble (run/ensemble.h), started at other crank
/// angles, get the same damping matrix as member 0.
Config DampingReference(const Config& cfg) {
  Config reference = cfg;
  reference.Set("drive.initial_angle", "0 rad");
  return reference;
}

/// The exact rod with damping.type = ratio | band | material: the ratios refer to the modes of
/// the assembled mechanism (crank held at angle 0, ideal small-end joint), as for the reduced
/// rod. Its modes up to kExactRodModalLimitHz, and below the first mode asked to be critically
/// damped, get exactly those ratios from a co-rotated modal damping of the node bodies plus
/// Kelvin–Voigt damping of the elements (FitCorotatedModalDamping); the modes above get
/// β ω / 2, at least their ratio (mechanisms/mechanism_damping.h says why).
MechanismModel BuildExactRodMechanism(const Config& cfg, bool ideal_joint) {
  if (!DampingRefersToMechanism(cfg)) return BuildMechanismPass(cfg, nullptr, ideal_joint, nullptr);
  const MechanismModel undamped = BuildMechanismWithRodDamping(
      DampingReference(cfg), nullptr, /*ideal_joint=*/true, multibody::DampingSpec::None());
  const multibody::MechanismModes modes = multibody::CalcMechanismModes(
      undamped.mechanism, undamped.p0, HeldForMechanismModes(undamped));
  const Vec zeta = DampingRatiosFor(undamped.damping, modes.frequencies_hz);
  int exact_modes = 0;
  while (exact_modes < modes.num_modes() &&
         modes.frequencies_hz(exact_modes) <= kExactRodModalLimitHz && zeta(exact_modes) < 1.0)
    ++exact_modes;
  const multibody::CorotatedModalFit fit =
      multibody::FitCorotatedModalDamping(undamped.mechanism, modes, undamped.exact->nodes,
                                          undamped.p0, zeta, std::max(exact_modes, 1));
  MechanismModel out = BuildMechanismPass(cfg, nullptr, ideal_joint, nullptr, &fit);
  out.mechanism_frequencies_hz = modes.frequencies_hz;
  out.mechanism_damping_ratios = fit.ratios;
  const int n = modes.num_modes(), above = n - exact_modes;
  if (above > 0) {
    std::ostringstream note;
    note.precision(3);
    note << "rod.type = exact: its " << above << " mechanism modes from "
         << modes.frequencies_hz(exact_modes) << " to " << modes.frequencies_hz(n - 1)
         << " Hz get Kelvin-Voigt ratios " << fit.ratios(exact_modes) << " to " << fit.ratios(n - 1)
         << " instead of the " << zeta(exact_modes) << " to " << zeta(n - 1)
         << " damping.type = " << cfg.Text("damping.type")
         << " asks; the modes below get exactly their ratios";
    out.damping_warning = note.str();
  }
  return out;
}

}  // namespace

MechanismModel BuildMechanism(const Config& cfg, std::shared_ptr<const fem::ReducedRod> rod,
                              bool ideal_joint) {
  if (ReadRodModel(cfg) == RodModel::kExact) return BuildExactRodMechanism(cfg, ideal_joint);
  if (!DampingRefersToMechanism(cfg))
    return BuildMechanismPass(cfg, std::move(rod), ideal_joint, nullptr);
  // Modal damping refers to the rod's modes in the assembled mechanism: build it undamped (ideal
  // small-end joint), take its modes, build it again with the matching damping matrix.
  if (!rod) rod = BuildReducedRod(cfg);
  const MechanismModel undamped = BuildMechanismWithRodDamping(
      DampingReference(cfg), rod, /*ideal_joint=*/true, multibody::DampingSpec::None());
  const MechanismDamping referred = ReferDampingToMechanism(undamped);
  MechanismModel out =
      BuildMechanismWithRodDamping(cfg, std::move(rod), ideal_joint, referred.spec);
  out.mechanism_frequencies_hz = referred.frequencies_hz;
  out.mechanism_damping_ratios = referred.ratios;
  return out;
}

}  // namespace flexrod
