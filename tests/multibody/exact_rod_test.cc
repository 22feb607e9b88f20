// tests/multibody/exact_rod_test.cc — the geometrically exact rod in the multibody engine
// (multibody/exact_rod.h): the beam element's analytic Jacobian against central differences of
// its outputs; the whole iteration Jacobian of a mechanism with an exact rod against central
// differences of the residual; a free, undamped rod spinning and vibrating conserves its energy;
// a very stiff exact rod reproduces the exact rigid slider-crank kinematics.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/exact_rod.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "mb_test_util.h"
#include "multibody/corotated_damping.h"
#include "multibody/dae.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

using testing::SliderCrankExact;
using testing::SliderCrankParams;

using testing::SteelRodSpec;

ElementOutput Outputs(const ReissnerBeamElement& el, const MarkerKinematics& a,
                      const MarkerKinematics& b) {
  ElementOutput o;
  EXPECT_TRUE(el.Evaluate(0.0, a, b, nullptr, nullptr, &o));
  return o;
}

Eigen::Matrix<double, 7, 1> Stack(const ElementOutput& o) {
  Eigen::Matrix<double, 7, 1> v;
  v << o.force_i, o.moment_i, o.force_j, o.moment_j, o.dissipation;
  return v;
}

double& Kappa(MarkerKinematics* k, int c) {
  switch (c) {
    case 0:
      return k->position.x();
    case 1:
      return k->position.y();
    case 2:
      return k->velocity.x();
    case 3:
      return k->velocity.y();
    case 4:
      return k->angle;
    default:
      return k->angular_velocity;
  }
}

// ∂o/∂κ of the Reissner element (forces, moments and dissipation) equals central differences
// at random, large-rotation, moving states (relative 1e-6 of each row's largest entry).
TEST(ExactRod, ElementJacobianIsTheDerivativeOfItsOutputs) {
  const fem::RodSpec rod = SteelRodSpec(0.2, 10);
  const ReissnerBeamElement el(fem::ReissnerStiffnessOf(rod.material, rod.section),
                               rod.element_length(), 3e-5);
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int trial = 0; trial < 10; ++trial) {
    const double L = rod.element_length(), th = 3.0 * U(gen);
    MarkerKinematics k[2];
    k[0].position = Vec2(U(gen), U(gen));
    k[0].angle = th + 0.05 * U(gen);
    k[1].position = k[0].position + L * (1.0 + 1e-3 * U(gen)) * Vec2(std::cos(th), std::sin(th)) +
                    1e-3 * L * Vec2(U(gen), U(gen));
    k[1].angle = th + 0.05 * U(gen);
    for (auto& ki : k) {
      ki.velocity = Vec2(U(gen), U(gen));
      ki.angular_velocity = 30.0 * U(gen);
    }
    Mat jac = Mat::Zero(7, kElementKinematicColumns), none(7, 0);
    ASSERT_TRUE(el.EvaluateJacobian(0.0, k[0], k[1], nullptr, nullptr, &jac, &none));
    Mat fd(7, kElementKinematicColumns);
    for (int side = 0; side < 2; ++side) {
      for (int c = 0; c < 6; ++c) {
        const double h = c == 4 ? 1e-7 : (c == 0 || c == 1 ? 1e-9 : 1e-5);
        MarkerKinematics kp[2] = {k[0], k[1]}, km[2] = {k[0], k[1]};
        Kappa(&kp[side], c) += h;
        Kappa(&km[side], c) -= h;
        fd.col(6 * side + c) =
            (Stack(Outputs(el, kp[0], kp[1])) - Stack(Outputs(el, km[0], km[1]))) / (2.0 * h);
      }
    }
    for (int r = 0; r < 7; ++r) {
      const double scale = std::max(fd.row(r).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LE((jac.row(r) - fd.row(r)).cwiseAbs().maxCoeff(), 1e-6 * scale)
          << "row " << r << " trial " << trial;
    }
  }
}

struct ExactPendulum {
  Mechanism model;
  ExactRod rod;
};

/// An exact rod pinned at node 0 to the ground, with gravity; with `modes` (3 elements × r)
/// and `coefficients` (r) also a co-rotated modal damping of its nodes.
ExactPendulum BuildExactPendulum(int elements, double beta, const Mat& modes = Mat(),
                                 const Vec& coefficients = Vec()) {
  MechanismBuilder b;
  ExactRodSpec spec;
  spec.name = "rod";
  spec.rod = SteelRodSpec(0.2, elements);
  spec.rod.attachments.push_back({"tip", elements, 0.05, 1e-6, Vec2(0.01, 0.005)});
  spec.beta = beta;
  spec.modal_damping_modes = modes;
  spec.modal_damping_coefficients = coefficients;
  ExactPendulum p;
  p.rod = AddExactRod(&b, spec);
  b.AddRevolute("pivot", b.AddGroundMarker("pivot", Vec2::Zero()), p.rod.node_markers[0]);
  b.SetGravity(Vec2(0.0, -9.81));
  p.model = b.Build();
  return p;
}

/// Worst column error of the iteration Jacobian dF/dy + c_j dF/dẏ against central differences
/// of the residual (Richardson-extrapolated) at a deformed, moving state of the pendulum.
double IterationJacobianError(const ExactPendulum& p) {
  RunData data(p.model);
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const int N = p.model.size(), np = p.model.num_coordinates();
  Vec y = Vec::Zero(N), yp = Vec::Zero(N);
  Vec pose = Vec::Zero(np);
  SetExactRodPose(p.model, p.rod, Vec2::Zero(), 0.4, &pose);
  for (int i = 0; i < np; ++i) y(i) = pose(i) + 1e-4 * U(gen);
  for (int i = np; i < N; ++i) y(i) = U(gen);
  for (int i = 0; i < N; ++i) yp(i) = U(gen);
  const double cj = 1e4, t = 0.0;
  const Mat J = CalcJacobian(p.model, &data, t, cj, y, yp);
  double worst = 0.0;
  for (int i = 0; i < N; ++i) {
    auto central = [&](double h) {
      Vec y1 = y, y2 = y, yp1 = yp, yp2 = yp;
      y1(i) += h;
      y2(i) -= h;
      yp1(i) += cj * h;
      yp2(i) -= cj * h;
      return Vec(
          (CalcResidual(p.model, &data, t, y1, yp1) - CalcResidual(p.model, &data, t, y2, yp2)) /
          (2.0 * h));
    };
    const double h = i < np ? 1e-8 : 1e-6;
    const Vec fd = (4.0 * central(0.5 * h) - central(h)) / 3.0;
    const double scale = std::max(fd.lpNorm<Eigen::Infinity>(), 1.0);
    const double err = (J.col(i) - fd).lpNorm<Eigen::Infinity>() / scale;
    worst = std::max(worst, err);
    EXPECT_LE(err, 1e-6) << "column " << i << " (" << p.model.VariableName(i) << ")";
  }
  // Every non-zero lies inside the sparsity pattern given to KLU.
  const SparsityPattern pat = JacobianPattern(p.model);
  Mat inside = Mat::Zero(N, N);
  for (int col = 0; col < N; ++col)
    for (int64_t k = pat.col_ptr[col]; k < pat.col_ptr[col + 1]; ++k)
      inside(pat.row_index[k], col) = 1;
  for (int r = 0; r < N; ++r) {
    for (int col = 0; col < N; ++col) {
      if (J(r, col) != 0.0) {
        EXPECT_EQ(inside(r, col), 1)
            << p.model.VariableName(r) << " / " << p.model.VariableName(col);
      }
    }
  }
  return worst;
}

// The iteration Jacobian with the analytic element Jacobian equals central differences.
TEST(ExactRod, IterationJacobianMatchesCentralDifferences) {
  testing::Record("worst_column_error", IterationJacobianError(BuildExactPendulum(4, 2e-5)));
}

/// Random modes (3 elements × r) and coefficients for a co-rotated damping of the pendulum.
std::pair<Mat, Vec> RandomModalDamping(int elements, int r) {
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Mat Y(3 * elements, r);
  for (int i = 0; i < Y.size(); ++i) Y.data()[i] = U(gen);
  Vec c(r);
  for (int i = 0; i < r; ++i) c(i) = 2.0 + U(gen);
  return {Y, c};
}

// With the co-rotated modal damping (multibody/corotated_damping.h): its forces, modal-state rows
// and dissipation differentiated analytically, in the rates, the positions (the frame's turn and
// the moment arms) and the states' rates, agree with central differences.
TEST(ExactRod, IterationJacobianWithCorotatedModalDampingMatchesCentralDifferences) {
  const auto [Y, c] = RandomModalDamping(4, 3);
  testing::Record("worst_column_error", IterationJacobianError(BuildExactPendulum(4, 2e-5, Y, c)));
}

// The co-rotated deformation rates vanish for every rigid motion of the chain (a translation
// and a rotation about any point), at any pose; a bending rate does not vanish.
TEST(ExactRod, CorotatedRatesVanishForRigidMotion) {
  const auto [Y, c] = RandomModalDamping(4, 3);
  const ExactPendulum p = BuildExactPendulum(4, 0.0, Y, c);
  const Mechanism& m = p.model;
  const int np = m.num_coordinates();
  Vec pose = Vec::Zero(np);
  SetExactRodPose(m, p.rod, Vec2(0.3, -0.1), 2.1, &pose);
  pose(m.coordinate(p.rod.nodes[2], kY)) += 1e-3;  // deformed: rigid rates must vanish anyway
  const Mat B = CorotatedRateMap(m, p.rod.nodes, pose);
  ASSERT_EQ(B.rows(), 12);
  const Vec2 velocity(1.5, -0.7), pivot(0.2, 0.4);
  const double omega = 7.0;
  Vec v(np);
  for (const BodyId node : p.rod.nodes) {
    const Vec2 r(pose(m.coordinate(node, kX)), pose(m.coordinate(node, kY)));
    const Vec2 vr = velocity + omega * Vec2(-(r - pivot).y(), (r - pivot).x());
    v(m.coordinate(node, kX)) = vr.x();
    v(m.coordinate(node, kY)) = vr.y();
    v(m.coordinate(node, kTheta)) = omega;
  }
  EXPECT_LT((B * v).lpNorm<Eigen::Infinity>(), 1e-13 * v.lpNorm<Eigen::Infinity>());
  v(m.coordinate(p.rod.nodes[2], kY)) += 0.1;  // the middle node moves across the rod
  EXPECT_GT((B * v).norm(), 0.099);
}

// A free, undamped exact rod, spinning at 40 rad/s about its centre and vibrating in its
// first bending mode's shape, conserves kinetic + strain energy (no external force, no
// damping) to the integration tolerance.
TEST(ExactRod, FreeSpinningRodConservesEnergy) {
  MechanismBuilder b;
  ExactRodSpec spec;
  spec.name = "rod";
  spec.rod = SteelRodSpec(0.2, 4);
  const ExactRod rod = AddExactRod(&b, spec);
  const Mechanism m = b.Build();
  RunData data(m);
  InitialConditionSpec ic;
  ic.coordinates = Vec::Zero(m.num_coordinates());
  ic.velocities = Vec::Zero(m.num_coordinates());
  const double L = spec.rod.length,
               omega = 40.0;  // 4 elements below: the undamped element modes set the step
  for (int k = 0; k < spec.rod.num_nodes(); ++k) {
    const double x = spec.rod.node_x(k) - 0.5 * L;
    const double w = 1e-3 * std::sin(std::numbers::pi * spec.rod.node_x(k) / L);  // bent
    const double slope =
        1e-3 * std::numbers::pi / L * std::cos(std::numbers::pi * spec.rod.node_x(k) / L);
    ic.coordinates[m.coordinate(rod.nodes[k], kX)] = x;
    ic.coordinates[m.coordinate(rod.nodes[k], kY)] = w;
    ic.coordinates[m.coordinate(rod.nodes[k], kTheta)] = slope;
    ic.velocities[m.coordinate(rod.nodes[k], kX)] = -omega * w;
    ic.velocities[m.coordinate(rod.nodes[k], kY)] = omega * x;
    ic.velocities[m.coordinate(rod.nodes[k], kTheta)] = omega;
  }
  SimulationOptions opt;
  opt.t_end = 0.01;
  opt.sample_rate = 4000.0;
  opt.velocity_tol_scale = 1.0;  // the velocities at the error test's own tolerance
  opt.integrator.rel_tol = 1e-9;
  opt.integrator.abs_tol = 1e-12;
  double e0 = NAN, worst = 0.0, strain_peak = 0.0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    const EnergyReport e = s.Energies();
    const double total = e.kinetic + e.element_potential;
    if (std::isnan(e0)) e0 = total;
    worst = std::max(worst, std::abs(total - e0));
    strain_peak = std::max(strain_peak, e.element_potential);
  };
  const SimulationStatus st = Simulate(m, &data, ic, opt, cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_GT(strain_peak, 1e-4 * e0);  // it does vibrate
  // BDF damps what it does not resolve: the nodal start excites the element's axial and shear
  // modes (≈ 10⁶ rad/s) slightly, and their energy is lost numerically (measured 1.4e-6 of E0
  // over 0.02 s with 8 elements at rel_tol 1e-9).
  EXPECT_LE(worst, 1e-5 * e0);
  testing::Record("relative_energy_drift", worst / e0);
  testing::Record("steps", static_cast<double>(st.stats.steps));
}

// A slider-crank whose rod is an exact rod 100 times stiffer than steel: the slider follows
// the exact rigid formulas (mb_test_util.h) to 1e-6 in position (relative to the largest value
// over a revolution) once the start-up ringing has died out. Note: the node coordinates are
// absolute, so their error weight is rel_tol × L0 (ResolvedLength); with undamped-enough
// element modes near 10⁶ rad/s the step stays near 5e-7 s (measured: 2 000 steps per ms).
TEST(ExactRod, VeryStiffExactRodReproducesTheRigidSliderCrank) {
  SliderCrankParams P;
  P.e = 0.01;
  MechanismBuilder b;
  const BodyId crank =
      b.AddRigidBody({"crank", P.m_crank, P.m_crank * P.r * P.r / 12.0, Vec2(0.5 * P.r, 0.0)});
  ExactRodSpec spec;
  spec.name = "rod";
  spec.rod = SteelRodSpec(P.l, 8, 1e2);
  spec.beta = 1e-5;  // ζ ≈ 0.1 on the first bending mode (22 800 rad/s)
  const ExactRod rod = AddExactRod(&b, spec);
  const BodyId slider = b.AddRigidBody({"slider", P.m_slider, 1e-4, Vec2(0.0, 0.0)});
  const testing::SliderCrankModel sc =
      testing::ConnectSliderCrank(b, P, crank, rod.nodes[0], slider, [&](MechanismBuilder&) {
        return std::pair{rod.node_markers.front(), rod.node_markers.back()};
      });
  const SliderCrankExact ex{P.r, P.l, P.e, P.omega};
  InitialConditionSpec ic;
  ic.coordinates = Vec::Zero(sc.model.num_coordinates());
  const double th = P.theta0;
  SetBodyPose(sc.model, crank, Vec2::Zero(), th, &ic.coordinates);
  SetExactRodPose(sc.model, rod, P.r * Vec2(std::cos(th), std::sin(th)), ex.rod_angle(th),
                  &ic.coordinates);
  SetBodyPose(sc.model, slider, Vec2(ex.x(th), P.e), 0.0, &ic.coordinates);
  RunData data(sc.model);
  SimulationOptions opt;
  opt.t_end = 0.03;  // a tenth of a revolution after the ringing (≈ 60 000 steps: see the note)
  opt.sample_rate = 2000.0;
  opt.integrator.rel_tol = 1e-8;
  opt.integrator.abs_tol = 1e-10;
  const int ix = sc.model.coordinate(sc.slider, kX);
  double ex_x = 0, ex_xd = 0, rx = 0, rxd = 0;
  SimulationCallbacks cb;
  cb.on_sample = [&](const SampleView& s) {
    if (s.t() < 5e-3) return;
    const double t_th = P.theta0 + P.omega * s.t();
    ex_x = std::max(ex_x, std::abs(s.coordinate(ix) - ex.x(t_th)));
    ex_xd = std::max(ex_xd, std::abs(s.velocity(ix) - ex.xd(t_th)));
    rx = std::max(rx, std::abs(ex.x(t_th)));
    rxd = std::max(rxd, std::abs(ex.xd(t_th)));
  };
  const SimulationStatus st = Simulate(sc.model, &data, ic, opt, cb);
  ASSERT_TRUE(st.ok()) << st.Summary();
  EXPECT_LE(ex_x / rx, 1e-6);
  EXPECT_LE(ex_xd / rxd, 1e-5);
  testing::Record("rel_err_x", ex_x / rx);
  testing::Record("rel_err_xd", ex_xd / rxd);
  testing::Record("steps", static_cast<double>(st.stats.steps));
}

}  // namespace
}  // namespace flexrod::multibody
