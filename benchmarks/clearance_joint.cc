// SPDX-License-Identifier: GPL-3.0-or-later
// Clearance-joint benchmarks (issue 4): the cost of one joint evaluation (ns per
// ClearanceJoint::Evaluate in contact, hybrid + Coulomb), and the CPU time of the two target
// runs integrated alone (no ideal twin, no files), once without output and once sampled at
// 100 kHz: rigid rig 177 rpm, 1 mm, 10 revolutions (target < 0.5 s) and flexible rig 250 rpm,
// 0.5 mm, 1 s + 3 s, 8 CB modes (target < 3 s). Thread CPU time is reported beside wall time
// because the machine may be shared. Usage: bench_clearance_joint [rigid|flexible|element ...].
#include "multibody/clearance_joint.h"

#include <time.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "contact/friction_law.h"
#include "contact/normal_law.h"
#include "input/config.h"
#include "input/presets.h"
#include "mechanisms/mechanism_model.h"
#include "multibody/simulate.h"

namespace {

using namespace flexrod;

double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void BenchElement() {
  const contact::ContactGeometry g{9.525e-3, 9.025e-3, 12.7e-3};
  const contact::ContactMaterials m{200e9, 0.29, 200e9, 0.29, 0.9};
  const multibody::ClearanceJoint joint(g, contact::MakeNormalLaw("hybrid", m, g),
                                        contact::MakeFrictionLaw("coulomb"));
  std::vector<double> memory(joint.num_memory(), 0.0);
  memory[multibody::kContactFlag] = 1.0;
  memory[multibody::kApproachVelocity] = 0.3;
  multibody::MarkerKinematics bush, pin;
  bush.velocity = Vec2(0.1, 0.2);
  pin.velocity = Vec2(0.3, -0.1);
  pin.angular_velocity = 2.0;
  const long n = 2000000;
  double sink = 0.0;
  const double c0 = CpuSeconds();
  for (long k = 0; k < n; ++k) {
    const double a = 1e-3 * static_cast<double>(k % 1000);
    pin.position = (g.clearance() + 2e-6 + 1e-9 * (k % 7)) * Vec2(std::cos(a), std::sin(a));
    multibody::ElementOutput out;
    joint.Evaluate(0.0, bush, pin, nullptr, memory.data(), &out);
    sink += out.force_j.x();
  }
  const double c1 = CpuSeconds();
  std::printf(
      "element: ClearanceJoint::Evaluate (hybrid + coulomb, in contact): %.1f ns per call "
      "(checksum %.3g); one FD Jacobian = 25 calls\n",
      1e9 * (c1 - c0) / n, sink);
}

void BenchRun(const char* name, const char* preset, const std::vector<std::string>& sets,
              const char* target) {
  Config cfg;
  cfg.LoadToml(FindPreset(preset)->toml, preset);
  for (const std::string& s : sets) cfg.SetAssignment(s);
  const double c_build = CpuSeconds();
  const MechanismModel mm = BuildMechanism(cfg, nullptr);
  const double build = CpuSeconds() - c_build;
  const multibody::Mechanism& mech = mm.mechanism;
  multibody::InitialConditionSpec ic;
  ic.coordinates = mm.p0;
  ic.velocities = Vec::Zero(mech.num_coordinates());
  ic.velocities[mech.coordinate(mm.crank, multibody::kTheta)] = cfg.Quantity("drive.speed");
  const double t_end = cfg.Quantity("sim.settle") + cfg.Quantity("sim.capture");
  std::printf("%s — target %s (build incl. rod reduction: %.3f s CPU)\n", name, target, build);
  for (const double rate : {1.0 / t_end, 1e5}) {
    multibody::SimulationOptions opt;
    opt.t_end = t_end;
    opt.sample_rate = rate;
    opt.integrator.rel_tol = cfg.Quantity("sim.rel_tol");
    opt.integrator.abs_tol = cfg.Quantity("sim.abs_tol");
    opt.time_elements = true;          // the contact share (two clock reads per element call)
    opt.integrator.time_calls = true;  // the residual, Jacobian and linear-solve shares
    long samples = 0;
    double sink = 0.0;
    multibody::SimulationCallbacks cb;
    if (rate > 1.0) {
      cb.on_sample = [&](const multibody::SampleView& s) {
        // What the run records for the joint: one joint evaluation per sample.
        sink += multibody::CalcClearanceResponse(s, mm.clearance).normal_force;
        ++samples;
      };
    }
    multibody::RunData data(mech);
    const double c0 = CpuSeconds(), w0 = WallSeconds();
    const multibody::SimulationStatus st = multibody::Simulate(mech, &data, ic, opt, cb);
    const double cpu = CpuSeconds() - c0, wall = WallSeconds() - w0;
    std::printf(
        "  %-22s %s: CPU %.3f s, wall %.3f s, simulated %.3f s; steps %ld, residuals %ld, "
        "Jacobians %ld, events %ld, error-test failures %ld, convergence failures %ld\n",
        rate > 1.0 ? "sampled at 100 kHz" : "no output", multibody::ToString(st.outcome), cpu, wall,
        st.t_reached, st.stats.steps, st.stats.residual_evaluations, st.stats.jacobian_evaluations,
        st.stats.roots_found, st.stats.error_test_failures,
        st.stats.nonlinear_convergence_failures);
    // The clearance joint: its evaluations in residuals and its Jacobian block.
    const double contact = st.element_seconds.at(static_cast<size_t>(mm.clearance.index));
    std::printf(
        "  %-22s time shares of wall: contact evaluation %.0f %% (inside residual and Jacobian), "
        "residual %.0f %%, Jacobian %.0f %%, linear solve %.0f "
        "%%, output %.0f %%, rest (IDA, events, restarts) %.0f %%; N = %d (%s)\n",
        "", 100 * contact / wall, 100 * st.stats.residual_seconds / wall,
        100 * st.stats.jacobian_seconds / wall, 100 * st.stats.linear_solve_seconds / wall,
        100 * st.output_seconds / wall,
        100 * (1.0 - (st.stats.residual_seconds + st.stats.jacobian_seconds +
                      st.stats.linear_solve_seconds + st.output_seconds) /
                         wall),
        mech.size(), multibody::ToString(st.linear_solver));
    (void)samples;
    (void)sink;
  }
}

}  // namespace

int main(int argc, char** argv) {
  auto selected = [&](const char* name) {
    if (argc == 1) return true;
    for (int i = 1; i < argc; ++i) {
      if (std::string(argv[i]) == name) return true;
    }
    return false;
  };
  if (selected("element")) BenchElement();
  if (selected("rigid")) {
    BenchRun("rigid rig, 1 mm, hybrid + coulomb 0.18, 177 rpm, 10 revolutions", "rigid-rig",
             {"joint.type=clearance", "joint.clearance=1 mm", "drive.speed=177 rpm",
              "sim.settle=0 s", "sim.capture=3.3898 s"},
             "< 0.5 s");
  }
  if (selected("flexible")) {
    BenchRun("flexible rig, 0.5 mm, hybrid + coulomb, 250 rpm, 1 s + 3 s, 8 CB modes",
             "flexible-rig",
             {"joint.type=clearance", "joint.clearance=0.5 mm", "drive.speed=250 rpm",
              "reduction.modes=8", "sim.settle=1 s", "sim.capture=3 s"},
             "< 3 s");
  }
  return 0;
}
