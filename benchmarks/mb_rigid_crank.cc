// benchmarks/mb_rigid_crank.cc — end-to-end timing of the multibody engine: the rigid
// slider-crank (10 revolutions at 200 rpm, 100 kHz output), the flexible slider-crank the
// study layer targets (Craig–Bampton steel rod with 8 modes, 4 s at 100 kHz, band damping),
// and a full-FE rod run with the dense and the KLU linear solver. Prints wall time, steps,
// real-time factor and the time shares of residual / Jacobian / linear solver / output.
// Measures; asserts nothing (STYLE.md §16).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "fem/reduced_rod.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

constexpr double kR = 0.05, kL = 0.2, kOffset = 0.0;  // crank radius, rod length, offset [m]
constexpr double kOmega = 200.0 * 2.0 * std::numbers::pi / 60.0;  // 200 rpm [rad/s]
constexpr double kTheta0 = 0.3;                                   // [rad]

struct Crank {
  Mechanism model;
  BodyId crank, rod, slider;
  DriverId driver;
};

// Slider-crank from generic parts; rod rigid (rod == nullptr) or flexible.
Crank Build(std::shared_ptr<const fem::ReducedRod> rod) {
  MechanismBuilder b;
  Crank c;
  c.crank = b.AddRigidBody({"crank", 0.5, 0.5 * kR * kR / 12.0, Vec2(0.5 * kR, 0.0)});
  MarkerId rod_a, rod_b;
  if (rod) {
    FlexibleBodySpec fs;
    fs.name = "rod";
    fs.rod = rod;
    fs.damping = DampingSpec::FrequencyBand();
    c.rod = b.AddFlexibleBody(fs);
    rod_a = b.AddNodeMarker(c.rod, "rod.A", 0);
    rod_b = b.AddNodeMarker(c.rod, "rod.B", rod->rod.num_nodes() - 1);
  } else {
    c.rod = b.AddRigidBody({"rod", 0.3, 0.3 * kL * kL / 12.0, Vec2(0.5 * kL, 0.0)});
    rod_a = b.AddBodyMarker(c.rod, "rod.A", Vec2(0.0, 0.0));
    rod_b = b.AddBodyMarker(c.rod, "rod.B", Vec2(kL, 0.0));
  }
  c.slider = b.AddRigidBody({"slider", 0.4, 1e-4, Vec2(0.0, 0.0)});
  const MarkerId o = b.AddGroundMarker("O", Vec2(0.0, 0.0));
  const MarkerId guide = b.AddGroundMarker("guide", Vec2(0.0, kOffset));
  const MarkerId c_o = b.AddBodyMarker(c.crank, "crank.O", Vec2(0.0, 0.0));
  const MarkerId c_a = b.AddBodyMarker(c.crank, "crank.A", Vec2(kR, 0.0));
  const MarkerId s_b = b.AddBodyMarker(c.slider, "slider.B", Vec2(0.0, 0.0));
  b.AddRevolute("pivot", o, c_o);
  b.AddRevolute("big_end", c_a, rod_a);
  b.AddRevolute("small_end", rod_b, s_b);
  PrismaticSpec ps;
  ps.name = "guide";
  ps.marker_i = guide;
  ps.marker_j = s_b;
  b.AddPrismatic(ps);
  c.driver = b.AddConstantSpeedDriver("motor", c.crank, kTheta0, kOmega);
  c.model = b.Build();
  return c;
}

InitialConditionSpec Guess(const Crank& c) {
  const double th = kTheta0;
  const double s = kR * std::sin(th) - kOffset;
  const double x = kR * std::cos(th) + std::sqrt(kL * kL - s * s);
  InitialConditionSpec ic;
  ic.coordinates = Vec::Zero(c.model.num_coordinates());
  SetBodyPose(c.model, c.crank, Vec2::Zero(), th, &ic.coordinates);
  SetBodyPose(c.model, c.rod, Vec2(kR * std::cos(th), kR * std::sin(th)),
              std::atan2(kOffset - kR * std::sin(th), x - kR * std::cos(th)), &ic.coordinates);
  SetBodyPose(c.model, c.slider, Vec2(x, kOffset), 0.0, &ic.coordinates);
  return ic;
}

std::shared_ptr<const fem::ReducedRod> SteelRod(int elements, fem::ReductionMethod method,
                                                int modes) {
  fem::RodSpec rod;
  rod.material = fem::MaterialByName("steel");
  rod.section.thickness = 6.35e-3;
  rod.section.height = 19.05e-3;
  rod.length = kL;
  rod.num_elements = elements;
  return std::make_shared<const fem::ReducedRod>(
      fem::Reduce(rod, fem::MechanismReduction(rod, method, modes)));
}

void Run(const std::string& label, const Crank& c, double t_end, double rel_tol,
         LinearSolverKind solver = LinearSolverKind::kAuto) {
  RunData data(c.model);
  SimulationOptions opt;
  opt.t_end = t_end;
  opt.sample_rate = 1e5;
  opt.integrator.rel_tol = rel_tol;
  opt.integrator.abs_tol = 1e-2 * rel_tol;
  opt.integrator.linear_solver = solver;
  opt.integrator.time_calls = true;  // the time shares below
  const int ix = c.model.coordinate(c.slider, kX);
  // A realistic observer: slider position/velocity/acceleration and driver torque per sample.
  std::vector<double> x, xd, xdd, torque;
  const size_t n = static_cast<size_t>(t_end * opt.sample_rate) + 2;
  x.reserve(n);
  xd.reserve(n);
  xdd.reserve(n);
  torque.reserve(n);
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    x.push_back(s.coordinate(ix));
    xd.push_back(s.velocity(ix));
    xdd.push_back(s.acceleration(ix));
    torque.push_back(s.Driver(c.driver).torque);
  };
  const SimulationStatus st = Simulate(c.model, &data, Guess(c), opt, cb);
  const IntegratorStats& s = st.stats;
  const double w = st.wall_seconds;
  const double other =
      w - s.residual_seconds - s.jacobian_seconds - s.linear_solve_seconds - st.output_seconds;
  std::printf("%s\n", label.c_str());
  std::printf("  unknowns %d, solver %s, rel_tol %.0e, status %s\n", c.model.size(),
              ToString(st.linear_solver), rel_tol, ToString(st.outcome));
  std::printf("  simulated %.3f s, wall %.4f s, real-time factor %.1f\n", t_end, w, t_end / w);
  std::printf(
      "  steps %ld, residuals %ld, Jacobians %ld, Newton iterations %ld, "
      "error-test failures %ld, samples %ld\n",
      s.steps, s.residual_evaluations, s.jacobian_evaluations, s.nonlinear_iterations,
      s.error_test_failures, st.num_samples);
  std::printf(
      "  time share: residual %.1f %%, Jacobian %.1f %%, linear solve %.1f %%, "
      "output %.1f %%, other (IDA internals) %.1f %%\n",
      100 * s.residual_seconds / w, 100 * s.jacobian_seconds / w, 100 * s.linear_solve_seconds / w,
      100 * st.output_seconds / w, 100 * other / w);
  std::printf("  per step: %.2f us; per sample (output): %.3f us\n", 1e6 * w / s.steps,
              1e6 * st.output_seconds / std::max(1L, st.num_samples));
  std::fflush(stdout);
}

// Usage: bench_mb_rigid_crank [rigid|flexible|full|all] (default all).
int Main(const std::string& which) {
  const double revolution = 2.0 * std::numbers::pi / kOmega;
  const bool all = which == "all";
  if (all || which == "rigid")
    Run("rigid slider-crank, 10 revolutions at 200 rpm, 100 kHz output", Build(nullptr),
        10.0 * revolution, 1e-6);
  if (all || which == "flexible")
    Run("flexible slider-crank (Craig-Bampton, 8 modes, band damping), 4 s at 100 kHz",
        Build(SteelRod(20, fem::ReductionMethod::kCraigBampton, 8)), 4.0, 1e-6);
  if (all || which == "flexible")
    Run("  same at rel_tol 1e-7", Build(SteelRod(20, fem::ReductionMethod::kCraigBampton, 8)), 4.0,
        1e-7);
  if (all || which == "full") {
    const Crank full = Build(SteelRod(40, fem::ReductionMethod::kFull, 0));
    Run("full-FE rod (40 elements), 0.01 s, dense LU", full, 0.01, 1e-6, LinearSolverKind::kDense);
    Run("full-FE rod (40 elements), 0.01 s, KLU", full, 0.01, 1e-6, LinearSolverKind::kKlu);
  }
  return 0;
}

}  // namespace
}  // namespace flexrod::multibody

int main(int argc, char** argv) { return flexrod::multibody::Main(argc > 1 ? argv[1] : "all"); }
