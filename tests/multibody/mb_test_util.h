// tests/multibody/mb_test_util.h — shared fixtures of the multibody tests: a slider-crank
// assembled from generic parts (crank revolute to ground, rod revolute to crank, slider
// revolute to rod and prismatic to ground, constant-speed driver) with its exact
// kinematics, and a synthetic fem::ReducedRod built from a random point-mass cloud so the
// FFRF tests do not depend on the fem stage.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <memory>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <utility>

#include "fem/reduced_rod.h"
#include "multibody/mechanism.h"
#include "multibody/simulate.h"

namespace flexrod::multibody::testing {

/// Records a named number on the current test (visible with --gtest_output=xml).
inline void Record(const std::string& key, double value) {
  std::ostringstream os;
  os << std::scientific << std::setprecision(3) << value;
  ::testing::Test::RecordProperty(key, os.str());
}

/// Exact slider kinematics of a slider-crank with crank radius r, rod length l and slider
/// offset e (slider line y = e), crank angle θ = θ0 + ω t at constant ω. From the loop
/// closure x = r cos θ + sqrt(l² − (r sin θ − e)²) by differentiation (e.g. Norton, Design of
/// Machinery, §7 — derived here): with s = r sin θ − e, D = sqrt(l² − s²), ṡ = rω cos θ,
/// s̈ = −rω² sin θ:
///   ẋ = −rω sin θ − s ṡ / D,
///   ẍ = −rω² cos θ − (ṡ² + s s̈)/D − (s ṡ)²/D³.
struct SliderCrankExact {
  double r, l, e, omega;
  double x(double th) const { return r * std::cos(th) + D(th); }
  double xd(double th) const {
    const double s = r * std::sin(th) - e, sd = r * omega * std::cos(th);
    return -r * omega * std::sin(th) - s * sd / D(th);
  }
  double xdd(double th) const {
    const double s = r * std::sin(th) - e, sd = r * omega * std::cos(th);
    const double sdd = -r * omega * omega * std::sin(th), d = D(th);
    return -r * omega * omega * std::cos(th) - (sd * sd + s * sdd) / d -
           (s * sd) * (s * sd) / (d * d * d);
  }
  double D(double th) const {
    const double s = r * std::sin(th) - e;
    return std::sqrt(l * l - s * s);
  }
  /// Rod angle (from the crank pin A to the slider pin B).
  double rod_angle(double th) const {
    return std::atan2(e - r * std::sin(th), x(th) - r * std::cos(th));
  }
};

struct SliderCrankParams {
  double r{0.05}, l{0.2}, e{0.0};
  double omega{200.0 * 2.0 * std::numbers::pi / 60.0};  // 200 rpm
  double theta0{0.3};
  double m_crank{0.5}, m_rod{0.3}, m_slider{0.4};
  double guide_damping{0.0}, guide_friction{0.0};
};

struct SliderCrankModel {
  Mechanism model;
  BodyId crank, rod, slider;
  MarkerId pin_a, pin_b;
  JointId pivot, big_end, small_end, guide;
  DriverId driver;
};

/// Markers, joints, guide and driver of the slider-crank around its three bodies;
/// `rod_markers(b)` adds the rod's big-end and small-end markers.
template <typename RodMarkers>
SliderCrankModel ConnectSliderCrank(MechanismBuilder& b, const SliderCrankParams& P, BodyId crank,
                                    BodyId rod, BodyId slider, RodMarkers rod_markers) {
  const MarkerId o = b.AddGroundMarker("O", Vec2(0.0, 0.0));
  const MarkerId guide_m = b.AddGroundMarker("guide", Vec2(0.0, P.e));
  const MarkerId crank_o = b.AddBodyMarker(crank, "crank.O", Vec2(0.0, 0.0));
  const MarkerId crank_a = b.AddBodyMarker(crank, "crank.A", Vec2(P.r, 0.0));
  const auto [rod_a, rod_b] = rod_markers(b);
  const MarkerId slider_b = b.AddBodyMarker(slider, "slider.B", Vec2(0.0, 0.0));
  SliderCrankModel m{Mechanism(), crank, rod, slider, crank_a, slider_b, {}, {}, {}, {}, {}};
  m.pivot = b.AddRevolute("pivot", o, crank_o);
  m.big_end = b.AddRevolute("big_end", crank_a, rod_a);
  m.small_end = b.AddRevolute("small_end", rod_b, slider_b);
  PrismaticSpec ps;
  ps.name = "guide";
  ps.marker_i = guide_m;
  ps.marker_j = slider_b;
  ps.damping = P.guide_damping;
  ps.friction_force = P.guide_friction;
  m.guide = b.AddPrismatic(ps);
  m.driver = b.AddConstantSpeedDriver("motor", crank, P.theta0, P.omega);
  m.model = b.Build();
  return m;
}

inline SliderCrankModel BuildRigidSliderCrank(const SliderCrankParams& P) {
  MechanismBuilder b;
  const BodyId crank =
      b.AddRigidBody({"crank", P.m_crank, P.m_crank * P.r * P.r / 12.0, Vec2(0.5 * P.r, 0.0)});
  const BodyId rod =
      b.AddRigidBody({"rod", P.m_rod, P.m_rod * P.l * P.l / 12.0, Vec2(0.5 * P.l, 0.0)});
  const BodyId slider = b.AddRigidBody({"slider", P.m_slider, 1e-4, Vec2(0.0, 0.0)});
  return ConnectSliderCrank(b, P, crank, rod, slider, [&](MechanismBuilder& mb) {
    return std::pair{mb.AddBodyMarker(rod, "rod.A", Vec2(0.0, 0.0)),
                     mb.AddBodyMarker(rod, "rod.B", Vec2(P.l, 0.0))};
  });
}

/// Initial guess near the assembled configuration (perturbed so Newton has work to do).
inline InitialConditionSpec SliderCrankGuess(const SliderCrankModel& m, const SliderCrankParams& P,
                                             double perturbation = 1e-3) {
  const SliderCrankExact ex{P.r, P.l, P.e, P.omega};
  InitialConditionSpec ic;
  Vec p = Vec::Zero(m.model.num_coordinates());
  const double th = P.theta0;
  SetBodyPose(m.model, m.crank, Vec2::Zero(), th, &p);
  SetBodyPose(m.model, m.rod, Vec2(P.r * std::cos(th), P.r * std::sin(th)) + Vec2(perturbation, 0),
              ex.rod_angle(th) + perturbation, &p);
  SetBodyPose(m.model, m.slider, Vec2(ex.x(th) - perturbation, P.e), 0.0, &p);
  ic.coordinates = p;
  return ic;
}

/// A steel rod spec: thickness × height = 6.35 × 19.05 mm, in-plane weak axis, length l.
inline fem::RodSpec SteelRodSpec(double length, int elements, double stiffness_factor = 1.0) {
  fem::RodSpec rod;
  rod.material = fem::MaterialByName("steel");
  rod.material.youngs_modulus *= stiffness_factor;
  rod.section.thickness = 6.35e-3;
  rod.section.height = 19.05e-3;
  rod.section.in_plane = fem::BendingAxis::kWeak;
  rod.length = length;
  rod.num_elements = elements;
  return rod;
}

/// SteelRodSpec reduced with fem::Reduce (Craig–Bampton, frame on node 0, interface the last
/// node).
inline std::shared_ptr<const fem::ReducedRod> MakeSteelRod(
    double length, int elements, int modes, double stiffness_factor = 1.0,
    fem::ReductionMethod method = fem::ReductionMethod::kCraigBampton) {
  const fem::RodSpec rod = SteelRodSpec(length, elements, stiffness_factor);
  const fem::ReductionSpec spec = fem::MechanismReduction(rod, method, modes);
  return std::make_shared<const fem::ReducedRod>(fem::Reduce(rod, spec));
}

/// The slider-crank of BuildRigidSliderCrank with the connecting rod replaced by a flexible
/// body (frame = big-end node 0, small end = last node).
inline SliderCrankModel BuildFlexibleSliderCrank(const SliderCrankParams& P,
                                                 std::shared_ptr<const fem::ReducedRod> rod,
                                                 DampingSpec damping = DampingSpec::FrequencyBand(),
                                                 bool stiffening = false) {
  MechanismBuilder b;
  const BodyId crank =
      b.AddRigidBody({"crank", P.m_crank, P.m_crank * P.r * P.r / 12.0, Vec2(0.5 * P.r, 0.0)});
  FlexibleBodySpec fs;
  fs.name = "rod";
  fs.rod = rod;
  fs.damping = damping;
  fs.geometric_stiffening = stiffening;
  const BodyId rb = b.AddFlexibleBody(fs);
  const BodyId slider = b.AddRigidBody({"slider", P.m_slider, 1e-4, Vec2(0.0, 0.0)});
  return ConnectSliderCrank(b, P, crank, rb, slider, [&](MechanismBuilder& mb) {
    return std::pair{mb.AddNodeMarker(rb, "rod.A", 0),
                     mb.AddNodeMarker(rb, "rod.B", rod->rod.num_nodes() - 1)};
  });
}

/// Synthetic reduced rod: N point masses m_k at ū₀,k with random shape rows S_k (2×n); the
/// inertia shape integrals are the exact sums over the cloud (ffrf-planar.md table); K is a
/// random symmetric positive definite matrix; nodes[k] are the points (S_φ random).
struct PointCloud {
  std::vector<double> m;
  std::vector<Vec2> u0;
  std::vector<Mat2X> S;
};

inline Mat2 Jmat() {
  Mat2 J;
  J << 0.0, -1.0, 1.0, 0.0;
  return J;
}

inline std::shared_ptr<fem::ReducedRod> MakeSyntheticRod(int n, int points, unsigned seed,
                                                         PointCloud* cloud_out = nullptr,
                                                         double stiffness = 4e4,
                                                         double length = 0.2) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  auto rod = std::make_shared<fem::ReducedRod>();
  PointCloud cloud;
  const Mat2 J = Jmat();
  fem::PlanarInertia& in = rod->inertia;
  in.S = Mat2X::Zero(2, n);
  in.I1 = Vec::Zero(n);
  in.Ibar = Vec::Zero(n);
  in.Mff = Mat::Zero(n, n);
  in.Stilde = Mat::Zero(n, n);
  for (int k = 0; k < points; ++k) {
    const double mk = 0.05 + 0.05 * (1.0 + U(gen));
    const Vec2 u0(length * 0.5 * (1.0 + U(gen)), 0.01 * U(gen));
    Mat2X Sk(2, n);
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < n; ++j) Sk(i, j) = 0.05 * U(gen);
    cloud.m.push_back(mk);
    cloud.u0.push_back(u0);
    cloud.S.push_back(Sk);
    in.mass += mk;
    in.S0 += mk * u0;
    in.S += mk * Sk;
    in.J0 += mk * u0.squaredNorm();
    in.I1 += mk * Sk.transpose() * u0;
    in.Ibar += mk * Sk.transpose() * (J * u0);
    in.Mff += mk * Sk.transpose() * Sk;
    in.Stilde += mk * Sk.transpose() * J * Sk;
    fem::MarkerShape node;
    node.position = u0;
    node.S_u = Sk;
    node.S_phi = RowVec(n);
    for (int j = 0; j < n; ++j) node.S_phi(j) = 0.5 * U(gen);
    rod->nodes.push_back(node);
  }
  Mat B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = U(gen);
  rod->K = stiffness * (B * B.transpose() + n * Mat::Identity(n, n));
  rod->M = in.Mff;
  Mat C(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) C(i, j) = U(gen);
  // Geometric stiffness of a synthetic 3-element rod: random element rows and K_G (on the
  // transverse dofs v, θ only, as the frame element's).
  rod->rod.num_elements = 3;
  rod->basis = Mat(rod->rod.num_dofs(), n);
  for (int i = 0; i < rod->basis.rows(); ++i)
    for (int j = 0; j < n; ++j) rod->basis(i, j) = 0.5 * U(gen);
  rod->element_axial_stiffness = 2e4;  // [N/m]
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) {
      rod->element_Kg(i, j) = i % 3 == 0 || j % 3 == 0 ? 0.0 : U(gen) + C(i % n, j % n);
    }
  }
  rod->element_Kg = 5.0 * (rod->element_Kg + rod->element_Kg.transpose()).eval();
  rod->frequencies_hz = Vec::Zero(n);
  if (cloud_out != nullptr) *cloud_out = cloud;
  return rod;
}

}  // namespace flexrod::multibody::testing
