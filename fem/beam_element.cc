// fem/beam_element.cc — 2-node frame element kernels (Euler–Bernoulli and Timoshenko).
//
// Bending uses the "interdependent interpolation" Timoshenko element: cubic transverse
// displacement and quadratic rotation chosen so that the homogeneous static equations are
// satisfied exactly, with shear parameter Φ = 12 E I / (κ G A L²). Φ = 0 recovers the
// Hermite-cubic Euler–Bernoulli element. Stiffness: Przemieniecki, Theory of Matrix
// Structural Analysis (1968), §5.6. Consistent mass with rotary inertia: Friedman & Kosmatka,
// "An improved two-node Timoshenko beam finite element", Computers & Structures 47 (1993)
// 473–481, eqs. (21)–(22). Every matrix here equals the quadrature of the shape functions in
// PlanarFrameShape (checked in tests/fem/elem_beam_test.cc).
//
// Kernels are pure functions on fixed-size Eigen types: no heap allocation.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "fem/beam_element.h"

#include "common/error.h"

namespace flexrod::fem {
namespace {

using Matrix4d = Eigen::Matrix4d;

// HRZ (Hinton, Rock & Zienkiewicz 1976) lumping of the Hermite mass: the consistent diagonal
// scaled so the translations carry ρAL/2 each; the rotational diagonal ρAL³/105 becomes
// ρAL³/105 · 35/26 = ρAL³/78.
constexpr double kLumpedRotaryFactor = 1.0 / 78.0;

/// Φ = 12 E I / (κ G A L²) for Timoshenko, 0 for Euler–Bernoulli.
double ShearParameter(const RectSection& s, const Material& m, double inertia, double length,
                      BeamTheory t) {
  if (t == BeamTheory::kEulerBernoulli) return 0.0;
  const double kappa = RectSection::CowperShearFactor(m.poisson_ratio);
  return 12.0 * m.youngs_modulus * inertia /
         (kappa * m.shear_modulus() * s.area() * length * length);
}

/// Bending stiffness on (v1, θ1, v2, θ2) with θ the section rotation, θ = v' for EB.
Matrix4d BendingStiffness(double EI, double phi, double L) {
  const double L2 = L * L;
  Matrix4d k;
  k << 12.0, 6.0 * L, -12.0, 6.0 * L,                         //
      6.0 * L, (4.0 + phi) * L2, -6.0 * L, (2.0 - phi) * L2,  //
      -12.0, -6.0 * L, 12.0, -6.0 * L,                        //
      6.0 * L, (2.0 - phi) * L2, -6.0 * L, (4.0 + phi) * L2;
  return EI / ((1.0 + phi) * L2 * L) * k;
}

/// Consistent bending mass on (v1, θ1, v2, θ2): translational part ρA and, if rho_i > 0,
/// rotary inertia ρI (Friedman & Kosmatka 1993).
Matrix4d BendingConsistentMass(double rho_a, double rho_i, double phi, double L) {
  const double p2 = phi * phi;
  const double L2 = L * L;
  const double a11 = 13.0 / 35.0 + 7.0 * phi / 10.0 + p2 / 3.0;
  const double a12 = (11.0 / 210.0 + 11.0 * phi / 120.0 + p2 / 24.0) * L;
  const double a13 = 9.0 / 70.0 + 3.0 * phi / 10.0 + p2 / 6.0;
  const double a14 = -(13.0 / 420.0 + 3.0 * phi / 40.0 + p2 / 24.0) * L;
  const double a22 = (1.0 / 105.0 + phi / 60.0 + p2 / 120.0) * L2;
  const double a24 = -(1.0 / 140.0 + phi / 60.0 + p2 / 120.0) * L2;
  Matrix4d mt;
  mt << a11, a12, a13, a14,  //
      a12, a22, -a14, a24,   //
      a13, -a14, a11, -a12,  //
      a14, a24, -a12, a22;
  const double b11 = 6.0 / 5.0;
  const double b12 = (1.0 / 10.0 - phi / 2.0) * L;
  const double b22 = (2.0 / 15.0 + phi / 6.0 + p2 / 3.0) * L2;
  const double b24 = (-1.0 / 30.0 - phi / 6.0 + p2 / 6.0) * L2;
  Matrix4d mr;
  mr << b11, b12, -b11, b12,  //
      b12, b22, -b12, b24,    //
      -b11, -b12, b11, -b12,  //
      b12, b24, -b12, b22;
  const double q = 1.0 / ((1.0 + phi) * (1.0 + phi));
  return rho_a * L * q * mt + rho_i / L * q * mr;
}

/// Lumped bending mass: ρAL/2 on each translation; HRZ rotary term ρAL³/78 plus the section's
/// own rotary inertia ρIL/2 (rho_i = 0 for Euler–Bernoulli).
Matrix4d BendingLumpedMass(double rho_a, double rho_i, double L) {
  const double trans = 0.5 * rho_a * L;
  const double rot = kLumpedRotaryFactor * rho_a * L * L * L + 0.5 * rho_i * L;
  return Eigen::Vector4d(trans, rot, trans, rot).asDiagonal();
}

Matrix4d BendingMass(double rho_a, double rho_i, double phi, double L, MassKind kind) {
  return kind == MassKind::kConsistent ? BendingConsistentMass(rho_a, rho_i, phi, L)
                                       : BendingLumpedMass(rho_a, rho_i, L);
}

/// Two-node bar (axial or torsion) matrices: stiffness c/L [1 −1; −1 1] and mass.
Eigen::Matrix2d BarStiffness(double c, double L) {
  Eigen::Matrix2d k;
  k << 1.0, -1.0, -1.0, 1.0;
  return c / L * k;
}
Eigen::Matrix2d BarMass(double inertia_per_length, double L, MassKind kind) {
  Eigen::Matrix2d m;
  if (kind == MassKind::kConsistent) {
    m << 2.0, 1.0, 1.0, 2.0;
    return inertia_per_length * L / 6.0 * m;
  }
  m << 1.0, 0.0, 0.0, 1.0;
  return inertia_per_length * L / 2.0 * m;
}

template <int N>
void Scatter2(const Eigen::Matrix2d& a, int i, int j, Eigen::Matrix<double, N, N>* out) {
  const int idx[2] = {i, j};
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c) (*out)(idx[r], idx[c]) += a(r, c);
}

/// Adds a bending block given on (v1, θ1, v2, θ2) at element dofs idx, with sign[k] = ±1
/// mapping the element's rotation dof to θ (−1 for φy, where θ = w' = −φy).
template <int N>
void Scatter4(const Matrix4d& a, const int (&idx)[4], const double (&sign)[4],
              Eigen::Matrix<double, N, N>* out) {
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) (*out)(idx[r], idx[c]) += sign[r] * sign[c] * a(r, c);
}

constexpr double kNoFlip[4] = {1.0, 1.0, 1.0, 1.0};
constexpr double kFlipRotation[4] = {1.0, -1.0, 1.0, -1.0};

}  // namespace

Matrix6d PlanarFrameStiffness(const RectSection& s, const Material& m, double length,
                              BeamTheory t) {
  FLEXROD_ASSERT(length > 0.0);
  const double E = m.youngs_modulus;
  const double I = s.inertia_in_plane();
  Matrix6d k = Matrix6d::Zero();
  Scatter2<6>(BarStiffness(E * s.area(), length), 0, 3, &k);
  Scatter4<6>(BendingStiffness(E * I, ShearParameter(s, m, I, length, t), length), {1, 2, 4, 5},
              kNoFlip, &k);
  return k;
}

Matrix6d PlanarFrameMass(const RectSection& s, const Material& m, double length, BeamTheory t,
                         MassKind kind) {
  FLEXROD_ASSERT(length > 0.0);
  const double rho_a = m.density * s.area();
  const double I = s.inertia_in_plane();
  const double rho_i = t == BeamTheory::kTimoshenko ? m.density * I : 0.0;
  Matrix6d mass = Matrix6d::Zero();
  Scatter2<6>(BarMass(rho_a, length, kind), 0, 3, &mass);
  Scatter4<6>(BendingMass(rho_a, rho_i, ShearParameter(s, m, I, length, t), length, kind),
              {1, 2, 4, 5}, kNoFlip, &mass);
  return mass;
}

// Consistent geometric stiffness of the Hermite element, from ½ N ∫ v'² dx
// (Przemieniecki 1968, §15; Cook et al., Concepts and Applications of FEA, §18.3).
Matrix6d PlanarFrameGeometricStiffness(double length) {
  FLEXROD_ASSERT(length > 0.0);
  const double L = length;
  Matrix4d g;
  g << 36.0, 3.0 * L, -36.0, 3.0 * L,          //
      3.0 * L, 4.0 * L * L, -3.0 * L, -L * L,  //
      -36.0, -3.0 * L, 36.0, -3.0 * L,         //
      3.0 * L, -L * L, -3.0 * L, 4.0 * L * L;
  Matrix6d kg = Matrix6d::Zero();
  Scatter4<6>(g / (30.0 * L), {1, 2, 4, 5}, kNoFlip, &kg);
  return kg;
}

// Spatial dofs per node (u, v, w, φx, φy, φz); node 2 at offset 6. In-plane bending (x–y)
// couples v with φz = v'; out-of-plane bending (x–z) couples w with φy = −w' (right-hand rule).
Matrix12d SpatialFrameStiffness(const RectSection& s, const Material& m, double length,
                                BeamTheory t) {
  FLEXROD_ASSERT(length > 0.0);
  const double E = m.youngs_modulus;
  const double I_in = s.inertia_in_plane();
  const double I_out = s.inertia_out_of_plane();
  Matrix12d k = Matrix12d::Zero();
  Scatter2<12>(BarStiffness(E * s.area(), length), 0, 6, &k);
  Scatter2<12>(BarStiffness(m.shear_modulus() * s.torsion_constant(), length), 3, 9, &k);
  Scatter4<12>(BendingStiffness(E * I_in, ShearParameter(s, m, I_in, length, t), length),
               {1, 5, 7, 11}, kNoFlip, &k);
  Scatter4<12>(BendingStiffness(E * I_out, ShearParameter(s, m, I_out, length, t), length),
               {2, 4, 8, 10}, kFlipRotation, &k);
  return k;
}

Matrix12d SpatialFrameMass(const RectSection& s, const Material& m, double length, BeamTheory t,
                           MassKind kind) {
  FLEXROD_ASSERT(length > 0.0);
  const double rho = m.density;
  const double rho_a = rho * s.area();
  const double I_in = s.inertia_in_plane();
  const double I_out = s.inertia_out_of_plane();
  const bool rotary = t == BeamTheory::kTimoshenko;
  Matrix12d mass = Matrix12d::Zero();
  Scatter2<12>(BarMass(rho_a, length, kind), 0, 6, &mass);
  // Torsion: the section spins about x with polar moment I_y + I_z (both theories).
  Scatter2<12>(BarMass(rho * (I_in + I_out), length, kind), 3, 9, &mass);
  Scatter4<12>(BendingMass(rho_a, rotary ? rho * I_in : 0.0, ShearParameter(s, m, I_in, length, t),
                           length, kind),
               {1, 5, 7, 11}, kNoFlip, &mass);
  Scatter4<12>(BendingMass(rho_a, rotary ? rho * I_out : 0.0,
                           ShearParameter(s, m, I_out, length, t), length, kind),
               {2, 4, 8, 10}, kFlipRotation, &mass);
  return mass;
}

// Interdependent-interpolation shape functions (Friedman & Kosmatka 1993, eq. (14)), with
// μ = 1/(1+Φ), ξ = x/L; Φ = 0 gives the Hermite cubics and ψ = v'.
PlanarShape PlanarFrameShape(const RectSection& s, const Material& m, double length, BeamTheory t,
                             double xi) {
  FLEXROD_ASSERT(length > 0.0);
  const double L = length;
  const double phi = ShearParameter(s, m, s.inertia_in_plane(), L, t);
  const double mu = 1.0 / (1.0 + phi);
  const double x = xi, x2 = xi * xi, x3 = x2 * xi;

  PlanarShape out;
  out.N.setZero();
  out.B.setZero();
  // axial, linear
  out.N(0, 0) = 1.0 - x;
  out.N(0, 3) = x;
  out.B(0, 0) = -1.0 / L;
  out.B(0, 3) = 1.0 / L;
  // transverse displacement v
  out.N(1, 1) = mu * (1.0 - 3.0 * x2 + 2.0 * x3 + phi * (1.0 - x));
  out.N(1, 2) = mu * L * (x - 2.0 * x2 + x3 + 0.5 * phi * (x - x2));
  out.N(1, 4) = mu * (3.0 * x2 - 2.0 * x3 + phi * x);
  out.N(1, 5) = mu * L * (-x2 + x3 - 0.5 * phi * (x - x2));
  // section rotation ψ
  out.N(2, 1) = mu * 6.0 / L * (x2 - x);
  out.N(2, 2) = mu * (1.0 - 4.0 * x + 3.0 * x2 + phi * (1.0 - x));
  out.N(2, 4) = mu * 6.0 / L * (x - x2);
  out.N(2, 5) = mu * (-2.0 * x + 3.0 * x2 + phi * x);
  // curvature κ = ψ'
  out.B(1, 1) = mu * 6.0 / (L * L) * (2.0 * x - 1.0);
  out.B(1, 2) = mu / L * (-4.0 + 6.0 * x - phi);
  out.B(1, 4) = mu * 6.0 / (L * L) * (1.0 - 2.0 * x);
  out.B(1, 5) = mu / L * (-2.0 + 6.0 * x + phi);
  return out;
}

}  // namespace flexrod::fem
