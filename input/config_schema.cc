// SPDX-License-Identifier: GPL-3.0-or-later
// The schema of every input key, with defaults and the reasoning behind assumed values.
#include <algorithm>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/error.h"
#include "contact/friction_law.h"
#include "contact/normal_law.h"
#include "input/config.h"

namespace flexrod {

namespace {

/// "none" (no friction) followed by the friction laws of contact/.
std::vector<std::string> WithNone(const std::vector<std::string>& laws) {
  std::vector<std::string> v{"none"};
  v.insert(v.end(), laws.begin(), laws.end());
  return v;
}

/// The keys whose admissible values are a plain interval (ValueRange), set on the schema.
/// Rules that involve other keys (a clearance below the bush radius, a probe on the rod) stay
/// with the builders.
std::vector<ParamDef> WithRanges(std::vector<ParamDef> schema) {
  const double inf = std::numeric_limits<double>::infinity();
  const ValueRange positive{0.0, true, inf, false}, non_negative{0.0, false, inf, false};
  const std::pair<const char*, ValueRange> ranges[] = {
      // > 0
      {"rod.thickness", positive},
      {"rod.height", positive},
      {"rod.length", positive},
      {"crank.length", positive},
      {"crank.mass", positive},
      {"slider.mass", positive},
      {"rocker.length", positive},
      {"rocker.mass", positive},
      {"slider.friction_velocity", positive},
      {"joint.clearance", positive},
      {"joint.bush_radius", positive},
      {"joint.length", positive},
      {"joint.friction", positive},
      {"drive.speed", positive},
      {"motor.stall_torque", positive},
      {"motor.no_load_speed", positive},
      {"motor.belt_ratio", positive},
      {"sim.capture", positive},
      {"sim.sample_rate", positive},
      {"sim.rel_tol", positive},
      {"sim.abs_tol", positive},
      {"vtk.rate", positive},
      // >= 0 (0 often = derive or none)
      {"rod.E", non_negative},
      {"rod.rho", non_negative},
      {"rod.loss_factor", non_negative},
      {"rod.yield", non_negative},
      {"reduction.modes", non_negative},
      {"reduction.cutoff", non_negative},
      {"rod.rigid_mass", non_negative},
      {"rod.rigid_inertia", non_negative},
      {"clamp.big_mass", non_negative},
      {"clamp.big_inertia", non_negative},
      {"clamp.small_mass", non_negative},
      {"clamp.small_inertia", non_negative},
      {"crank.inertia", non_negative},
      {"rocker.inertia", non_negative},
      {"slider.damping", non_negative},
      {"slider.friction", non_negative},
      {"joint.stiffness", non_negative},
      {"joint.damping", non_negative},
      {"joint.effective_mass", non_negative},
      {"joint.working_penetration", non_negative},
      {"joint.min_approach_velocity", non_negative},
      {"motor.flywheel_inertia", non_negative},
      {"damping.ratio", non_negative},
      {"damping.alpha", non_negative},
      {"damping.beta", non_negative},
      {"sim.settle", non_negative},
      {"sim.max_settle", non_negative},
      {"sim.max_step", non_negative},
      {"sim.max_steps", non_negative},
      {"sim.max_wall_time", non_negative},
      {"output.rate", non_negative},
      {"output.midspan", non_negative},
      {"vtk.scale", non_negative},
      {"vtk.duration", non_negative},
      {"modes.count", non_negative},
      // others
      {"rod.elements", {1.0, false, 1e5, false}},  // more elements than a beam model needs
      {"sim.steady_revolutions", {2.0, false, inf, false}},
      {"ensemble.members", {0.0, false, 64.0, false}},
      {"ensemble.settle_spread", non_negative},
      {"ensemble.confidence", {0.5, false, 1.0, true}},
      {"joint.restitution", {0.0, true, 1.0, false}},
  };
  for (const auto& entry : ranges) {  // not a structured binding: clang 14 cannot capture one
    const std::string key = entry.first;
    auto it =
        std::find_if(schema.begin(), schema.end(), [&](const ParamDef& p) { return p.key == key; });
    if (it == schema.end() ||
        (it->kind != ParamKind::kQuantity && it->kind != ParamKind::kInteger)) {
      throw std::logic_error("schema range for '" + key + "': no such numeric key");
    }
    it->range = entry.second;
  }
  return schema;
}

}  // namespace

const std::vector<ParamDef>& Schema() {
  using D = Dimension;
  using K = ParamKind;
  static const std::vector<ParamDef> schema = WithRanges({
      // ---- the rod (RIG.md §2, Table 1) ----
      {"rod.material",
       K::kChoice,
       D::kDimensionless,
       "steel",
       "rod material; E, nu, rho, yield override it",
       {"steel", "brass", "aluminium", "aluminum"}},
      {"rod.E", K::kQuantity, D::kPressure, "0", "Young's modulus override [Pa]; 0 = material's"},
      {"rod.nu", K::kQuantity, D::kDimensionless, "0",
       "Poisson ratio override [-]; 0 = material's"},
      {"rod.rho", K::kQuantity, D::kDensity, "0", "density override [kg/m^3]; 0 = material's"},
      {"rod.yield", K::kQuantity, D::kPressure, "0",
       "yield strength override [Pa]; 0 = material's"},
      {"rod.loss_factor", K::kQuantity, D::kDimensionless, "0",
       "material loss factor override [-] (damping.type = material); 0 = material's: steel "
       "4e-4, brass 1e-3, aluminium 1e-4 (Cremer, Heckl & Petersson, Structure-Borne Sound)"},
      {"rod.thickness", K::kQuantity, D::kLength, "3.175 mm",
       "bar thickness [m], > 0 (RIG.md Table 1; chapter 4's 6.25 mm conflicts)"},
      {"rod.height", K::kQuantity, D::kLength, "19.05 mm", "bar height [m], > 0"},
      {"rod.length", K::kQuantity, D::kLength, "280 mm", "free length between the clamps [m], > 0"},
      {"rod.elements", K::kInteger, D::kDimensionless, "40", "number of beam elements, >= 1"},
      {"rod.element",
       K::kChoice,
       D::kDimensionless,
       "euler-bernoulli",
       "beam theory of the reduced and full FE rods; the exact rod (rod.type = exact) is always "
       "a shear-deformable Reissner (Timoshenko) beam and refuses euler-bernoulli when set",
       {"euler-bernoulli", "timoshenko"}},
      {"rod.bending",
       K::kChoice,
       D::kDimensionless,
       "weak",
       "which section axis bends in the mechanism plane (weak: I = h t^3/12)",
       {"weak", "strong"}},
      {"rod.mass",
       K::kChoice,
       D::kDimensionless,
       "consistent",
       "element mass matrix, used for the basis and the body inertia",
       {"consistent", "lumped"}},
      // ---- model reduction ----
      {"reduction.method",
       K::kChoice,
       D::kDimensionless,
       "craig-bampton",
       "rod basis (full: every FE coordinate; run it at sim.abs_tol = 1e-8, as `study reduction` "
       "does: at 1e-10 its stiffest modes hold the step)",
       {"craig-bampton", "orthonormal-cb", "free-free", "full"}},
      {"reduction.modes", K::kInteger, D::kDimensionless, "8",
       "fixed-interface normal modes kept, >= 0"},
      {"reduction.cutoff", K::kQuantity, D::kFrequency, "0",
       "if > 0: keep every mode below this frequency instead of a count [Hz]"},
      {"reduction.axial_modes", K::kBool, D::kDimensionless, "true",
       "craig-bampton: add the two static responses to axial inertia loads, so the axial force "
       "can vary along the rod"},
      // ---- the mechanism (mechanisms/mechanism_recipe.h; RIG.md §1 rigid rig, §2 flexible rig)
      // ----
      {"mechanism.type",
       K::kChoice,
       D::kDimensionless,
       "slider-crank",
       "mechanism",
       {"slider-crank", "pendulum",
        "four-bar"}},  // one per recipe of mechanisms/mechanism_recipe.cc (tested)
      {"rod.type",
       K::kChoice,
       D::kDimensionless,
       "flexible",
       "connecting rod model: flexible = reduced floating-frame rod (reduction.*), exact = "
       "geometrically exact beam (Simo-Reissner, a body per FE node; the reference), rigid",
       {"flexible", "exact", "rigid"}},
      {"rod.rigid_mass", K::kQuantity, D::kMass, "0",
       "rigid rod mass [kg]; 0 = from material and section (rigid rod only)"},
      {"rod.rigid_inertia", K::kQuantity, D::kInertia, "0",
       "rigid rod inertia about its centre [kg m^2]; 0 = m L^2/12 (rigid rod only)"},
      {"rod.geometric_stiffening", K::kBool, D::kDimensionless, "true",
       "reduced rod: geometric stiffness of the distributed axial force, per element (P-delta); "
       "false = linear elastic forces (wrong under axial load)"},
      {"rod.big_end_x", K::kQuantity, D::kLength, "-15 mm",
       "crank-pin centre relative to the big-end clamp node, along the rod [m] (assumed)"},
      {"rod.big_end_y", K::kQuantity, D::kLength, "-8 mm",
       "crank-pin centre relative to the big-end clamp node, across the rod [m] (assumed)"},
      {"rod.small_end_x", K::kQuantity, D::kLength, "15 mm",
       "bush centre relative to the small-end clamp node, along the rod [m] (assumed)"},
      {"rod.small_end_y", K::kQuantity, D::kLength, "-8 mm",
       "bush centre relative to the small-end clamp node, across the rod [m] (assumed)"},
      {"clamp.big_mass", K::kQuantity, D::kMass, "0.10 kg",
       "big-end clamp mass, welded to node 0 [kg] (assumed)"},
      {"clamp.big_inertia", K::kQuantity, D::kInertia, "3e-5 kg m^2",
       "big-end clamp inertia [kg m^2] (assumed)"},
      {"clamp.small_mass", K::kQuantity, D::kMass, "0.15 kg",
       "small-end clamp + bush mass, welded to the last node [kg] (assumed)"},
      {"clamp.small_inertia", K::kQuantity, D::kInertia, "4e-5 kg m^2",
       "small-end clamp inertia about its centre of mass [kg m^2] (assumed)"},
      {"clamp.small_com_x", K::kQuantity, D::kLength, "12 mm",
       "small-end clamp centre of mass from the last node, along the rod [m] (assumed)"},
      {"clamp.small_com_y", K::kQuantity, D::kLength, "-6 mm",
       "small-end clamp centre of mass from the last node, across the rod (off-axis, RIG.md §2) "
       "[m] (assumed)"},
      {"crank.length", K::kQuantity, D::kLength, "30 mm", "crank throw [m], > 0"},
      {"crank.mass", K::kQuantity, D::kMass, "2.8 kg",
       "crank disc mass [kg] (assumed: steel disc 150 x 20 mm)"},
      {"crank.inertia", K::kQuantity, D::kInertia, "7.9e-3 kg m^2",
       "crank inertia about its axis [kg m^2] (assumed: m r^2/2 of that disc)"},
      {"slider.mass", K::kQuantity, D::kMass, "2.71 kg", "slider + journal mass [kg], > 0"},
      {"rocker.length", K::kQuantity, D::kLength, "150 mm",
       "four-bar: rocker from its pivot to the rod's small end [m], > 0"},
      {"rocker.pivot_x", K::kQuantity, D::kLength, "250 mm",
       "four-bar: rocker pivot, world x (the crank's pivot at the origin) [m]"},
      {"rocker.pivot_y", K::kQuantity, D::kLength, "0 mm", "four-bar: rocker pivot, world y [m]"},
      {"rocker.mass", K::kQuantity, D::kMass, "0.3 kg", "four-bar: rocker mass [kg], > 0"},
      {"rocker.inertia", K::kQuantity, D::kInertia, "5.6e-4 kg m^2",
       "four-bar: rocker inertia about its centre of mass (mid-length) [kg m^2], >= 0"},
      {"slider.offset", K::kQuantity, D::kLength, "0 mm",
       "guide line offset from the crank axis [m]"},
      {"slider.damping", K::kQuantity, D::kDamping, "20 N s/m",
       "viscous damping of the guide [N s/m] (assumed; the rigid-rig preset sets its calibrated "
       "value)"},
      {"slider.friction", K::kQuantity, D::kForce, "2 N",
       "Coulomb friction force of the guide [N] (assumed)"},
      {"slider.friction_velocity", K::kQuantity, D::kVelocity, "1 mm/s",
       "regularisation velocity of the guide friction, F = Fc tanh(v/v_reg) [m/s]"},
      {"joint.type",
       K::kChoice,
       D::kDimensionless,
       "ideal",
       "small-end joint",
       {"ideal", "clearance"}},
      // ---- the clearance joint (joint.type = clearance; mechanisms/joint_config.h) ----
      {"joint.clearance",
       K::kQuantity,
       D::kLength,
       "0.5 mm",
       "radial clearance c = R_bush - R_pin [m], > 0 and < joint.bush_radius (RIG.md: 0.5 or 1.0 "
       "mm)",
       {}},
      {"joint.bush_radius",
       K::kQuantity,
       D::kLength,
       "9.525 mm",
       "bush (bore) radius [m], > 0 (RIG.md §2: the 3/4 in bore of the small-end clamp)",
       {}},
      {"joint.length",
       K::kQuantity,
       D::kLength,
       "12.7 mm",
       "axial length of the pin-bush line contact [m], > 0 (assumed: 1/2 in)",
       {}},
      {"joint.law", K::kChoice, D::kDimensionless, "hybrid",
       "normal contact law (reference/contact-models.md; hybrid = thesis eq. 29)",
       contact::NormalLawNames()},  // a new law in contact/ is a choice here by itself
      {"joint.restitution",
       K::kQuantity,
       D::kDimensionless,
       "0.9",
       "coefficient of restitution [-], in (0, 1] (assumed; thesis used up to 0.995)",
       {}},
      {"joint.friction_law", K::kChoice, D::kDimensionless, "coulomb",
       "joint friction law (none = frictionless)", WithNone(contact::FrictionLawNames())},
      {"joint.friction",
       K::kQuantity,
       D::kDimensionless,
       "0.18",
       "joint friction coefficient [-], > 0 (thesis §3.3.2: 60 % of steel railway wheels)",
       {}},
      {"joint.pin_material",
       K::kChoice,
       D::kDimensionless,
       "steel",
       "journal material (E, nu)",
       {"steel", "brass", "aluminium", "aluminum"}},
      {"joint.bush_material",
       K::kChoice,
       D::kDimensionless,
       "steel",
       "bush (clamp bore) material (E, nu)",
       {"steel", "brass", "aluminium", "aluminum"}},
      {"joint.stiffness",
       K::kQuantity,
       D::kAny,
       "0",
       "contact stiffness override K [N/m^n, SI]; 0 = derived from materials and geometry",
       {}},
      {"joint.exponent",
       K::kQuantity,
       D::kDimensionless,
       "0",
       "force exponent override n [-], in [1, 10]; 0 = the law's (1.5)",
       {}},
      {"joint.damping",
       K::kQuantity,
       D::kDamping,
       "0",
       "damping override d [N s/m] (kelvin-voigt, maxwell, standard-linear-solid); 0 = from "
       "joint.restitution",
       {}},
      {"joint.effective_mass",
       K::kQuantity,
       D::kMass,
       "0",
       "impact mass for damping calibration (kelvin-voigt, maxwell, standard-linear-solid, impact) "
       "[kg]; "
       "0 = slider.mass",
       {}},
      {"joint.working_penetration",
       K::kQuantity,
       D::kLength,
       "0",
       "penetration range of the power-law fits (hybrid, linear laws) [m]; 0 = 10 um",
       {}},
      {"joint.min_approach_velocity",
       K::kQuantity,
       D::kVelocity,
       "0",
       "floor on the onset approach velocity of the hysteresis laws [m/s]; 0 = 1 mm/s",
       {}},
      // ---- the drive ----
      {"drive.type",
       K::kChoice,
       D::kDimensionless,
       "constant",
       "crank drive",
       {"constant", "profile", "motor"}},
      {"drive.speed", K::kQuantity, D::kAngularVelocity, "200 rpm",
       "crank speed [rad/s], > 0; with drive.type = motor the no-load crank speed the armature "
       "voltage is set to (the mean speed droops under load)"},
      {"drive.profile", K::kText, D::kDimensionless, "",
       "speed profile: comma-separated time:speed pairs in s and rpm, e.g. \"0:0,0.5:200\""},
      {"drive.initial_angle", K::kQuantity, D::kAngle, "0 deg",
       "crank angle at t = 0 [rad], reduced to [0, 2 pi)"},
      {"motor.stall_torque", K::kQuantity, D::kTorque, "20 N m",
       "DC motor stall torque at the motor shaft at rated armature voltage [N m] (assumed for 0.75 "
       "hp)"},
      {"motor.no_load_speed", K::kQuantity, D::kAngularVelocity, "1900 rpm",
       "DC motor no-load speed at rated armature voltage [rad/s]; with the stall torque it sets "
       "the torque-speed slope"},
      {"motor.belt_ratio", K::kQuantity, D::kDimensionless, "3", "motor speed / crank speed [-]"},
      {"motor.flywheel_inertia", K::kQuantity, D::kInertia, "0.35 kg m^2",
       "driven pulley (flywheel) inertia on the crank shaft [kg m^2] (assumed: 485 mm cast "
       "pulley)"},
      // ---- elastic damping of the rod ----
      {"damping.type",
       K::kChoice,
       D::kDimensionless,
       "band",
       "band: 1 % < 100 Hz, 10 % < 1 kHz, critical above (the thesis's commercial code's "
       "convention); ratio; rayleigh; material: every mode zeta = eta / 2 of the rod's material "
       "loss factor (rod.loss_factor). band, ratio and material "
       "damp the rod's modes in the assembled mechanism (crank held at 0, whatever "
       "drive.initial_angle is, ideal small-end joint), not those of the rod clamped to its "
       "frame",
       {"band", "ratio", "rayleigh", "material"}},
      {"damping.ratio", K::kQuantity, D::kDimensionless, "0.02",
       "modal damping ratio (type ratio) of every mode of the rod in the assembled mechanism "
       "(crank held at 0) [-]"},
      {"damping.alpha", K::kQuantity, D::kFrequency, "0", "Rayleigh mass factor [1/s]"},
      {"damping.beta", K::kQuantity, D::kTime, "0", "Rayleigh stiffness factor [s]"},
      {"gravity.enabled", K::kBool, D::kDimensionless, "false",
       "gravity (the rigs are horizontal)"},
      {"gravity.x", K::kQuantity, D::kAcceleration, "0", "gravity, world x [m/s^2]"},
      {"gravity.y", K::kQuantity, D::kAcceleration, "-9.80665", "gravity, world y [m/s^2]"},
      // ---- simulation and output ----
      {"sim.start",
       K::kChoice,
       D::kDimensionless,
       "rigid",
       "initial rod state: rigid (undeformed on the rigid motion), static (static equilibrium), "
       "steady (constant drive: revolutions from index to index until the rod's elastic state "
       "repeats to "
       "1000 sim.rel_tol of its peak (within [1e-6, 1e-2]), at most sim.steady_revolutions; then "
       "the capture, "
       "sim.settle unused)",
       {"rigid", "static", "steady"}},
      {"sim.steady_revolutions", K::kInteger, D::kDimensionless, "100",
       "sim.start = steady: most revolutions of the search, >= 2 (the capture then starts where it "
       "stopped, "
       "with a warning)"},
      {"sim.settle", K::kQuantity, D::kTime, "1 s",
       "settling time before capture [s], >= 0 (with sim.steady_window: the shortest)"},
      {"ensemble.members", K::kInteger, D::kDimensionless, "0",
       "members of a run's ensemble: the same case from different starts (member k: crank start "
       "drive.initial_angle + k ensemble.angle_step, sim.settle + k "
       "ensemble.settle_spread / members), in parallel, sharing member 0's ideal-joint twin; each "
       "headline figure then has an interval (summary ensemble), 0 .. 64; 0 = 3 for `flexrod run` "
       "of a clearance joint on a crank, 1 otherwise (sweeps, studies, ideal joints)"},
      {"ensemble.angle_step", K::kQuantity, D::kAngle, "0 deg",
       "ensemble: member k starts its crank at drive.initial_angle + k times this [rad]; 0 = "
       "360 deg / ensemble.members (spread evenly over the revolution)"},
      {"ensemble.settle_spread", K::kQuantity, D::kTime, "0 s",
       "ensemble: the members' sim.settle spread evenly over this [s], >= 0"},
      {"ensemble.confidence", K::kQuantity, D::kDimensionless, "0.95",
       "ensemble: two-sided coverage of the figures' bootstrap intervals, in [0.5, 1)"},
      {"sim.steady_window", K::kBool, D::kDimensionless, "true",
       "a crank's run (sim.start rigid or static) settles until its captured window is "
       "stationary: no leading block of the window's per-revolution peaks (slider acceleration "
       "+/-, bearing force, gauge stress; the first 1 .. n/2 revolutions) differs in mean from "
       "the rest by more than max(t se, 1 %) (Student, alpha 0.01 shared by the tests); else "
       "the window becomes settling and the next one is captured, up to sim.max_settle (then a "
       "warning); false: the fixed sim.settle"},
      {"sim.max_settle", K::kQuantity, D::kTime, "12 s",
       "sim.steady_window: latest start of the captured window [s], >= 0"},
      {"sim.capture", K::kQuantity, D::kTime, "3 s", "captured duration [s], > 0 (RIG.md Table 2)"},
      {"sim.sample_rate", K::kQuantity, D::kFrequency, "100 kHz", "output sample rate [Hz], > 0"},
      {"sim.index_angle", K::kQuantity, D::kAngle, "0 deg",
       "crank index angle that triggers capture [rad], reduced to [0, 2 pi)"},
      {"sim.rel_tol", K::kQuantity, D::kDimensionless, "1e-6",
       "integrator relative tolerance (of the frame coordinates that move a clearance joint: "
       "relative to the clearance)"},
      // 1e-10: a flexible rod's elastic coordinates are 1e-8..1e-5 (the axial ones carry the
      // slider's load), which a coarser absolute tolerance leaves uncontrolled
      // (tests/run/default_accuracy_slowtest.cc checks the defaults against 1e-12).
      {"sim.abs_tol", K::kQuantity, D::kDimensionless, "1e-10",
       "integrator absolute tolerance (coordinates [m, rad, 1]; velocities: times 1e4 1/s when "
       "a joint or force element moves with elastic coordinates)"},
      {"sim.max_step", K::kQuantity, D::kTime, "0", "integrator step limit [s]; 0 = none"},
      {"sim.max_steps", K::kInteger, D::kDimensionless, "0",
       "integrator steps allowed for each integration of a run (settling and capture, a steady "
       "start's revolution), >= 0; 0 = 10^6 per simulated second + 10^5; a run that reaches it "
       "fails, keeping what it computed"},
      {"sim.max_wall_time", K::kQuantity, D::kTime, "0",
       "wall-clock time allowed for a run (all its integrations: settling, a steady start's "
       "revolutions, capture, the ideal twin's separately) [s], >= 0; 0 = unlimited; a run that "
       "exceeds it fails, keeping what it computed"},
      {"sim.linear_solver",
       K::kChoice,
       D::kDimensionless,
       "auto",
       "linear solver of the integrator's Newton iterations: auto = the dense LU when the "
       "iteration matrix is at least 20 % non-zero (the reduced and full-FE rods), KLU below "
       "(the exact rod); dense; klu",
       {"auto", "dense", "klu"}},
      {"sim.eliminate_prescribed", K::kBool, D::kDimensionless, "true",
       "integrate without the coordinates that ground-side constraints prescribe (driven crank, "
       "guided slider); false integrates the full DAE: the same solution, slower (for checks)"},
      {"output.gauges", K::kText, D::kDimensionless, "0.02,0.14,0.26",
       "strain gauge positions along the rod from the big-end clamp [m], comma-separated"},
      {"output.midspan", K::kQuantity, D::kLength, "0",
       "position of the deflection probe along the rod [m]; 0 = midspan"},
      {"output.format", K::kText, D::kDimensionless, "hdf5",
       "files of a run's channels: hdf5 (run.h5: every channel of the run and of its ideal "
       "twin, the impact log, the summary; compressed), csv (channels.csv, ideal/channels.csv, "
       "impacts.csv) or hdf5,csv"},
      {"output.channels", K::kText, D::kDimensionless, "standard",
       "channels written to a run's channel files (run.h5, channels.csv): standard (crank, "
       "slider, rod angle, bearing force, journal centre, contact forces, rod deflection, gauge "
       "strains), all, or a comma-separated list; the summary always uses every channel"},
      {"output.rate", K::kQuantity, D::kFrequency, "0",
       "sample rate of a run's channel files [Hz]; every n-th sample (no filtering), must "
       "divide sim.sample_rate; 0 = sim.sample_rate"},
      // ---- ParaView output of one run (`flexrod run --vtk DIR`; run/vtk.h) ----
      {"vtk.rate", K::kQuantity, D::kFrequency, "1 kHz",
       "frame rate of the --vtk animation [Hz], > 0; a frame every round(sim.sample_rate / "
       "rate)-th sample"},
      {"vtk.scale", K::kQuantity, D::kDimensionless, "100",
       "scale of the drawn rod's deflection from the chord of its end nodes [1], >= 0; 1 = true "
       "shape, 0 = straight"},
      {"vtk.duration", K::kQuantity, D::kTime, "0",
       "window of the --vtk animation from the capture start [s], >= 0; 0 = the whole capture"},
      // ---- `flexrod modes` (modal analysis of one rod) ----
      {"modes.dim",
       K::kChoice,
       D::kDimensionless,
       "planar",
       "element family",
       {"planar", "spatial"}},
      {"modes.bc",
       K::kChoice,
       D::kDimensionless,
       "clamped-free",
       "supports of the full model (clamped = big end clamped in the frame)",
       {"clamped-clamped", "clamped-free", "free-free", "pinned-pinned", "clamped-pinned"}},
      {"modes.interface", K::kText, D::kDimensionless, "small-end",
       "Craig-Bampton interface: small-end, ends, or a comma-separated node list"},
      {"modes.count", K::kInteger, D::kDimensionless, "0",
       "modes reported; 0 = number of reduced coordinates (at least 10)"},
  });
  return schema;
}

}  // namespace flexrod
