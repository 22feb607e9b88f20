// SPDX-License-Identifier: GPL-3.0-or-later
// End-to-end run benchmarks (issues 3, 4, 5): wall time, steps, events, real-time factor and
// the share of time in residual, Jacobian, linear solve and output, for the cases the issues
// set targets for. Usage: bench_runs [case ...]  (no argument: all cases).
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
  flexrod::RunOutputOptions outputs;
  outputs.time_elements = true;  // the contact share below (two clock reads per element call)
  const flexrod::RunResult r = flexrod::RunSimulation(cfg, nullptr, false, outputs);
  const auto& st = r.status;
  const double simulated = st.t_reached;
  const double wall = st.wall_seconds;
  std::printf("%-28s target %s\n", c.name, c.target);
  std::printf("  outcome %s, simulated %.3f s, wall %.3f s (solver only), real-time factor %.2f\n",
              flexrod::multibody::ToString(st.outcome), simulated, wall, simulated / wall);
  std::printf("  steps %ld, residuals %ld, Jacobians %ld, roots/events %ld, error-test failures %ld, "
              "convergence failures %ld, samples %zu\n",
              st.stats.steps, st.stats.residual_evaluations, st.stats.jacobian_evaluations, st.stats.roots_found,
              st.stats.error_test_failures, st.stats.nonlinear_convergence_failures, r.channels.num_samples());
  std::printf("  time share: residual %.1f %%, Jacobian %.1f %%, linear solve %.1f %%, output %.1f %%\n",
              100 * st.stats.residual_seconds / wall, 100 * st.stats.jacobian_seconds / wall,
              100 * st.stats.linear_solve_seconds / wall, 100 * st.output_seconds / wall);
  const nlohmann::json& et = r.summary["integrator"]["element_time [s]"];
  if (et.contains("clearance-joint")) {
    double other = 0.0;
    for (const auto& [type, seconds] : et.items()) {
      if (type != "clearance-joint") other += seconds.get<double>();
    }
    std::printf("  contact evaluation (clearance joint in residuals and its Jacobian block): %.1f %% of wall; "
                "other force elements %.1f %%\n",
                100 * et["clearance-joint"].get<double>() / wall, 100 * other / wall);
  }
  std::printf("  whole run incl. rod reduction, channels and summaries (and the ideal twin if any): %.3f s\n",
              r.summary["wall_time [s]"].get<double>());
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
