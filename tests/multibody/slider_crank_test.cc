// tests/multibody/slider_crank_test.cc — the rigid ideal slider-crank built from generic
// parts reproduces the exact kinematics (in-line and offset), keeps its constraints over
// many revolutions, and reports index crossings at the exact times.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mb_test_util.h"
#include "multibody/outputs.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

using testing::BuildRigidSliderCrank;
using testing::SliderCrankExact;
using testing::SliderCrankGuess;
using testing::SliderCrankParams;

struct KinematicErrors {
  double x{0.0}, xd{0.0}, xdd{0.0};              // max |error|
  double x_ref{0.0}, xd_ref{0.0}, xdd_ref{0.0};  // max |exact|
  long samples{0};
};

KinematicErrors RunOneRevolution(const SliderCrankParams& P, double rel_tol, double abs_tol) {
  auto m = BuildRigidSliderCrank(P);
  RunData data(m.model);
  SimulationOptions opt;
  opt.t_start = 0.0;
  opt.t_end = 2.0 * std::numbers::pi / P.omega;  // one revolution
  opt.sample_rate = 2000.0;
  opt.integrator.rel_tol = rel_tol;
  opt.integrator.abs_tol = abs_tol;
  const SliderCrankExact ex{P.r, P.l, P.e, P.omega};
  const int ix = m.model.coordinate(m.slider, kX);
  KinematicErrors err;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    const double th = P.theta0 + P.omega * s.t();
    err.x = std::max(err.x, std::abs(s.coordinate(ix) - ex.x(th)));
    err.xd = std::max(err.xd, std::abs(s.velocity(ix) - ex.xd(th)));
    err.xdd = std::max(err.xdd, std::abs(s.acceleration(ix) - ex.xdd(th)));
    err.x_ref = std::max(err.x_ref, std::abs(ex.x(th)));
    err.xd_ref = std::max(err.xd_ref, std::abs(ex.xd(th)));
    err.xdd_ref = std::max(err.xdd_ref, std::abs(ex.xdd(th)));
    ++err.samples;
  };
  const SimulationStatus st = Simulate(m.model, &data, SliderCrankGuess(m, P), opt, cb);
  EXPECT_TRUE(st.ok()) << st.Summary();
  return err;
}

// Exact formulas in mb_test_util.h (SliderCrankExact). Tolerance: 1e-6 relative to the
// largest value over the revolution, at rel_tol = 1e-10 (brief requirement).
// Slider position, velocity and acceleration within 1e-6 of the exact kinematics (relative to
// their peaks over the revolution).
void ExpectExactKinematics(const KinematicErrors& e) {
  EXPECT_LE(e.x / e.x_ref, 1e-6);
  EXPECT_LE(e.xd / e.xd_ref, 1e-6);
  EXPECT_LE(e.xdd / e.xdd_ref, 1e-6);
  testing::Record("rel_err_x", e.x / e.x_ref);
  testing::Record("rel_err_xd", e.xd / e.xd_ref);
  testing::Record("rel_err_xdd", e.xdd / e.xdd_ref);
}

TEST(RigidSliderCrank, InLineSliderMatchesExactKinematics) {
  SliderCrankParams P;
  P.e = 0.0;
  const KinematicErrors e = RunOneRevolution(P, 1e-10, 1e-12);
  EXPECT_GT(e.samples, 500);
  ExpectExactKinematics(e);
}

TEST(RigidSliderCrank, OffsetSliderMatchesExactKinematics) {
  SliderCrankParams P;
  P.e = 0.02;  // 20 mm offset of the slider line
  const KinematicErrors e = RunOneRevolution(P, 1e-10, 1e-12);
  ExpectExactKinematics(e);
}

// The GGL form enforces position and velocity constraints at every step: over 20
// revolutions the worst constraint violation at the output samples stays below 1e-9 m and
// does not grow (last revolution no worse than 10x the first).
TEST(RigidSliderCrank, ConstraintDriftStaysBelowOneNanometreOverTwentyRevolutions) {
  SliderCrankParams P;
  P.e = 0.01;
  auto m = BuildRigidSliderCrank(P);
  RunData data(m.model);
  SimulationOptions opt;
  const double period = 2.0 * std::numbers::pi / P.omega;
  opt.t_end = 20.0 * period;
  opt.sample_rate = 1000.0;
  opt.integrator.rel_tol = 1e-8;
  opt.integrator.abs_tol = 1e-10;
  double worst = 0.0, first_rev = 0.0, last_rev = 0.0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    const double g = s.ConstraintViolation();
    worst = std::max(worst, g);
    if (s.t() < period) first_rev = std::max(first_rev, g);
    if (s.t() > 19.0 * period) last_rev = std::max(last_rev, g);
  };
  const SimulationStatus st = Simulate(m.model, &data, SliderCrankGuess(m, P), opt, cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_LT(worst, 1e-9);
  EXPECT_LE(last_rev, 10.0 * first_rev + 1e-12);
  testing::Record("max_constraint_violation", worst);
  testing::Record("first_revolution", first_rev);
  testing::Record("last_revolution", last_rev);
}

// θ = θ0 + ωt crosses θ_index + 2πk at t_k = (θ_index + 2πk − θ0)/ω exactly.
TEST(RigidSliderCrank, IndexCrossingsOccurAtExactTimes) {
  SliderCrankParams P;
  auto m = BuildRigidSliderCrank(P);
  RunData data(m.model);
  SimulationOptions opt;
  const double period = 2.0 * std::numbers::pi / P.omega;
  opt.t_end = 3.2 * period;
  opt.sample_rate = 1000.0;
  opt.sample_start = 0.0;
  opt.start_sampling_at_index = true;
  const double theta_index = 1.0;
  opt.index_event = IndexEventSpec{m.crank, theta_index};
  double first_sample = -1.0;
  int index_calls = 0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    if (first_sample < 0.0) first_sample = s.t();
  };
  cb.on_index = [&](const IndexCrossing& c, const SampleView& s) {
    ++index_calls;
    const double th = s.coordinate(m.model.coordinate(m.crank, kTheta));
    EXPECT_NEAR(std::remainder(th - theta_index, 2.0 * std::numbers::pi), 0.0, 1e-8);
    EXPECT_NEAR(c.speed, P.omega, 1e-8);
  };
  const SimulationStatus st = Simulate(m.model, &data, SliderCrankGuess(m, P), opt, cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  const double theta_end = P.theta0 + P.omega * opt.t_end;
  const size_t expected =
      static_cast<size_t>(std::floor((theta_end - theta_index) / (2.0 * std::numbers::pi))) + 1;
  ASSERT_EQ(expected, 4u);
  ASSERT_EQ(st.index_crossings.size(), expected);
  EXPECT_EQ(index_calls, static_cast<int>(expected));
  for (size_t k = 0; k < st.index_crossings.size(); ++k) {
    const double t_exact = (theta_index + 2.0 * std::numbers::pi * k - P.theta0) / P.omega;
    EXPECT_NEAR(st.index_crossings[k].t, t_exact, 1e-9) << "crossing " << k;
    EXPECT_EQ(st.index_crossings[k].revolution, static_cast<long>(k));
  }
  EXPECT_NEAR(first_sample, st.index_crossings[0].t, 1e-12);  // triggered capture
}

// Sampling is decoupled from the step: the number of samples is exactly the number of grid
// points in [t0, t_end], whatever the steps were.
TEST(RigidSliderCrank, OutputIsSampledAtTheFixedRate) {
  SliderCrankParams P;
  auto m = BuildRigidSliderCrank(P);
  RunData data(m.model);
  SimulationOptions opt;
  opt.t_end = 0.05;
  opt.sample_rate = 1e5;
  opt.sample_start = 0.01;
  std::vector<double> times;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) { times.push_back(s.t()); };
  const SimulationStatus st = Simulate(m.model, &data, SliderCrankGuess(m, P), opt, cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  ASSERT_EQ(times.size(), 4001u);  // 0.01 .. 0.05 s inclusive at 10 µs
  for (size_t k = 0; k < times.size(); ++k) EXPECT_NEAR(times[k], 0.01 + 1e-5 * k, 1e-12);
  EXPECT_LT(st.stats.steps, 4000);  // far fewer steps than samples: not step-limited
}

}  // namespace
}  // namespace flexrod::multibody
