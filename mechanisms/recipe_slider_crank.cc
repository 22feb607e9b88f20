// SPDX-License-Identifier: GPL-3.0-or-later
// The slider-crank recipe (mechanism.type = slider-crank, both rigs of RIG.md): a crank on a
// ground pivot turned by the drive (constant speed, speed profile or DC motor), the rod's big end
// on the crank pin, the slider on a guide along +x at y = slider.offset, and the small-end joint
// between the rod's bush and the slider's pin: ideal, or with clearance
// (mechanisms/joint_config.h).
#include <cmath>
#include <numbers>
#include <sstream>

#include "common/error.h"
#include "mechanisms/joint_config.h"
#include "mechanisms/mechanism_recipe.h"
#include "multibody/clearance_joint.h"

namespace flexrod {
namespace {

using multibody::MarkerId;
using multibody::SampleView;

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// The slider on its guide, and the small-end joint between the rod's bush and its pin.
void AddSliderAndJoint(const Config& cfg, bool ideal_joint, multibody::MechanismBuilder* b,
                       MechanismModel* out) {
  const double slider_mass = cfg.Quantity("slider.mass");
  const double r = out->crank_length, e = cfg.Quantity("slider.offset");
  if (!(out->effective_length > r + std::abs(e))) {
    throw InputError("rod.length", FormatValue(out->rod_length),
                     "the joint-to-joint length (" + FormatValue(out->effective_length) +
                         " m) must exceed crank.length + |slider.offset| (" +
                         FormatValue(r + std::abs(e)) + " m) for the crank to turn");
  }
  out->slider = b->AddRigidBody({"slider", slider_mass, 0.0, Vec2::Zero()});
  out->journal = b->AddBodyMarker(out->slider, "journal", Vec2::Zero());
  const MarkerId guide = b->AddGroundMarker("guide", Vec2(0.0, e));
  multibody::PrismaticSpec ps;
  ps.name = "guide";
  ps.marker_i = guide;
  ps.marker_j = out->journal;
  ps.axis = Vec2(1.0, 0.0);
  ps.damping = cfg.Quantity("slider.damping");
  ps.friction_force = cfg.Quantity("slider.friction");
  ps.friction_regularisation_speed = cfg.Quantity("slider.friction_velocity");
  out->guide_joint = b->AddPrismatic(ps);

  if (ideal_joint || cfg.Text("joint.type") == "ideal") {
    out->small_end_joint = b->AddRevolute("small-end", out->small_end, out->journal);
  } else {
    // Clearance joint: bush on the rod's small-end clamp (marker i), pin on the slider (marker
    // j). The slider keeps its guide (y and angle held); along it, it is free. p0 puts the
    // journal at the bush centre (concentric pin: zero eccentricity, joint open).
    ClearanceJointConfig joint = ResolveClearanceJoint(cfg, slider_mass);
    out->clearance = b->AddForceElement("small-end-clearance", out->small_end, out->journal,
                                        MakeClearanceJoint(joint));
    out->joint_parameters = std::move(joint.parameters);
  }
}

/// p0 and v0: the rigid motion's configuration and velocity at crank angle drive.initial_angle.
void SetRigidMotion(const Config& cfg, MechanismModel* out) {
  const multibody::Mechanism& mech = out->mechanism;
  const double r = out->crank_length, e = cfg.Quantity("slider.offset");
  const Vec2 d = out->small_end_point - out->big_end_point;  // joint to joint, rod frame
  auto rigid_pose = [&](double theta) {
    Vec p = Vec::Zero(mech.num_coordinates());
    const Vec2 P = r * Vec2(std::cos(theta), std::sin(theta));
    const double ell = out->effective_length;
    const Vec2 S(P.x() + std::sqrt(ell * ell - (e - P.y()) * (e - P.y())), e);
    const double theta_rod = std::atan2(S.y() - P.y(), S.x() - P.x()) - std::atan2(d.y(), d.x());
    p[mech.coordinate(out->crank, multibody::kTheta)] = theta;
    PlaceRod(*out, P - Rotation(theta_rod) * out->big_end_point, theta_rod, &p);
    p[mech.coordinate(out->slider, multibody::kX)] = S.x();
    p[mech.coordinate(out->slider, multibody::kY)] = S.y();
    return p;
  };
  SetCrankRigidMotion(rigid_pose, out);
}

class SliderCrank final : public MechanismRecipe {
 public:
  const char* name() const override { return "slider-crank"; }
  bool turns_a_crank() const override { return true; }

  void Build(const Config& cfg, bool ideal_joint, multibody::MechanismBuilder* b,
             MechanismModel* out) const override {
    AddDrivenCrankParts(cfg, b, out);
    AddSliderAndJoint(cfg, ideal_joint, b, out);
    AddCrankDrive(b, out);
    out->mechanism = b->Build();
    SetRigidMotion(cfg, out);
  }

  std::vector<int> HeldForModes(const MechanismModel& mm) const override {
    return {mm.mechanism.coordinate(mm.crank, multibody::kTheta)};
  }

  void DefineChannels(const MechanismModel& mm, Recorder* rec,
                      study::ImpactLogger* impacts) const override;

  RunWindow SetUpRun(const SimOptions& sim, const MechanismModel& mm,
                     multibody::InitialConditionSpec* ic,
                     multibody::SimulationOptions* opt) const override;

  std::unique_ptr<study::PartsDrawing> LayOutParts(const Config& cfg, const MechanismModel& mm,
                                                   study::VtkLayout* layout) const override;
};

/// The slider: a rectangle centred on the journal, aligned with the journal marker. Its size is
/// a drawing size, not physics: kHalfLength × kHalfHeight bush radii, long enough along the
/// guide to read as a block, high enough to enclose the pin circle.
class SliderDrawing final : public study::PartsDrawing {
 public:
  static constexpr double kHalfLength = 2.0, kHalfHeight = 1.25;  ///< [bush radii]

  SliderDrawing(multibody::MarkerId journal, int first, double bush_radius)
      : journal_(journal),
        first_(first),
        half_length_(kHalfLength * bush_radius),
        half_height_(kHalfHeight * bush_radius) {}

  void Draw(const multibody::SampleView& s, study::VtkFrame* f) const override {
    const multibody::MarkerKinematics& journal = s.Marker(journal_);
    const Mat2 A = Rotation(journal.angle);
    const double a = half_length_, b = half_height_;
    const Vec2 corners[4] = {Vec2(-a, -b), Vec2(a, -b), Vec2(a, b), Vec2(-a, b)};
    for (int i = 0; i < 4; ++i) f->points[first_ + i] = journal.position + A * corners[i];
  }

 private:
  multibody::MarkerId journal_;
  int first_;
  double half_length_, half_height_;  ///< [m]
};

std::unique_ptr<study::PartsDrawing> SliderCrank::LayOutParts(const Config& cfg,
                                                              const MechanismModel& mm,
                                                              study::VtkLayout* layout) const {
  const double bush = cfg.Quantity("joint.bush_radius");
  RequirePositive("joint.bush_radius", bush);
  const int first = layout->slider_first = layout->AddPoints(4);
  layout->cells.push_back(
      {study::kVtkQuad, study::VtkPart::kSlider, {first, first + 1, first + 2, first + 3}});
  return std::make_unique<SliderDrawing>(mm.journal, first, bush);
}

void SliderCrank::DefineChannels(const MechanismModel& mm, Recorder* rec,
                                 study::ImpactLogger* impacts) const {
  const multibody::Mechanism& m = mm.mechanism;
  const int crank_theta = m.coordinate(mm.crank, multibody::kTheta);
  const int sx = m.coordinate(mm.slider, multibody::kX);
  AddCrankChannels(mm, rec);
  rec->Add({{"slider_position", "m"}, {"slider_velocity", "m/s"}, {"slider_acceleration", "m/s^2"}},
           [=](const SampleView& s, double* v) {
             v[0] = s.coordinate(sx);
             v[1] = s.velocity(sx);
             v[2] = s.acceleration(sx);
           });
  // Force the crank pin exerts on the rod at the big end (marker j of the joint is the rod's).
  rec->Add({{"big_end_force_x", "N"}, {"big_end_force_y", "N"}},
           [joint = mm.big_end_joint](const SampleView& s, double* v) {
             const Vec2 f = s.Reaction(joint).force_j;
             v[0] = f.x();
             v[1] = f.y();
           });
  if (mm.small_end_joint.index >= 0) {  // ideal small-end joint
    // Force the journal exerts on the rod's bush (marker i of the small-end joint is the rod's).
    rec->Add({{"bearing_force_x", "N"}, {"bearing_force_y", "N"}, {"bearing_force", "N"}},
             [joint = mm.small_end_joint](const SampleView& s, double* v) {
               const Vec2 f = s.Reaction(joint).force_i;
               v[0] = f.x();
               v[1] = f.y();
               v[2] = f.norm();
             });
  }
  if (mm.clearance.index >= 0) {  // clearance small-end joint (multibody/clearance_joint.h)
    // Pin centre relative to the bush centre (world axes); penetration < 0 is the open gap.
    rec->Add({{"journal_eccentricity_x", "m"},
              {"journal_eccentricity_y", "m"},
              {"journal_eccentricity", "m"},
              {"penetration", "m"},
              {"penetration_rate", "m/s"},
              {"contact_normal_force", "N"},
              {"contact_friction_force", "N"},
              {"contact_dissipation", "W"},
              {"bearing_force", "N"}},
             [=, joint = mm.clearance](const SampleView& s, double* v) {
               const multibody::ClearanceResponse r = multibody::CalcClearanceResponse(s, joint);
               if (impacts)
                 impacts->Observe(study::MakeContactPoint(s.t(), s.coordinate(crank_theta), r));
               v[0] = r.kinematics.eccentricity.x();
               v[1] = r.kinematics.eccentricity.y();
               v[2] = r.kinematics.eccentricity_norm;
               v[3] = r.kinematics.penetration;
               v[4] = r.kinematics.penetration_rate;
               v[5] = r.normal_force;
               v[6] = r.friction_force;
               v[7] = r.dissipation();
               v[8] = std::hypot(r.normal_force, r.friction_force);  // |force on the bush|
             });
  }
}

RunWindow SliderCrank::SetUpRun(const SimOptions& sim, const MechanismModel& mm,
                                multibody::InitialConditionSpec* ic,
                                multibody::SimulationOptions* opt) const {
  const multibody::Mechanism& m = mm.mechanism;
  const double settle = sim.settle;
  RunWindow window{settle, 0.0};
  const int ct = m.coordinate(mm.crank, multibody::kTheta);
  const bool constant = mm.drive.type == DriveOptions::Type::kConstant;
  const double w0 = constant ? mm.drive.speed : 0.0;
  if (mm.drive.type == DriveOptions::Type::kMotor) {  // constraint drivers fix the crank themselves
    ic->fixed_coordinates = {ct};
    ic->fixed_velocities = {ct};
  }
  if (mm.clearance.index >= 0) {
    // With a clearance joint the rod angle and the slider are free: start them concentric on
    // the rigid motion (p0, v0), so the run does not begin with an artificial impact.
    const int rod_theta = m.coordinate(mm.conrod, multibody::kTheta);
    const int slider_x = m.coordinate(mm.slider, multibody::kX);
    ic->fixed_coordinates.insert(ic->fixed_coordinates.end(), {rod_theta, slider_x});
    ic->fixed_velocities.insert(ic->fixed_velocities.end(), {rod_theta, slider_x});
  }
  opt->index_event = multibody::IndexEventSpec{mm.crank, sim.index_angle};
  opt->start_sampling_at_index = true;
  if (constant) {
    // Exact index time: θ0 + ω t = θ_index + 2πk, first k with t ≥ settle.
    const double theta0 = mm.drive.initial_angle, idx = sim.index_angle;
    const double k = std::ceil((theta0 + w0 * settle - idx) / kTwoPi - 1e-12);
    window.capture_start = (idx + kTwoPi * k - theta0) / w0;
    opt->start_sampling_at_index = false;  // the grid starts exactly at the index time
  } else {
    // The index event after sim.settle starts the grid: allow up to 1 s of waiting for it.
    window.extra_time = 1.0;
  }
  return window;
}

}  // namespace

const MechanismRecipe& SliderCrankRecipe() {
  static const SliderCrank recipe;
  return recipe;
}

}  // namespace flexrod
