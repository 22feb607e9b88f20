// tests/multibody/mb_composite.h — a mechanism that uses every modelling feature at once
// (rigid and flexible bodies with geometric stiffening and modal damping, all joint kinds,
// all driver kinds, all built-in force elements, gravity, and a user element with states,
// memory and roots), for the Jacobian, sparsity and allocation tests; plus a Maxwell-type
// user element.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cmath>
#include <memory>
#include <random>

#include "mb_test_util.h"
#include "multibody/force_element.h"
#include "multibody/mechanism.h"

namespace flexrod::multibody::testing {

/// Maxwell link (spring k in series with dashpot c) along the marker line: state z = force
/// (tension), ż = k L̇ − (k/c) z, F_i = z e, F_j = −z e, dissipation z²/c, stored z²/(2k).
/// One root L − L_trigger; OnRoot records L̇ into memory[0] and asks for a restart.
class MaxwellLink final : public ForceElement {
 public:
  MaxwellLink(double k, double c, double trigger) : k_(k), c_(c), trigger_(trigger) {}
  int num_states() const override { return 1; }
  int num_memory() const override { return 1; }
  int num_roots() const override { return 1; }
  bool Evaluate(double /*t*/, const MarkerKinematics& i, const MarkerKinematics& j, const double* z,
                const double* /*memory*/, ElementOutput* out) const override {
    const Vec2 d = j.position - i.position;
    const double L = d.norm();
    if (!(L > 1e-12)) return false;
    const Vec2 e = d / L;
    const double Ld = e.dot(j.velocity - i.velocity);
    out->force_i = z[0] * e;
    out->force_j = -z[0] * e;
    out->state_rates[0] = k_ * Ld - (k_ / c_) * z[0];
    out->dissipation = z[0] * z[0] / c_;
    return true;
  }
  double PotentialEnergy(const MarkerKinematics&, const MarkerKinematics&, const double* z,
                         const double*) const override {
    return 0.5 * z[0] * z[0] / k_;
  }
  void Roots(double, const MarkerKinematics& i, const MarkerKinematics& j, const double*,
             const double*, double* g) const override {
    g[0] = (j.position - i.position).norm() - trigger_;
  }
  bool OnRoot(int, int, double, const MarkerKinematics& i, const MarkerKinematics& j, const double*,
              double* memory) const override {
    const Vec2 d = j.position - i.position;
    memory[0] = d.normalized().dot(j.velocity - i.velocity);
    return true;
  }
  FiniteDifferenceScales fd_scales() const override {
    FiniteDifferenceScales s;
    s.length = 1e-2;
    s.speed = 1e-2;
    return s;
  }
  double StateScale(int) const override { return 10.0; }
  std::string type_name() const override { return "maxwell-link"; }

 private:
  double k_, c_, trigger_;
};

struct CompositeModel {
  Mechanism model;
  std::shared_ptr<fem::ReducedRod> rod;
};

/// The composite with the rod's damping given (default: modal ratios); Rayleigh damping with
/// β > 0 and the geometric stiffening adds the Kelvin–Voigt damping of the second-order strains.
/// The rod (n = 4, 3 elements, 3 elongation fields) takes the modal strain kernel unless told.
inline CompositeModel BuildComposite(
    bool stiffening = true, DampingSpec damping = DampingSpec::ModalRatio({0.02, 0.05, 0.1, 0.3}),
    FlexibleBodySpec::StrainKernel kernel = FlexibleBodySpec::StrainKernel::kAuto) {
  CompositeModel out;
  out.rod = MakeSyntheticRod(4, 12, 7);
  MechanismBuilder b;
  const BodyId crank = b.AddRigidBody({"crank", 0.6, 2e-4, Vec2(0.02, 0.003)});
  FlexibleBodySpec fs;
  fs.name = "rod";
  fs.rod = out.rod;
  fs.damping = damping;
  fs.geometric_stiffening = stiffening;
  fs.strain_kernel = kernel;
  const BodyId rod = b.AddFlexibleBody(fs);
  const BodyId slider = b.AddRigidBody({"slider", 0.4, 1e-4, Vec2(0.0, 0.0)});
  const BodyId welded = b.AddRigidBody({"welded", 0.1, 3e-5, Vec2(0.01, -0.004)});
  const BodyId fixed = b.AddRigidBody({"fixed", 0.2, 5e-5, Vec2(0.0, 0.0)});
  const BodyId pend = b.AddRigidBody({"pendulum", 0.3, 4e-4, Vec2(0.05, 0.0)});
  const BodyId wheel = b.AddRigidBody({"wheel", 0.5, 1e-3, Vec2(0.0, 0.0)});
  const MarkerId o = b.AddGroundMarker("O", Vec2(0.0, 0.0));
  const MarkerId guide = b.AddGroundMarker("guide", Vec2(0.0, 0.01), 0.05);
  const MarkerId anchor = b.AddGroundMarker("anchor", Vec2(0.1, 0.15));
  const MarkerId pend_pivot = b.AddGroundMarker("pend.pivot", Vec2(-0.1, 0.0));
  const MarkerId wheel_pivot = b.AddGroundMarker("wheel.pivot", Vec2(0.3, 0.2));
  const MarkerId c_o = b.AddBodyMarker(crank, "crank.O", Vec2(0.0, 0.0));
  const MarkerId c_a = b.AddBodyMarker(crank, "crank.A", Vec2(0.05, 0.0));
  const MarkerId r_a = b.AddNodeMarker(rod, "rod.A", 0, Vec2(0.001, -0.002));
  const MarkerId r_b = b.AddNodeMarker(rod, "rod.B", 5, Vec2(0.0, 0.003), 0.1);
  const MarkerId r_c = b.AddNodeMarker(rod, "rod.C", 9);
  const MarkerId r_f = b.AddBodyMarker(rod, "rod.frame", Vec2(0.02, 0.0));
  const MarkerId s_b = b.AddBodyMarker(slider, "slider.B", Vec2(0.0, 0.0));
  const MarkerId s_w = b.AddBodyMarker(slider, "slider.W", Vec2(0.01, 0.02), 0.2);
  const MarkerId w_w = b.AddBodyMarker(welded, "welded.W", Vec2(-0.01, 0.0), -0.1);
  const MarkerId p_o = b.AddBodyMarker(pend, "pend.O", Vec2(0.0, 0.0));
  const MarkerId p_t = b.AddBodyMarker(pend, "pend.tip", Vec2(0.1, 0.0));
  const MarkerId w_o = b.AddBodyMarker(wheel, "wheel.O", Vec2(0.0, 0.0));
  const MarkerId f_m = b.AddBodyMarker(fixed, "fixed.M", Vec2(0.02, 0.01), 0.3);
  b.AddRevolute("pivot", o, c_o);
  b.AddRevolute("big_end", c_a, r_a);
  b.AddRevolute("small_end", r_b, s_b);
  PrismaticSpec ps;
  ps.name = "guide";
  ps.marker_i = guide;
  ps.marker_j = s_b;
  ps.relative_angle = -0.05;
  ps.axis = Vec2(1.0, 0.1);
  ps.damping = 3.0;
  ps.friction_force = 2.0;
  ps.friction_regularisation_speed = 0.5;
  b.AddPrismatic(ps);
  b.AddWeld("weld", s_w, w_w, 0.3);
  // A prismatic joint between two moving bodies (guide on the pendulum, slider on the
  // flexible rod): over-constrains the model, which the derivative checks do not mind.
  PrismaticSpec p2;
  p2.name = "prism2";
  p2.marker_i = p_t;
  p2.marker_j = r_c;
  p2.axis = Vec2(0.3, 1.0);
  p2.relative_angle = 0.7;
  b.AddPrismatic(p2);
  b.AddGroundJoint("ground", fixed, Vec2(0.2, -0.1), 0.4);
  b.AddRevolute("pend.pin", pend_pivot, p_o);
  b.AddRevolute("wheel.pin", wheel_pivot, w_o);
  b.AddConstantSpeedDriver("motor", crank, 0.3, 20.0);
  b.AddSpeedProfileDriver("profile", wheel, 0.1, {0.0, 0.5, 1.0}, {0.0, 10.0, 5.0});
  DcMotorSpec dc;
  dc.stall_torque = 2.0;
  dc.no_load_speed = 300.0;
  dc.ratio = 3.0;
  dc.flywheel_inertia = 1e-3;
  dc.rotor_inertia = 1e-5;
  b.AddDcMotorDriver("dc", pend, dc);
  b.AddSpringDamper("spring", anchor, p_t, 500.0, 2.0, 0.1);
  b.AddRotationalSpringDamper("torsion", f_m, r_f, 20.0, 0.3, 0.2);
  b.AddForceElement("maxwell", r_c, p_t, std::make_shared<MaxwellLink>(2e3, 5.0, 0.3));
  b.AddSpringDamper("rod.internal", r_a, r_c, 100.0, 1.0, 0.15);  // both markers on one body
  b.SetGravity(Vec2(0.0, -9.81));
  out.model = b.Build();
  return out;
}

/// A random, non-consistent (y, ẏ) with sensible magnitudes for derivative checks.
inline void RandomState(const Mechanism& m, unsigned seed, Vec* y, Vec* yp) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const int N = m.size(), np = m.num_coordinates();
  y->resize(N);
  yp->resize(N);
  for (int i = 0; i < N; ++i) {
    (*y)(i) = U(gen);
    (*yp)(i) = U(gen);
  }
  for (const Body& b : m.bodies()) {
    (*y)(b.coordinate(kX)) *= 0.2;
    (*y)(b.coordinate(kY)) *= 0.2;
    for (int k = 0; k < b.num_modes; ++k) {
      (*y)(b.coordinate(kFirstMode + k)) *= 0.02;
      (*y)(np + b.coordinate(kFirstMode + k)) *= 2.0;
    }
  }
  y->segment(m.lambda_offset(), m.num_constraints()) *= 50.0;
  y->segment(m.mu_offset(), m.num_constraints()) *= 1e-3;
}

}  // namespace flexrod::multibody::testing
