// SPDX-License-Identifier: GPL-3.0-or-later
// End-to-end run benchmarks (issues 3, 4, 5): the wall time of RunSimulation (model, run,
// channels, summaries and, for a clearance run, its ideal-joint twin; no files), split into the
// run and the twin; steps, events, real-time factor and the share of time in residual,
// Jacobian, linear solve, output and contact evaluation, for the cases the issues set targets
// for. Usage: bench_runs [case ...]  (no argument: all cases).
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "study/config.h"
#include "study/presets.h"
#include "study/run.h"

namespace {

struct Case {
  const char* name;
  const char* preset;
  std::vector<std::string> sets;
  const char* target;
};

const std::vector<Case> kCases = {
    {"flexible-ideal-200rpm", "flexible-rig",
     {"joint.type=ideal", "drive.speed=200 rpm", "reduction.modes=8", "sim.settle=1 s", "sim.capture=3 s"},
     "< 1 s wall (issue 3)"},
    {"rigid-clearance-177rpm", "rigid-rig",
     {"joint.type=clearance", "joint.clearance=1 mm", "joint.law=hybrid", "joint.friction=0.18", "drive.speed=177 rpm",
      "sim.settle=0 s", "sim.capture=3.3898 s"},  // 10 revolutions at 177 rpm
     "< 0.5 s wall (issue 4)"},
    {"flexible-clearance-250rpm", "flexible-rig",
     {"joint.type=clearance", "joint.clearance=0.5 mm", "joint.law=hybrid", "drive.speed=250 rpm",
      "reduction.modes=8", "sim.settle=1 s", "sim.capture=3 s"},
     "< 3 s wall (issues 4, 5)"},
};

int RunCase(const Case& c) {
  flexrod::Config cfg;
  cfg.LoadToml(flexrod::FindPreset(c.preset)->toml, c.preset);
  try {
    for (const std::string& s : c.sets) cfg.SetAssignment(s);
  } catch (const std::exception& e) {
    std::printf("%-28s skipped: %s\n", c.name, e.what());
    return 0;
  }
  // Wall times from a plain run, which computes its ideal-joint twin.
  flexrod::TwinCache twins;
  flexrod::RunOutputOptions plain;
  plain.twins = &twins;
  const auto w0 = std::chrono::steady_clock::now();
  const flexrod::RunResult r = flexrod::RunSimulation(cfg, nullptr, false, plain);
  const double end_to_end = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  const auto& st = r.status;
  const double simulated = st.t_reached;
  const double wall = st.wall_seconds;
  std::printf("%-28s target %s\n", c.name, c.target);
  std::printf("  wall, end to end (RunSimulation: model, run, channels, summaries%s): %.3f s\n",
              r.summary.contains("ideal") ? ", ideal-joint twin" : "", end_to_end);
  if (r.summary.contains("ideal")) {
    std::printf("    of which the run itself %.3f s, its ideal-joint twin %.3f s (twin's output %.3f s)\n",
                r.summary["wall_time [s]"].get<double>(), r.summary["ideal"]["wall_time [s]"].get<double>(),
                r.summary["ideal"]["integrator"]["output_time [s]"].get<double>());
  }
  std::printf("  outcome %s, simulated %.3f s, solver wall %.3f s (integration and sampling), real-time factor %.2f\n",
              flexrod::multibody::ToString(st.outcome), simulated, wall, simulated / wall);
  std::printf("  unknowns integrated %d, steps %ld, residuals %ld, Jacobians %ld, roots/events %ld, error-test failures %ld, "
              "convergence failures %ld, samples %zu\n",
              st.unknowns, st.stats.steps, st.stats.residual_evaluations, st.stats.jacobian_evaluations, st.stats.roots_found,
              st.stats.error_test_failures, st.stats.nonlinear_convergence_failures, r.channels.num_samples());
  // Time shares from a second, profiled run (clock reads around every residual, Jacobian, linear
  // solve and force-element call, which would inflate the first) that reuses the twin.
  flexrod::RunOutputOptions profiled = plain;
  profiled.profile = true;
  const flexrod::RunResult rp = flexrod::RunSimulation(cfg, nullptr, false, profiled);
  const auto& sp = rp.status;
  const double wp = sp.wall_seconds;
  std::printf("  time share of solver wall (second run, profiled): residual %.1f %%, Jacobian %.1f %%, linear solve "
              "%.1f %%, output %.1f %%\n",
              100 * sp.stats.residual_seconds / wp, 100 * sp.stats.jacobian_seconds / wp,
              100 * sp.stats.linear_solve_seconds / wp, 100 * sp.output_seconds / wp);
  const nlohmann::json& et = rp.summary["integrator"]["element_time [s]"];
  if (et.contains("clearance-joint")) {
    double other = 0.0;
    for (const auto& [type, seconds] : et.items()) {
      if (type != "clearance-joint") other += seconds.get<double>();
    }
    std::printf("  contact evaluation (clearance joint in residuals and its Jacobian block, same run): %.1f %% of "
                "solver wall; other force elements %.1f %%\n",
                100 * et.at("clearance-joint").get<double>() / wp, 100 * other / wp);
  }
  if (r.summary.contains("load_amplification")) {
    std::printf("  load amplification: %s\n", r.summary["load_amplification"].dump().c_str());
  }
  return st.ok() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  int rc = 0;
  for (const Case& c : kCases) {
    bool selected = argc == 1;
    for (int i = 1; i < argc; ++i) selected |= (c.name == std::string(argv[i]));
    if (selected) rc |= RunCase(c);
  }
  return rc;
}
