// tests/multibody/failure_test.cc — numerical failures are returned as a status with the
// time reached, the state (norms, worst residual and local-error components named) and a
// hint, and every sample produced before the failure is kept (STYLE.md §12). A root function
// that stays exactly zero after its root (IDA's "root found at and very near t") is not a
// failure: the run re-initialises there and goes on.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "mb_test_util.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

using testing::BuildRigidSliderCrank;
using testing::SliderCrankGuess;
using testing::SliderCrankParams;

// A force element whose force stops being computable after t_break (as a contact law
// whose penetration leaves its validity range would): Evaluate reports a recoverable failure.
class BreaksDownAt final : public ForceElement {
 public:
  explicit BreaksDownAt(double t_break) : t_break_(t_break) {}
  bool Evaluate(double t, const MarkerKinematics&, const MarkerKinematics&, const double*,
                const double*, ElementOutput*) const override {
    return t <= t_break_;
  }
  std::string type_name() const override { return "breaks-down"; }

 private:
  double t_break_;
};

struct Collected {
  std::vector<double> times;
};

SimulationCallbacks Collect(Collected* c) {
  SimulationCallbacks cb;
  cb.on_sample = [c](const SampleView& s) { c->times.push_back(s.t()); };
  return cb;
}

// A crank turning at 20 rad/s about the origin, with `element` between the ground point
// (1 m, 0) and the crank pin (50 mm from the axis).
Mechanism DrivenCrankWith(const std::string& name, std::shared_ptr<ForceElement> element) {
  MechanismBuilder b;
  const BodyId crank = b.AddRigidBody({"crank", 0.5, 1e-4, Vec2(0.025, 0.0)});
  const MarkerId o = b.AddGroundMarker("O", Vec2(0.0, 0.0));
  const MarkerId far = b.AddGroundMarker("far", Vec2(1.0, 0.0));
  const MarkerId c_o = b.AddBodyMarker(crank, "crank.O", Vec2(0.0, 0.0));
  const MarkerId c_a = b.AddBodyMarker(crank, "crank.A", Vec2(0.05, 0.0));
  b.AddRevolute("pivot", o, c_o);
  b.AddConstantSpeedDriver("motor", crank, 0.0, 20.0);
  b.AddForceElement(name, far, c_a, std::move(element));
  return b.Build();
}

TEST(IntegratorFailure, ElementBreakdownReturnsTimeStateHintAndKeepsSamples) {
  const double t_break = 0.05;
  const Mechanism m = DrivenCrankWith("fragile", std::make_shared<BreaksDownAt>(t_break));
  RunData data(m);
  SimulationOptions opt;
  opt.t_end = 0.2;
  opt.sample_rate = 1000.0;
  opt.max_steps = 20000;
  Collected c;
  const SimulationStatus st = Simulate(m, &data, InitialConditionSpec{}, opt, Collect(&c));
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.outcome, SimulationOutcome::kIntegratorFailure) << st.Summary();
  EXPECT_NEAR(st.t_reached, t_break, 1e-3);
  EXPECT_LE(st.t_reached, t_break + 1e-12);
  EXPECT_FALSE(st.message.empty());
  EXPECT_FALSE(st.hint.empty());
  EXPECT_GT(st.norm_velocities, 0.0);
  EXPECT_GE(st.worst_error_index, -1);
  // Samples up to the failure are kept: one per millisecond up to t_reached.
  ASSERT_FALSE(c.times.empty());
  EXPECT_EQ(static_cast<long>(c.times.size()), st.num_samples);
  EXPECT_LE(c.times.back(), st.t_reached + 1e-12);
  EXPECT_EQ(static_cast<long>(c.times.size()),
            static_cast<long>(std::floor(st.t_reached * 1000.0 + 1e-9)) + 1);
  const std::string summary = st.Summary();
  EXPECT_NE(summary.find("hint"), std::string::npos);
}

// Tolerances beyond the doubles' reach are refused as input: rel_tol 1e-17 is below the unit
// round-off, abs_tol 1e-300 overflows the error weights of components at zero.
TEST(IntegratorFailure, TolerancesBeyondDoublePrecisionAreRefused) {
  auto refused_key = [](double rel_tol, double abs_tol) -> std::string {
    IntegratorOptions o;
    o.rel_tol = rel_tol;
    o.abs_tol = abs_tol;
    try {
      o.Validate();
    } catch (const InputError& e) {
      return e.key();
    }
    return "(accepted)";
  };
  EXPECT_EQ(refused_key(1e-17, 1e-8), "integrator.rel_tol");
  EXPECT_EQ(refused_key(1e-6, 1e-300), "integrator.abs_tol");
  EXPECT_EQ(refused_key(1e-14, 1e-20), "(accepted)");
}

// The tightest tolerances accepted, 1e-14 / 1e-20: the slider-crank does not get to 0.1 s within
// 5000 steps, and the failure is reported with its time, state and a hint, keeping the samples.
TEST(IntegratorFailure, AbsurdToleranceIsReportedWithAHint) {
  SliderCrankParams P;
  auto sc = BuildRigidSliderCrank(P);
  RunData data(sc.model);
  SimulationOptions opt;
  opt.t_end = 0.1;
  opt.sample_rate = 1000.0;
  opt.integrator.rel_tol = 1e-14;
  opt.integrator.abs_tol = 1e-20;
  opt.max_steps = 5000;
  Collected c;
  const SimulationStatus st = Simulate(sc.model, &data, SliderCrankGuess(sc, P), opt, Collect(&c));
  ASSERT_FALSE(st.ok());
  EXPECT_LT(st.t_reached, opt.t_end);
  EXPECT_FALSE(st.hint.empty());
  EXPECT_GE(c.times.size(), 1u);  // the t = 0 sample at least
  EXPECT_GT(st.norm_coordinates, 0.0);
  EXPECT_FALSE(st.worst_residual_variable.empty()) << st.Summary();
}

TEST(IntegratorFailure, StopFlagEndsTheRunAtTheNextStepAndKeepsSamples) {
  SliderCrankParams P;
  auto sc = BuildRigidSliderCrank(P);
  RunData data(sc.model);
  SimulationOptions opt;
  opt.t_end = 1.0;
  opt.sample_rate = 1e4;
  std::atomic<bool> stop{false};
  opt.stop = &stop;
  Collected c;
  SimulationCallbacks callbacks = Collect(&c);
  callbacks.on_sample = [&, record = callbacks.on_sample](const SampleView& s) {
    record(s);
    if (s.t() >= 0.25) stop = true;  // the caller asks to stop (Ctrl-C) a quarter in
  };
  const SimulationStatus st = Simulate(sc.model, &data, SliderCrankGuess(sc, P), opt, callbacks);
  EXPECT_EQ(st.outcome, SimulationOutcome::kInterrupted);
  EXPECT_STREQ(ToString(st.outcome), "interrupted");
  EXPECT_GE(st.t_reached, 0.25);
  EXPECT_LT(st.t_reached, 0.3);  // one step after the flag, not the whole second
  EXPECT_EQ(static_cast<long>(c.times.size()),
            static_cast<long>(std::floor(st.t_reached * 1e4 + 1e-9)) + 1);
}

/// The rigid slider-crank for 1 s at 10 kHz with a budget set by `limit`: the run stops as
/// `expected`, with the samples up to where it stopped.
SimulationStatus RunOutOfBudget(const std::function<void(SimulationOptions*)>& limit,
                                SimulationOutcome expected) {
  SliderCrankParams P;
  auto sc = BuildRigidSliderCrank(P);
  RunData data(sc.model);
  SimulationOptions opt;
  opt.t_end = 1.0;
  opt.sample_rate = 1e4;
  limit(&opt);
  Collected c;
  const SimulationStatus st = Simulate(sc.model, &data, SliderCrankGuess(sc, P), opt, Collect(&c));
  EXPECT_EQ(st.outcome, expected);
  EXPECT_GT(st.t_reached, 0.0);
  EXPECT_LT(st.t_reached, 1.0);
  EXPECT_EQ(static_cast<long>(c.times.size()),
            static_cast<long>(std::floor(st.t_reached * 1e4 + 1e-9)) + 1);
  return st;
}

TEST(IntegratorFailure, StepBudgetStopsTheRunAndKeepsSamples) {
  const SimulationStatus st = RunOutOfBudget([](SimulationOptions* o) { o->max_steps = 40; },
                                             SimulationOutcome::kStepLimit);
  EXPECT_EQ(st.stats.steps, 40);
}

// A deadline already passed stops the run after its first step.
TEST(IntegratorFailure, WallClockBudgetStopsTheRunAndKeepsSamples) {
  const SimulationStatus st =
      RunOutOfBudget([](SimulationOptions* o) { o->deadline = std::chrono::steady_clock::now(); },
                     SimulationOutcome::kWallTimeLimit);
  EXPECT_STREQ(ToString(st.outcome), "wall-time-limit");
  EXPECT_NE(st.hint.find("sim.max_wall_time"), std::string::npos) << st.hint;
  EXPECT_EQ(st.stats.steps, 1);
}

// A root function that reaches zero at t_graze and stays exactly zero afterwards (a contact
// that grazes: penetration 0 with rate 0). IDA returns the root, then refuses to go on
// (IDA_ILL_INPUT, "Root found at and very near t"); Simulate re-initialises there, and IDA's
// start-up root check deactivates the vanished function until it moves away from zero.
class GrazesAt final : public ForceElement {
 public:
  explicit GrazesAt(double t_graze) : t_graze_(t_graze) {}
  int num_roots() const override { return 1; }
  bool Evaluate(double, const MarkerKinematics&, const MarkerKinematics&, const double*,
                const double*, ElementOutput*) const override {
    return true;  // no force
  }
  void Roots(double t, const MarkerKinematics&, const MarkerKinematics&, const double*,
             const double*, double* g) const override {
    g[0] = std::min(0.0, t - t_graze_);
  }
  std::string type_name() const override { return "grazes"; }

 private:
  double t_graze_;
};

TEST(IntegratorFailure, RootThatStaysZeroIsPassedByReinitialising) {
  const Mechanism m = DrivenCrankWith("grazing", std::make_shared<GrazesAt>(0.05));
  RunData data(m);
  SimulationOptions opt;
  opt.t_end = 0.2;
  opt.sample_rate = 1000.0;
  Collected c;
  const SimulationStatus st = Simulate(m, &data, InitialConditionSpec{}, opt, Collect(&c));
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_EQ(st.root_stall_restarts, 1);
  EXPECT_EQ(st.stats.roots_found, 1);
  EXPECT_NEAR(st.t_reached, opt.t_end, 1e-12);
  EXPECT_EQ(static_cast<long>(c.times.size()), 201);  // every millisecond, none lost or repeated
  for (size_t k = 0; k < c.times.size(); ++k) EXPECT_NEAR(c.times[k], 1e-3 * k, 1e-12) << k;
}

// A run whose step control stiff elastic coordinates caught gets a note with the keys a user
// can set (CaughtStepControlNote, which Summary prints): when most of its steps failed the
// error test, or when a fifth or more of them were taken at BDF order 1 (kCaughtOrderOneShare);
// not below, nor for a run too short to tell.
TEST(IntegratorFailure, ACaughtStepControlGivesANoteWithInputKeys) {
  struct Case {
    long steps, error_test_failures, order_one_steps;
    const char* note;  // nullptr: none
  };
  for (const Case& c : {Case{2000, 1500, 0, "error-test failures on most steps (1500 of 2000)"},
                        Case{2000, 900, 0, nullptr},
                        Case{2000, 0, 500, "25 % of the steps at BDF order 1 (500 of 2000)"},
                        Case{2000, 0, 399, nullptr}, Case{999, 600, 900, nullptr}}) {
    SimulationStatus st;
    st.outcome = SimulationOutcome::kCompleted;
    st.stats.steps = c.steps;
    st.stats.error_test_failures = c.error_test_failures;
    st.stats.steps_by_order[1] = c.order_one_steps;
    const std::string note = CaughtStepControlNote(st.stats), text = st.Summary();
    if (c.note == nullptr) {
      EXPECT_EQ(note, "") << c.steps;
      EXPECT_EQ(text.find("note:"), std::string::npos) << text;
      continue;
    }
    EXPECT_EQ(note.find(c.note), 0u) << note;
    EXPECT_NE(text.find("note: " + note), std::string::npos) << text;
    EXPECT_NE(note.find("sim.rel_tol"), std::string::npos) << note;
    EXPECT_NE(note.find("sim.abs_tol"), std::string::npos) << note;
  }
}

// A slider line 0.3 m away from a 0.05 m crank with a 0.2 m rod cannot be assembled.
TEST(IntegratorFailure, ImpossibleAssemblyIsAnInitialConditionFailure) {
  SliderCrankParams P;
  P.e = 0.3;
  auto sc = BuildRigidSliderCrank(P);
  RunData data(sc.model);
  SimulationOptions opt;
  opt.t_end = 0.1;
  Collected c;
  InitialConditionSpec ic;
  ic.coordinates = Vec::Zero(sc.model.num_coordinates());
  SetBodyPose(sc.model, sc.crank, Vec2::Zero(), P.theta0, &ic.coordinates);
  const SimulationStatus st = Simulate(sc.model, &data, ic, opt, Collect(&c));
  EXPECT_EQ(st.outcome, SimulationOutcome::kInitialConditionFailure);
  EXPECT_NE(st.message.find("initial conditions"), std::string::npos) << st.message;
  EXPECT_TRUE(c.times.empty());
}

}  // namespace
}  // namespace flexrod::multibody
