// SPDX-License-Identifier: GPL-3.0-or-later
#include "mechanisms/modal_analysis.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "mechanisms/mechanism_damping.h"
#include "mechanisms/mechanism_model.h"
#include "mechanisms/rod_config.h"

namespace flexrod {

const std::vector<ModesFlag>& ModesFlags() {
  static const std::vector<ModesFlag> kFlags = {
      {"--material", "rod.material", "steel|brass|aluminium"},
      {"--E", "rod.E", "Young's modulus, e.g. \"200 GPa\" (custom material)"},
      {"--nu", "rod.nu", "Poisson ratio (custom material)"},
      {"--rho", "rod.rho", "density, e.g. \"7850 kg/m^3\" (custom material)"},
      {"--thickness", "rod.thickness", "bar thickness, e.g. \"3.175 mm\""},
      {"--height", "rod.height", "bar height, e.g. \"19.05 mm\""},
      {"--length", "rod.length", "free length, e.g. \"280 mm\""},
      {"--elements", "rod.elements", "number of elements"},
      {"--element", "rod.element", "euler-bernoulli|timoshenko"},
      {"--bending", "rod.bending", "weak|strong (axis bending in the plane)"},
      {"--mass", "rod.mass", "consistent|lumped"},
      {"--dim", "modes.dim", "planar|spatial"},
      {"--bc", "modes.bc", "clamped-clamped|clamped-free|free-free|pinned-pinned|clamped-pinned"},
      {"--reduction", "reduction.method", "craig-bampton|orthonormal-cb|free-free|full"},
      {"--modes", "reduction.modes", "number of fixed-interface (or free-free) modes k"},
      {"--cutoff", "reduction.cutoff",
       "keep every mode below this frequency instead, e.g. \"5 kHz\""},
      {"--interface", "modes.interface", "small-end|ends|<node list>"},
      {"--report", "modes.count", "number of modes in the table"},
  };
  return kFlags;
}

ModalAnalysis AnalyseModes(const Config& cfg) {
  ModalAnalysis a;
  fem::RodSpec& rod = a.rod;
  rod = RodFromConfig(cfg);
  rod.dim = cfg.Text("modes.dim") == "spatial" ? fem::MeshDim::kSpatial : fem::MeshDim::kPlanar;
  rod.Validate();
  fem::ReductionSpec& spec = a.spec;
  spec.method = fem::ReductionMethodFromString("reduction.method", cfg.Text("reduction.method"));
  spec.num_modes = cfg.Integer("reduction.modes");
  spec.cutoff_hz = cfg.Quantity("reduction.cutoff");
  spec.fixed_dofs = fem::BoundaryDofs(rod, cfg.Text("modes.bc"));
  spec.interface_nodes = InterfaceNodes("modes.interface", cfg.Text("modes.interface"), rod);
  {  // Interface nodes whose dofs are all fixed contribute nothing; drop them.
    std::vector<int> kept;
    for (int k : spec.interface_nodes) {
      int fixed = 0;
      for (int d : spec.fixed_dofs) fixed += (d / rod.dofs_per_node() == k);
      if (fixed < rod.dofs_per_node()) kept.push_back(k);
    }
    spec.interface_nodes = kept;
  }
  spec.Validate(rod);
  const int free_dofs = rod.num_dofs() - static_cast<int>(spec.fixed_dofs.size());
  Require(spec.num_modes <= free_dofs, "reduction.modes", spec.num_modes,
          "more modes than free dofs (" + std::to_string(free_dofs) + ")");
  int count = cfg.Integer("modes.count");
  Require(count >= 0, "modes.count", count, "must be >= 0");

  const fem::ReducedRod reduced = fem::Reduce(rod, spec);
  a.num_coordinates = reduced.num_coordinates();
  a.warning = fem::MeshPrecisionWarning(rod, spec.method);
  if (count == 0) count = std::max(10, reduced.num_coordinates());
  count = std::min(count, free_dofs);
  a.rows = fem::CompareWithFullModel(reduced, count);
  if (rod.dim == fem::MeshDim::kPlanar && DampingRefersToMechanism(cfg)) {
    const MechanismModel mm = BuildMechanism(cfg, nullptr, /*ideal_joint=*/true);
    a.mechanism_hz = mm.mechanism_frequencies_hz;
    a.mechanism_ratios = mm.mechanism_damping_ratios;
  }
  return a;
}

nlohmann::json ModesJson(const Config& cfg, const ModalAnalysis& analysis) {
  nlohmann::json j;
  nlohmann::json inputs;
  for (const auto& r : cfg.Resolve()) {
    if (r.key.rfind("rod.", 0) == 0 || r.key.rfind("reduction.", 0) == 0 ||
        r.key.rfind("modes.", 0) == 0 || r.key.rfind("damping.", 0) == 0) {
      inputs[r.key] = {{"value", r.value}, {"unit", r.unit}};
    }
  }
  j["inputs"] = inputs;
  j["num_coordinates"] = analysis.num_coordinates;
  j["units"] = {{"full_hz", "Hz"},     {"reduced_hz", "Hz"},     {"rel_error", "1"},
                {"mac", "1"},          {"effective_mass", "kg"}, {"frequency_hz", "Hz"},
                {"damping_ratio", "1"}};
  auto num = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  for (const auto& r : analysis.rows) {
    j["modes"].push_back({{"mode", r.index},
                          {"full_hz", num(r.full_hz)},
                          {"reduced_hz", num(r.reduced_hz)},
                          {"rel_error", num(r.rel_error)},
                          {"mac", num(r.mac)},
                          {"effective_mass", num(r.effective_mass)},
                          {"rigid_body", r.rigid_body}});
  }
  j["mechanism_modes"] = nlohmann::json::array();
  for (int i = 0; i < analysis.mechanism_hz.size(); ++i) {
    j["mechanism_modes"].push_back({{"mode", i + 1},
                                    {"frequency_hz", num(analysis.mechanism_hz(i))},
                                    {"damping_ratio", num(analysis.mechanism_ratios(i))}});
  }
  return j;
}

}  // namespace flexrod
