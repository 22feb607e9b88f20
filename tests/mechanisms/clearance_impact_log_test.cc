// tests/mechanisms/clearance_impact_log_test.cc — the impact log (mechanisms/impact_log.h) is built
// from the located contact events and the solution points between them.
//  * Synthetic points with an exact answer: penetration δ(t) = A sin(ω(t − t0)) (contact on
//    every other half period, T = π/ω), a hysteresis force F = kδ(1 + Dδ̇/v₀) with v₀ = Aω
//    whose loop dissipates ∫F δ̇ dt = (2/3) k D A² per impact (∫₀^T sin(ωt) cos²(ωt) dt =
//    2/(3ω)); the onsets and separations are offered as event points at their exact times,
//    with irregular points between them. Onset, approach velocity, crank angle and duration
//    are then exact; peaks and energy carry the spacing of the points.
//  * The engine: a free pin hits a fixed bush once (multibody/clearance_fixture.h) and the log
//    reproduces the single impact of contact::SimulateImpact (RK8(9) at 1e-12) although not one
//    output sample falls inside the contact.
//  * The peak search's view of a step (StepInterpolant::ElementAt: the joint's unknowns only)
//    gives the full view's response, also for a bush on a driven, prescribed crank.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <vector>

#include "../multibody/clearance_fixture.h"
#include "common/units.h"
#include "contact/impact.h"
#include "mechanisms/impact_log.h"
#include "signals/signals.h"
#include "tests/test_util.h"

namespace flexrod::study {
namespace {

using flexrod::test::kPi;

struct Synthetic {
  double A = 1e-5, T = 1e-4, t0 = 10.3e-6, k = 1e8, D = 0.5;
  double crank_speed = 20;  // [rad/s]
  double omega() const { return kPi / T; }
  double v0() const { return A * omega(); }
  /// Per impact: the hysteresis loop ∮F dδ.
  double LoopEnergy() const { return 2.0 / 3.0 * k * D * A * A; }
  /// max over a loading half of kA sin u (1 + D cos u).
  double PeakForce() const {
    // d/du [sin u + D sin u cos u] = cos u + D cos 2u = 0 → 2D c² + c − D = 0.
    const double c = (-1.0 + std::sqrt(1.0 + 8.0 * D * D)) / (4.0 * D);
    const double s = std::sqrt(1.0 - c * c);
    return k * A * s * (1.0 + D * c);
  }
  /// The point at t; `contact`, `onsets` and `onset_time` as the joint would hold them.
  ContactPoint Point(double t, bool contact, long onsets, double onset_time) const {
    ContactPoint p;
    p.time = t;
    p.crank_angle = 3.0 + crank_speed * t;
    p.contact = contact;
    p.onsets = onsets;
    p.onset_time = onset_time;
    p.penetration = A * std::sin(omega() * (t - t0));
    p.penetration_rate = A * omega() * std::cos(omega() * (t - t0));
    if (contact) {
      p.normal_force = std::max(0.0, k * p.penetration * (1.0 + D * p.penetration_rate / v0()));
      p.dissipation = p.normal_force * p.penetration_rate - k * p.penetration * p.penetration_rate;
    }
    return p;
  }
  /// Points from t_begin to t_end: irregular spacing (T/100 to T/40), plus the event points.
  std::vector<ContactPoint> Points(double t_begin, double t_end) const {
    std::vector<ContactPoint> out;
    long onsets = 0;
    double onset_time = 0.0;
    bool contact = false;
    // Events at t0 + jT: onsets for even j, separations for odd j.
    int j = 0;
    while (t0 + j * T <= t_begin) ++j;
    if (j % 2 == 1) {  // the record starts inside a contact that began at t0 + (j − 1)T
      contact = true;
      onsets = 1;
      onset_time = t0 + (j - 1) * T;
    }
    double t = t_begin;
    for (int i = 0; t <= t_end; ++i) {
      const double event = t0 + j * T;
      if (event <= t) {
        contact = j % 2 == 0;
        if (contact) {
          ++onsets;
          onset_time = event;
        }
        out.push_back(Point(event, contact, onsets, onset_time));
        ++j;
        continue;
      }
      if (out.empty() || t > out.back().time) out.push_back(Point(t, contact, onsets, onset_time));
      t += T * (0.01 + 0.015 * (0.5 + 0.5 * std::sin(1.7 * i)));
    }
    return out;
  }
};

TEST(ImpactLog,
     OnsetApproachVelocityAndDurationAreExactAtTheEventsPeaksAndEnergyWithinThePointSpacing) {
  const Synthetic s;
  // The record starts at 0.5T inside the first contact (started at t0) and ends at 6.5T inside
  // the fourth; the second and third (onsets t0 + 2T, t0 + 4T) are complete.
  ImpactLogger logger;
  for (const ContactPoint& p : s.Points(0.5 * s.T, 6.5 * s.T)) logger.Observe(p);
  const std::vector<Impact> log = logger.Finish();
  ASSERT_EQ(log.size(), 4u);
  EXPECT_FALSE(log[0].complete);
  EXPECT_NEAR(log[0].time, 0.5 * s.T, 1e-18);
  EXPECT_NEAR(log[0].duration, s.t0 + s.T - 0.5 * s.T, 1e-18);
  EXPECT_FALSE(log[3].complete);
  for (int i = 1; i <= 2; ++i) {
    const Impact& im = log[i];
    EXPECT_TRUE(im.complete);
    const double onset = s.t0 + 2.0 * i * s.T;
    EXPECT_DOUBLE_EQ(im.time, onset);
    EXPECT_NEAR(im.duration, s.T, 1e-18);
    EXPECT_NEAR(im.crank_angle, WrapToTwoPi(3.0 + s.crank_speed * onset), 1e-12);
    EXPECT_NEAR(im.approach_velocity, s.v0(), 1e-12 * s.v0());
    // Points T/100 to T/40 apart: the sampled maximum of a sine is within 1 − cos(π/80) ≈ 8e-4
    // of the peak; the trapezoidal rule is second order (≈ 3e-4 at this spacing).
    EXPECT_NEAR(im.peak_penetration, s.A, 1e-3 * s.A);
    EXPECT_LE(im.peak_penetration, s.A);
    EXPECT_NEAR(im.peak_force, s.PeakForce(), 1e-3 * s.PeakForce());
    EXPECT_NEAR(im.dissipated_energy, s.LoopEnergy(), 1e-3 * s.LoopEnergy());
  }
  const ImpactStatistics st = CalcImpactStatistics(log);
  EXPECT_EQ(st.count, 2u);
  EXPECT_EQ(st.incomplete, 2u);
  EXPECT_NEAR(st.total_dissipated_energy, 2.0 * s.LoopEnergy(), 2e-3 * s.LoopEnergy());
  EXPECT_NEAR(st.mean_duration, s.T, 1e-18);
}

TEST(ImpactLog, AnOpenJointHasNoImpacts) {
  const Synthetic s;
  ImpactLogger logger;
  for (int i = 0; i < 100; ++i) logger.Observe(s.Point(i * 1e-6, false, 7, 0.0));
  EXPECT_TRUE(logger.Finish().empty());
  const ImpactStatistics st = CalcImpactStatistics({});
  EXPECT_EQ(st.count, 0u);
  EXPECT_EQ(st.max_peak_force, 0.0);
}

TEST(ImpactLog, ASingleEngineImpactBetweenTwoSamplesMatchesTheContactLayer) {
  using namespace multibody;
  const double mass = 1.0, speed = 0.5, c = testing::RigJointGeometry().clearance();
  for (const auto& [name, e] : {std::pair<const char*, double>{"hybrid", 0.9}, {"flores", 0.6}}) {
    SCOPED_TRACE(name);
    const contact::NormalLaw law = testing::RigLaw(name, e);
    const contact::ImpactResult ref = contact::SimulateImpact(law, mass, speed);
    const double alpha = 0.3;
    const Vec2 n(std::cos(alpha), std::sin(alpha));
    const testing::PinInBush p = testing::BuildPinInBush(law, std::nullopt, mass);
    RunData data(p.model);
    const double t_onset = c / speed;  // 1 ms
    SimulationOptions opt;
    opt.t_end = t_onset + 4e-4;
    opt.sample_start = 2.5e-4;
    opt.sample_rate = 2e3;  // samples at 0.75 ms and 1.25 ms; the contacts last 0.12 and 0.2 ms
    opt.integrator.rel_tol = 1e-9;
    opt.integrator.abs_tol = 1e-13;
    ImpactLogger logger;
    long samples_in_contact = 0;
    SimulationCallbacks cb;
    cb.on_sample = [&](const SampleView& s) {
      const ClearanceResponse r = CalcClearanceResponse(s, p.joint);
      samples_in_contact += r.normal_force > 0.0;
      logger.Observe(MakeContactPoint(s.t(), 0.0, r));
    };
    cb.on_step = [&](const SampleView& s) {
      logger.Observe(MakeContactPoint(s.t(), 0.0, CalcClearanceResponse(s, p.joint)));
    };
    const SimulationStatus st =
        Simulate(p.model, &data, testing::PinStart(p, Vec2::Zero(), speed * n, 0.0), opt, cb);
    ASSERT_TRUE(st.ok()) << st.Summary();
    EXPECT_EQ(samples_in_contact, 0);
    const std::vector<Impact> log = logger.Finish();
    ASSERT_EQ(log.size(), 1u);
    const Impact& im = log[0];
    EXPECT_TRUE(im.complete);
    // Onset and separation are located where δ crosses ±b (ClearanceJoint::EventBand).
    const double b = p.element->EventBand();
    EXPECT_NEAR(im.time, t_onset + b / speed, 1e-13);
    EXPECT_NEAR(im.approach_velocity, speed, 1e-9);
    EXPECT_NEAR(im.duration, ref.exit_time, 4.0 * b / speed + 1e-6 * ref.exit_time);
    // Peaks over the integrator's steps (about 400 in the run at rel_tol 1e-9; observed within
    // 3e-5); the energy is the mass's loss ½m(v₀² − v_out²) of the reference (observed 6e-5).
    EXPECT_NEAR(im.peak_force, ref.peak_force, 1e-4 * ref.peak_force);
    EXPECT_LE(im.peak_force, ref.peak_force * (1.0 + 1e-7));
    EXPECT_NEAR(im.peak_penetration, ref.peak_penetration, 1e-4 * ref.peak_penetration);
    EXPECT_NEAR(im.dissipated_energy, ref.dissipated_energy, 3e-4 * ref.dissipated_energy);
  }
}

TEST(ImpactLog, LocatedPeaksMatchTheContactLayerWhereTheStepsMissThem) {
  // The same single impact at rel_tol 1e-6 (about 40 steps in the contact), at six approach
  // speeds: the peak located inside the steps (LocateImpactPeaks) agrees with the RK8(9)
  // reference to 2e-6, for the force and the penetration, at every speed; the largest force at
  // a solution point misses it by more than 1e-4 at one speed at least. How far the nearest
  // solution point falls from the peak depends on where the steps land: measured 6.1e-5 to
  // 1.8e-4 over these speeds, three of them above 1e-4. The test used one speed (0.5 m/s), and
  // a change of the Newton iteration that moved the steps took its miss to 4e-5.
  using namespace multibody;
  const double mass = 1.0, c = testing::RigJointGeometry().clearance();
  const contact::NormalLaw law = testing::RigLaw("hybrid", 0.9);
  const Vec2 n(std::cos(0.3), std::sin(0.3));
  const testing::PinInBush p = testing::BuildPinInBush(law, std::nullopt, mass);
  double largest_miss = 0.0;  // of the solution points' peak force, over the speeds
  for (const double speed : {0.3, 0.35, 0.45, 0.5, 0.6, 0.7}) {
    SCOPED_TRACE("approach speed " + std::to_string(speed) + " m/s");
    const contact::ImpactResult ref = contact::SimulateImpact(law, mass, speed);
    SimulationOptions opt;
    opt.t_end = c / speed + 4e-4;
    opt.sample_rate = 1e3;  // no sample inside the 0.12 ms contact
    opt.integrator.rel_tol = 1e-6;
    opt.integrator.abs_tol = 1e-12;
    for (const bool locate : {false, true}) {
      SCOPED_TRACE(locate ? "located" : "solution points");
      RunData data(p.model);
      ImpactLogger logger;
      SimulationCallbacks cb;
      // The search's response at its step's end (LocateImpactPeaks's result) is the solution
      // point's, bit for bit: run.cc observes the one in place of the other.
      std::optional<ClearanceResponse> end;
      double end_time = 0.0;
      int ends = 0;
      cb.on_step = [&](const SampleView& s) {
        const ClearanceResponse r = CalcClearanceResponse(s, p.joint);
        if (end && end_time == s.t()) {
          EXPECT_EQ(end->normal_force, r.normal_force);
          EXPECT_EQ(end->friction_force, r.friction_force);
          EXPECT_EQ(end->kinematics.penetration, r.kinematics.penetration);
          EXPECT_EQ(end->kinematics.penetration_rate, r.kinematics.penetration_rate);
          EXPECT_EQ(end->dissipation(), r.dissipation());
          EXPECT_EQ(end->onsets, r.onsets);
          ++ends;
        }
        end.reset();
        logger.Observe(MakeContactPoint(s.t(), 0.0, r));
      };
      int compared = 0;  // steps in contact where ElementAt is compared with At
      if (locate) {
        cb.on_step_interval = [&](const StepInterpolant& step) {
          // ElementAt (the peak search's view) evaluates only the joint's unknowns (the pin's,
          // and the held bush's from its prescribed motion): the same response as At at the
          // same time, whatever the buffers held before (here the step's start).
          const double tm = 0.5 * (step.t_begin() + step.t_end());
          (void)step.At(step.t_begin());
          const ClearanceResponse some =
              CalcClearanceResponse(step.ElementAt(tm, p.joint), p.joint);
          const ClearanceResponse all = CalcClearanceResponse(step.At(tm), p.joint);
          EXPECT_EQ(some.normal_force, all.normal_force);
          EXPECT_EQ(some.kinematics.penetration, all.kinematics.penetration);
          EXPECT_EQ(some.kinematics.penetration_rate, all.kinematics.penetration_rate);
          if (all.normal_force > 0.0) ++compared;
          end = LocateImpactPeaks(step, p.joint, &logger);
          end_time = step.t_end();
        };
      }
      const SimulationStatus st =
          Simulate(p.model, &data, testing::PinStart(p, Vec2::Zero(), speed * n, 0.0), opt, cb);
      ASSERT_TRUE(st.ok()) << st.Summary();
      const std::vector<Impact> log = logger.Finish();
      ASSERT_EQ(log.size(), 1u);
      const double force_error = std::abs(log[0].peak_force / ref.peak_force - 1.0);
      const double depth_error = std::abs(log[0].peak_penetration / ref.peak_penetration - 1.0);
      std::printf("%s: peak force %.9g N (reference %.9g N, %.2e), penetration %.2e\n",
                  locate ? "located" : "solution points", log[0].peak_force, ref.peak_force,
                  force_error, depth_error);
      if (locate) {
        EXPECT_GT(compared, 10);
        EXPECT_GT(ends, 10);
        EXPECT_LT(force_error, 2e-6);
        EXPECT_LT(depth_error, 2e-6);
      } else {
        largest_miss = std::max(largest_miss, force_error);
      }
    }
  }
  EXPECT_GT(largest_miss, 1e-4);  // what the located peaks fix
}

// ElementAt evaluates only the joint's unknowns; a body the integrator does not carry (a crank
// turned by a constant-speed driver, eliminated as prescribed) comes from its motion at the
// asked time. The bush rides on such a crank, 50 mm off its axis at 20 rad/s; a free pin starts
// in it with its velocity and soon strikes it. In every step, ElementAt at the step's midpoint
// gives At's clearance response there, after At at the step's start left the bush's stale
// coordinates in the buffers.
TEST(ImpactLog, ElementAtTakesADrivenBodyFromItsMotion) {
  using namespace multibody;
  MechanismBuilder b;
  const BodyId crank = b.AddRigidBody({"crank", 1.0, 1e-3, Vec2::Zero()});
  b.AddRevolute("bearing", b.AddGroundMarker("pivot", Vec2::Zero()),
                b.AddBodyMarker(crank, "axis", Vec2::Zero()));
  b.AddConstantSpeedDriver("drive", crank, 0.0, 20.0);
  const BodyId pin = b.AddRigidBody({"pin", 0.1, 1e-5, Vec2::Zero()});
  const MarkerId bush = b.AddBodyMarker(crank, "bush", Vec2(0.05, 0.0));
  const MarkerId centre = b.AddBodyMarker(pin, "pin-centre", Vec2::Zero());
  const ElementId joint = b.AddForceElement(
      "clearance", bush, centre,
      std::make_shared<const ClearanceJoint>(testing::RigJointGeometry(),
                                             testing::RigLaw("hybrid", 0.9), std::nullopt));
  const Mechanism model = b.Build();
  InitialConditionSpec ic;
  ic.coordinates = Vec::Zero(model.num_coordinates());
  ic.velocities = Vec::Zero(model.num_coordinates());
  SetBodyPose(model, pin, Vec2(0.05, 0.0), 0.0, &ic.coordinates);
  SetBodyVelocity(model, pin, Vec2(0.0, 1.0), 0.0, &ic.velocities);
  SimulationOptions opt;
  opt.t_end = 0.05;
  opt.sample_rate = 1e3;
  RunData data(model);
  int compared = 0, in_contact = 0;
  SimulationCallbacks cb;
  cb.on_step_interval = [&](const StepInterpolant& step) {
    const double tm = 0.5 * (step.t_begin() + step.t_end());
    (void)step.At(step.t_begin());
    const ClearanceResponse some = CalcClearanceResponse(step.ElementAt(tm, joint), joint);
    const ClearanceResponse all = CalcClearanceResponse(step.At(tm), joint);
    EXPECT_EQ(some.kinematics.penetration, all.kinematics.penetration) << tm;
    EXPECT_EQ(some.kinematics.penetration_rate, all.kinematics.penetration_rate) << tm;
    EXPECT_EQ(some.normal_force, all.normal_force) << tm;
    ++compared;
    if (all.normal_force > 0.0) ++in_contact;
  };
  const SimulationStatus st = Simulate(model, &data, ic, opt, cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_GT(compared, 50);
  EXPECT_GT(in_contact, 5);  // the crank's bush does strike the pin
}

TEST(ImpactLog, InteriorMaximumIsLocatedAndAnEndMaximumIsLeftToTheSolutionPoints) {
  auto parabola = [](double t) { return 1.0 - (t - 0.3) * (t - 0.3); };
  const LocatedMaximum m = LocateInteriorMaximum(parabola, 0.0, 1.0);
  EXPECT_NEAR(m.t, 0.3, 1e-7);  // f is flat to round-off within ~sqrt(eps) of its peak
  EXPECT_DOUBLE_EQ(m.value, 1.0);
  // A skewed peak near the end of the step, against a scan of 1e6 points.
  auto skewed = [](double t) { return std::exp(-std::pow(t - 0.8, 2) / 0.09) + 0.1 * t; };
  double t_scan = 0.0;
  for (int i = 0; i <= 1000000; ++i) {
    if (skewed(i * 1e-6) > skewed(t_scan)) t_scan = i * 1e-6;
  }
  int evaluations = 0;
  const LocatedMaximum s = LocateInteriorMaximum(
      [&](double t) {
        ++evaluations;
        return skewed(t);
      },
      0.0, 1.0);
  EXPECT_NEAR(s.t, t_scan, 2e-6);
  EXPECT_GE(s.value, skewed(t_scan) - 1e-12);
  // Brent's parabolic steps: 23 evaluations, where golden section alone took 50.
  std::printf("skewed peak: %d evaluations\n", evaluations);
  EXPECT_LE(evaluations, 25);
  // Monotone: the maximum is an end, a solution point the log sees anyway.
  EXPECT_EQ(LocateInteriorMaximum([](double t) { return t; }, 0.0, 1.0).value,
            -std::numeric_limits<double>::infinity());
  // Only a maximum that could lie above `wanted_above` is searched for. The parabola's three
  // points, 0.91, 0.96, 0.51, bound it by 0.96 + 0.05 + 0.45 = 1.46: it is searched (and its 1.0
  // found) for 0.9 and 1.45; for 1.47 it is out of reach and costs those three evaluations alone.
  EXPECT_DOUBLE_EQ(LocateInteriorMaximum(parabola, 0.0, 1.0, 0.9).value, 1.0);
  EXPECT_DOUBLE_EQ(LocateInteriorMaximum(parabola, 0.0, 1.0, 1.45).value, 1.0);
  evaluations = 0;
  const LocatedMaximum out_of_reach = LocateInteriorMaximum(
      [&](double t) {
        ++evaluations;
        return parabola(t);
      },
      0.0, 1.0, 1.47);
  EXPECT_EQ(out_of_reach.value, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(evaluations, 3);
  // A step a few ulp of t long terminates (a bracket of 1e-9 of it is below t's resolution).
  const double t0 = 2.7935215, t1 = std::nextafter(std::nextafter(t0, 3.0), 3.0);
  (void)LocateInteriorMaximum([&](double t) { return -(t - t0) * (t - t1); }, t0, t1);
}

}  // namespace
}  // namespace flexrod::study
