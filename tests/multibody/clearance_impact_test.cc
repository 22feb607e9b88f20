// tests/multibody/clearance_impact_test.cc — a free pin (1 kg) launched from the centre of a
// fixed bush (gravity off) hits the bore once; integrated by the multibody engine (IDA, contact
// onset/separation located by root finding, restart at onset) it reproduces the single-impact
// result of contact::SimulateImpact (RK8(9) at rel. tol. 1e-12) for the same law, mass and
// approach speed: restitution, peak force and contact duration. Laws: hertz and flores (the
// brief), plus hybrid (the default), elasto-plastic (history updated at the located maximum
// penetration) and maxwell (an element state reset at onset).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "clearance_fixture.h"
#include "contact/impact.h"
#include "multibody/clearance_joint.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

using testing::BuildPinInBush;
using testing::PinStart;
using testing::RigJointGeometry;
using testing::RigLaw;

struct ImpactCase {
  std::string law;
  double restitution;
  contact::ParameterMap overrides;
};

void PrintTo(const ImpactCase& c, std::ostream* os) { *os << c.law; }

class ClearanceImpact : public ::testing::TestWithParam<ImpactCase> {};

TEST_P(ClearanceImpact, EngineReproducesTheSingleImpactOfTheContactLayer) {
  const ImpactCase& tc = GetParam();
  const double mass = 1.0, speed = 0.5, c = RigJointGeometry().clearance();
  const contact::NormalLaw law = RigLaw(tc.law, tc.restitution, tc.overrides);
  contact::ImpactOptions io;
  io.num_samples = 50;
  const contact::ImpactResult ref = contact::SimulateImpact(law, mass, speed, io);

  // Launched from the centre along a direction that is not a coordinate axis, so the impact is
  // along the normal n = (cos α, sin α): a 1-D mass–wall impact with the bush held fixed.
  const double alpha = 0.3;
  const Vec2 n(std::cos(alpha), std::sin(alpha));
  const testing::PinInBush p = BuildPinInBush(law, std::nullopt, mass);
  RunData data(p.model);
  const double t_onset = c / speed;
  SimulationOptions opt;
  opt.t_end = t_onset + ref.exit_time + 2e-4;  // well before the pin reaches the far side
  opt.sample_start = t_onset - 2e-6;
  opt.sample_rate = 2e7;  // 0.05 µs: ~4000 samples over the contact
  opt.integrator.rel_tol = 1e-9;
  opt.integrator.abs_tol = 1e-13;
  double peak = 0.0, first_force = -1.0, last_force = -1.0;
  Vec2 v_end = Vec2::Zero();
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    const ClearanceResponse r = CalcClearanceResponse(s, p.joint);
    if (r.normal_force > 0.0) {
      if (first_force < 0.0) first_force = s.t();
      last_force = s.t();
      peak = std::max(peak, r.normal_force);
    }
    v_end = s.Marker(p.pin_centre).velocity;
  };
  const SimulationStatus st =
      Simulate(p.model, &data, PinStart(p, Vec2::Zero(), speed * n, 0.0), opt, cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  const ElementSlot& slot = p.model.element(p.joint);
  const double* memory = data.element_memory.data() + slot.memory_offset;
  EXPECT_EQ(memory[kOnsetCount], 1.0);
  // The onset is located where δ crosses the event band b upwards (ClearanceJoint::EventBand).
  EXPECT_NEAR(memory[kOnsetTime], t_onset + p.element->EventBand() / speed, 1e-13);
  EXPECT_NEAR(memory[kApproachVelocity], speed, 1e-9);

  const double restitution = -v_end.dot(n) / speed;
  EXPECT_NEAR(v_end.dot(Vec2(-n.y(), n.x())), 0.0, 1e-9);  // no tangential velocity created
  // Tolerances: restitution and peak force to 1e-5 relative (integrator tolerance 1e-9, sampled
  // peak at 0.05 µs; observed agreement ≈ 1e-7); duration to 2 sample periods.
  EXPECT_NEAR(restitution, ref.achieved_restitution, 1e-5) << tc.law;
  EXPECT_NEAR(peak, ref.peak_force, 1e-5 * ref.peak_force) << tc.law;
  const double duration = last_force - memory[kOnsetTime];
  EXPECT_NEAR(duration, ref.contact_duration, 2.0 / opt.sample_rate) << tc.law;
  EXPECT_GT(first_force, t_onset - 1e-9);  // no force before the located onset
  ::testing::Test::RecordProperty("restitution", std::to_string(restitution));
  ::testing::Test::RecordProperty("peak_force", std::to_string(peak));
}

INSTANTIATE_TEST_SUITE_P(Laws, ClearanceImpact,
                         ::testing::Values(ImpactCase{"hertz", 1.0, {}},
                                           ImpactCase{"flores", 0.6, {}},
                                           ImpactCase{"hybrid", 0.9, {}},
                                           ImpactCase{"elasto-plastic", 0.7, {}},
                                           ImpactCase{"maxwell", 0.8, {{"damping", 3e4}}}),
                         [](const ::testing::TestParamInfo<ImpactCase>& info) {
                           std::string name = info.param.law;
                           for (char& ch : name) {
                             if (ch == '-') ch = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace flexrod::multibody

namespace flexrod::multibody {
namespace {

// SimulationCallbacks::on_step sees the accepted steps, each located root (the joint's memory
// already updated by OnRoot) and the stop at t_end, in time order with the samples.
TEST(SimulationCallbacks, OnStepSeesTheStepsAndEveryEventInTimeOrderWithTheSamples) {
  const contact::NormalLaw law = testing::RigLaw("hybrid", 0.9);
  const testing::PinInBush p = testing::BuildPinInBush(law, std::nullopt, 1.0);
  RunData data(p.model);
  const double speed = 0.5, t_onset = testing::RigJointGeometry().clearance() / speed;
  SimulationOptions opt;
  opt.t_end = t_onset + 4e-4;
  opt.sample_rate = 1e5;
  std::vector<double> times;
  long step_points = 0, onset_points = 0, separation_points = 0;
  bool was_on = false;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) { times.push_back(s.t()); };
  cb.on_step = [&](const SampleView& s) {
    times.push_back(s.t());
    ++step_points;
    const ClearanceResponse r = CalcClearanceResponse(s, p.joint);
    onset_points += r.contact_flag && r.onset_time == s.t();
    separation_points +=
        was_on && !r.contact_flag && r.kinematics.penetration < 0.0 &&
        std::abs(r.kinematics.penetration + p.element->EventBand()) < 1e-3 * p.element->EventBand();
    was_on = r.contact_flag;
  };
  const SimulationStatus st =
      Simulate(p.model, &data, testing::PinStart(p, Vec2::Zero(), Vec2(speed, 0.0), 0.0), opt, cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_EQ(st.stats.roots_found, 2);  // onset and separation
  EXPECT_EQ(onset_points, 1);
  EXPECT_EQ(separation_points, 1);  // at δ = −b
  // Every step but those a restart discards (at most one per root), and the stop.
  EXPECT_GE(step_points, st.stats.steps - st.stats.roots_found + 1);
  EXPECT_TRUE(std::is_sorted(times.begin(), times.end()));
  EXPECT_DOUBLE_EQ(times.back(), opt.t_end);
}

}  // namespace
}  // namespace flexrod::multibody
