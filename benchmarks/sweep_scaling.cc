// benchmarks/sweep_scaling.cc — how a sweep scales with worker threads, and how large its store
// gets. (1) An 8-run matrix (two steel rods x four speeds, 0.5 mm clearance joint with its
// ideal twin, 0.2 s settling + 0.3 s at 10 kHz) with 1 and with 2 threads: wall times and the
// parallel efficiency T1 / (2 T2). (2) One run of RIG.md Table 2 at its full settings (1 s
// settling, 3 s at 100 kHz, channels stored at 10 kHz): wall time and bytes in the store per
// run, extrapolated to the 189 runs of the table. `--quick` skips (2). `--table2` instead runs
// (3): the whole Table 2 (189 runs, full settings) with 1 and with 2 threads — about 8 minutes
// on 2 idle cores — and prints wall times, parallel efficiency, failures and the store size.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>

#include "sweep/sweep.h"

namespace {

namespace fs = std::filesystem;
using flexrod::study::SweepMatrix;

const char* kScalingMatrix = R"(
[sweep]
name = "scaling"
base = "flexible-rig"
[set]
"joint.type" = "clearance"
"joint.clearance" = "0.5 mm"
"sim.settle" = "0.2 s"
"sim.capture" = "0.3 s"
"sim.sample_rate" = "10 kHz"
[axes]
"rod.height" = ["12.7 mm", "19.05 mm"]
"drive.speed" = ["150 rpm", "180 rpm", "210 rpm", "250 rpm"]
)";

/// CPU time of this process so far (user + system, all threads) [s].
double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Timing {
  double wall{0.0}, cpu{0.0};  // [s]
};

Timing TimeSweep(const SweepMatrix& m, const fs::path& store, int jobs) {
  fs::remove(store);
  flexrod::study::SweepOptions options;
  options.jobs = jobs;
  double load[1] = {0.0};
  getloadavg(load, 1);
  const double cpu0 = CpuSeconds();
  const auto t0 = std::chrono::steady_clock::now();
  const auto outcome = flexrod::study::RunSweep(m, store.string(), options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // The CPU time shows whether threads add work; the wall time is what a user waits (it
  // depends on what else the machine runs: the load average is printed with it).
  const double cpu = CpuSeconds() - cpu0;
  std::printf(
      "  --jobs %d: %6.2f s wall, %6.2f s CPU for %d runs (%d failed); load average before %.1f\n",
      jobs, seconds, cpu, outcome.num_runs, outcome.num_failed, load[0]);
  return {seconds, cpu};
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const bool full = argc > 1 && std::strcmp(argv[1], "--table2") == 0;
  const fs::path dir =
      fs::temp_directory_path() / ("flexrod_bench_sweep_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const unsigned cores = std::thread::hardware_concurrency();
  std::printf("sweep scaling (%u hardware threads)\n", cores);

  if (full) {
    const SweepMatrix table2 = flexrod::study::LoadSweepMatrix(flexrod::study::kDefaultSweepMatrix);
    std::printf("(3) the whole Table 2: %zu runs, 1 s settling + 3 s at 100 kHz, ideal twins\n",
                table2.num_runs());
    const Timing t1 = TimeSweep(table2, dir / "table2-1.h5", 1);
    const Timing t2 = TimeSweep(table2, dir / "table2-2.h5", 2);
    std::printf(
        "  speed-up %.3f, parallel efficiency T1 / (2 T2) = %.1f %% (target >= 90 %%); "
        "2 threads: %.1f min (target < 10 min)\n",
        t1.wall / t2.wall, 100.0 * t1.wall / (2.0 * t2.wall), t2.wall / 60.0);
    std::printf("  store: %.1f MB (%s)\n",
                static_cast<double>(fs::file_size(dir / "table2-2.h5")) / 1e6,
                "channels at 10 kHz, spectra to 5 kHz, turning points, Poincare points");
    fs::remove_all(dir);
    return 0;
  }

  const SweepMatrix scaling = flexrod::study::ParseSweepMatrix(kScalingMatrix, "scaling", ".");
  std::printf(
      "(1) %zu-run matrix: steel 12.7 / 19.05 mm x 150-250 rpm, 0.5 mm clearance + ideal twin\n",
      scaling.num_runs());
  const Timing t1 = TimeSweep(scaling, dir / "one.h5", 1);
  const Timing t2 = TimeSweep(scaling, dir / "two.h5", 2);
  std::printf(
      "  speed-up %.2f, parallel efficiency T1 / (2 T2) = %.0f %% (wall; meaningful on an idle "
      "machine)\n",
      t1.wall / t2.wall, 100.0 * t1.wall / (2.0 * t2.wall));
  std::printf("  CPU time with 2 threads / with 1 thread = %.3f (1 = threads add no work)\n",
              t2.cpu / t1.cpu);
  const double small_bytes = static_cast<double>(fs::file_size(dir / "one.h5"));
  std::printf("  store: %.0f kB, %.1f kB per run (0.3 s of 2 channels at 10 kHz)\n",
              small_bytes / 1e3, small_bytes / 1e3 / static_cast<double>(scaling.num_runs()));

  if (!quick) {
    SweepMatrix table2 = flexrod::study::LoadSweepMatrix(flexrod::study::kDefaultSweepMatrix);
    const std::size_t total = table2.num_runs();
    // steel 19.05 mm, 0.5 mm, 200 rpm: a middle run of the table.
    int pick = -1;
    for (const auto& r : table2.runs) {
      if (r.Label() ==
          "rod.material=steel, rod.height=19.05 mm, joint.clearance=0.5 mm, drive.speed=200 rpm")
        pick = r.id;
    }
    if (pick < 0) pick = static_cast<int>(total / 2);
    SweepMatrix one = table2;
    one.runs = {table2.runs[static_cast<std::size_t>(pick)]};
    one.runs[0].id = 0;
    std::printf("(2) one Table 2 run at full settings: %s\n", one.runs[0].Label().c_str());
    const Timing t = TimeSweep(one, dir / "table2-one.h5", 1);
    const double bytes = static_cast<double>(fs::file_size(dir / "table2-one.h5"));
    std::printf(
        "  store: %.2f MB for 1 run (3 s, channels at 10 kHz, spectrum to 5 kHz, turning points)\n",
        bytes / 1e6);
    // CPU time is what an idle core would take; runs are independent, so cores divide it.
    std::printf(
        "  Table 2 extrapolated: %zu runs -> %.0f MB store; %.2f h of CPU, %.2f h on %u idle "
        "cores\n",
        total, bytes * static_cast<double>(total) / 1e6,
        t.cpu * static_cast<double>(total) / 3600.0,
        t.cpu * static_cast<double>(total) / 3600.0 / std::max(1u, cores), cores);
  }
  fs::remove_all(dir);
  return 0;
}
