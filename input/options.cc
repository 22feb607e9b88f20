// SPDX-License-Identifier: GPL-3.0-or-later
#include "input/options.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "common/error.h"
#include "common/units.h"

namespace flexrod {
namespace {

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

/// A choice key as its enumerator E(ChoiceIndex).
template <class E>
E ReadChoice(const Config& cfg, const std::string& key) {
  return static_cast<E>(ChoiceIndex(cfg, key));
}

}  // namespace

int ChoiceIndex(const Config& cfg, const std::string& key) {
  const std::string value = cfg.Text(key);
  const ParamDef* def = FindParam(key);
  if (def == nullptr || def->kind != ParamKind::kChoice)
    throw std::logic_error("ChoiceIndex: " + key + " is not a choice key");
  for (size_t i = 0; i < def->choices.size(); ++i) {
    if (value == def->choices[i]) return static_cast<int>(i);
  }
  throw std::logic_error("ChoiceIndex: " + key + " = " + value + " is not among its choices");
}

RodModel ReadRodModel(const Config& cfg) {
  const RodModel model = ReadChoice<RodModel>(cfg, "rod.type");
  // The exact rod is a shear-deformable (Reissner) beam: it cannot honour Euler-Bernoulli.
  if (model == RodModel::kExact && cfg.IsSet("rod.element") &&
      cfg.Text("rod.element") == "euler-bernoulli") {
    throw InputError("rod.element", "euler-bernoulli",
                     "rod.type = exact is a geometrically exact shear-deformable (Reissner, "
                     "Timoshenko) beam; leave rod.element unset or set it to timoshenko");
  }
  return model;
}

SimOptions ReadSimOptions(const Config& cfg) {
  SimOptions o;
  o.sample_rate = cfg.Quantity("sim.sample_rate");
  RequirePositive("sim.sample_rate", o.sample_rate);
  o.rel_tol = cfg.Quantity("sim.rel_tol");
  o.abs_tol = cfg.Quantity("sim.abs_tol");
  o.max_step = cfg.Quantity("sim.max_step");
  o.linear_solver = ReadChoice<SimOptions::LinearSolver>(cfg, "sim.linear_solver");
  o.eliminate_prescribed = cfg.Bool("sim.eliminate_prescribed");
  o.settle = cfg.Quantity("sim.settle");
  o.steady_window = cfg.Bool("sim.steady_window");
  o.max_settle = cfg.Quantity("sim.max_settle");
  o.capture = cfg.Quantity("sim.capture");
  o.index_angle = cfg.Quantity("sim.index_angle");
  o.max_steps = cfg.Integer("sim.max_steps");
  o.max_wall_time = cfg.Quantity("sim.max_wall_time");
  o.start = ReadChoice<SimOptions::Start>(cfg, "sim.start");
  o.steady_revolutions = cfg.Integer("sim.steady_revolutions");
  return o;
}

EnsembleOptions ReadEnsembleOptions(const Config& cfg) {
  EnsembleOptions e;
  e.members = cfg.Integer("ensemble.members");
  e.angle_step = cfg.Quantity("ensemble.angle_step");
  e.settle_spread = cfg.Quantity("ensemble.settle_spread");
  e.confidence = cfg.Quantity("ensemble.confidence");
  return e;
}

namespace {

/// A value as text that reads back to the same double.
std::string Exact(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

int EnsembleMembers(const EnsembleOptions& options, bool automatic_ensemble) {
  if (options.members > 0) return options.members;
  return automatic_ensemble ? kDefaultRunMembers : 1;
}

std::vector<std::pair<std::string, std::string>> EnsembleMemberSettings(
    const Config& cfg, const EnsembleOptions& options, int members, int k) {
  if (k == 0) return {};  // member 0 is the input itself, bit for bit
  const double step =
      options.angle_step > 0.0 ? options.angle_step : 2.0 * std::numbers::pi / members;
  const double f = static_cast<double>(k) / static_cast<double>(members);
  return {{"drive.initial_angle", Exact(cfg.Quantity("drive.initial_angle") + k * step) + " rad"},
          {"sim.settle", Exact(cfg.Quantity("sim.settle") + f * options.settle_spread) + " s"}};
}

DriveOptions ReadDriveOptions(const Config& cfg) {
  DriveOptions d;
  d.type = ReadChoice<DriveOptions::Type>(cfg, "drive.type");
  d.speed = cfg.Quantity("drive.speed");
  d.initial_angle = cfg.Quantity("drive.initial_angle");
  // Checked whenever given, and required by a profile drive.
  const std::string profile = cfg.Text("drive.profile");
  if (!profile.empty() || d.type == DriveOptions::Type::kProfile) d.profile = ParseProfile(profile);
  d.motor.stall_torque = cfg.Quantity("motor.stall_torque");
  d.motor.no_load_speed = cfg.Quantity("motor.no_load_speed");
  d.motor.belt_ratio = cfg.Quantity("motor.belt_ratio");
  d.motor.flywheel_inertia = cfg.Quantity("motor.flywheel_inertia");
  return d;
}

DampingOptions ReadDampingOptions(const Config& cfg) {
  DampingOptions d;
  d.type = ReadChoice<DampingOptions::Type>(cfg, "damping.type");
  d.ratio = cfg.Quantity("damping.ratio");
  d.alpha = cfg.Quantity("damping.alpha");
  d.beta = cfg.Quantity("damping.beta");
  return d;
}

void VtkOptions::Validate() const {
  Require(rate > 0.0 && std::isfinite(rate), "vtk.rate", rate,
          "must be a finite frame rate > 0 Hz");
  Require(scale >= 0.0 && std::isfinite(scale), "vtk.scale", scale, "must be a finite factor >= 0");
  Require(duration >= 0.0 && std::isfinite(duration), "vtk.duration", duration,
          "must be >= 0 s (0 = the whole capture)");
}

VtkOptions ReadVtkOptions(const Config& cfg) {
  VtkOptions o;
  o.rate = cfg.Quantity("vtk.rate");
  o.scale = cfg.Quantity("vtk.scale");
  o.duration = cfg.Quantity("vtk.duration");
  o.Validate();
  return o;
}

}  // namespace flexrod
