// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/run_setup.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <memory>
#include <optional>
#include <sstream>

#include "common/error.h"
#include "common/matvec.h"
#include "common/units.h"
#include "input/output_selection.h"
#include "mechanisms/exact_rod_view.h"
#include "mechanisms/mechanism_recipe.h"
#include "mechanisms/rod_config.h"
#include "run/run.h"

namespace flexrod {
namespace {

using multibody::SampleView;

std::vector<double> ParseList(const std::string& key, const std::string& text, Dimension dim) {
  std::vector<double> out;
  for (const std::string& item : SplitUserList(key, text))
    out.push_back(ParseQuantity(key, item, dim));
  return out;
}

/// The rod node nearest to output.midspan (0 = midspan); InputError unless it lies on the rod.
int ProbeNode(const Config& cfg, const fem::RodSpec& rod) {
  double x = cfg.Quantity("output.midspan");
  if (!(x >= 0.0 && x <= rod.length)) {
    throw InputError("output.midspan", FormatValue(x) + " m",
                     "must lie on the rod, 0 <= x <= rod.length = " + FormatValue(rod.length) +
                         " m (0 = midspan)");
  }
  if (x == 0.0) x = 0.5 * rod.length;
  return static_cast<int>(std::lround(x / rod.element_length()));
}

/// output.gauges [m]; InputError unless every position lies on the rod.
std::vector<double> GaugePositions(const Config& cfg, const fem::RodSpec& rod) {
  const std::vector<double> xs =
      ParseList("output.gauges", cfg.Text("output.gauges"), Dimension::kLength);
  for (const double x : xs) {
    if (!(x >= 0.0 && x <= rod.length)) {
      throw InputError(
          "output.gauges", FormatValue(x) + " m",
          "must lie on the rod, 0 <= x <= rod.length = " + FormatValue(rod.length) + " m");
    }
  }
  return xs;
}

}  // namespace

/// The reduced rod's channels: deflection from the chord at output.midspan, the gauges' strain
/// and stress, its modal coordinates.
void DefineReducedRodChannels(const Config& cfg, const MechanismModel& mm, Recorder* rec,
                              nlohmann::json* gauges_json) {
  const multibody::Mechanism& m = mm.mechanism;
  const auto conrod = mm.conrod;
  const fem::ReducedRod& rod = *mm.rod;
  const int n = rod.num_coordinates();
  const int q0 = m.coordinate(conrod, multibody::kFirstMode);
  // Deflection probe: node nearest to output.midspan, relative to the chord.
  const int probe = ProbeNode(cfg, rod.rod);
  const int last = rod.rod.num_nodes() - 1;
  const std::shared_ptr<const fem::ReducedRod> keep = mm.rod;
  rec->Add({{"rod_deflection", "m"}}, [=](const SampleView& s, double* v) {
    const Eigen::Map<const Vec> q(s.y() + q0, n);
    auto pos = [&](int k) -> Vec2 { return keep->nodes[k].position + keep->nodes[k].S_u * q; };
    const Vec2 a = pos(0), b = pos(last), c = pos(probe);
    const Vec2 chord = (b - a).normalized();
    v[0] = chord.x() * (c - a).y() - chord.y() * (c - a).x();  // signed distance from the chord
  });
  const double E = rod.rod.material.youngs_modulus;
  const double y = rod.rod.section.half_depth_in_plane();
  const std::vector<double> xs = GaugePositions(cfg, rod.rod);
  // All gauges in one channel group (strain, stress of gauge 1, then gauge 2, ...): their linear
  // rows as one product, and with rod.geometric_stiffening the second-order parts too (their
  // n × n matrices stacked), instead of a small product per gauge and sample.
  const int num_gauges = static_cast<int>(xs.size());
  const bool membrane = cfg.Bool("rod.geometric_stiffening");
  Mat rows(num_gauges, n), membranes(membrane ? num_gauges * n : 0, n);
  std::vector<Recorder::Spec> gauge_channels;
  for (int g = 0; g < num_gauges; ++g) {
    const std::string name = "gauge" + std::to_string(g + 1);
    const fem::StrainGaugeRows r = rod.Gauge(name, xs[g], y);
    rows.row(g) = r.axial + r.bending;
    // The second-order axial strain (rod.geometric_stiffening): the chord's shortening.
    if (membrane) membranes.middleRows(g * n, n) = r.membrane;
    gauge_channels.push_back({"strain_" + name, "1"});
    gauge_channels.push_back({"stress_" + name, "Pa"});
    (*gauges_json)[name] = {{"x [m]", xs[g]}, {"y [m]", y}};
  }
  if (num_gauges > 0) {
    // Dense for a modal basis, by their non-zeros for the full FE rod's element-local rows.
    rec->Add(std::move(gauge_channels),
             [=, linear_rows = ProductMatrix(rows), membrane_rows = ProductMatrix(membranes),
              linear = Vec(num_gauges),
              work = Vec(membranes.rows())](const SampleView& s, double* v) mutable {
               const Eigen::Map<const Vec> q(s.y() + q0, n);
               linear_rows.Apply(q.data(), linear.data());  // into linear and work: no allocation
               if (membrane) membrane_rows.Apply(q.data(), work.data());
               for (int g = 0; g < num_gauges; ++g) {
                 double strain = linear(g);
                 if (membrane) strain += q.dot(work.segment(g * n, n));
                 v[2 * g] = strain;
                 v[2 * g + 1] = E * strain;
               }
             });
  }
  std::vector<Recorder::Spec> modal;
  for (int k = 0; k < n; ++k) {
    std::string name = "q";  // (not "q" + to_string: GCC 12 -Wrestrict false positive, PR 105329)
    name += std::to_string(k + 1);
    modal.push_back({name, "1"});
  }
  rec->Add(std::move(modal),
           [=](const SampleView& s, double* v) { std::copy_n(s.y() + q0, n, v); });
}

void DefineChannels(const Config& cfg, const MechanismModel& mm, Recorder* rec,
                    nlohmann::json* gauges_json, study::ImpactLogger* impacts) {
  const multibody::Mechanism& m = mm.mechanism;
  mm.recipe->DefineChannels(mm, rec, impacts);
  if (mm.rod) DefineReducedRodChannels(cfg, mm, rec, gauges_json);
  std::shared_ptr<const study::ExactRodView> exact;
  if (mm.exact) {
    // The exact rod (rod.type = exact): deflection and gauges from its node bodies.
    exact = std::make_shared<const study::ExactRodView>(m, *mm.exact);
    const fem::RodSpec& rod = mm.exact->rod;
    const int probe = ProbeNode(cfg, rod);
    rec->Add({{"rod_deflection", "m"}},
             [=](const SampleView& s, double* v) { v[0] = exact->Deflection(s.y(), probe); });
    const double E = rod.material.youngs_modulus;
    const double y = rod.section.half_depth_in_plane();
    const std::vector<double> xs = GaugePositions(cfg, rod);
    for (size_t g = 0; g < xs.size(); ++g) {
      const std::string name = "gauge" + std::to_string(g + 1);
      const double x = xs[g];
      rec->Add({{"strain_" + name, "1"}, {"stress_" + name, "Pa"}},
               [=](const SampleView& s, double* v) {
                 v[0] = exact->Strain(s.y(), x, y);
                 v[1] = E * v[0];
               });
      (*gauges_json)[name] = {{"x [m]", xs[g]}, {"y [m]", y}};
    }
  }
  // Strain energy only with an elastic rod (a rigid one has none: the channel would be zeros).
  const bool elastic = mm.rod != nullptr || mm.exact != nullptr;
  std::vector<Recorder::Spec> energies = {{"energy_kinetic", "J"}};
  if (elastic) energies.push_back({"energy_strain", "J"});
  energies.insert(
      energies.end(),
      {{"energy_dissipated", "J"}, {"driver_work", "J"}, {"energy_balance_error", "J"}});
  rec->Add(std::move(energies), [elastic, exact](const SampleView& s, double* v) {
    const multibody::EnergyReport e = s.Energies();
    *v++ = e.kinetic;
    if (elastic) *v++ = exact ? exact->StrainEnergy(s.y()) : e.strain;
    *v++ = e.dissipated_elements + e.dissipated_damping;
    *v++ = e.driver_work;
    *v = e.balance_error;
  });
  rec->Add({{"constraint_violation", "m"}},
           [](const SampleView& s, double* v) { v[0] = s.ConstraintViolation(); });
}

multibody::SimulationOptions IntegratorOptions(const SimOptions& sim) {
  multibody::SimulationOptions o;
  o.sample_rate = sim.sample_rate;
  o.integrator.rel_tol = sim.rel_tol;
  o.integrator.abs_tol = sim.abs_tol;
  o.integrator.max_step = sim.max_step;
  o.integrator.linear_solver =
      sim.linear_solver == SimOptions::LinearSolver::kDense ? multibody::LinearSolverKind::kDense
      : sim.linear_solver == SimOptions::LinearSolver::kKlu ? multibody::LinearSolverKind::kKlu
                                                            : multibody::LinearSolverKind::kAuto;
  o.eliminate_prescribed = sim.eliminate_prescribed;
  try {
    o.integrator.Validate();
  } catch (const InputError& e) {  // the integrator's option is the user's sim.* key
    const std::string prefix = "integrator.";
    const std::string key =
        e.key().rfind(prefix, 0) == 0 ? "sim." + e.key().substr(prefix.size()) : e.key();
    throw InputError(key, e.value(), e.rule());
  }
  return o;
}

namespace {

/// The memory this process may use [B]: the physical memory, or the address-space limit if
/// lower (ulimit -v).
double AvailableMemory() {
  double bytes = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * sysconf(_SC_PAGE_SIZE);
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
    bytes = std::min(bytes, static_cast<double>(limit.rlim_cur));
  return bytes;
}

/// The record (8 B per channel and sample) must fit in half the memory available: a capture
/// beyond it is refused before the run, naming the keys that set its size.
void CheckRecordFitsMemory(const Config& cfg, const MechanismModel& mm, double samples) {
  const double channels = static_cast<double>(RunChannelNames(cfg, mm).size());
  const double need = samples * channels * sizeof(double), budget = 0.5 * AvailableMemory();
  if (need <= budget) return;
  std::ostringstream rule;
  rule.precision(3);
  rule << "records " << samples << " samples of " << channels << " channels, " << need / 1e9
       << " GB; the memory budget is half the memory available, " << budget / 1e9
       << " GB: shorten sim.capture or lower sim.sample_rate";
  throw InputError("sim.capture × sim.sample_rate",
                   cfg.Text("sim.capture") + " × " + cfg.Text("sim.sample_rate"), rule.str());
}

}  // namespace

std::vector<std::string> RunChannelNames(const Config& cfg, const MechanismModel& mm) {
  Recorder scratch;
  nlohmann::json gauges;
  std::optional<study::ImpactLogger> impacts;
  if (mm.clearance.index >= 0) impacts.emplace();
  DefineChannels(cfg, mm, &scratch, &gauges, impacts ? &*impacts : nullptr);
  return scratch.names();
}

SimOptions CheckRunInput(const Config& cfg, const MechanismModel& mm) {
  const SimOptions sim = ReadSimOptions(cfg);
  const multibody::SimulationOptions opt = IntegratorOptions(sim);
  const double capture = sim.capture;
  if (!(capture * opt.sample_rate >= 2.0)) {
    throw InputError(
        "sim.capture", FormatValue(capture) + " s",
        "must hold at least 2 samples at sim.sample_rate = " + FormatValue(opt.sample_rate) +
            " Hz (>= " + FormatValue(2.0 / opt.sample_rate) + " s)");
  }
  const bool steady = sim.start == SimOptions::Start::kSteady;
  const int max_revolutions = sim.steady_revolutions;
  if (max_revolutions < 2) {
    throw InputError("sim.steady_revolutions", std::to_string(max_revolutions),
                     "must be >= 2 (two revolutions are the least that can repeat)");
  }
  if (steady && (!mm.recipe->turns_a_crank() || !(mm.rod || mm.exact))) {
    throw InputError(
        "sim.start", "steady",
        "needs a slider-crank with a flexible rod: the periodic steady state is found on the "
        "rod's elastic state at the crank index; use sim.settle instead");
  }
  if (steady && mm.drive.type != DriveOptions::Type::kConstant) {
    throw InputError(
        "sim.start", "steady",
        "needs drive.type = constant (a periodic state has the crank's period; a motor's speed "
        "droops and fluctuates, a profile changes it); use sim.settle instead");
  }
  // Positions on the rod are checked also where this run does not use them (a rigid rod has
  // no deflection channel, run no modal interface): a value the rules refuse is refused.
  fem::RodSpec rigid;  // the mesh the keys would give a rigid rod (it has no material)
  rigid.length = cfg.Quantity("rod.length");
  rigid.num_elements = cfg.Integer("rod.elements");
  const fem::RodSpec& rod = mm.rod ? mm.rod->rod : mm.exact ? mm.exact->rod : rigid;
  (void)ProbeNode(cfg, rod);
  (void)GaugePositions(cfg, rod);
  if (cfg.IsSet("modes.interface"))
    (void)InterfaceNodes("modes.interface", cfg.Text("modes.interface"), rod);
  (void)ReadOutputSelection(cfg, opt.sample_rate, nullptr);
  CheckRecordFitsMemory(cfg, mm, capture * opt.sample_rate);
  return sim;
}

}  // namespace flexrod
