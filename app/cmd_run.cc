// SPDX-License-Identifier: GPL-3.0-or-later
// `flexrod run [preset-or-file.toml] [--set key=value ...] [--out DIR]` and `flexrod keys`.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>

#include "app/commands.h"
#include "app/plotting.h"
#include "common/error.h"
#include "common/files.h"
#include "input/presets.h"
#include "io/run_vtk.h"
#include "io/run_writer.h"
#include "run/ensemble.h"
#include "run/run.h"

namespace flexrod::app {
namespace {

struct RunOptions {
  std::string input{"flexible-rig"};
  std::vector<std::string> sets;
  std::string out_dir{"out/run"};
  std::string vtk_dir;  ///< ParaView output directory, "" = none
  bool no_plot{false};
  bool check{false};    ///< --check: repeat at 100x tighter tolerances, report the differences
  bool profile{false};  ///< --profile: time the integrator's calls (RunOutputOptions::profile)
  int ensemble{-1};     ///< --ensemble N: ensemble.members; -1 = the key's value
};

/// A summary ratio to 4 significant digits; "n/a" when absent or null (undefined ratio).
std::string Ratio(const nlohmann::json& object, const char* key) {
  if (!object.contains(key) || !object[key].is_number()) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", object[key].get<double>());
  return buf;
}

/// The report's figures: integrator, samples, slider acceleration, crank speed, amplification,
/// rod, energy balance.
void PrintFigures(const RunOptions& opt, const RunResult& run) {
  const auto& s = run.summary;
  std::printf("flexrod run %s -> %s\n", opt.input.c_str(), opt.out_dir.c_str());
  std::printf("  integrator: %s, %ld steps, %ld residuals, %ld Jacobians, wall %.3f s\n",
              multibody::ToString(run.status.outcome), run.status.stats.steps,
              run.status.stats.residual_evaluations, run.status.stats.jacobian_evaluations,
              run.status.wall_seconds);
  const multibody::IntegratorStats& st = run.status.stats;
  if (opt.profile && run.status.wall_seconds > 0.0) {
    const double w = run.status.wall_seconds, output = run.status.output_seconds;
    const double rest =
        w - st.residual_seconds - st.jacobian_seconds - st.linear_solve_seconds - output;
    std::printf(
        "  solver wall shares (--profile): residuals %.1f %%, Jacobians %.1f %%, linear solves "
        "%.1f %%, output %.1f %%, the rest (IDA, events, step bookkeeping) %.1f %%\n",
        100.0 * st.residual_seconds / w, 100.0 * st.jacobian_seconds / w,
        100.0 * st.linear_solve_seconds / w, 100.0 * output / w, 100.0 * rest / w);
  }
  if (opt.profile && st.steps > 0 && !run.status.step_limiting.empty()) {
    // The unknowns with the largest weighted local error after a step: what sets the step.
    std::printf("  step set by (--profile, largest weighted local error):");
    const auto& limiting = run.status.step_limiting;
    for (size_t k = 0; k < std::min<size_t>(limiting.size(), 4); ++k) {
      std::printf("%s %s %.0f %%", k > 0 ? "," : "", limiting[k].first.c_str(),
                  100.0 * static_cast<double>(limiting[k].second) / static_cast<double>(st.steps));
    }
    std::printf("\n");
  }
  if (opt.profile && st.steps > 0) {
    // Held at a stability limit, IDA mostly runs at orders 3-5; held at order 1, its step
    // control is caught (CaughtStepControlNote).
    std::printf("  steps by BDF order (--profile):");
    for (int k = 1; k <= 5; ++k) {
      std::printf("%s %d: %.1f %%", k > 1 ? "," : "", k,
                  100.0 * static_cast<double>(st.steps_by_order[static_cast<size_t>(k)]) /
                      static_cast<double>(st.steps));
    }
    std::printf("\n");
  }
  std::printf("  samples: %zu at %.6g Hz from t = %.6g s\n", run.channels.num_samples(),
              run.channels.sample_rate(), run.channels.start_time());
  if (s.contains("slider_acceleration")) {
    const auto& a = s["slider_acceleration"];
    std::printf(
        "  slider acceleration: peak +%.4g / -%.4g m/s^2, rms %.4g m/s^2 over %d revolutions\n",
        a["peak_positive"].get<double>(), a["peak_negative"].get<double>(), a["rms"].get<double>(),
        a["revolutions"].get<int>());
  }
  if (s.contains("crank_speed")) {
    const auto& w = s["crank_speed"];
    constexpr double kRpm = 60.0 / (2.0 * std::numbers::pi);
    std::printf("  crank speed: mean %.5g rpm (min %.5g, max %.5g)",
                w["mean [rad/s]"].get<double>() * kRpm, w["min [rad/s]"].get<double>() * kRpm,
                w["max [rad/s]"].get<double>() * kRpm);
    if (!w["set [rad/s]"].is_null())
      std::printf(", set %.5g rpm", w["set [rad/s]"].get<double>() * kRpm);
    std::printf("\n");
  }
  if (s.contains("load_amplification")) {
    const auto& a = s["load_amplification"];
    std::printf(
        "  load amplification (real / ideal joint): slider acceleration +%s / -%s "
        "(p95 of per-rev peaks: +%s / -%s), bearing force %s (p95 %s)\n",
        Ratio(a, "slider_acceleration_positive").c_str(),
        Ratio(a, "slider_acceleration_negative").c_str(),
        Ratio(a, "slider_acceleration_positive_p95").c_str(),
        Ratio(a, "slider_acceleration_negative_p95").c_str(), Ratio(a, "bearing_force").c_str(),
        Ratio(a, "bearing_force_p95").c_str());
  }
  if (s.contains("rod")) {
    std::printf("  rod: peak gauge stress %.4g MPa, safety factor against yield %s\n",
                s["rod"]["peak_gauge_stress [Pa]"].get<double>() * 1e-6,
                Ratio(s["rod"], "safety_factor").c_str());
  }
  if (s.contains("energy")) {
    std::printf("  energy balance error: %.3g J (%.3g of peak kinetic energy)\n",
                s["energy"]["max_balance_error [J]"].get<double>(),
                s["energy"]["relative_balance_error"].get<double>());
  }
}

/// "c [lo, hi]" of an ensemble figure, each to 4 significant digits, scaled by `scale`.
std::string CentreInterval(const nlohmann::json& f, double scale = 1.0) {
  char buf[96];
  if (f.contains("interval")) {
    std::snprintf(buf, sizeof buf, "%.4g [%.4g, %.4g]", f["centre"].get<double>() * scale,
                  f["interval"][0].get<double>() * scale, f["interval"][1].get<double>() * scale);
  } else {
    std::snprintf(buf, sizeof buf, "%.4g (members %.4g .. %.4g)", f["centre"].get<double>() * scale,
                  f["members_range"][0].get<double>() * scale,
                  f["members_range"][1].get<double>() * scale);
  }
  return buf;
}

/// The ensemble's figures with their intervals, and its regimes.
void PrintEnsemble(const RunResult& run) {
  const auto& s = run.summary;
  if (s.contains("regime"))
    std::printf("  window: %s (%s)\n", s["regime"]["window"].get<std::string>().c_str(),
                s["regime"]["reason"].get<std::string>().c_str());
  if (!s.contains("ensemble") || !s["ensemble"].contains("figures")) return;
  const auto& e = s["ensemble"];
  const auto& f = e["figures"];
  std::string starts;
  for (const auto& m : e["member_runs"]) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%.4g", starts.empty() ? "" : ", ",
                  m["drive.initial_angle [rad]"].get<double>() * 180.0 / std::numbers::pi);
    starts += buf;
  }
  std::printf("  ensemble: %d members (crank starts %s deg): %s\n", e["members"].get<int>(),
              starts.c_str(), e["regime"]["label"].get<std::string>().c_str());
  const int percent = static_cast<int>(std::lround(100.0 * e["confidence"].get<double>()));
  if (f.contains("slider_acceleration_positive_p95")) {
    std::printf(
        "    load amplification, p95 of per-rev peaks over members and revolutions (%d %% "
        "interval): slider acceleration +%s / -%s, bearing force %s\n",
        percent, CentreInterval(f["slider_acceleration_positive_p95"]).c_str(),
        CentreInterval(f["slider_acceleration_negative_p95"]).c_str(),
        CentreInterval(f["bearing_force_p95"]).c_str());
  }
  if (f.contains("gauge_stress_p95 [Pa]")) {
    std::printf("    gauge stress, p95 of per-rev peaks: %s MPa\n",
                CentreInterval(f["gauge_stress_p95 [Pa]"], 1e-6).c_str());
  }
  if (e.contains("states")) {
    for (size_t k = 0; k < e["states"].size(); ++k) {
      const auto& st = e["states"][k];
      std::string members;
      for (const auto& m : st["members"]) members += (members.empty() ? "" : ",") + m.dump();
      const auto& sf = st["figures"];
      if (!sf.contains("slider_acceleration_positive_p95")) continue;
      std::printf(
          "    steady state %zu (members %s): slider acceleration +%s / -%s, bearing force %s\n",
          k + 1, members.c_str(), CentreInterval(sf["slider_acceleration_positive_p95"]).c_str(),
          CentreInterval(sf["slider_acceleration_negative_p95"]).c_str(),
          CentreInterval(sf["bearing_force_p95"]).c_str());
    }
  }
}

/// The integration error (--check), the warnings (on stderr) and the ParaView series.
void PrintCheckWarningsAndVtk(const RunResult& run, const std::string& vtk_dir) {
  const auto& s = run.summary;
  if (s.contains("accuracy_check")) {
    const auto& c = s["accuracy_check"];
    std::printf(
        "  integration error (--check: the same start at rel_tol %.3g, abs_tol %.3g; not the "
        "spread over starts, which the ensemble interval gives): largest difference %+.3g "
        "%% (%s)\n",
        c["rel_tol"].get<double>(), c["abs_tol"].get<double>(),
        c["max_difference [%]"].get<double>(),
        c["max_difference_figure"].get<std::string>().c_str());
    for (const auto& [name, f] : c["figures"].items()) {
      std::printf("    %-52s %+.3g %%\n", name.c_str(), f["difference [%]"].get<double>());
    }
  }
  if (s.contains("warnings")) {
    for (const auto& w : s["warnings"])
      std::fprintf(stderr, "flexrod: warning: %s\n", w.get<std::string>().c_str());
  }
  if (s.contains("ideal") &&
      s["ideal"].contains("warnings")) {  // the twin's own, e.g. its energy balance
    for (const auto& w : s["ideal"]["warnings"]) {
      std::fprintf(stderr, "flexrod: warning: ideal-joint twin: %s\n",
                   w.get<std::string>().c_str());
    }
  }
  if (run.vtk && !vtk_dir.empty()) {
    std::printf("  paraview: %zu frames at %.6g Hz, rod deformation x%.6g -> %s\n",
                run.vtk->frames.size(), run.vtk->frame_rate, run.vtk->options.scale,
                VtkCollectionPath(vtk_dir).c_str());
  }
}

int Run(const RunOptions& opt) {
  std::vector<std::string> sets = opt.sets;
  if (opt.ensemble >= 0) sets.push_back("ensemble.members=" + std::to_string(opt.ensemble));
  const Config cfg = LoadRunInput(opt.input, sets);
  CheckCanCreateDirectory("--out", opt.out_dir);  // before the run, not after it
  const std::optional<Config> check_cfg =
      opt.check ? std::optional<Config>(TightenedForCheck(cfg)) : std::nullopt;
  if (!opt.vtk_dir.empty()) CheckCanCreateDirectory("--vtk", opt.vtk_dir);
  RunOutputOptions outputs;
  outputs.record_vtk = !opt.vtk_dir.empty();
  outputs.profile = opt.profile;
  outputs.keep_channel = ChannelsTheFilesRead(cfg);  // the rest only feed the summary
  std::optional<RunPlotter> plotter;
  if (!opt.no_plot) plotter.emplace(opt.out_dir);  // its imports overlap the run
  RunResult run = RunEnsemble(cfg, outputs);
  if (check_cfg && run.ok()) {
    std::fprintf(stderr, "flexrod: --check: the same run at rel_tol %s, abs_tol %s\n",
                 check_cfg->Text("sim.rel_tol").c_str(), check_cfg->Text("sim.abs_tol").c_str());
    AddAccuracyCheck(*check_cfg, &run);
  }
  const auto t_files = std::chrono::steady_clock::now();
  const double bytes = WriteRun({opt.out_dir, "", opt.vtk_dir}, cfg, run);
  const double files_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_files).count();
  PrintFigures(opt, run);
  PrintEnsemble(run);
  PrintCheckWarningsAndVtk(run, opt.vtk_dir);
  std::printf("  files: %.3g MB in %.2f s\n", bytes * 1e-6, files_seconds);
  if (plotter && run.channels.num_samples() > 1) plotter->Finish();
  if (!run.ok()) {
    // The status's summary: message, hint, the state's norms, the variables with the largest
    // residual and local error, and the integrator's counters.
    std::fprintf(stderr, "flexrod: numerical failure: %s\n  kept %zu samples in %s\n",
                 run.status.Summary().c_str(), run.channels.num_samples(), opt.out_dir.c_str());
    return 1;
  }
  return 0;
}

}  // namespace

void RegisterRun(CLI::App& app, Handler* handler) {
  auto opt = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "run one simulation (default: the flexible rig)");
  cmd->add_option("input", opt->input,
                  "preset name or TOML file (presets: flexible-rig, rigid-rig, "
                  "simeon-crank, flexible-pendulum)");
  cmd->add_option("--set", opt->sets, "override a key: --set rod.height=\"25.4 mm\"")->take_all();
  cmd->add_option("--out", opt->out_dir, "output directory")->capture_default_str();
  cmd->add_flag("--no-plot", opt->no_plot, "skip the PNG plot");
  cmd->add_option("--ensemble", opt->ensemble,
                  "run N members from crank starts spread over the revolution (the key "
                  "ensemble.members; default: 3 with a clearance joint on a crank) and report "
                  "each headline figure with its bootstrap interval (summary ensemble): the "
                  "figure to quote")
      ->check(CLI::Range(0, 64));
  cmd->add_flag("--check", opt->check,
                "integration error: repeat the run from the same start at 100x tighter "
                "sim.rel_tol and sim.abs_tol and report each headline figure's difference "
                "(summary accuracy_check); it does not see how the answer depends on the start "
                "(the ensemble interval does)");
  cmd->add_flag(
      "--profile", opt->profile,
      "time the integrator's residuals, Jacobians and linear solves (clock reads around "
      "each call: a few % slower) and print their shares of the solver wall (summary "
      "integrator residual_time, jacobian_time, linear_solve_time), and the unknowns "
      "whose local error sets the step (summary integrator step_limiting_unknowns), and the "
      "shares of the steps at each BDF order (summary integrator steps_by_order)");
  cmd->add_option(
      "--vtk", opt->vtk_dir,
      "write a ParaView time series (DIR/run.pvd + one .vtu per frame) of the deformed rod, "
      "crank and slider; keys vtk.rate, vtk.scale, vtk.duration");
  cmd->callback([opt, handler] { *handler = [opt] { return Run(*opt); }; });

  CLI::App* keys = app.add_subcommand("keys", "list every input key with its default and unit");
  keys->callback([handler] {
    *handler = [] {
      for (const ParamDef& p : Schema()) {
        std::printf("%-28s %-16s %s\n", p.key.c_str(),
                    p.default_text.empty() ? "\"\"" : p.default_text.c_str(), p.doc.c_str());
      }
      return 0;
    };
  });
}

}  // namespace flexrod::app
