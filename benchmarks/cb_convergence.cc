// SPDX-License-Identifier: GPL-3.0-or-later
// Craig–Bampton convergence in the mechanism (issue 3): the flexible rig with an ideal joint,
// 200 rpm, one captured revolution after settling, for an increasing number of fixed-interface
// modes and for the full FE rod (every FE dof a coordinate). Prints modes, coordinates, peak
// |slider acceleration|, peak |midspan deflection|, their differences from full FE, wall time.
// Usage: bench_cb_convergence [elements]   (default 20 elements, so full FE stays small)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "input/presets.h"
#include "run/run.h"

namespace {

struct Result {
  int coordinates;
  double peak_acc, peak_defl, wall;
};

Result Run(const std::string& method, int modes, int elements) {
  flexrod::Config cfg;
  cfg.LoadToml(flexrod::FindPreset("flexible-rig")->toml, "flexible-rig");
  const std::vector<std::string> sets = {"joint.type=ideal",
                                         "sim.settle=0.5 s",
                                         "sim.capture=0.3 s",
                                         "sim.sample_rate=20 kHz",
                                         "reduction.method=" + method,
                                         "reduction.modes=" + std::to_string(modes),
                                         "rod.elements=" + std::to_string(elements)};
  for (const std::string& s : sets) cfg.SetAssignment(s);
  const auto t0 = std::chrono::steady_clock::now();
  const flexrod::RunResult r = flexrod::RunSimulation(cfg);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double acc = 0, defl = 0;
  for (double a : r.channels.values("slider_acceleration")) acc = std::max(acc, std::abs(a));
  for (double d : r.channels.values("rod_deflection")) defl = std::max(defl, std::abs(d));
  int n = 0;
  // (std::string("q") += ... avoids GCC 12's false -Wrestrict on "literal" + std::string&&)
  while (r.channels.HasChannel(std::string("q") += std::to_string(n + 1))) ++n;
  return {n, acc, defl, wall};
}

}  // namespace

int main(int argc, char** argv) {
  const int elements = argc > 1 ? std::atoi(argv[1]) : 20;
  const Result full = Run("full", 0, elements);
  std::printf("flexible rig, ideal joint, 200 rpm, %d elements; full FE: %d coordinates\n",
              elements, full.coordinates);
  std::printf("%-16s %6s %12s %22s %10s %24s %10s %9s\n", "basis", "modes", "coordinates",
              "peak |a_slider| [m/s^2]", "rel. diff", "peak |midspan defl.| [m]", "rel. diff",
              "wall [s]");
  for (int k : {0, 1, 2, 4, 8, 16}) {
    const Result r = Run("craig-bampton", k, elements);
    std::printf("%-16s %6d %12d %22.6f %10.2e %24.6e %10.2e %9.3f\n", "craig-bampton", k,
                r.coordinates, r.peak_acc, std::abs(r.peak_acc / full.peak_acc - 1), r.peak_defl,
                std::abs(r.peak_defl / full.peak_defl - 1), r.wall);
  }
  std::printf("%-16s %6s %12d %22.6f %10s %24.6e %10s %9.3f\n", "full FE", "-", full.coordinates,
              full.peak_acc, "0", full.peak_defl, "0", full.wall);
  return 0;
}
