// SPDX-License-Identifier: GPL-3.0-or-later
#include "study/slider_crank.h"

#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.h"
#include "multibody/mechanism_modes.h"
#include "study/joint_config.h"
#include "study/mechanism_damping.h"
#include "study/rod_config.h"

namespace flexrod {
namespace {

using multibody::BodyId;
using multibody::MarkerId;

Mat2 Rotation(double angle) {
  Mat2 A;
  A << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return A;
}

multibody::DampingSpec DampingFromConfig(const Config& cfg) {
  const std::string type = cfg.Text("damping.type");
  multibody::DampingSpec d;
  if (type == "band") {
    d = multibody::DampingSpec::FrequencyBand();
  } else if (type == "ratio") {
    const double zeta = cfg.Quantity("damping.ratio");
    d = zeta > 0.0 ? multibody::DampingSpec::ModalRatio({zeta}) : multibody::DampingSpec::None();
  } else {
    d = multibody::DampingSpec::Rayleigh(cfg.Quantity("damping.alpha"),
                                         cfg.Quantity("damping.beta"));
  }
  return d;
}

std::vector<std::pair<double, double>> ParseProfile(const std::string& text) {
  std::vector<std::pair<double, double>> knots;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const size_t colon = item.find(':');
    if (colon == std::string::npos) {
      throw InputError("drive.profile", text, "must be comma-separated time:speed pairs (s:rpm)");
    }
    const double t = ParseQuantity("drive.profile", item.substr(0, colon), Dimension::kTime);
    const double rpm =
        ParseQuantity("drive.profile", item.substr(colon + 1), Dimension::kDimensionless);
    knots.emplace_back(t, rpm * 2.0 * std::numbers::pi / 60.0);
  }
  if (knots.size() < 2)
    throw InputError("drive.profile", text, "needs at least two time:speed pairs");
  for (size_t k = 1; k < knots.size(); ++k) {
    if (!(knots[k].first > knots[k - 1].first)) {
      throw InputError("drive.profile", text, "the times must be strictly increasing");
    }
  }
  return knots;
}

}  // namespace

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
  return cfg.Text("rod.type") == "flexible" && cfg.Quantity("clamp.small_mass") > 0.0;
}

std::shared_ptr<const fem::ReducedRod> BuildReducedRod(const Config& cfg) {
  if (cfg.Text("rod.type") != "flexible") return nullptr;
  const fem::RodSpec rod = RodWithClamps(cfg, !SmallClampIsABody(cfg));
  const fem::ReductionSpec spec = MechanismReductionFromConfig(cfg, rod);
  return std::make_shared<const fem::ReducedRod>(fem::Reduce(rod, spec));
}

/// One build of the mechanism; `rod_damping` (may be null: damping.* as is) is the flexible
/// rod's damping. BuildMechanism below decides which.
static MechanismModel BuildMechanismPass(const Config& cfg,
                                         std::shared_ptr<const fem::ReducedRod> rod,
                                         bool ideal_joint,
                                         const multibody::DampingSpec* rod_damping) {
  MechanismModel out;
  multibody::MechanismBuilder b;
  const bool flexible = cfg.Text("rod.type") == "flexible";
  if (flexible && !rod) rod = BuildReducedRod(cfg);
  out.rod = rod;
  const double length = cfg.Quantity("rod.length");
  const Vec2 big_offset(cfg.Quantity("rod.big_end_x"), cfg.Quantity("rod.big_end_y"));
  const Vec2 small_offset(cfg.Quantity("rod.small_end_x"), cfg.Quantity("rod.small_end_y"));
  const bool exact = cfg.Text("rod.type") == "exact";
  const int last_node = flexible ? rod->rod.num_nodes() - 1 : 0;
  // Joint-to-joint vector in the rod frame (undeformed).
  const Vec2 big_point = big_offset;
  const Vec2 small_point = Vec2(length, 0.0) + small_offset;
  const Vec2 d = small_point - big_point;
  out.effective_length = d.norm();

  // ---- the connecting rod ----
  if (flexible) {
    multibody::FlexibleBodySpec fs;
    fs.name = "rod";
    fs.rod = rod;
    fs.damping = rod_damping != nullptr ? *rod_damping : DampingFromConfig(cfg);
    fs.geometric_stiffening = cfg.Bool("rod.geometric_stiffening");
    out.conrod = b.AddFlexibleBody(fs);
    out.big_end = b.AddNodeMarker(out.conrod, "big-end", 0, big_offset);
    if (SmallClampIsABody(cfg)) {
      // The small-end clamp is a rigid body welded to the last node: the bush, 17 mm off the
      // node on the rig, then turns with the node's rotation exactly. A node marker's offset
      // turns with it only to first order (S_u + J d S_φ), which misplaced the bush by
      // ½ |d| φ² and dropped the offset's second-order stiffness: 8 % on the flexible rig's
      // peak slider acceleration against the exact rod (tests/study/exact_rod_slowtest.cc).
      out.small_clamp = b.AddRigidBody(
          {"small-end clamp", cfg.Quantity("clamp.small_mass"), cfg.Quantity("clamp.small_inertia"),
           Vec2(cfg.Quantity("clamp.small_com_x"), cfg.Quantity("clamp.small_com_y"))});
      b.AddWeld("small-end clamp", b.AddNodeMarker(out.conrod, "small-end node", last_node),
                b.AddBodyMarker(out.small_clamp, "small-end clamp origin", Vec2::Zero()));
      out.small_end = b.AddBodyMarker(out.small_clamp, "small-end", small_offset);
    } else {
      out.small_end = b.AddNodeMarker(out.conrod, "small-end", last_node, small_offset);
    }
  } else if (exact) {
    // The geometrically exact rod (multibody/exact_rod.h): Kelvin–Voigt damping β from the
    // Rayleigh stiffness factor (BuildMechanism refers ratio and band damping to it).
    const multibody::DampingSpec damping =
        rod_damping != nullptr ? *rod_damping : DampingFromConfig(cfg);
    if (damping.kind == multibody::DampingKind::kRayleigh && damping.rayleigh_alpha != 0.0) {
      throw InputError("damping.alpha", FormatValue(damping.rayleigh_alpha) + " 1/s",
                       "must be 0 with rod.type = exact: mass-proportional damping would damp the "
                       "rod's rigid motion");
    }
    multibody::ExactRodSpec es;
    es.name = "rod";
    es.rod = RodWithClamps(cfg, true);
    es.beta = damping.kind == multibody::DampingKind::kRayleigh ? damping.rayleigh_beta : 0.0;
    out.exact = std::make_shared<const multibody::ExactRod>(multibody::AddExactRod(&b, es));
    out.conrod = out.exact->nodes.front();
    out.big_end = b.AddBodyMarker(out.exact->nodes.front(), "big-end", big_offset);
    out.small_end = b.AddBodyMarker(out.exact->nodes.back(), "small-end", small_offset);
  } else {
    double mass = cfg.Quantity("rod.rigid_mass");
    double inertia = cfg.Quantity("rod.rigid_inertia");
    if (mass == 0.0) {
      const fem::RodSpec spec = RodFromConfig(cfg);
      mass = spec.material.density * spec.section.area() * length;
    }
    if (inertia == 0.0) inertia = mass * length * length / 12.0;
    RequirePositive("rod.rigid_mass", mass);
    out.conrod = b.AddRigidBody({"rod", mass, inertia, Vec2(0.5 * length, 0.0)});
    out.big_end = b.AddBodyMarker(out.conrod, "big-end", big_offset);
    out.small_end = b.AddBodyMarker(out.conrod, "small-end", small_point);
  }

  if (cfg.Bool("gravity.enabled"))
    b.SetGravity(Vec2(cfg.Quantity("gravity.x"), cfg.Quantity("gravity.y")));

  if (cfg.Text("mechanism.type") == "pendulum") {
    // Rod pinned at the big-end point to the ground at the origin, released horizontally.
    out.is_pendulum = true;
    const MarkerId pivot = b.AddGroundMarker("pivot", Vec2::Zero());
    out.big_end_joint = b.AddRevolute("pivot", pivot, out.big_end);
    out.mechanism = b.Build();
    out.p0 = Vec::Zero(out.mechanism.num_coordinates());
    const Vec2 R = -big_offset;
    out.p0[out.mechanism.coordinate(out.conrod, multibody::kX)] = R.x();
    out.p0[out.mechanism.coordinate(out.conrod, multibody::kY)] = R.y();
    if (out.exact) multibody::SetExactRodPose(out.mechanism, *out.exact, R, 0.0, &out.p0);
    out.v0 = Vec::Zero(out.mechanism.num_coordinates());
    return out;
  }

  // ---- crank ----
  const double r = cfg.Quantity("crank.length");
  out.crank_length = r;
  const double crank_mass = cfg.Quantity("crank.mass");
  const double crank_inertia = cfg.Quantity("crank.inertia");
  out.crank = b.AddRigidBody({"crank", crank_mass, crank_inertia, Vec2::Zero()});
  const MarkerId origin = b.AddGroundMarker("ground-axis", Vec2::Zero());
  const MarkerId crank_axis = b.AddBodyMarker(out.crank, "crank-axis", Vec2::Zero());
  out.crank_pin = b.AddBodyMarker(out.crank, "crank-pin", Vec2(r, 0.0));
  out.crank_pivot_joint = b.AddRevolute("crank-pivot", origin, crank_axis);
  out.big_end_joint = b.AddRevolute("big-end", out.crank_pin, out.big_end);

  // ---- slider on its guide ----
  const double slider_mass = cfg.Quantity("slider.mass");
  const double e = cfg.Quantity("slider.offset");
  if (!(out.effective_length > r + std::abs(e))) {
    throw InputError("rod.length", FormatValue(length),
                     "the joint-to-joint length (" + FormatValue(out.effective_length) +
                         " m) must exceed crank.length + |slider.offset| (" +
                         FormatValue(r + std::abs(e)) + " m) for the crank to turn");
  }
  out.slider = b.AddRigidBody({"slider", slider_mass, 0.0, Vec2::Zero()});
  out.journal = b.AddBodyMarker(out.slider, "journal", Vec2::Zero());
  const MarkerId guide = b.AddGroundMarker("guide", Vec2(0.0, e));
  multibody::PrismaticSpec ps;
  ps.name = "guide";
  ps.marker_i = guide;
  ps.marker_j = out.journal;
  ps.axis = Vec2(1.0, 0.0);
  ps.damping = cfg.Quantity("slider.damping");
  ps.friction_force = cfg.Quantity("slider.friction");
  ps.friction_regularisation_speed = cfg.Quantity("slider.friction_velocity");
  out.guide_joint = b.AddPrismatic(ps);

  if (ideal_joint || cfg.Text("joint.type") == "ideal") {
    out.small_end_joint = b.AddRevolute("small-end", out.small_end, out.journal);
  } else {
    // Clearance joint: bush on the rod's small-end clamp (marker i), pin on the slider (marker
    // j). The slider keeps its guide (y and angle held); along it, it is free. p0 below puts the
    // journal at the bush centre (concentric pin: zero eccentricity, joint open).
    ClearanceJointConfig joint = ResolveClearanceJoint(cfg, slider_mass);
    out.clearance = b.AddForceElement("small-end-clearance", out.small_end, out.journal,
                                      MakeClearanceJoint(joint));
    out.joint_parameters = std::move(joint.parameters);
  }

  // ---- drive ----
  const double theta0 = cfg.Quantity("drive.initial_angle");
  const std::string drive = cfg.Text("drive.type");
  // A profile given with another drive type is still checked: its rules hold whatever is used.
  if (drive != "profile" && !cfg.Text("drive.profile").empty())
    (void)ParseProfile(cfg.Text("drive.profile"));
  if (drive == "constant") {
    const double w = cfg.Quantity("drive.speed");
    out.driver = b.AddConstantSpeedDriver("drive", out.crank, theta0, w);
  } else if (drive == "profile") {
    std::vector<double> times, speeds;
    for (const auto& [t, w] : ParseProfile(cfg.Text("drive.profile"))) {
      times.push_back(t);
      speeds.push_back(w);
    }
    out.driver = b.AddSpeedProfileDriver("drive", out.crank, theta0, times, speeds);
  } else {
    // DC motor on armature-voltage (SCR) control: motor.* is the rated line, T = T_s (1 − ω/ω₀)
    // at full voltage. A DC motor's torque line at armature voltage V is T = (k/R)(V − k ω): the
    // slope k²/R = T_s/ω₀ is the motor's, the no-load speed scales with V. The SCR is set so
    // that the no-load crank speed is drive.speed (V/V_rated = belt ratio · drive.speed / ω₀);
    // under load the mean speed droops by the mean load torque / slope, and impacts make it
    // fluctuate through the flywheel.
    multibody::DcMotorSpec m;
    const double rated_stall = cfg.Quantity("motor.stall_torque");
    const double rated_no_load = cfg.Quantity("motor.no_load_speed");
    m.ratio = cfg.Quantity("motor.belt_ratio");
    const double w = cfg.Quantity("drive.speed");
    const double voltage_fraction = m.ratio * w / rated_no_load;
    if (voltage_fraction > 1.0 + 1e-12) {
      throw InputError(
          "drive.speed", FormatValue(w) + " rad/s",
          "with drive.type = motor must be at most motor.no_load_speed / motor.belt_ratio = " +
              FormatValue(rated_no_load / m.ratio) +
              " rad/s: the no-load speed at full armature voltage");
    }
    m.stall_torque = voltage_fraction * rated_stall;
    m.no_load_speed = voltage_fraction * rated_no_load;  // = belt ratio · drive.speed
    m.flywheel_inertia = cfg.Quantity("motor.flywheel_inertia");
    m.Validate("motor");
    out.driver = b.AddDcMotorDriver("drive", out.crank, m);
  }
  out.mechanism = b.Build();

  // ---- initial configuration and velocity of the rigid motion at crank angle θ0 ----
  const multibody::Mechanism& mech = out.mechanism;
  auto rigid_pose = [&](double theta) {
    Vec p = Vec::Zero(mech.num_coordinates());
    const Vec2 P = r * Vec2(std::cos(theta), std::sin(theta));
    const double ell = out.effective_length;
    const Vec2 S(P.x() + std::sqrt(ell * ell - (e - P.y()) * (e - P.y())), e);
    const double theta_rod = std::atan2(S.y() - P.y(), S.x() - P.x()) - std::atan2(d.y(), d.x());
    const Vec2 R = P - Rotation(theta_rod) * big_point;
    p[mech.coordinate(out.crank, multibody::kTheta)] = theta;
    p[mech.coordinate(out.conrod, multibody::kX)] = R.x();
    p[mech.coordinate(out.conrod, multibody::kY)] = R.y();
    p[mech.coordinate(out.conrod, multibody::kTheta)] = theta_rod;
    if (out.exact) multibody::SetExactRodPose(mech, *out.exact, R, theta_rod, &p);
    if (out.small_clamp.index >= 0) {
      const Vec2 C = R + Rotation(theta_rod) * Vec2(length, 0.0);
      p[mech.coordinate(out.small_clamp, multibody::kX)] = C.x();
      p[mech.coordinate(out.small_clamp, multibody::kY)] = C.y();
      p[mech.coordinate(out.small_clamp, multibody::kTheta)] = theta_rod;
    }
    p[mech.coordinate(out.slider, multibody::kX)] = S.x();
    p[mech.coordinate(out.slider, multibody::kY)] = S.y();
    return p;
  };
  out.p0 = rigid_pose(theta0);
  // v = ω dp/dθ by a central difference (h = 1e-6 rad: error ~1e-12 relative).
  // Constant drive and motor start at drive.speed (the motor at its no-load speed), a speed
  // profile at rest: the profile's driver constraint sets its own velocity.
  const double w0 = drive == "profile" ? 0.0 : cfg.Quantity("drive.speed");
  constexpr double kH = 1e-6;
  out.v0 = w0 * (rigid_pose(theta0 + kH) - rigid_pose(theta0 - kH)) / (2.0 * kH);
  return out;
}

MechanismModel BuildMechanismWithRodDamping(const Config& cfg,
                                            std::shared_ptr<const fem::ReducedRod> rod,
                                            bool ideal_joint,
                                            const multibody::DampingSpec& rod_damping) {
  return BuildMechanismPass(cfg, std::move(rod), ideal_joint, &rod_damping);
}

namespace {

/// The exact rod's Kelvin–Voigt β for damping.type = ratio | band: fitted so that the rod's
/// first mode in the assembled mechanism (crank held, initial crank angle, ideal small-end joint,
/// as for the reduced rod) has the requested ratio, ζ_1 = β ω_1 / 2; higher modes get more
/// (ζ_i = β ω_i / 2), as from a Rayleigh stiffness term fitted to mode 1.
MechanismModel BuildExactRodMechanism(const Config& cfg, bool ideal_joint) {
  if (!DampingRefersToMechanism(cfg)) return BuildMechanismPass(cfg, nullptr, ideal_joint, nullptr);
  const MechanismModel undamped = BuildMechanismWithRodDamping(cfg, nullptr, /*ideal_joint=*/true,
                                                               multibody::DampingSpec::None());
  const multibody::MechanismModes modes = multibody::CalcMechanismModes(
      undamped.mechanism, undamped.p0, HeldForMechanismModes(undamped));
  int first = 0;
  while (first < modes.frequencies_hz.size() && !(modes.frequencies_hz[first] > 0.0)) ++first;
  if (first == modes.frequencies_hz.size()) {
    throw NumericalError(
        "rod.type = exact: the mechanism has no elastic mode to refer damping.* to");
  }
  const double f1 = modes.frequencies_hz[first];
  const double zeta = DampingRatiosFor(cfg, Vec::Constant(1, f1))(0);
  const double beta = 2.0 * zeta / (2.0 * std::numbers::pi * f1);
  MechanismModel out = BuildMechanismWithRodDamping(cfg, nullptr, ideal_joint,
                                                    multibody::DampingSpec::Rayleigh(0.0, beta));
  const int count = std::min<int>(8, static_cast<int>(modes.frequencies_hz.size()) - first);
  out.mechanism_frequencies_hz = modes.frequencies_hz.segment(first, count);
  out.mechanism_damping_ratios =
      (std::numbers::pi * beta) * out.mechanism_frequencies_hz;  // β ω / 2
  return out;
}

}  // namespace

MechanismModel BuildMechanism(const Config& cfg, std::shared_ptr<const fem::ReducedRod> rod,
                              bool ideal_joint) {
  if (cfg.Text("rod.type") == "exact") return BuildExactRodMechanism(cfg, ideal_joint);
  if (!DampingRefersToMechanism(cfg))
    return BuildMechanismPass(cfg, std::move(rod), ideal_joint, nullptr);
  // Modal damping refers to the rod's modes in the assembled mechanism: build it undamped (ideal
  // small-end joint), take its modes, build it again with the matching damping matrix.
  if (!rod) rod = BuildReducedRod(cfg);
  const MechanismModel undamped =
      BuildMechanismWithRodDamping(cfg, rod, /*ideal_joint=*/true, multibody::DampingSpec::None());
  const MechanismDamping referred = ReferDampingToMechanism(cfg, undamped);
  MechanismModel out =
      BuildMechanismWithRodDamping(cfg, std::move(rod), ideal_joint, referred.spec);
  out.mechanism_frequencies_hz = referred.frequencies_hz;
  out.mechanism_damping_ratios = referred.ratios;
  return out;
}

}  // namespace flexrod
