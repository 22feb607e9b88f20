// SPDX-License-Identifier: GPL-3.0-or-later
// `flexrod modes`: modal analysis of one rod — full FE against the reduced model, per mode.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "app/commands.h"
#include "common/error.h"
#include "common/files.h"
#include "study/config.h"
#include "study/rod_config.h"

namespace flexrod::app {
namespace {

struct ModesOptions {
  std::string config_file, json_file;
  std::vector<std::pair<std::string, std::string>> flags;  // (key, text) in command-line order
};

int RunModes(const ModesOptions& opt) {
  Config cfg;
  if (!opt.config_file.empty()) cfg.LoadTomlFile(opt.config_file);
  for (const auto& [key, text] : opt.flags) cfg.Set(key, text);

  fem::RodSpec rod = RodFromConfig(cfg);
  rod.dim = cfg.Text("modes.dim") == "spatial" ? fem::MeshDim::kSpatial : fem::MeshDim::kPlanar;
  rod.Validate();
  fem::ReductionSpec spec;
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

  const fem::ReducedRod reduced = fem::Reduce(rod, spec);
  const std::string precision = fem::MeshPrecisionWarning(rod, spec.method);
  if (!precision.empty()) std::fprintf(stderr, "flexrod: warning: %s\n", precision.c_str());
  int count = cfg.Integer("modes.count");
  Require(count >= 0, "modes.count", count, "must be >= 0");
  if (count == 0) count = std::max(10, reduced.num_coordinates());
  count = std::min(count, free_dofs);
  const std::vector<fem::ModeReportRow> rows = fem::CompareWithFullModel(reduced, count);

  std::printf("rod: %s, %.4g x %.4g mm (%s axis in plane), L = %.4g mm, %d %s elements, %s, bc %s\n",
              rod.material.name.c_str(), rod.section.thickness * 1e3, rod.section.height * 1e3,
              fem::ToString(rod.section.in_plane), rod.length * 1e3, rod.num_elements,
              cfg.Text("rod.element").c_str(), cfg.Text("modes.dim").c_str(), cfg.Text("modes.bc").c_str());
  std::printf("reduction: %s, %d coordinates\n", fem::ToString(spec.method), reduced.num_coordinates());
  std::printf("%5s %16s %16s %12s %10s %14s\n", "mode", "full-FE [Hz]", "reduced [Hz]", "rel. error",
              "MAC", "eff. mass [kg]");
  for (const auto& r : rows) {
    std::printf("%5d %16.6f %16.6f %12.3e %10.6f %14.6e%s\n", r.index, r.full_hz, r.reduced_hz, r.rel_error,
                r.mac, r.effective_mass, r.rigid_body ? "  (rigid-body)" : "");
  }

  if (!opt.json_file.empty()) {
    nlohmann::json j;
    nlohmann::json inputs;
    for (const auto& r : cfg.Resolve()) {
      if (r.key.rfind("rod.", 0) == 0 || r.key.rfind("reduction.", 0) == 0 || r.key.rfind("modes.", 0) == 0) {
        inputs[r.key] = {{"value", r.value}, {"unit", r.unit}};
      }
    }
    j["inputs"] = inputs;
    j["num_coordinates"] = reduced.num_coordinates();
    j["units"] = {{"full_hz", "Hz"}, {"reduced_hz", "Hz"}, {"rel_error", "1"}, {"mac", "1"},
                  {"effective_mass", "kg"}};
    auto num = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
    for (const auto& r : rows) {
      j["modes"].push_back({{"mode", r.index}, {"full_hz", num(r.full_hz)}, {"reduced_hz", num(r.reduced_hz)},
                            {"rel_error", num(r.rel_error)}, {"mac", num(r.mac)},
                            {"effective_mass", num(r.effective_mass)}, {"rigid_body", r.rigid_body}});
    }
    WriteFileAtomic(opt.json_file, j.dump(2) + "\n");
  }
  return 0;
}

}  // namespace

void RegisterModes(CLI::App& app, Handler* handler) {
  auto opt = std::make_shared<ModesOptions>();
  CLI::App* cmd = app.add_subcommand("modes", "modal analysis of one rod: full FE vs reduced model");
  cmd->add_option("--config", opt->config_file, "TOML file with rod.*, reduction.*, modes.* keys");
  cmd->add_option("--json", opt->json_file, "write the resolved inputs and the mode table as JSON");
  struct Flag {
    const char* name;
    const char* key;
    const char* help;
  };
  static const Flag kFlags[] = {
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
      {"--cutoff", "reduction.cutoff", "keep every mode below this frequency instead, e.g. \"5 kHz\""},
      {"--interface", "modes.interface", "small-end|ends|<node list>"},
      {"--report", "modes.count", "number of modes in the table"},
  };
  for (const Flag& f : kFlags) {
    const std::string key = f.key;
    cmd->add_option_function<std::string>(
        f.name, [opt, key](const std::string& v) { opt->flags.emplace_back(key, v); },
        std::string(f.help) + " [key " + key + "]");
  }
  cmd->callback([opt, handler] { *handler = [opt] { return RunModes(*opt); }; });
}

}  // namespace flexrod::app
