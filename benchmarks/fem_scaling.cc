// benchmarks/fem_scaling.cc — end-to-end timing of the FE pipeline on SPATIAL rod meshes
// (6 dofs per node) of 1 000, 10 000 and 100 000 elements: assembly of K and M, restriction to
// a clamped–free rod, the lowest-20 ARPACK eigen solve (shift-invert, CHOLMOD factorisation of
// K − σM) with the default request and with ARPACK tol = 1e-10, the dense oracle where it fits
// (≤ 1 000 elements = 6 006 dofs) and the peak resident memory (VmHWM, monotone, so the increase
// per size is printed too). Measures and prints; correctness lives in tests/fem/. The first
// bending frequency is compared with the Euler–Bernoulli continuum value: on fine meshes it
// shows the loss of accuracy to round-off (cond K grows like (L/h)^4), not a solver defect.
//
// One function per stage (Time*), each returning its result with wall and CPU time, so that
// further stages (Craig–Bampton reduction) can be added the same way. Single-threaded throughout
// (reference BLAS/LAPACK; SuiteSparse and ARPACK call them from one thread), so CPU time is the
// figure to compare on a shared machine.
//
// Usage: bench_fem_scaling [--skip-dense] [num_elements ...]   (default 1000 10000 100000)
// SPDX-License-Identifier: GPL-3.0-or-later
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fem/eigensolver.h"
#include "fem/material.h"
#include "fem/rod_mesh.h"
#include "fem/section.h"

namespace flexrod::bench {
namespace {

constexpr int kNumModes = 20;
constexpr double kLooseTolerance = 1e-10;  // ARPACK tol of the tuned run
constexpr int kMaxDenseDofs = 6006;        // 1 000 spatial elements
constexpr const char* kBoundary = "clamped-free";
constexpr double kRodLength = 0.280;        // [m] free length of the rig's rod (RIG.md §2)
constexpr double kRodThickness = 3.175e-3;  // [m] (RIG.md Table 1)
constexpr double kRodHeight = 25.4e-3;      // [m] tallest rig rod

using Clock = std::chrono::steady_clock;

/// CPU time of this process [s]: on a shared machine the wall time also counts other jobs.
double CpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Stopwatch {
  Clock::time_point wall_start{Clock::now()};
  double cpu_start{CpuSeconds()};
};

template <typename T>
struct Timed {
  T value;
  double wall;  ///< wall time [s]
  double cpu;   ///< process CPU time [s]
};

template <typename T>
Timed<T> Stop(T value, const Stopwatch& watch) {
  return {std::move(value), std::chrono::duration<double>(Clock::now() - watch.wall_start).count(),
          CpuSeconds() - watch.cpu_start};
}

/// Peak resident set size so far [kB] (VmHWM in /proc/self/status; monotone over the run).
long PeakResidentKb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::strtol(line.c_str() + 6, nullptr, 10);
  }
  return -1;
}

/// Resets VmHWM to the current resident size (Linux ≥ 4.0: "5" > /proc/self/clear_refs), so
/// that each size reports its own peak; false where that is not supported.
bool ResetPeakResident() {
  std::ofstream clear_refs("/proc/self/clear_refs");
  clear_refs << "5";
  clear_refs.flush();
  return static_cast<bool>(clear_refs);
}

fem::RodSpec SpatialRod(int num_elements) {
  fem::RodSpec spec{};
  spec.material = fem::MaterialByName("steel");
  spec.section.thickness = kRodThickness;
  spec.section.height = kRodHeight;
  spec.section.in_plane = fem::BendingAxis::kWeak;
  spec.length = kRodLength;
  spec.num_elements = num_elements;
  spec.theory = fem::BeamTheory::kEulerBernoulli;
  spec.mass_kind = fem::MassKind::kConsistent;
  spec.dim = fem::MeshDim::kSpatial;
  return spec;
}

// ---- stages -----------------------------------------------------------------------------------

Timed<fem::AssembledRod> TimeAssembly(const fem::RodSpec& spec) {
  const Stopwatch watch;
  return Stop(fem::AssembleRod(spec), watch);
}

struct Restricted {
  SpMat K, M;  ///< free-dof stiffness [N/m, ...] and mass [kg, ...]
};

Timed<Restricted> TimeBoundaryConditions(const fem::RodSpec& spec, const fem::AssembledRod& rod) {
  const Stopwatch watch;
  const std::vector<int> free = fem::FreeDofs(spec.num_dofs(), fem::BoundaryDofs(spec, kBoundary));
  return Stop(Restricted{fem::Restrict(rod.K, free), fem::Restrict(rod.M, free)}, watch);
}

/// Lowest kNumModes with the default request (tolerance 0 = machine precision, automatic ncv)
/// or with a looser ARPACK tolerance.
Timed<fem::EigenResult> TimeArpack(const Restricted& r, double tolerance = 0.0) {
  fem::EigenRequest request;
  request.num_modes = kNumModes;
  request.tolerance = tolerance;
  const Stopwatch watch;
  return Stop(fem::SolveEigenArpack(r.K, r.M, request), watch);
}

std::optional<Timed<fem::EigenResult>> TimeDense(const Restricted& r, int num_dofs) {
  if (num_dofs > kMaxDenseDofs) return std::nullopt;
  const Stopwatch watch;
  return Stop(fem::SolveEigenDense(Mat(r.K), Mat(r.M), kNumModes), watch);
}

/// First clamped–free bending frequency of the continuum Euler–Bernoulli rod about its weak
/// axis: f₁ = (β₁L)² / (2π L²) · sqrt(E I / (ρ A)), β₁L = 1.8751040687 [Hz].
double AnalyticFirstBendingHz(const fem::RodSpec& spec) {
  constexpr double kBeta1L = 1.8751040687;
  const double inertia =
      std::min(spec.section.inertia_in_plane(), spec.section.inertia_out_of_plane());
  return kBeta1L * kBeta1L / (2.0 * std::numbers::pi * spec.length * spec.length) *
         std::sqrt(spec.material.youngs_modulus * inertia /
                   (spec.material.density * spec.section.area()));
}

double MaxRelativeDeviation(const Vec& a, const Vec& reference) {
  return ((a - reference).cwiseAbs().array() / reference.cwiseAbs().array()).maxCoeff();
}

// ---- driver -----------------------------------------------------------------------------------

void PrintStage(const char* name, double wall, double cpu, const std::string& note = "") {
  std::printf("  %-30s %8.3f s wall %8.3f s cpu  %s\n", name, wall, cpu, note.c_str());
}

void RunSize(int num_elements, bool skip_dense, long* last_peak_kb) {
  const bool reset = ResetPeakResident();
  const fem::RodSpec spec = SpatialRod(num_elements);
  const auto assembly = TimeAssembly(spec);
  const auto bc = TimeBoundaryConditions(spec, assembly.value);
  const auto arpack = TimeArpack(bc.value);
  const auto arpack_loose = TimeArpack(bc.value, kLooseTolerance);
  const long peak_kb = PeakResidentKb();
  std::optional<Timed<fem::EigenResult>> dense;
  long dense_peak_kb = -1;
  if (!skip_dense) {
    if (reset) ResetPeakResident();
    dense = TimeDense(bc.value, spec.num_dofs());
    dense_peak_kb = PeakResidentKb();
  }

  const Vec f = arpack.value.frequencies_hz();
  const double f1_exact = AnalyticFirstBendingHz(spec);
  char note[200];
  std::printf("\n== %d spatial elements: %d dofs, %d free (%s), nnz(K) = %ld\n", num_elements,
              spec.num_dofs(), static_cast<int>(bc.value.K.rows()), kBoundary,
              static_cast<long>(assembly.value.K.nonZeros()));
  PrintStage("assembly (K, M)", assembly.wall, assembly.cpu);
  PrintStage("boundary conditions", bc.wall, bc.cpu);
  std::snprintf(
      note, sizeof note, "%d restarts; f1 = %.4f Hz (EB continuum %.4f, %+.1e), f%d = %.2f Hz",
      arpack.value.iterations, f[0], f1_exact, f[0] / f1_exact - 1.0, kNumModes, f[kNumModes - 1]);
  PrintStage("ARPACK lowest 20, default tol", arpack.wall, arpack.cpu, note);
  std::snprintf(note, sizeof note, "%d restarts; max |dlambda|/lambda vs default %.1e",
                arpack_loose.value.iterations,
                MaxRelativeDeviation(arpack_loose.value.eigenvalues, arpack.value.eigenvalues));
  PrintStage("ARPACK lowest 20, tol 1e-10", arpack_loose.wall, arpack_loose.cpu, note);
  PrintStage("total: assembly + bc + ARPACK", assembly.wall + bc.wall + arpack.wall,
             assembly.cpu + bc.cpu + arpack.cpu);
  if (dense) {
    std::snprintf(note, sizeof note, "max |dlambda|/lambda vs ARPACK %.1e; peak RSS %.1f MB",
                  MaxRelativeDeviation(arpack.value.eigenvalues, dense->value.eigenvalues),
                  dense_peak_kb / 1024.0);
    PrintStage("dense oracle lowest 20", dense->wall, dense->cpu, note);
  } else {
    std::printf("  %-30s skipped (%s)\n", "dense oracle",
                skip_dense ? "--skip-dense" : "more than 6006 dofs");
  }
  // With the reset, VmHWM is this size's own peak; without it, VmHWM is monotone over the run.
  std::printf("  %-30s %8.1f MB (%+.1f MB vs the previous size%s)\n", "peak RSS, assembly..ARPACK",
              peak_kb / 1024.0, (peak_kb - *last_peak_kb) / 1024.0,
              reset ? "; VmHWM reset before each size" : "; VmHWM is monotone");
  *last_peak_kb = reset ? peak_kb : std::max(peak_kb, dense_peak_kb);
  std::fflush(stdout);  // long runs: show each size as it finishes
}

int RunFemScaling(int argc, char** argv) {
  bool skip_dense = false;
  std::vector<int> sizes;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--skip-dense") {
      skip_dense = true;
    } else {
      const int n = std::atoi(arg.c_str());
      if (n < 1) {
        std::fprintf(stderr, "usage: %s [--skip-dense] [num_elements ...]\n", argv[0]);
        return 2;
      }
      sizes.push_back(n);
    }
  }
  if (sizes.empty()) sizes = {1000, 10000, 100000};
  std::printf(
      "flexrod FE scaling: steel rod %.0f mm x %.3f mm x %.1f mm, spatial Euler-Bernoulli,"
      " consistent mass, %s, lowest %d modes\n",
      kRodLength * 1e3, kRodThickness * 1e3, kRodHeight * 1e3, kBoundary, kNumModes);
  long last_peak_kb = PeakResidentKb();
  std::printf("peak RSS before the first size: %.1f MB\n", last_peak_kb / 1024.0);
  for (int n : sizes) RunSize(n, skip_dense, &last_peak_kb);
  return 0;
}

}  // namespace
}  // namespace flexrod::bench

int main(int argc, char** argv) { return flexrod::bench::RunFemScaling(argc, argv); }
