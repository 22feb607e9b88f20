// SPDX-License-Identifier: GPL-3.0-or-later
#include "mechanisms/rod_config.h"

#include <sstream>
#include <stdexcept>

#include "common/error.h"

namespace flexrod {

fem::RodSpec RodFromConfig(const Config& cfg) {
  fem::RodSpec rod;
  rod.material = fem::MaterialByName(cfg.Text("rod.material"));
  // Overrides make a custom material derived from the named one.
  bool custom = false;
  // 0 means "the material's" (the keys' documented default), also where an input sets it: a
  // resolved.toml writes every key, and must run again as an input.
  auto override_with = [&](const char* key, double* field) {
    if (cfg.IsSet(key) && cfg.Quantity(key) != 0.0) {
      *field = cfg.Quantity(key);
      custom = true;
    }
  };
  override_with("rod.E", &rod.material.youngs_modulus);
  override_with("rod.nu", &rod.material.poisson_ratio);
  override_with("rod.rho", &rod.material.density);
  override_with("rod.yield", &rod.material.yield_strength);
  override_with("rod.loss_factor", &rod.material.loss_factor);
  if (custom) {
    rod.material.name = "custom (" + rod.material.name + " with overrides)";
    rod.material.source = "user input";
  }
  rod.material.Validate("rod");
  rod.section.thickness = cfg.Quantity("rod.thickness");
  rod.section.height = cfg.Quantity("rod.height");
  rod.section.in_plane = fem::BendingAxisFromString("rod.bending", cfg.Text("rod.bending"));
  rod.length = cfg.Quantity("rod.length");
  rod.num_elements = cfg.Integer("rod.elements");
  rod.theory = cfg.Text("rod.element") == "timoshenko" ? fem::BeamTheory::kTimoshenko
                                                       : fem::BeamTheory::kEulerBernoulli;
  rod.mass_kind =
      cfg.Text("rod.mass") == "lumped" ? fem::MassKind::kLumped : fem::MassKind::kConsistent;
  rod.Validate();
  return rod;
}

fem::ReductionSpec MechanismReductionFromConfig(const Config& cfg, const fem::RodSpec& rod) {
  const fem::ReductionMethod method =
      fem::ReductionMethodFromString("reduction.method", cfg.Text("reduction.method"));
  fem::ReductionSpec spec = fem::MechanismReduction(rod, method, cfg.Integer("reduction.modes"));
  spec.cutoff_hz = cfg.Quantity("reduction.cutoff");
  spec.axial_load_modes = cfg.Bool("reduction.axial_modes") &&
                          (method == fem::ReductionMethod::kCraigBampton ||
                           method == fem::ReductionMethod::kOrthonormalCraigBampton);
  spec.Validate(rod);
  return spec;
}

std::vector<int> InterfaceNodes(const std::string& key, const std::string& text,
                                const fem::RodSpec& rod) {
  const int last = rod.num_nodes() - 1;
  if (text == "small-end") return {last};
  if (text == "ends") return {0, last};
  std::vector<int> nodes;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    size_t used = 0;
    int node = -1;
    try {
      node = std::stoi(item, &used);
    } catch (const std::invalid_argument&) {  // not a number: refused below
      used = 0;
    } catch (const std::out_of_range&) {
      used = 0;
    }
    if (used == 0 || used != item.size()) {
      throw InputError(key, text,
                       "must be small-end, ends, or a comma-separated list of node numbers");
    }
    Require(node >= 0 && node <= last, key, node, "node must be in 0.." + std::to_string(last));
    nodes.push_back(node);
  }
  if (nodes.empty()) throw InputError(key, text, "needs at least one node");
  return nodes;
}

}  // namespace flexrod
