// SPDX-License-Identifier: GPL-3.0-or-later
// The dense LU of multibody/ida_dense_solver.h on the mechanism's iteration matrices: µs per
// factorisation (DenseLuFactor) and per solve (DenseLuSolve) of dF/dy + c_j dF/dẏ, the
// unknowns the integrator keeps (prescribed coordinates dropped), at c_j = 2e5 1/s (steps of
// about 5 µs, as in contact) and 2e3 1/s. Matrices: the flexible rig (the main job: clearance
// and ideal joint) and the exudyn-match rod (steel 19.05 mm, 3 + 3 Craig–Bampton modes), each
// at its rigid start at t = 0 with the crank turning. At these sizes (n of 37 to 63) the
// solve's time is set by its chains of dependent operations, not its multiply-adds. Process
// CPU time, minimum of 5 rounds. Usage: bench_dense_lu.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "input/config.h"
#include "input/presets.h"
#include "mechanisms/mechanism_model.h"
#include "multibody/ida_dense_solver.h"
#include "multibody/prescribed.h"
#include "multibody/simulate.h"

namespace {

using namespace flexrod;

double CpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

void Bench(const char* name, const std::vector<std::string>& sets) {
  Config cfg;
  cfg.LoadToml(FindPreset("flexible-rig")->toml, "flexible-rig");
  for (const std::string& s : sets) cfg.SetAssignment(s);
  const MechanismModel mm = BuildMechanism(cfg, nullptr);
  const multibody::Mechanism& mech = mm.mechanism;
  multibody::RunData data(mech);
  multibody::InitialConditionSpec ic;
  ic.coordinates = mm.p0;
  ic.velocities = mm.v0;  // the run's rigid start: the recipe's rigid-motion velocities
  const multibody::ConsistentState s = multibody::ComputeConsistentState(mech, &data, 0.0, ic);
  const multibody::PrescribedMotion pm(mech, true);
  multibody::MechanismDae dae(mech, &data, pm, std::nullopt);
  const int n = dae.size();
  Vec y(n), yp(n);
  pm.Reduce(s.y.data(), y.data());
  pm.Reduce(s.yp.data(), yp.data());
  for (const double cj : {2e5, 2e3}) {
    Mat J = Mat::Zero(n, n);
    dae.Jacobian(0.0, cj, y.data(), yp.data(), J.data());
    std::vector<double> lu(J.data(), J.data() + J.size()), row_scale(n);
    std::vector<int> pivot(n);
    std::vector<double> b(n), x(n);
    for (int i = 0; i < n; ++i) b[i] = J.row(i).cwiseAbs().maxCoeff() * std::cos(1.0 + i);
    double factor_us = 1e30, solve_us = 1e30, sink = 0.0;
    for (int round = 0; round < 5; ++round) {
      const int reps = 20000;
      double c0 = CpuSeconds();
      for (int r = 0; r < reps; ++r) {
        std::copy(J.data(), J.data() + J.size(), lu.begin());
        multibody::DenseLuFactor(lu.data(), n, pivot.data(), row_scale.data());
      }
      factor_us = std::min(factor_us, 1e6 * (CpuSeconds() - c0) / reps);
      c0 = CpuSeconds();
      for (int r = 0; r < 10 * reps; ++r) {
        std::copy(b.begin(), b.end(), x.begin());
        x[static_cast<size_t>(r % n)] += 1e-3;
        multibody::DenseLuSolve(lu.data(), n, pivot.data(), row_scale.data(), x.data());
        sink += x[0];
      }
      solve_us = std::min(solve_us, 1e6 * (CpuSeconds() - c0) / (10 * reps));
    }
    std::printf("%-40s n = %2d, c_j = %.0e 1/s: factor %.3f us, solve %.3f us (checksum %.3g)\n",
                name, n, cj, factor_us, solve_us, sink);
  }
}

}  // namespace

int main() {
  Bench("flexible rig (main job), clearance", {});
  Bench("flexible rig, ideal joint", {"joint.type=ideal"});
  const std::vector<std::string> exudyn = {
      "rod.height=19.05 mm", "rod.length=280 mm",   "rod.elements=40",    "reduction.modes=3",
      "rod.big_end_x=0",     "rod.big_end_y=0",     "rod.small_end_x=0",  "rod.small_end_y=0",
      "clamp.big_mass=0",    "clamp.big_inertia=0", "clamp.small_mass=0", "clamp.small_inertia=0",
      "clamp.small_com_x=0", "clamp.small_com_y=0", "crank.length=30 mm", "slider.mass=2.71 kg"};
  Bench("exudyn-match rod, clearance", exudyn);
  std::vector<std::string> ideal = exudyn;
  ideal.push_back("joint.type=ideal");
  Bench("exudyn-match rod, ideal joint", ideal);
  return 0;
}
