// input/options.h — the typed options of a run, each read and checked once from the keys
// (input/config_schema.cc): sim.* (window, tolerances, start), drive.* and motor.* (the crank's
// drive), damping.* (the rod's elastic damping). SI throughout. The other groups have their own
// readers: output.* input/output_selection.h; rod.*, reduction.*, clamp.* mechanisms/rod_config.h;
// joint.* mechanisms/joint_config.h; vtk.* run/vtk.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "input/config.h"

namespace flexrod {

/// The index of a choice key's value among the schema's choices for it (input/config_schema.cc):
/// the typed options declare their enumerators in that order and cast it. The schema has
/// checked the value; a key that is not a choice is a logic error.
int ChoiceIndex(const Config& cfg, const std::string& key);

/// rod.type: the connecting rod's model.
enum class RodModel { kFlexible, kExact, kRigid };  ///< in the order of the schema's choices
RodModel ReadRodModel(const Config& cfg);

/// sim.*: the run's window, the integrator's tolerances and limits, the start.
struct SimOptions {
  enum class Start { kRigid, kStatic, kSteady };    ///< in the order of the schema's choices
  enum class LinearSolver { kAuto, kDense, kKlu };  ///< likewise
  Start start{Start::kRigid};
  int steady_revolutions{100};  ///< sim.start = steady: most revolutions of the search, >= 2
  double settle{0.0};           ///< settling time before the capture [s]
  bool steady_window{true};     ///< settle until the captured window is stationary
  double max_settle{0.0};       ///< steady_window: latest start of the capture [s]
  double capture{0.0};          ///< captured duration [s]
  double sample_rate{0.0};      ///< [Hz]
  double index_angle{0.0};      ///< crank angle that starts the capture [rad]
  double rel_tol{0.0};          ///< [1]
  double abs_tol{0.0};          ///< [m, rad, 1]
  double max_step{0.0};         ///< [s], 0 = none
  int max_steps{0};             ///< per integration, 0 = from the simulated time
  double max_wall_time{0.0};    ///< [s], 0 = unlimited
  LinearSolver linear_solver{LinearSolver::kAuto};
  bool eliminate_prescribed{true};
};

/// Reads sim.*; throws InputError naming sim.sample_rate if it is not positive. The rules that
/// combine keys (a capture of at least 2 samples, a steady start's drive) and the integrator's
/// own are checked by CheckRunInput (run/run.h).
SimOptions ReadSimOptions(const Config& cfg);

/// ensemble.*: the members of a run's ensemble (run/ensemble.h).
struct EnsembleOptions {
  int members{0};             ///< 0: automatic (4 for `flexrod run` of a clearance crank)
  double angle_step{0.0};     ///< [rad] between members' crank starts; 0 = 2π / members
  double settle_spread{0.0};  ///< [s] the members' sim.settle spread over it
  double confidence{0.95};    ///< two-sided coverage of the bootstrap intervals
};
EnsembleOptions ReadEnsembleOptions(const Config& cfg);
/// The members of `flexrod run`'s automatic ensemble (run/ensemble.h).
inline constexpr int kDefaultRunMembers = 3;
/// The number of members `options` asks for: ensemble.members, or for 0 (automatic)
/// kDefaultRunMembers where `automatic_ensemble` (a `flexrod run` of a clearance joint on a
/// crank) and 1 otherwise.
int EnsembleMembers(const EnsembleOptions& options, bool automatic_ensemble);

/// The keys member k (0 ≤ k < members) of the ensemble of `cfg` sets, as (key, text that reads
/// back to the same double): none for member 0, drive.initial_angle and sim.settle for the others
/// (EnsembleMemberInputs). Sweeps expand a case into its members with these.
std::vector<std::pair<std::string, std::string>> EnsembleMemberSettings(
    const Config& cfg, const EnsembleOptions& options, int members, int k);

/// drive.* and motor.*: the crank's drive.
struct DriveOptions {
  enum class Type { kConstant, kProfile, kMotor };  ///< in the order of the schema's choices
  Type type{Type::kConstant};
  double speed{0.0};          ///< drive.speed [rad/s]
  double initial_angle{0.0};  ///< drive.initial_angle [rad]
  /// drive.profile as (time [s], crank speed [rad/s]) knots, empty if not given; checked
  /// whatever drive.type is (its rules hold whether or not it is used).
  std::vector<std::pair<double, double>> profile;
  struct Motor {                   ///< motor.*: the rated DC motor line
    double stall_torque{0.0};      ///< [N m]
    double no_load_speed{0.0};     ///< [rad/s]
    double belt_ratio{0.0};        ///< motor speed / crank speed [1]
    double flywheel_inertia{0.0};  ///< [kg m^2]
  } motor;
};

/// Reads drive.* and motor.*; throws InputError naming drive.profile for a malformed profile.
DriveOptions ReadDriveOptions(const Config& cfg);

/// damping.*: the rod's elastic damping.
struct DampingOptions {
  enum class Type {
    kBand,
    kRatio,
    kRayleigh,
    kMaterial
  };  ///< in the order of the schema's choices
  Type type{Type::kBand};
  double ratio{0.0};  ///< damping.ratio [1]
  /// kMaterial: the rod material's loss factor η [1] (set where the material is resolved:
  /// BuildMechanism); every mode gets ζ = η / 2.
  double loss_factor{0.0};
  double alpha{0.0};  ///< Rayleigh mass factor [1/s]
  double beta{0.0};   ///< Rayleigh stiffness factor [s]
};

DampingOptions ReadDampingOptions(const Config& cfg);

/// vtk.*: the ParaView frames of `flexrod run --vtk` (run/vtk.h). Frames are taken from the
/// run's output samples (no extra integration): every stride-th sample of the capture window,
/// stride = max(1, round(sim.sample_rate / rate)), so the frame rate is sim.sample_rate / stride
/// (exactly `rate` when it divides the sample rate, otherwise the nearest such rate, at most
/// sim.sample_rate).
struct VtkOptions {
  double rate{1000.0};   ///< requested frame rate [Hz], > 0 (key vtk.rate)
  double scale{100.0};   ///< deformation scale factor s [1], >= 0 (key vtk.scale)
  double duration{0.0};  ///< window written from the capture start [s], >= 0; 0 = the whole
                         ///< capture (key vtk.duration)
  /// Throws InputError naming the vtk.* key, the value and the rule.
  void Validate() const;
};

/// Reads and validates vtk.rate, vtk.scale, vtk.duration.
VtkOptions ReadVtkOptions(const Config& cfg);

}  // namespace flexrod
