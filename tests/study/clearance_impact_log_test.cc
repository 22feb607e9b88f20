// tests/study/clearance_impact_log_test.cc — the impact log (study/impact_log.h) recovers the
// contact events of a sampled record. Synthetic record with an exact answer: penetration
// δ(t) = A sin(ω(t − t0)) (contact on every other half period, T = π/ω), a hysteresis force
// F = kδ(1 + Dδ̇/v₀) with v₀ = Aω, whose loop dissipates ∫F δ̇ dt = (2/3) k D A² per impact
// (∫₀^T sin(ωt) cos²(ωt) dt = 2/(3ω)); onset times t0 + 2kT, duration T, peak penetration A,
// approach velocity Aω, peak force from the formula. The record ends inside a contact, which is
// logged as incomplete.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "study/impact_log.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "common/error.h"
#include "study/signals.h"

namespace flexrod::study {
namespace {

constexpr double kPi = std::numbers::pi;

struct Synthetic {
  double A = 1e-5, T = 1e-4, t0 = 10.3e-6, k = 1e8, D = 0.5;
  double rate = 1e6;        // 100 samples per contact
  double crank_speed = 20;  // [rad/s]
  double omega() const { return kPi / T; }
  double v0() const { return A * omega(); }
  double Delta(double t) const { return A * std::sin(omega() * (t - t0)); }
  double Rate(double t) const { return A * omega() * std::cos(omega() * (t - t0)); }
  double Force(double t) const {
    const double d = Delta(t);
    return d > 0.0 ? std::max(0.0, k * d * (1.0 + D * Rate(t) / v0())) : 0.0;
  }
  /// Per impact: the hysteresis loop ∮F dδ.
  double LoopEnergy() const { return 2.0 / 3.0 * k * D * A * A; }
  /// max over a loading half of kA sin u (1 + D cos u).
  double PeakForce() const {
    // d/du [sin u + D sin u cos u] = cos u + D cos 2u = 0 → 2D c² + c − D = 0.
    const double c = (-1.0 + std::sqrt(1.0 + 8.0 * D * D)) / (4.0 * D);
    const double s = std::sqrt(1.0 - c * c);
    return k * A * s * (1.0 + D * c);
  }
  TimeSeries Record(std::size_t n, bool with_dissipation) const {
    TimeSeries ts(rate, 0.0);
    std::vector<double> d(n), f(n), r(n), th(n), p(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = ts.time(i);
      d[i] = Delta(t);
      r[i] = Rate(t);
      f[i] = Force(t);
      th[i] = 3.0 + crank_speed * t;
      p[i] = d[i] > 0.0 ? f[i] * r[i] - k * d[i] * r[i] : 0.0;  // the damping power
    }
    ts.AddChannel("penetration", "m", d);
    ts.AddChannel("contact_normal_force", "N", f);
    ts.AddChannel("penetration_rate", "m/s", r);
    ts.AddChannel("crank_angle", "rad", th);
    if (with_dissipation) ts.AddChannel("contact_dissipation", "W", p);
    return ts;
  }
};

TEST(ImpactLog, RecoversOnsetDurationPeaksAndLoopEnergyOfASyntheticRecord) {
  const Synthetic s;
  // Contacts start at t0, t0 + 2T, t0 + 4T; the record ends at 4.5T, inside the third.
  const std::size_t n = static_cast<std::size_t>(4.5 * s.T * s.rate);
  for (bool with_dissipation : {false, true}) {
    SCOPED_TRACE(with_dissipation ? "dissipation channel" : "F·rate");
    const std::vector<Impact> log = FindImpacts(s.Record(n, with_dissipation));
    ASSERT_EQ(log.size(), 3u);
    for (int k = 0; k < 2; ++k) {
      const Impact& im = log[k];
      EXPECT_TRUE(im.complete);
      const double onset = s.t0 + 2.0 * k * s.T;
      // Linear interpolation at a zero of a sine (an inflection point): error ≪ 1 ns.
      EXPECT_NEAR(im.time, onset, 1e-10);
      EXPECT_NEAR(im.duration, s.T, 2e-10);
      EXPECT_NEAR(im.crank_angle, WrapToTwoPi(3.0 + s.crank_speed * onset), 1e-8);
      // Sampled quantities: second order in the sample period (100 samples per contact).
      EXPECT_NEAR(im.approach_velocity, s.v0(), 1e-3 * s.v0());
      EXPECT_NEAR(im.peak_penetration, s.A, 1e-3 * s.A);
      EXPECT_NEAR(im.peak_force, s.PeakForce(), 1e-3 * s.PeakForce());
      EXPECT_NEAR(im.dissipated_energy, s.LoopEnergy(), 1e-3 * s.LoopEnergy());
    }
    EXPECT_FALSE(log[2].complete);
    const ImpactStatistics st = CalcImpactStatistics(log);
    EXPECT_EQ(st.count, 2u);
    EXPECT_EQ(st.incomplete, 1u);
    EXPECT_NEAR(st.total_dissipated_energy, 2.0 * s.LoopEnergy(), 2e-3 * s.LoopEnergy());
    EXPECT_NEAR(st.mean_duration, s.T, 2e-10);
  }
}

TEST(ImpactLog, AnOpenJointHasNoImpactsAndMissingChannelsAreInputErrors) {
  TimeSeries ts(1e5, 0.0);
  ts.AddChannel("penetration", "m", std::vector<double>(100, -1e-4));
  ts.AddChannel("contact_normal_force", "N", std::vector<double>(100, 0.0));
  ts.AddChannel("penetration_rate", "m/s", std::vector<double>(100, 0.0));
  EXPECT_TRUE(FindImpacts(ts).empty());
  const ImpactStatistics st = CalcImpactStatistics({});
  EXPECT_EQ(st.count, 0u);
  EXPECT_EQ(st.max_peak_force, 0.0);
  TimeSeries bad(1e5, 0.0);
  bad.AddChannel("penetration", "m", std::vector<double>(10, 0.0));
  EXPECT_THROW(FindImpacts(bad), InputError);
}

}  // namespace
}  // namespace flexrod::study
