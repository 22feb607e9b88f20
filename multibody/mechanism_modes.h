// multibody/mechanism_modes.h — the undamped small-vibration modes of an assembled mechanism
// about a configuration at rest (selected coordinates held), and the elastic damping matrix of
// one flexible body that gives those modes prescribed damping ratios. What does not live
// here: the body's own (clamped-frame) modes and the damping kinds built from them
// (DampingSpec, multibody/mechanism.h); choosing the ratios from user input
// (mechanisms/mechanism_damping.h).
//
// Linearisation (at p with v = 0, λ = μ = 0, element states z = 0): M δp̈ + K δp = 0 on the
// tangent space of the constraints, G δp = 0 and δp_i = 0 for each held coordinate i, with
// M = M(p) (CalcMassMatrix) and K = ∂F2/∂p, the position block of the equations of motion
// F2 = M v̇ − Q + Gᵀλ (CalcJacobian): the bodies' elastic stiffness, the tangent stiffness of
// the force elements and, where present, gravity's position derivative. With λ = 0 the
// constraint-curvature term Σ λ_k ∂²g_k/∂p² is absent, so p should be an equilibrium with
// zero constraint forces (a mechanism at rest without gravity, as the rigs are). K is
// symmetrised on the tangent space.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <vector>

#include "common/eigen.h"
#include "multibody/mechanism.h"

namespace flexrod::multibody {

/// Undamped modes of a mechanism, ascending in frequency.
struct MechanismModes {
  Vec frequencies_hz;  ///< f_i = ω_i / 2π [Hz] (m); zero or negative ω² are reported as 0 Hz
  /// np × m: column i is mode i in the full coordinate vector p, M-normalised
  /// (Ψᵀ M Ψ = I, Ψᵀ K Ψ = diag(ω²) on the constraints' tangent space).
  Mat shapes;
  int num_modes() const { return static_cast<int>(frequencies_hz.size()); }
};

/// Modes about the configuration p (np) at rest at time t, with the coordinates `held`
/// (indices into p) fixed as well as the mechanism's constraints (joints, constraint
/// drivers). The tangent space is the null space of [G; rows e_iᵀ of the held coordinates]
/// from a singular value decomposition (singular values below 1e-10 of the largest count as
/// zero, so redundant rows — a held coordinate that a driver already holds — are harmless).
/// Throws InputError for a bad p or held index, NumericalError when the projected mass matrix
/// is not positive definite (a free coordinate without inertia) or the eigensolver fails.
MechanismModes CalcMechanismModes(const Mechanism& m, const Vec& p, const std::vector<int>& held,
                                  double t = 0.0);

/// The n×n elastic damping matrix D of flexible body `body` (n = its elastic coordinates q)
/// such that the mechanism modes get Ψᵀ D_full Ψ = diag(2 ζ_i ω_i), D_full being D in the
/// q–q block of the np × np damping matrix: with Q the n×n matrix of the modes' q rows,
/// D = Q⁻ᵀ diag(2 ζ_i ω_i) Q⁻¹ (symmetric, positive semi-definite). The modes then stay
/// uncoupled and mode i decays with ratio ζ_i (no other damping in the mechanism). `zeta`
/// has one entry per mode, >= 0. Needs modes.num_modes() == n (one mechanism mode per elastic
/// coordinate: the body's q must parametrise the mechanism's motion) and Q invertible;
/// otherwise throws NumericalError saying which.
Mat ModalDampingForBody(const Mechanism& m, const MechanismModes& modes, BodyId body,
                        const Vec& zeta);

/// Modal damping of a chain of rigid bodies on its co-rotated deformation rates
/// (multibody/corotated_damping.h) with Kelvin–Voigt damping β of its elements beside it.
struct CorotatedModalFit {
  Mat modes;         ///< Y, 3(n − 1) × r, for MechanismBuilder::AddCorotatedDamping
  Vec coefficients;  ///< c_i = 2 ζ_i ω_i − β ω_i² (r)
  double beta{0.0};  ///< the elements' Kelvin–Voigt factor [s]
  Vec ratios;        ///< ζ every mechanism mode gets: ζ_i for i < r, β ω_i / 2 above [-]
};

/// The damping that gives the mechanism modes 1 … r (r = min(exact_modes, all)) exactly the
/// ratios ζ_i, when the chain `bodies` — every body of the mechanism that moves with its
/// crank held, in chain order — is joined by elements whose stiffness is the mechanism's only
/// stiffness and which carry Kelvin–Voigt damping β (ψᵢᵀ β K ψⱼ = β ω_i² δ_ij): with Q = B(p) Ψ
/// the modes' co-rotated deformation rates (square: one mode per deformation coordinate),
/// Y = the first r columns of Q⁻ᵀ (Yᵀ B ψ_j = δ_ij), c_i = 2 ζ_i ω_i − β ω_i², and
/// β = 2 ζ_r / ω_r fitted to mode r + 1, so that it gets its ratio, and the higher modes
/// β ω / 2, more than mode r + 1. All modes stay uncoupled (ΨᵀCΨ diagonal; c_i < 0 where
/// β ω_i² exceeds 2 ζ_i ω_i, with C still positive semi-definite about the reference).
/// Throws as ModalDampingForBody.
CorotatedModalFit FitCorotatedModalDamping(const Mechanism& m, const MechanismModes& modes,
                                           const std::vector<BodyId>& bodies, const Vec& p,
                                           const Vec& zeta, int exact_modes);

}  // namespace flexrod::multibody
