// SPDX-License-Identifier: GPL-3.0-or-later
// The four-bar recipe (mechanism.type = four-bar): the crank on its ground pivot at the origin
// turned by the drive, the connecting rod as the coupler from the crank pin to the tip of a
// rocker on a second ground pivot at (rocker.pivot_x, rocker.pivot_y), all joints ideal. The
// rocker is a rigid bar of rocker.length with its centre of mass at mid-length. The assembly is
// the open branch: the rod–rocker joint left of the line from the crank pin to the rocker
// pivot. A crank-rocker (the crank turns fully) is required; it has no slider, so the
// per-revolution statistics, the ideal-joint twin and the amplification, which read the slider
// and the bearing force, are not computed (turns_a_crank() is false).
#include <cmath>
#include <numbers>

#include "common/error.h"
#include "mechanisms/mechanism_recipe.h"

namespace flexrod {
namespace {

using multibody::SampleView;

/// The rod–rocker joint S [m] of the open assembly with the crank pin at P [m]: the
/// intersection of the circles about P (radius ell, the rod's joint-to-joint length) and about
/// the rocker pivot O (radius c), left of the line P → O.
Vec2 CouplerJoint(const Vec2& P, const Vec2& O, double ell, double c) {
  const Vec2 D = O - P;
  const double dist = D.norm();
  const double a = (ell * ell - c * c + dist * dist) / (2.0 * dist);
  const double h = std::sqrt(std::max(ell * ell - a * a, 0.0));
  return P + (a / dist) * D + (h / dist) * Vec2(-D.y(), D.x());
}

class FourBar final : public MechanismRecipe {
 public:
  const char* name() const override { return "four-bar"; }
  bool turns_a_crank() const override { return false; }

  void Build(const Config& cfg, bool ideal_joint, multibody::MechanismBuilder* b,
             MechanismModel* out) const override {
    if (!ideal_joint && cfg.Text("joint.type") != "ideal") {
      throw InputError("joint.type", cfg.Text("joint.type"),
                       "must be ideal with mechanism.type = four-bar (its joints are ideal)");
    }
    AddDrivenCrankParts(cfg, b, out);
    const double c = cfg.Quantity("rocker.length");
    const Vec2 pivot(cfg.Quantity("rocker.pivot_x"), cfg.Quantity("rocker.pivot_y"));
    CheckCrankTurns(out->crank_length, out->effective_length, c, pivot.norm());
    const multibody::BodyId rocker = b->AddRigidBody(
        {"rocker", cfg.Quantity("rocker.mass"), cfg.Quantity("rocker.inertia"), Vec2(0.5 * c, 0)});
    b->AddRevolute("rocker-pivot", b->AddGroundMarker("rocker-pivot", pivot),
                   b->AddBodyMarker(rocker, "rocker-axis", Vec2::Zero()));
    out->small_end_joint =
        b->AddRevolute("small-end", out->small_end, b->AddBodyMarker(rocker, "tip", Vec2(c, 0)));
    AddCrankDrive(b, out);
    out->mechanism = b->Build();
    SetRigidMotion(pivot, c, out);
  }

  std::vector<int> HeldForModes(const MechanismModel& mm) const override {
    return {mm.mechanism.coordinate(mm.crank, multibody::kTheta)};
  }

  void DefineChannels(const MechanismModel& mm, Recorder* rec,
                      study::ImpactLogger* /*impacts*/) const override {
    const multibody::Mechanism& m = mm.mechanism;
    const int rocker_theta = m.coordinate(m.FindBody("rocker"), multibody::kTheta);
    AddCrankChannels(mm, rec);
    rec->Add({{"rocker_angle", "rad"},
              {"rocker_angular_velocity", "rad/s"},
              {"rocker_angular_acceleration", "rad/s^2"}},
             [=](const SampleView& s, double* v) {
               v[0] = s.coordinate(rocker_theta);
               v[1] = s.velocity(rocker_theta);
               v[2] = s.acceleration(rocker_theta);
             });
    // Force the rocker's tip exerts on the rod's small end (marker i is the rod's).
    rec->Add({{"bearing_force_x", "N"}, {"bearing_force_y", "N"}, {"bearing_force", "N"}},
             [joint = mm.small_end_joint](const SampleView& s, double* v) {
               const Vec2 f = s.Reaction(joint).force_i;
               v[0] = f.x();
               v[1] = f.y();
               v[2] = f.norm();
             });
  }

  RunWindow SetUpRun(const SimOptions& sim, const MechanismModel& mm,
                     multibody::InitialConditionSpec* ic,
                     multibody::SimulationOptions* /*opt*/) const override {
    // The rigid motion p0, v0 is consistent; a constant-speed or profile driver fixes the crank
    // itself, a motor's crank is held by the initialisation.
    if (mm.drive.type == DriveOptions::Type::kMotor) {
      const int ct = mm.mechanism.coordinate(mm.crank, multibody::kTheta);
      ic->fixed_coordinates = {ct};
      ic->fixed_velocities = {ct};
    }
    return {sim.settle, 0.0};
  }

  std::unique_ptr<study::PartsDrawing> LayOutParts(const Config& cfg, const MechanismModel& mm,
                                                   study::VtkLayout* layout) const override {
    layout->rocker_axis = layout->AddPoints(1);
    layout->rocker_tip = layout->AddPoints(1);
    layout->cells.push_back(
        {study::kVtkLine, study::VtkPart::kRocker, {layout->rocker_axis, layout->rocker_tip}});
    return std::make_unique<RockerDrawing>(mm, cfg.Quantity("rocker.length"), layout->rocker_axis,
                                           layout->rocker_tip);
  }

 private:
  /// The rocker: its pivot (its frame's origin) to its tip, rocker.length along its x axis.
  class RockerDrawing final : public study::PartsDrawing {
   public:
    RockerDrawing(const MechanismModel& mm, double length, int axis, int tip)
        : length_(length), axis_(axis), tip_(tip) {
      const multibody::Mechanism& m = mm.mechanism;
      const multibody::BodyId rocker = m.FindBody("rocker");
      x_ = m.coordinate(rocker, multibody::kX);
      y_ = m.coordinate(rocker, multibody::kY);
      theta_ = m.coordinate(rocker, multibody::kTheta);
    }
    void Draw(const multibody::SampleView& s, study::VtkFrame* f) const override {
      const Vec2 pivot(s.coordinate(x_), s.coordinate(y_));
      f->points[axis_] = pivot;
      f->points[tip_] = pivot + Rotation(s.coordinate(theta_)) * Vec2(length_, 0.0);
    }

   private:
    double length_;  ///< [m]
    int axis_, tip_;
    int x_{0}, y_{0}, theta_{0};  ///< the rocker's coordinates
  };

  /// A crank-rocker: the crank pin's distance to the rocker pivot, between |d − r| and d + r,
  /// must stay within the reach of rod and rocker, [|ell − c|, ell + c] (Grashof).
  static void CheckCrankTurns(double r, double ell, double c, double d) {
    if (!(d + r < ell + c && std::abs(d - r) > std::abs(ell - c))) {
      throw InputError("rocker.length", FormatValue(c) + " m",
                       "with crank.length = " + FormatValue(r) + " m, the rod's " +
                           FormatValue(ell) + " m and the rocker pivot " + FormatValue(d) +
                           " m from the crank's, the crank cannot turn fully: need d + r < "
                           "ell + c and |d - r| > |ell - c|");
    }
  }

  /// p0 and v0: the rigid motion at crank angle drive.initial_angle.
  static void SetRigidMotion(const Vec2& pivot, double c, MechanismModel* out) {
    const multibody::Mechanism& mech = out->mechanism;
    const multibody::BodyId rocker = mech.FindBody("rocker");
    const Vec2 d = out->small_end_point - out->big_end_point;  // joint to joint, rod frame
    auto rigid_pose = [&](double theta) {
      Vec p = Vec::Zero(mech.num_coordinates());
      const Vec2 P = out->crank_length * Vec2(std::cos(theta), std::sin(theta));
      const Vec2 S = CouplerJoint(P, pivot, out->effective_length, c);
      const double theta_rod = std::atan2(S.y() - P.y(), S.x() - P.x()) - std::atan2(d.y(), d.x());
      p[mech.coordinate(out->crank, multibody::kTheta)] = theta;
      PlaceRod(*out, P - Rotation(theta_rod) * out->big_end_point, theta_rod, &p);
      p[mech.coordinate(rocker, multibody::kX)] = pivot.x();
      p[mech.coordinate(rocker, multibody::kY)] = pivot.y();
      p[mech.coordinate(rocker, multibody::kTheta)] =
          std::atan2(S.y() - pivot.y(), S.x() - pivot.x());
      return p;
    };
    SetCrankRigidMotion(rigid_pose, out);
  }
};

}  // namespace

const MechanismRecipe& FourBarRecipe() {
  static const FourBar recipe;
  return recipe;
}

}  // namespace flexrod
