// contact/friction_law.h — tangential friction laws of a clearance joint as value types in one
// closed std::variant, selected by kebab-case name: coulomb (with Ambrósio's dynamic
// correction), threlfall, stribeck (+ viscous), lugre (one internal state z). Each returns the
// friction force F_t on the pin along the contact tangent t (contact/geometry.h), opposing the
// slip velocity v_t, with its derivatives for the multibody Jacobian. What does not live here: the
// geometry producing v_t and F_n (contact/geometry.h), normal laws (contact/normal_law.h).
//
// Formulas (reference/contact-models.md; Ambrósio, "Impact of rigid and flexible multibody
// systems", 2003; Threlfall, Computer-Aided Design 10 (1978) 325; Canudas de Wit et al., IEEE
// TAC 40 (1995) 419):
//   coulomb    F_t = −μ c_d(|v|) F_n sign(v),  c_d = 0 (|v| ≤ v₀), (|v|−v₀)/(v₁−v₀), 1 (|v| ≥ v₁)
//   threlfall  F_t = −μ F_n (1 − exp(−3|v|/v₀)) sign(v)
//   stribeck   F_t = −[F_c + (F_s − F_c) exp(−(|v|/v_s)^i)] tanh(v/v_r) − σ_v v,  F_c = μ_c F_n,
//              F_s = μ_s F_n. The published law has sign(v); tanh(v/v_r) with v_r = 1e-5 m/s
//              (1 % of v_s: the static peak is kept, tanh(5) = 0.9999 at 5 v_r) smooths the jump
//              for the implicit integrator. With sign(v) the pin of the flexible rig, whose
//              slip crosses zero as it rolls, took 10 min of wall time for 0.02 s.
//   lugre      ż = v − |v| z/g(v),  g(v) = μ(v)/σ̂₀,  μ(v) = μ_c + (μ_s − μ_c) exp(−(v/v_s)²)
//              F_t = −F_n (σ̂₀ z + σ̂₁ ż + σ̂₂ v)
// LuGre for a contact: contact-models.md scales F_c, F_s by F_n. We scale the bristle stiffness,
// bristle damping and viscous term with it too (σ₀ = σ̂₀ F_n, σ₁ = σ̂₁ F_n, σ₂ = σ̂₂ F_n), so
// g(v) = μ(v)/σ̂₀ is a length independent of F_n: ż stays finite when the contact opens
// (F_n → 0), an open contact has no friction, and the published unit-mass set (σ₀ = 1e5 N/m,
// σ₁ = √1e5 N·s/m, σ₂ = 0.4 N·s/m, F_c = 1 N, F_s = 1.5 N, v_s = 1e-3 m/s) is recovered
// exactly at F_n = 1 N, μ_c = 1, μ_s = 1.5. (The reference writes ż = v − σ₀|v|z/g(v) with g in
// force units — the same equation.) Steady state (ż = 0): F_t = −F_n [μ(v) sign(v) + σ̂₂ v],
// i.e. σ₀ g(v) + σ₂ v with σ₀ g(v) = F_n μ(v).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "contact/normal_law.h"  // ParameterMap, ResolvedParameter

namespace flexrod::contact {

/// Default kinetic friction coefficient [-]: the thesis's joint value (60 % of steel railway
/// wheels, thesis §3.3.2).
inline constexpr double kDefaultFrictionCoefficient = 0.18;

/// Coulomb with Ambrósio's dynamic correction (velocity thresholds; assumed defaults of the
/// order used by Flores & Ambrósio for revolute clearance joints).
struct CoulombFrictionLaw {
  double friction_coefficient{kDefaultFrictionCoefficient};  ///< μ [-]
  double stick_velocity{1e-4};                               ///< v₀ [m/s]: no friction below
  double slip_velocity{1e-3};  ///< v₁ [m/s]: full friction above, > v₀
};
/// Threlfall 1978: 95 % of full friction at |v| = v₀ (1 − e⁻³).
struct ThrelfallFrictionLaw {
  double friction_coefficient{kDefaultFrictionCoefficient};  ///< μ [-]
  double velocity_scale{1e-3};                               ///< v₀ [m/s] (assumed)
};
/// Stribeck with viscous term.
struct StribeckFrictionLaw {
  double friction_coefficient{kDefaultFrictionCoefficient};      ///< μ_c, kinetic [-]
  double static_coefficient{1.5 * kDefaultFrictionCoefficient};  ///< μ_s [-] (LuGre set ratio)
  double stribeck_velocity{1e-3};                                ///< v_s [m/s]
  double stribeck_exponent{2.0};                                 ///< i [-]
  double viscous_coefficient{0.0};                               ///< σ_v [N·s/m]
  double regularisation_velocity{1e-5};  ///< v_r [m/s] of tanh(v/v_r) in place of sign(v)
};
/// LuGre with load-proportional bristles (see the file comment).
struct LuGreFrictionLaw {
  double friction_coefficient{kDefaultFrictionCoefficient};      ///< μ_c [-]
  double static_coefficient{1.5 * kDefaultFrictionCoefficient};  ///< μ_s [-]
  double stribeck_velocity{1e-3};                                ///< v_s [m/s]
  double bristle_stiffness{1e5};               ///< σ̂₀ [1/m] (N/m per N of normal force)
  double bristle_damping{316.22776601683796};  ///< σ̂₁ = √1e5 [s/m] (N·s/m per N)
  double viscous_coefficient{0.4};             ///< σ̂₂ [s/m] (N·s/m per N of normal force)
};

using FrictionLaw =
    std::variant<CoulombFrictionLaw, ThrelfallFrictionLaw, StribeckFrictionLaw, LuGreFrictionLaw>;

/// coulomb, threlfall, stribeck, lugre.
const std::vector<std::string>& FrictionLawNames();
std::string_view FrictionLawName(const FrictionLaw& law);

struct ResolvedFrictionLaw {
  FrictionLaw law;
  std::vector<ResolvedParameter> parameters;
};

/// Builds a friction law by name with kebab-case overrides (SI):
///  coulomb:   friction-coefficient, stick-velocity, slip-velocity
///  threlfall: friction-coefficient, velocity-scale
///  stribeck:  friction-coefficient, static-coefficient, stribeck-velocity, stribeck-exponent,
///             viscous-coefficient, regularisation-velocity
///  lugre:     friction-coefficient, static-coefficient, stribeck-velocity, bristle-stiffness
///             [1/m], bristle-damping [s/m], viscous-coefficient [s/m] (all three per N of F_n)
/// The static coefficient defaults to 1.5 × the given kinetic one. Throws InputError for an
/// unknown name ("contact.friction"), a key the law does not take, or a value outside its rule.
ResolvedFrictionLaw ResolveFrictionLaw(std::string_view name, const ParameterMap& overrides = {});
inline FrictionLaw MakeFrictionLaw(std::string_view name, const ParameterMap& overrides = {}) {
  return ResolveFrictionLaw(name, overrides).law;
}

/// Number of internal states (lugre: 1, bristle deflection z [m]; others 0); z = 0 at onset.
int NumFrictionStates(const FrictionLaw& law);

struct FrictionForce {
  double force{0.0};     ///< F_t [N], along the tangent t; F_t·v_t ≤ 0 in steady sliding
  double d_slip{0.0};    ///< ∂F_t/∂v_t [N·s/m]
  double d_normal{0.0};  ///< ∂F_t/∂F_n [-]
  double d_state{0.0};   ///< ∂F_t/∂z [N/m] (lugre)
};

/// F_t(v_t, F_n, z). Normal force F_n ≥ 0 [N]; z is ignored by stateless laws.
FrictionForce CalcFrictionForce(const FrictionLaw& law, double slip_velocity, double normal_force,
                                double state = 0.0);

struct FrictionStateRate {
  double rate{0.0};     ///< ż [m/s]
  double d_slip{0.0};   ///< ∂ż/∂v_t [-]
  double d_state{0.0};  ///< ∂ż/∂z [1/s]
};
/// ż for lugre (zero for the others).
FrictionStateRate CalcFrictionStateRate(const FrictionLaw& law, double slip_velocity, double state);

}  // namespace flexrod::contact
