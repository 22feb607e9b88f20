// mechanisms/mechanism_recipe.h — one kind of mechanism (mechanism.type) as a recipe: what it
// builds around the connecting rod, the coordinates it holds for the rod's modes in the assembled
// mechanism, the channels it records, how a run of it starts and is captured, and how its own
// parts are drawn. The rod itself (rigid, reduced, exact; clamps, gauges, deflection, energies,
// its drawing) is shared by every recipe (mechanisms/mechanism_model.cc, run/run_setup.cc,
// run/vtk.cc).
//
// A new mechanism is one file that defines its recipe and one line in the list of FindRecipe
// (mechanisms/mechanism_recipe.cc); docs/architecture.md shows the steps.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "input/config.h"
#include "mechanisms/drawing.h"
#include "mechanisms/impact_log.h"
#include "mechanisms/mechanism_model.h"
#include "mechanisms/recorder.h"
#include "multibody/simulate.h"

namespace flexrod {

/// The capture window of a run, as a recipe sets it up (MechanismRecipe::SetUpRun).
struct RunWindow {
  double capture_start{0.0};  ///< [s] first sample (with an index event: its earliest time)
  double extra_time{0.0};     ///< [s] integrated beyond capture_start + sim.capture
};

class MechanismRecipe {
 public:
  virtual ~MechanismRecipe() = default;

  /// The value of mechanism.type that selects it.
  virtual const char* name() const = 0;

  /// Whether it turns a crank: the per-revolution statistics, the steady start (sim.start =
  /// steady), the ideal-joint twin and the load amplification need one.
  virtual bool turns_a_crank() const = 0;

  /// Adds its bodies, joints and drive around the rod already in `b` (out->conrod, big_end,
  /// small_end and the rod geometry are set), builds out->mechanism, and sets out->p0 and
  /// out->v0, the rigid motion's coordinates and velocities at the start. `ideal_joint` forces
  /// an ideal small-end joint where the input has a clearance joint.
  virtual void Build(const Config& cfg, bool ideal_joint, multibody::MechanismBuilder* b,
                     MechanismModel* out) const = 0;

  /// The coordinates held while the rod's modes in the assembled mechanism are computed
  /// (mechanisms/mechanism_damping.h): its rigid motion's degree of freedom.
  virtual std::vector<int> HeldForModes(const MechanismModel& mm) const = 0;

  /// Adds its own channels to `rec`, before the rod's. `impacts` (clearance runs) sees the
  /// contact at every sample.
  virtual void DefineChannels(const MechanismModel& mm, Recorder* rec,
                              study::ImpactLogger* impacts) const = 0;

  /// Completes the initial conditions (`ic`: the coordinates consistent initialisation keeps)
  /// and the integrator's options (an index event starting the capture) of a run with `sim`,
  /// and returns its capture window.
  virtual RunWindow SetUpRun(const SimOptions& sim, const MechanismModel& mm,
                             multibody::InitialConditionSpec* ic,
                             multibody::SimulationOptions* opt) const = 0;

  /// Lays out its own parts in the drawing of a run (mechanisms/drawing.h) beyond what every
  /// mechanism's drawing has (the rod with its clamp arms, the crank where there is one, a
  /// clearance joint's circles): its points (layout->AddPoints) and cells. Returns what draws
  /// them in each frame, or nullptr when it has no parts of its own.
  virtual std::unique_ptr<study::PartsDrawing> LayOutParts(const Config& cfg,
                                                           const MechanismModel& mm,
                                                           study::VtkLayout* layout) const = 0;
};

/// Parts a recipe with a driven crank shares. The crank (crank.*) on its ground pivot at the
/// origin, its pin at crank.length along its x axis, the rod's big end on the pin
/// (MechanismModel::crank, crank_pin, crank_pivot_joint, big_end_joint, crank_length).
void AddDrivenCrankParts(const Config& cfg, multibody::MechanismBuilder* b, MechanismModel* out);
/// The crank's drive of MechanismModel::drive: constant speed, speed profile or DC motor.
void AddCrankDrive(multibody::MechanismBuilder* b, MechanismModel* out);
/// The channels crank_angle [rad], crank_speed [rad/s] and crank_torque [N m] (the drive's).
void AddCrankChannels(const MechanismModel& mm, Recorder* rec);
/// p0 = pose(θ0) and v0 = ω0 dpose/dθ at θ0 = drive.initial_angle, with `pose` the mechanism's
/// rigid-motion coordinates at a crank angle [rad].
void SetCrankRigidMotion(const std::function<Vec(double)>& pose, MechanismModel* out);

/// The recipe of mechanism.type = `type` (a value the schema accepts).
const MechanismRecipe& FindRecipe(const std::string& type);

/// The values mechanism.type takes, one per recipe.
std::vector<std::string> RecipeNames();

}  // namespace flexrod
