// SPDX-License-Identifier: GPL-3.0-or-later
// End-to-end run benchmarks (issues 3, 4, 5): the wall time of RunSimulation (model, run,
// channels, summaries and, for a clearance run, its ideal-joint twin; no files), split into the
// run and the twin; steps, events, real-time factor and the share of time in residual,
// Jacobian, linear solve, output and contact evaluation, for the cases the issues set targets
// for. Usage: bench_runs [--repeat N] [case ...]  (no case: all cases). Each case runs N times
// (default 5; single runs on a shared machine spread by 10 % and more), each in a fresh child
// process (a run's first touch of its record's memory is part of its cost, which a repetition
// in the same process would hide), the first one with the full report; then the minimum,
// median and maximum of the wall times over the N. --repeat 1: one run, in this process.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "input/config.h"
#include "input/presets.h"
#include "run/run.h"

namespace {

struct Case {
  const char* name;
  const char* preset;
  std::vector<std::string> sets;
  const char* target;
  const char* reference{nullptr};  ///< a case whose run time this one's is compared with
};

const std::vector<Case> kCases = {
    {"main-job",
     "flexible-rig",
     {},
     "the run <= 1.20 x main-job-linear-rod's (issue 23: at most 20 % over the linear rod)",
     "main-job-linear-rod"},
    {"main-job-linear-rod",
     "flexible-rig",
     {"rod.geometric_stiffening=false"},
     "none (main-job's reference: the rod without the second-order strain, as before issue 23)"},
    {"flexible-ideal-200rpm",
     "flexible-rig",
     {"joint.type=ideal", "drive.speed=200 rpm", "reduction.modes=8", "sim.settle=1 s",
      "sim.capture=3 s"},
     "< 1 s wall (issue 3)"},
    {"rigid-clearance-177rpm",
     "rigid-rig",
     {"joint.type=clearance", "joint.clearance=1 mm", "joint.law=hybrid", "joint.friction=0.18",
      "drive.speed=177 rpm", "sim.settle=0 s",
      "sim.capture=3.3898 s"},  // 10 revolutions at 177 rpm
     "< 0.5 s wall (issue 4)"},
    {"flexible-clearance-250rpm",
     "flexible-rig",
     {"joint.type=clearance", "joint.clearance=0.5 mm", "joint.law=hybrid", "drive.speed=250 rpm",
      "reduction.modes=8", "sim.settle=1 s", "sim.capture=3 s"},
     "< 3 s wall (issues 4, 5)"},
};

struct Timing {
  double end_to_end{0.0}, run{0.0}, twin{0.0};  // [s]; twin 0 without one
  int rc{0};
};

/// One plain run of the case; with `report`, its figures and a second, profiled run's time shares.
Timing RunCase(const Case& c, bool report) {
  Timing out;
  flexrod::Config cfg;
  cfg.LoadToml(flexrod::FindPreset(c.preset)->toml, c.preset);
  try {
    for (const std::string& s : c.sets) cfg.SetAssignment(s);
  } catch (const std::exception& e) {
    if (report) std::printf("%-28s skipped: %s\n", c.name, e.what());
    return out;
  }
  // Wall times from a plain run, which computes its ideal-joint twin.
  flexrod::TwinCache twins;
  flexrod::RunOutputOptions plain;
  plain.twins = &twins;
  const auto w0 = std::chrono::steady_clock::now();
  const flexrod::RunResult r = flexrod::RunSimulation(cfg, nullptr, false, plain);
  const double end_to_end =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  const auto& st = r.status;
  out = {end_to_end, r.summary["wall_time [s]"].get<double>(),
         r.summary.contains("ideal") ? r.summary["ideal"]["wall_time [s]"].get<double>() : 0.0,
         st.ok() ? 0 : 1};
  if (!report) return out;
  const double simulated = st.t_reached;
  const double wall = st.wall_seconds;
  std::printf("%-28s target %s\n", c.name, c.target);
  std::printf("  wall, end to end (RunSimulation: model, run, channels, summaries%s): %.3f s\n",
              r.summary.contains("ideal") ? ", ideal-joint twin" : "", end_to_end);
  if (r.summary.contains("ideal")) {
    std::printf(
        "    of which the run itself %.3f s, its ideal-joint twin %.3f s (twin's output %.3f s)\n",
        r.summary["wall_time [s]"].get<double>(), r.summary["ideal"]["wall_time [s]"].get<double>(),
        r.summary["ideal"]["integrator"]["output_time [s]"].get<double>());
  }
  std::printf(
      "  outcome %s, simulated %.3f s, solver wall %.3f s (integration and sampling), real-time "
      "factor %.2f\n",
      flexrod::multibody::ToString(st.outcome), simulated, wall, simulated / wall);
  std::printf(
      "  unknowns integrated %d, steps %ld, residuals %ld, Jacobians %ld, roots/events %ld, "
      "error-test failures %ld, "
      "convergence failures %ld, samples %zu\n",
      st.unknowns, st.stats.steps, st.stats.residual_evaluations, st.stats.jacobian_evaluations,
      st.stats.roots_found, st.stats.error_test_failures, st.stats.nonlinear_convergence_failures,
      r.channels.num_samples());
  // Time shares from a second, profiled run (clock reads around every residual, Jacobian, linear
  // solve and force-element call, which would inflate the first) that reuses the twin.
  flexrod::RunOutputOptions profiled = plain;
  profiled.profile = true;
  const flexrod::RunResult rp = flexrod::RunSimulation(cfg, nullptr, false, profiled);
  const auto& sp = rp.status;
  const double wp = sp.wall_seconds;
  std::printf(
      "  time share of solver wall (second run, profiled): residual %.1f %%, Jacobian %.1f %%, "
      "linear solve "
      "%.1f %%, output %.1f %%\n",
      100 * sp.stats.residual_seconds / wp, 100 * sp.stats.jacobian_seconds / wp,
      100 * sp.stats.linear_solve_seconds / wp, 100 * sp.output_seconds / wp);
  const nlohmann::json& et = rp.summary["integrator"]["element_time [s]"];
  if (et.contains("clearance-joint")) {
    double other = 0.0;
    for (const auto& [type, seconds] : et.items()) {
      if (type != "clearance-joint") other += seconds.get<double>();
    }
    std::printf(
        "  contact evaluation (clearance joint in residuals and its Jacobian block, same run): "
        "%.1f %% of "
        "solver wall; other force elements %.1f %%\n",
        100 * et.at("clearance-joint").get<double>() / wp, 100 * other / wp);
  }
  if (r.summary.contains("load_amplification")) {
    std::printf("  load amplification: %s\n", r.summary["load_amplification"].dump().c_str());
  }
  return out;
}

/// RunCase in a child process; the child's Timing comes back through a pipe.
Timing RunCaseInChild(const Case& c, bool report) {
  std::fflush(stdout);
  int fd[2];
  if (pipe(fd) != 0) {
    std::perror("bench_runs: pipe");
    std::exit(1);
  }
  const pid_t pid = fork();
  if (pid < 0) {
    std::perror("bench_runs: fork");
    std::exit(1);
  }
  if (pid == 0) {
    close(fd[0]);
    const Timing t = RunCase(c, report);
    std::fflush(stdout);
    const bool written = write(fd[1], &t, sizeof t) == static_cast<ssize_t>(sizeof t);
    _exit(written ? 0 : 1);
  }
  close(fd[1]);
  Timing t;
  const bool complete = read(fd[0], &t, sizeof t) == static_cast<ssize_t>(sizeof t);
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (!complete || !WIFEXITED(status) || WEXITSTATUS(status) != 0) t.rc = 1;
  return t;
}

void PrintSpread(const char* what, std::vector<double> v) {
  std::sort(v.begin(), v.end());
  std::printf("  %s min %.3f s, median %.3f s, max %.3f s\n", what, v.front(), v[v.size() / 2],
              v.back());
}

}  // namespace

int main(int argc, char** argv) {
  int repeat = 5;
  std::vector<std::string> names;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repeat" && i + 1 < argc) {
      repeat = std::atoi(argv[++i]);
      if (repeat < 1) {
        std::fprintf(stderr, "bench_runs: --repeat %s: must be an integer >= 1\n", argv[i]);
        return 2;
      }
    } else if (std::none_of(kCases.begin(), kCases.end(),
                            [&](const Case& c) { return arg == c.name; })) {
      std::string known;
      for (const Case& c : kCases) known += std::string(known.empty() ? "" : ", ") + c.name;
      std::fprintf(stderr, "bench_runs: %s: not a case (cases: %s; option: --repeat N)\n",
                   arg.c_str(), known.c_str());
      return 2;
    } else {
      names.push_back(arg);
    }
  }
  int rc = 0;
  std::vector<std::pair<const Case*, std::vector<double>>> runs;  // the run's times per case
  for (const Case& c : kCases) {
    if (!names.empty() && std::find(names.begin(), names.end(), c.name) == names.end()) continue;
    if (repeat == 1) {
      rc |= RunCase(c, true).rc;
      continue;
    }
    std::vector<double> end_to_end, run, twin;
    for (int k = 0; k < repeat; ++k) {
      const Timing t = RunCaseInChild(c, k == 0);
      rc |= t.rc;
      end_to_end.push_back(t.end_to_end);
      run.push_back(t.run);
      twin.push_back(t.twin);
    }
    std::printf("  over %d runs, each in a fresh process:\n", repeat);
    PrintSpread("end to end:", end_to_end);
    PrintSpread("the run itself:", run);
    if (twin.front() > 0.0) PrintSpread("its ideal-joint twin:", twin);
    runs.emplace_back(&c, run);
  }
  // Ratios of the run times to the reference case's, when both ran.
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  for (const auto& [c, t] : runs) {
    if (c->reference == nullptr) continue;
    for (const auto& [ref, tr] : runs) {
      if (std::string(ref->name) != c->reference) continue;
      std::printf("%s / %s, the run itself: %.3f (min over min), %.3f (median over median)\n",
                  c->name, ref->name,
                  *std::min_element(t.begin(), t.end()) / *std::min_element(tr.begin(), tr.end()),
                  median(t) / median(tr));
    }
  }
  return rc;
}
