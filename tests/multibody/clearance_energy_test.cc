// tests/multibody/clearance_energy_test.cc — whole runs of a spinning pin bouncing and sliding
// inside a fixed bush (gravity off): with a dissipative normal law and friction the run's energy
// balance (kinetic + contact elastic energy + dissipated, multibody/outputs.h) stays constant to
// the integrator tolerance while the contact removes a large share of the energy; friction opposes
// slip at every sample (F_t v_t ≤ 0, friction dissipation ≥ 0) and the normal dissipation is
// never negative; without friction and with an elastic law, nothing is dissipated. Also: the
// engine's iteration Jacobian, whose contact blocks come from finite differences with the
// joint's fd_scales, matches a central-difference Jacobian of the residual in contact.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "clearance_fixture.h"
#include "multibody/clearance_joint.h"
#include "multibody/dae.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

using testing::BuildPinInBush;
using testing::PinStart;
using testing::RigJointGeometry;
using testing::RigLaw;

struct BounceResult {
  double kinetic0{0.0};
  double worst_balance{0.0};  // max |balance error| [J]
  double dissipated{0.0};     // at the end [J]
  double min_friction_dissipation{0.0};
  double max_friction_power{0.0};  // max F_t v_t (must be ≤ 0)
  double min_normal_dissipation{0.0};
  double max_normal_force{0.0};
  double onsets{0.0};
  long samples_in_contact{0};
  // Largest |difference| between a sample's element potential energy evaluated by Energies()
  // and the one it takes from the clearance response (SampleView::NotePotentialEnergy) [J].
  double potential_memo_difference{0.0};
  double max_element_potential{0.0};  // [J]
  SimulationStatus status;
};

BounceResult Bounce(const contact::NormalLaw& law, std::optional<contact::FrictionLaw> friction,
                    double t_end) {
  const double c = RigJointGeometry().clearance();
  const testing::PinInBush p = BuildPinInBush(law, friction);
  RunData data(p.model);
  SimulationOptions opt;
  opt.t_end = t_end;
  opt.sample_rate = 2e5;
  opt.integrator.rel_tol = 1e-8;
  opt.integrator.abs_tol = 1e-11;
  BounceResult res;
  res.min_friction_dissipation = res.min_normal_dissipation = 1e300;
  res.max_friction_power = -1e300;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    const EnergyReport e = s.Energies();
    if (s.t() == 0.0) res.kinetic0 = e.kinetic;
    res.worst_balance = std::max(res.worst_balance, std::abs(e.balance_error));
    res.dissipated = e.dissipated_elements;
    const ClearanceResponse r = CalcClearanceResponse(s, p.joint);
    res.min_friction_dissipation = std::min(res.min_friction_dissipation, r.friction_dissipation);
    res.max_friction_power =
        std::max(res.max_friction_power, r.friction_force * r.kinematics.slip_velocity);
    res.min_normal_dissipation = std::min(res.min_normal_dissipation, r.normal_dissipation);
    res.max_normal_force = std::max(res.max_normal_force, r.normal_force);
    if (r.in_contact) ++res.samples_in_contact;
    const EnergyReport again = s.Energies();  // now with the response's potential energy
    res.potential_memo_difference = std::max(
        res.potential_memo_difference, std::abs(again.element_potential - e.element_potential));
    res.max_element_potential = std::max(res.max_element_potential, e.element_potential);
  };
  // Oblique launch off-centre with spin: impacts all round the bore, then rolling/sliding.
  res.status =
      Simulate(p.model, &data, PinStart(p, Vec2(0.0, 0.6 * c), Vec2(0.6, 0.1), 30.0), opt, cb);
  res.onsets = data.element_memory[p.model.element(p.joint).memory_offset + kOnsetCount];
  return res;
}

TEST(ClearanceEnergy, BalanceClosesWithDissipativeContactAndFrictionAndFrictionOpposesSlip) {
  for (const char* name : {"flores", "hybrid"}) {
    SCOPED_TRACE(name);
    const BounceResult r =
        Bounce(RigLaw(name, 0.7),
               contact::MakeFrictionLaw("coulomb", {{"friction-coefficient", 0.3}}), 0.04);
    ASSERT_TRUE(r.status.ok()) << r.status.Summary();
    EXPECT_GE(r.onsets, 5.0);                   // many impacts
    EXPECT_GT(r.samples_in_contact, 100);       // and sustained contact
    EXPECT_GT(r.dissipated, 0.2 * r.kinetic0);  // the contact takes a large share of the energy
    // Balance: |error| ≤ 1e-4 of the initial kinetic energy (rel_tol 1e-8; observed ≈ 1e-6),
    // while the contact dissipates > 0.2 of it: a bookkeeping error of 0.05 % of the
    // dissipation would show.
    EXPECT_LE(r.worst_balance, 1e-4 * r.kinetic0)
        << "worst " << r.worst_balance << " J of " << r.kinetic0 << " J";
    EXPECT_GE(r.min_friction_dissipation, 0.0);
    EXPECT_LE(r.max_friction_power, 0.0);
    EXPECT_GE(r.min_normal_dissipation, 0.0);
    // The potential energy a sample's clearance response leaves for its energies is the one
    // the energies would evaluate, to the bit.
    EXPECT_GT(r.max_element_potential, 0.0);
    EXPECT_EQ(r.potential_memo_difference, 0.0);
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.3e", r.worst_balance / r.kinetic0);
    ::testing::Test::RecordProperty(std::string(name) + "_balance_rel", buf);
  }
}

TEST(ClearanceEnergy, ElasticFrictionlessContactDissipatesNothing) {
  const BounceResult r = Bounce(RigLaw("hertz", 1.0), std::nullopt, 0.02);
  ASSERT_TRUE(r.status.ok()) << r.status.Summary();
  EXPECT_GE(r.onsets, 5.0);
  EXPECT_GT(r.max_normal_force, 1e3);
  // The dissipation rate is F − ∂E/∂δ = 0 up to round-off of the two power evaluations.
  EXPECT_LE(std::abs(r.dissipated), 1e-12 * r.kinetic0);
  EXPECT_LE(r.worst_balance, 1e-4 * r.kinetic0);  // observed ≈ 1e-5 (restitution 1: hard impacts)
}

// Central differences of the residual, Richardson-extrapolated, with per-unknown steps on the
// scale of the contact (positions 1e-10 m, velocities 1e-7 m/s, multipliers 1e-4, states
// 1e-12 m, quadratures 1e-8 J).
TEST(ClearanceEnergy, IterationJacobianInContactMatchesCentralDifferences) {
  const double c = RigJointGeometry().clearance();
  const testing::PinInBush p =
      BuildPinInBush(RigLaw("flores", 0.7), contact::MakeFrictionLaw("lugre"));
  RunData data(p.model);
  const Vec2 n(std::cos(0.9), std::sin(0.9));
  const ConsistentState s0 = ComputeConsistentState(
      p.model, &data, 0.0, PinStart(p, (c + 4e-6) * n, Vec2(0.2, 0.3), 25.0));
  ASSERT_EQ(data.element_memory[p.model.element(p.joint).memory_offset + kContactFlag], 1.0);
  Vec y = s0.y, yp = s0.yp;
  const int zi = p.model.z_offset();  // the LuGre state: off its rest value
  y(zi) = 1.5e-6;
  const double cj = 2e5, t = 0.0;
  const Mat J = CalcJacobian(p.model, &data, t, cj, y, yp);
  const int N = p.model.size(), np = p.model.num_coordinates();
  auto step = [&](int i) {
    if (i < np) return 1e-10;
    if (i < 2 * np) return 1e-7;
    if (i < zi) return 1e-4;
    if (i < p.model.quadrature_offset()) return 1e-12;
    return 1e-8;
  };
  double worst = 0.0;
  for (int i = 0; i < N; ++i) {
    auto central = [&](double h) {
      Vec y1 = y, y2 = y, yp1 = yp, yp2 = yp;
      y1(i) += h;
      y2(i) -= h;
      yp1(i) += cj * h;  // d/dy + cj d/dẏ in one sweep: ẏ moves with cj·Δy
      yp2(i) -= cj * h;
      return Vec(
          (CalcResidual(p.model, &data, t, y1, yp1) - CalcResidual(p.model, &data, t, y2, yp2)) /
          (2.0 * h));
    };
    const double h = step(i);
    const Vec fd = (4.0 * central(0.5 * h) - central(h)) / 3.0;
    const double scale = std::max(fd.lpNorm<Eigen::Infinity>(), 1.0);
    const double err = (J.col(i) - fd).lpNorm<Eigen::Infinity>() / scale;
    worst = std::max(worst, err);
    EXPECT_LE(err, 1e-5) << "column " << i << " (" << p.model.VariableName(i) << ")";
  }
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.3e", worst);
  ::testing::Test::RecordProperty("worst_column_error", buf);
}

}  // namespace
}  // namespace flexrod::multibody
