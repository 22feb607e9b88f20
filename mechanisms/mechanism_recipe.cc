// SPDX-License-Identifier: GPL-3.0-or-later
#include "mechanisms/mechanism_recipe.h"

#include <stdexcept>

#include "common/error.h"

namespace flexrod {

// Defined in mechanisms/recipe_<name>.cc, one per recipe.
const MechanismRecipe& SliderCrankRecipe();
const MechanismRecipe& PendulumRecipe();
const MechanismRecipe& FourBarRecipe();

namespace {

/// DC motor on armature-voltage (SCR) control: motor.* is the rated line, T = T_s (1 − ω/ω₀)
/// at full voltage. A DC motor's torque line at armature voltage V is T = (k/R)(V − k ω): the
/// slope k²/R = T_s/ω₀ is the motor's, the no-load speed scales with V. The SCR is set so that
/// the no-load crank speed is drive.speed (V/V_rated = belt ratio · drive.speed / ω₀); under
/// load the mean speed droops by the mean load torque / slope, and impacts make it fluctuate
/// through the flywheel.
multibody::DcMotorSpec MotorOf(const DriveOptions& drive) {
  multibody::DcMotorSpec m;
  const double rated_stall = drive.motor.stall_torque;
  const double rated_no_load = drive.motor.no_load_speed;
  m.ratio = drive.motor.belt_ratio;
  const double w = drive.speed;
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
  m.flywheel_inertia = drive.motor.flywheel_inertia;
  m.Validate("motor");
  return m;
}

std::vector<const MechanismRecipe*> Recipes() {
  return {&SliderCrankRecipe(), &PendulumRecipe(), &FourBarRecipe()};
}

}  // namespace

void AddDrivenCrankParts(const Config& cfg, multibody::MechanismBuilder* b, MechanismModel* out) {
  const double r = cfg.Quantity("crank.length");
  out->crank_length = r;
  out->crank = b->AddRigidBody(
      {"crank", cfg.Quantity("crank.mass"), cfg.Quantity("crank.inertia"), Vec2::Zero()});
  const multibody::MarkerId origin = b->AddGroundMarker("ground-axis", Vec2::Zero());
  const multibody::MarkerId crank_axis = b->AddBodyMarker(out->crank, "crank-axis", Vec2::Zero());
  out->crank_pin = b->AddBodyMarker(out->crank, "crank-pin", Vec2(r, 0.0));
  out->crank_pivot_joint = b->AddRevolute("crank-pivot", origin, crank_axis);
  out->big_end_joint = b->AddRevolute("big-end", out->crank_pin, out->big_end);
}

void AddCrankDrive(multibody::MechanismBuilder* b, MechanismModel* out) {
  const DriveOptions& drive = out->drive;
  const double theta0 = drive.initial_angle;
  if (drive.type == DriveOptions::Type::kConstant) {
    out->driver = b->AddConstantSpeedDriver("drive", out->crank, theta0, drive.speed);
  } else if (drive.type == DriveOptions::Type::kProfile) {
    std::vector<double> times, speeds;
    for (const auto& [t, w] : drive.profile) {
      times.push_back(t);
      speeds.push_back(w);
    }
    out->driver = b->AddSpeedProfileDriver("drive", out->crank, theta0, times, speeds);
  } else {
    out->driver = b->AddDcMotorDriver("drive", out->crank, MotorOf(drive));
  }
}

void AddCrankChannels(const MechanismModel& mm, Recorder* rec) {
  const int crank_theta = mm.mechanism.coordinate(mm.crank, multibody::kTheta);
  rec->Add({{"crank_angle", "rad"}, {"crank_speed", "rad/s"}, {"crank_torque", "N*m"}},
           [=, driver = mm.driver](const multibody::SampleView& s, double* v) {
             v[0] = s.coordinate(crank_theta);
             v[1] = s.velocity(crank_theta);
             v[2] = s.Driver(driver).torque;
           });
}

void SetCrankRigidMotion(const std::function<Vec(double)>& rigid_pose, MechanismModel* out) {
  const double theta0 = out->drive.initial_angle;
  out->p0 = rigid_pose(theta0);
  // v = ω dp/dθ by a central difference (h = 1e-6 rad: error ~1e-12 relative).
  // Constant drive and motor start at drive.speed (the motor at its no-load speed), a speed
  // profile at rest: the profile's driver constraint sets its own velocity.
  const double w0 = out->drive.type == DriveOptions::Type::kProfile ? 0.0 : out->drive.speed;
  constexpr double kH = 1e-6;
  out->v0 = w0 * (rigid_pose(theta0 + kH) - rigid_pose(theta0 - kH)) / (2.0 * kH);
}

const MechanismRecipe& FindRecipe(const std::string& type) {
  for (const MechanismRecipe* r : Recipes()) {
    if (type == r->name()) return *r;
  }
  // The schema's choices of mechanism.type are RecipeNames(): any other value is refused on input.
  throw std::logic_error("no mechanism recipe named \"" + type + "\"");
}

std::vector<std::string> RecipeNames() {
  std::vector<std::string> names;
  for (const MechanismRecipe* r : Recipes()) names.emplace_back(r->name());
  return names;
}

}  // namespace flexrod
