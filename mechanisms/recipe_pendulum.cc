// SPDX-License-Identifier: GPL-3.0-or-later
// The pendulum recipe (mechanism.type = pendulum): the rod pinned at its big-end point to the
// ground at the origin, released horizontally from rest.
#include "mechanisms/mechanism_recipe.h"

namespace flexrod {
namespace {

class Pendulum final : public MechanismRecipe {
 public:
  const char* name() const override { return "pendulum"; }
  bool turns_a_crank() const override { return false; }

  void Build(const Config& /*cfg*/, bool /*ideal_joint*/, multibody::MechanismBuilder* b,
             MechanismModel* out) const override {
    const multibody::MarkerId pivot = b->AddGroundMarker("pivot", Vec2::Zero());
    out->big_end_joint = b->AddRevolute("pivot", pivot, out->big_end);
    out->mechanism = b->Build();
    out->p0 = Vec::Zero(out->mechanism.num_coordinates());
    PlaceRod(*out, -out->big_end_point, 0.0, &out->p0);
    out->v0 = Vec::Zero(out->mechanism.num_coordinates());
  }

  std::vector<int> HeldForModes(const MechanismModel& mm) const override {
    return {mm.mechanism.coordinate(mm.conrod, multibody::kTheta)};
  }

  void DefineChannels(const MechanismModel& mm, Recorder* rec,
                      study::ImpactLogger* /*impacts*/) const override {
    const int rod_theta = mm.mechanism.coordinate(mm.conrod, multibody::kTheta);
    rec->Add({{"rod_angle", "rad"}, {"rod_angular_velocity", "rad/s"}},
             [=](const multibody::SampleView& s, double* v) {
               v[0] = s.coordinate(rod_theta);
               v[1] = s.velocity(rod_theta);
             });
  }

  RunWindow SetUpRun(const SimOptions& sim, const MechanismModel& mm,
                     multibody::InitialConditionSpec* ic,
                     multibody::SimulationOptions* /*opt*/) const override {
    // Released from the horizontal: consistent initialisation keeps the rod's angle.
    const int rod_theta = mm.mechanism.coordinate(mm.conrod, multibody::kTheta);
    ic->fixed_coordinates = {rod_theta};
    ic->fixed_velocities = {rod_theta};
    return {sim.settle, 0.0};
  }

  /// The rod is the whole pendulum: nothing of its own to draw.
  std::unique_ptr<study::PartsDrawing> LayOutParts(const Config& /*cfg*/,
                                                   const MechanismModel& /*mm*/,
                                                   study::VtkLayout* /*layout*/) const override {
    return nullptr;
  }
};

}  // namespace

const MechanismRecipe& PendulumRecipe() {
  static const Pendulum recipe;
  return recipe;
}

}  // namespace flexrod
