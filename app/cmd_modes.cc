// SPDX-License-Identifier: GPL-3.0-or-later
// `flexrod modes`: modal analysis of one rod — full FE against the reduced model, per mode — and
// the run's rod in its assembled mechanism with the damping ratio of each mode.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "common/error.h"
#include "common/files.h"
#include "input/config.h"
#include "mechanisms/modal_analysis.h"

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
  if (!opt.json_file.empty()) CheckCanWriteFile("--json", opt.json_file);  // before the work
  const ModalAnalysis a = AnalyseModes(cfg);
  const fem::RodSpec& rod = a.rod;
  if (!a.warning.empty()) std::fprintf(stderr, "flexrod: warning: %s\n", a.warning.c_str());

  std::printf(
      "rod: %s, %.4g x %.4g mm (%s axis in plane), L = %.4g mm, %d %s elements, %s, bc %s\n",
      rod.material.name.c_str(), rod.section.thickness * 1e3, rod.section.height * 1e3,
      fem::ToString(rod.section.in_plane), rod.length * 1e3, rod.num_elements,
      cfg.Text("rod.element").c_str(), cfg.Text("modes.dim").c_str(), cfg.Text("modes.bc").c_str());
  std::printf("reduction: %s, %d coordinates\n", fem::ToString(a.spec.method), a.num_coordinates);
  std::printf("%5s %16s %16s %12s %10s %14s\n", "mode", "full-FE [Hz]", "reduced [Hz]",
              "rel. error", "MAC", "eff. mass [kg]");
  for (const auto& r : a.rows) {
    std::printf("%5d %16.6f %16.6f %12.3e %10.6f %14.6e%s\n", r.index, r.full_hz, r.reduced_hz,
                r.rel_error, r.mac, r.effective_mass, r.rigid_body ? "  (rigid-body)" : "");
  }
  if (a.mechanism_hz.size() > 0) {
    const int shown = std::min<int>(static_cast<int>(a.mechanism_hz.size()),
                                    std::max<int>(static_cast<int>(a.rows.size()), 10));
    std::printf(
        "\nthe run's rod in its mechanism (%s, ideal small-end joint, crank held at 0 deg), "
        "damping.type = %s: %d modes, first %d\n",
        cfg.Text("mechanism.type").c_str(), cfg.Text("damping.type").c_str(),
        static_cast<int>(a.mechanism_hz.size()), shown);
    std::printf("%5s %16s %14s\n", "mode", "frequency [Hz]", "damping ratio");
    for (int i = 0; i < shown; ++i)
      std::printf("%5d %16.6f %14.6g\n", i + 1, a.mechanism_hz(i), a.mechanism_ratios(i));
  }
  if (!opt.json_file.empty()) WriteFileAtomic(opt.json_file, ModesJson(cfg, a).dump(2) + "\n");
  return 0;
}

}  // namespace

void RegisterModes(CLI::App& app, Handler* handler) {
  auto opt = std::make_shared<ModesOptions>();
  CLI::App* cmd =
      app.add_subcommand("modes", "modal analysis of one rod: full FE vs reduced model");
  cmd->add_option("--config", opt->config_file, "TOML file with rod.*, reduction.*, modes.* keys");
  cmd->add_option("--json", opt->json_file, "write the resolved inputs and the mode table as JSON");
  for (const ModesFlag& f : ModesFlags()) {
    const std::string key = f.key;
    cmd->add_option_function<std::string>(
        f.name, [opt, key](const std::string& v) { opt->flags.emplace_back(key, v); },
        std::string(f.help) + " [key " + key + "]");
  }
  cmd->callback([opt, handler] { *handler = [opt] { return RunModes(*opt); }; });
}

}  // namespace flexrod::app
