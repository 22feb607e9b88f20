// contact/normal_law.h — normal contact-force laws F(δ, δ̇, v₀, state) of a clearance joint:
// the sixteen laws of reference/contact-models.md as value types in one closed std::variant,
// selected by kebab-case name; their parameters derived from materials and geometry
// (ContactMaterials, ContactGeometry) with per-key overrides; cheap allocation-free evaluation
// with analytic derivatives dF/dδ, dF/dδ̇ (implicit laws: implicit differentiation); the
// internal-state interface (Maxwell, standard linear solid: ODE states; elasto-plastic:
// history). What does not live here: the geometry that produces δ and δ̇
// (contact/geometry.h), friction (contact/friction_law.h), single-impact simulation
// (contact/impact.h), and anything about bodies (multibody/).
//
// Notation (SI): δ penetration [m] (> 0 in contact), δ̇ = dδ/dt [m/s] (> 0 approaching), v₀ the
// approach velocity δ̇ at contact onset [m/s], cₑ restitution [-], n exponent [-], K [N/m^n].
// Every law returns F = 0 for δ ≤ 0 and never pulls: a negative value is clipped to 0 (and its
// derivatives are then 0).
//
// Compliance conventions (contact-models.md: not interchangeable, off by π):
//   σ_k = (1 − ν_k²)/E_k,   1/E* = σ_pin + σ_bush                used by the Hertz family
//   h_k = (1 − ν_k²)/(π E_k) = σ_k/π,  Σh = h_pin + h_bush = 1/(π E*)   used by the line laws
// Hertz family (hertz, lankarani-nikravesh, hunt-crossley, flores, gonthier, elasto-plastic,
// impact; linear laws through it): K = (4/3) E* √R*, R* = R_b R_p/(R_b − R_p) (a pin inside a
// bush: the radii of curvature subtract). Pinned by the Hertz contact-radius solution
// a³ = 3FR*/(4E*), δ = a²/R* (Johnson 1985, eqs. 4.22–4.23) and by the h-form of Lankarani &
// Nikravesh 1990, K = 4/(3π(h_i+h_j))·√R*.
// Line-contact laws (esdu-78035, johnson, dubowsky-freudenstein) all have the form
//   δ(F) = a F [ln(b/F) + c₀],  a = Σh/L  [m/N].
// The coefficient a of F·ln(1/F) is fixed by 2-D elasticity: a line load P per length on an
// elastic half-plane gives surface displacements 2(1−ν²)P/(πE)·ln(1/r) (Flamant; Johnson 1985
// §2.2), and with contact half-width ∝ √P each body contributes (1−ν²)/(πE)·P·ln(1/P), i.e. h.
// Johnson's two-cylinder formula δ = F/(πLE*)[ln(4πLE*ΔR/F) − 1] already has a = 1/(πLE*) = Σh/L.
// ESDU-78035 is published as δ = F(σᵢ+σⱼ)/L·[ln(4πLΔR/(F(σᵢ+σⱼ))) + 1] in one form; with
// σ = (1−ν²)/E its log coefficient would be π times the elastic value while its log argument
// 4πLΔR/(Fσ) = 4LΔR/(FΣh) is the h-argument. We therefore read it with the leading factor in the
// h convention: δ = F Σh/L·[ln(4LΔR/(F Σh)) + 1], which differs from Johnson only by the constant
// (+1 vs −1, a different displacement datum): δ_ESDU − δ_Johnson = 2FΣh/L (tested).
// Dubowsky–Freudenstein is stated in h: δ = F Σh/L·[ln(L³ΔR/(F R_b R_p Σh)) + 1].
// Pereira et al. 2011: E* (σ convention), fit in mm/N/(N/mm²), converted once (see PereiraLaw).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "contact/geometry.h"

namespace flexrod::contact {

/// Default coefficient of restitution [-] when none is given. Assumed (the thesis used values up
/// to 0.995 from Schnurmann's steel-ball measurements, RIG.md §1); 0.9 is a common engineering
/// value for hardened steel at moderate impact speed.
inline constexpr double kDefaultRestitution = 0.9;

/// Elastic properties of the pin and bush materials and the restitution of the pair.
struct ContactMaterials {
  double pin_youngs_modulus{0.0};           ///< E_pin [Pa], > 0
  double pin_poisson_ratio{0.0};            ///< ν_pin [-], in (−1, 0.5)
  double bush_youngs_modulus{0.0};          ///< E_bush [Pa], > 0
  double bush_poisson_ratio{0.0};           ///< ν_bush [-], in (−1, 0.5)
  double restitution{kDefaultRestitution};  ///< cₑ [-], in (0, 1]
  /// Throws InputError("contact.<field>", value, rule) for any invalid field.
  void Validate() const;
};

/// σ = (1 − ν²)/E [1/Pa] for one material.
double MaterialCompliance(double youngs_modulus, double poisson_ratio);
/// E* = 1/(σ_pin + σ_bush) [Pa].
double EffectiveModulus(const ContactMaterials& materials);
/// Σh = (σ_pin + σ_bush)/π = 1/(π E*) [1/Pa] (the "h" convention).
double PiCompliance(const ContactMaterials& materials);
/// R* = R_bush R_pin/(R_bush − R_pin) [m] for a pin inside a bush.
double InternalContactRadius(const ContactGeometry& geometry);
/// K = (4/3) E* √R* [N/m^1.5].
double HertzStiffness(const ContactMaterials& materials, const ContactGeometry& geometry);

/// Default working penetration [m] over which ESDU-78035 (hybrid) and Hertz (linear spring,
/// Kelvin–Voigt, Maxwell, SLS) are fitted by a single power law. Assumed: 10 µm covers the
/// steel pin-in-bush forces of the rigs (ESDU gives δ ≈ 4 µm at 2 kN for L = 12.7 mm,
/// ΔR = 0.5 mm); the thesis fitted "the area of interest" without stating it (§3.3.4).
inline constexpr double kDefaultWorkingPenetration = 1e-5;
/// Default floor on the approach velocity v₀ in the hysteresis damping term D̃ δ̇/v₀ [m/s].
/// Assumed: keeps the damping finite for contacts that begin with a vanishing approach speed
/// (a joint rolling into persistent contact); impacts slower than this are damped as if they
/// arrived at this speed.
inline constexpr double kDefaultMinApproachVelocity = 1e-3;
/// ADAMS IMPACT default penetration over which the damping ramps in, d_max = 0.01 mm [m] (the
/// MSC ADAMS/Solver IMPACT guideline value).
inline constexpr double kDefaultImpactDampingPenetration = 1e-5;
/// Approach speed [m/s] at which the ADAMS IMPACT damping is calibrated to the restitution when
/// no calibration-velocity is given. Assumed: the order of the relative speeds in the rigs'
/// clearance (crank pin speed 0.3–1.3 m/s at 100–250 rpm).
inline constexpr double kDefaultCalibrationVelocity = 0.5;

// ---------------------------------------------------------------------------------------------
// Law value types. All fields SI; they are produced by ResolveNormalLaw (validated) and never
// change afterwards.

/// F = k δ.
struct LinearSpringLaw {
  double stiffness;  ///< k [N/m]
};
/// F = k δ + d δ̇ (clipped at 0). The one law whose force jumps at δ = 0 while approaching
/// (by d·δ̇): the known defect of the Kelvin–Voigt contact.
struct KelvinVoigtLaw {
  double stiffness;  ///< k [N/m]
  double damping;    ///< d [N·s/m], ≥ 0
};
/// Spring k in series with dashpot d (Ḟ/k + F/d = δ̇). State x_d: dashpot displacement [m];
/// F = k·max(0, δ − x_d), ẋ_d = F/d. The element cannot pull: once the spring is slack the
/// dashpot stops (the wall keeps its set). damping = +∞ is a pure spring.
struct MaxwellLaw {
  double stiffness;  ///< k [N/m]
  double damping;    ///< d [N·s/m], > 0, may be +∞
};
/// Standard linear solid (Zener): spring k₁ in parallel with a Maxwell arm (k₂, d).
/// State x_d: arm dashpot displacement [m]; F = max(0, k₁δ + k₂(δ − x_d)),
/// ẋ_d = k₂(δ − x_d)/d.
struct StandardLinearSolidLaw {
  double stiffness;      ///< k₁ [N/m], the equilibrium spring
  double arm_stiffness;  ///< k₂ [N/m]
  double damping;        ///< d [N·s/m], > 0
};
/// F = K δⁿ (Hertz 1882).
struct HertzLaw {
  double stiffness;  ///< K [N/m^n]
  double exponent;   ///< n [-]
};

/// Parameters shared by the hysteresis family F = K δⁿ (1 + D̃ δ̇/v₀).
struct HysteresisParameters {
  double stiffness;              ///< K [N/m^n]
  double exponent;               ///< n [-]
  double restitution;            ///< cₑ [-]
  double damping_factor;         ///< D̃ [-], from cₑ by the law's formula
  double min_approach_velocity;  ///< floor on v₀ [m/s]
};
/// D̃ = 3(1 − cₑ²)/4 (Lankarani & Nikravesh 1990); accurate for cₑ near 1 only.
struct LankaraniNikraveshLaw {
  HysteresisParameters hysteresis;
};
/// D̃ = 3(1 − cₑ)/2 (Hunt & Crossley 1975).
struct HuntCrossleyLaw {
  HysteresisParameters hysteresis;
};
/// D̃ = 8(1 − cₑ)/(5cₑ) (Flores, Machado, Silva, Martins 2011); valid over the whole cₑ range.
struct FloresLaw {
  HysteresisParameters hysteresis;
};
/// D̃ = (1 − cₑ²)/cₑ (Gonthier et al. 2004, approximate form).
struct GonthierLaw {
  HysteresisParameters hysteresis;
};
/// Pereira, Ramalho, Ambrósio 2011, internal cylindrical contact: K = (aΔR + b) L E*/ΔR and
/// n = Y ΔR^(−0.005) from a fit in mm, N, N/mm²; D̃ = 3(1 − cₑ²)/4. With the fit constants
/// K_mm [N/mm^n], K = K_mm·1000ⁿ [N/m^n].
struct PereiraLaw {
  HysteresisParameters hysteresis;
  double clearance;  ///< ΔR [m] (for the record)
};
/// The thesis's modified model (eq. 29), our reading: the Lankarani–Nikravesh framework
/// F = K δⁿ + χ δⁿ δ̇ with the stiffness replaced by k_ES, the ESDU-78035 law fitted by k_ES·δⁿ
/// over the working range [0, δ_w] (least squares; for n = 1 this is exactly the thesis's
/// linearisation, §3.3.4), and the damping scaled by the stiffness ratio,
/// C_mod = C_LN·k_ES/k_LN with C_LN = χ_LN δⁿ = 3 K_LN (1−cₑ²)/(4v₀)·δⁿ. The ratio cancels K_LN:
/// χ_mod = 3 k_ES (1 − cₑ²)/(4v₀), so the hybrid is Lankarani–Nikravesh with K = k_ES.
/// Exponent default 1.5 ("a value of 1.5 for the contact model exponent seems to work best",
/// thesis §3.5).
struct HybridLaw {
  HysteresisParameters hysteresis;
  double working_penetration;            ///< δ_w [m], top of the fitted range
  double fit_r_squared;                  ///< R² of the fit over [0, δ_w] [-] (thesis: > 0.9)
  double lankarani_nikravesh_stiffness;  ///< K_LN = Hertz K [N/m^1.5] (for the record)
};
/// ADAMS-style IMPACT: F = K δⁿ + STEP(δ; 0 → d_max; 0 → c_max)·δ̇ with the cubic
/// STEP(x) = h₀ + (h₁ − h₀)Δ²(3 − 2Δ), Δ = clamp(x/d_max, 0, 1). (ADAMS writes −STEP·ẋ with ẋ
/// the separation rate; here δ̇ > 0 approaching, so the damping term is +.)
struct ImpactFunctionLaw {
  double stiffness;            ///< K [N/m^n]
  double exponent;             ///< n [-]
  double max_damping;          ///< c_max [N·s/m]
  double damping_penetration;  ///< d_max [m]
};

/// δ(F) = a F [ln(b/F) + c₀] for F in (0, F_lim], F_lim = b·e^(c₀−1), where dδ/dF = 0.
/// F(δ) is solved at each evaluation by a safeguarded Newton iteration in ln F, whose
/// convergence from any start is guaranteed because the residual is increasing and concave in
/// ln F (normal_law.cc); relative residual ≤ 1e-12 (tested against the exact Lambert-W₋₁
/// solution). dF/dδ = 1/(dδ/dF) = 1/(a[ln(b/F) + c₀ − 1]) by implicit differentiation.
/// Monotone on that branch up to δ_lim = a F_lim; beyond δ_lim the law has no elastic solution
/// (the formula turns over) and the force is continued linearly with the secant slope
/// F_lim/δ_lim (continuous, monotone; δ_lim is ≥ 0.5 ΔR for these laws, far beyond any elastic
/// penetration; ValidPenetrationLimit() reports it).
struct LogLineCurve {
  double coefficient;  ///< a [m/N]
  double force_scale;  ///< b [N]
  double constant;     ///< c₀ [-]
};
/// ESDU-78035, cylinder in a bore: a = Σh/L, b = 4LΔR/Σh, c₀ = +1; δ_lim = 4ΔR.
struct Esdu78035Law {
  double compliance;  ///< Σh [1/Pa]
  double length;      ///< L [m]
  double clearance;   ///< ΔR [m]
  LogLineCurve curve;
};
/// Johnson 1985 (two cylinders): a = Σh/L, b = 4LΔR/Σh (= 4πLE*ΔR), c₀ = −1; δ_lim = 4ΔR/e².
struct JohnsonLaw {
  double compliance;  ///< Σh [1/Pa]
  double length;      ///< L [m]
  double clearance;   ///< ΔR [m]
  LogLineCurve curve;
};
/// Dubowsky & Freudenstein 1971: a = Σh/L, b = L³ΔR/(R_b R_p Σh), c₀ = +1;
/// δ_lim = L²ΔR/(R_b R_p).
struct DubowskyFreudensteinLaw {
  double compliance;   ///< Σh [1/Pa]
  double length;       ///< L [m]
  double clearance;    ///< ΔR [m]
  double bush_radius;  ///< R_b [m]
  double pin_radius;   ///< R_p [m]
  LogLineCurve curve;
};
/// Lankarani & Nikravesh 1994: loading F = K δⁿ; unloading/reloading below δ_max
/// F = F_max [(δ − δ_p)/(δ_max − δ_p)]ⁿ, δ_p = δ_max(1 − cₑ²) (so the energy returned is cₑ² of
/// that absorbed: the restitution is exactly cₑ). History state: {δ_max [m], F_max [N]}.
struct ElastoPlasticLaw {
  double stiffness;    ///< K [N/m^n]
  double exponent;     ///< n [-]
  double restitution;  ///< cₑ [-]
};

using NormalLaw = std::variant<LinearSpringLaw, KelvinVoigtLaw, MaxwellLaw, StandardLinearSolidLaw,
                               HertzLaw, LankaraniNikraveshLaw, HuntCrossleyLaw, FloresLaw,
                               GonthierLaw, ImpactFunctionLaw, Esdu78035Law, JohnsonLaw,
                               DubowskyFreudensteinLaw, PereiraLaw, ElastoPlasticLaw, HybridLaw>;

/// The kebab-case names, in variant order: linear-spring, kelvin-voigt, maxwell,
/// standard-linear-solid, hertz, lankarani-nikravesh, hunt-crossley, flores, gonthier, impact,
/// esdu-78035, johnson, dubowsky-freudenstein, pereira, elasto-plastic, hybrid.
const std::vector<std::string>& NormalLawNames();
std::string_view NormalLawName(const NormalLaw& law);
/// The override keys a law accepts (e.g. {"stiffness", "exponent"} for hertz). Throws
/// InputError("contact.law", name, ...) for an unknown name.
const std::vector<std::string>& NormalLawParameterKeys(std::string_view name);

// ---------------------------------------------------------------------------------------------
// Construction

/// Parameter overrides by kebab-case key, SI values. Keys: stiffness [N/m or N/m^n],
/// stiffness-2 [N/m], damping [N·s/m], exponent [-], restitution [-], effective-mass [kg],
/// working-penetration [m], min-approach-velocity [m/s], max-damping [N·s/m],
/// damping-penetration [m], calibration-velocity [m/s], compliance (Σh) [1/Pa].
using ParameterMap = std::map<std::string, double, std::less<>>;

/// One entry of the resolved-input record.
struct ResolvedParameter {
  std::string name;    ///< kebab-case key or derived quantity name
  double value;        ///< SI
  std::string unit;    ///< SI unit, e.g. "N/m^1.5"
  std::string source;  ///< "input" (override), "derived" (from materials/geometry), "default"
};

struct ResolvedNormalLaw {
  NormalLaw law;
  std::vector<ResolvedParameter> parameters;
};

/// Builds a law by name. Defaults are derived from materials and geometry:
///  * hertz & hysteresis family, elasto-plastic, impact: K = (4/3)E*√R*, n = 1.5;
///  * linear-spring, kelvin-voigt, maxwell: k = least-squares fit of K_Hertz δ^1.5 by kδ on
///    [0, δ_w], k = (6/7)K√δ_w (δ_w = working-penetration, default 10 µm);
///    standard-linear-solid: k₁ = k/2, k₂ = k₁ (instantaneous stiffness k);
///  * kelvin-voigt damping: d = 2ζ√(k m) with ζ such that the non-tensile oscillator reaches cₑ
///    (KelvinVoigtRestitution); maxwell: d = √(k m)/(2ζ), cₑ = exp(−πζ/√(1−ζ²)) exactly;
///    standard-linear-solid: d calibrated numerically so a single impact reaches cₑ, on the
///    branch of larger d (the arm close to elastic). These three need effective-mass m unless
///    damping is given or cₑ = 1;
///  * impact: d_max = 0.01 mm; c_max calibrated numerically so one impact of effective-mass m at
///    calibration-velocity v reaches cₑ (the law is not scale-invariant; needs m unless
///    max-damping is given);
///  * pereira: Pereira et al. 2011 fit; esdu-78035/johnson/dubowsky-freudenstein: Σh, L, ΔR;
///  * hybrid: k_ES fitted to ESDU-78035 over [0, δ_w], n = 1.5.
/// Throws InputError for an unknown name ("contact.law"), a key the law does not take, a value
/// outside its rule, invalid materials/geometry, or an unreachable restitution.
ResolvedNormalLaw ResolveNormalLaw(std::string_view name, const ContactMaterials& materials,
                                   const ContactGeometry& geometry,
                                   const ParameterMap& overrides = {});
inline NormalLaw MakeNormalLaw(std::string_view name, const ContactMaterials& materials,
                               const ContactGeometry& geometry,
                               const ParameterMap& overrides = {}) {
  return ResolveNormalLaw(name, materials, geometry, overrides).law;
}

// ---------------------------------------------------------------------------------------------
// Evaluation (hot path: no allocation, no virtual call)

inline constexpr int kMaxLawStates = 2;
/// Internal state of a law; unused entries are 0.
using LawState = std::array<double, kMaxLawStates>;

enum class LawStateKind {
  kNone,          ///< stateless
  kDifferential,  ///< maxwell, standard-linear-solid: one ODE state x_d [m], integrated by the
                  ///< caller with CalcLawStateRate
  kHistory,       ///< elasto-plastic: {δ_max [m], F_max [N]}, updated by the caller with
                  ///< UpdateLawHistory after each accepted step
};
LawStateKind StateKind(const NormalLaw& law);
int NumLawStates(const NormalLaw& law);
/// State at contact onset (δ crossing 0 upwards): all zeros for every law. The caller resets
/// the state at every onset.
LawState InitialLawState(const NormalLaw& law);

/// δ^e for a penetration δ ≥ 0, exact-rounded square roots for the common Hertzian exponents
/// (e = 0.5, 1.5: 3× cheaper than std::pow, which the contact residual calls on every evaluation).
inline double PenetrationPower(double d, double e) {
  if (e == 0.5) return std::sqrt(d);
  if (e == 1.5) return d * std::sqrt(d);
  if (e == 1.0) return d;
  if (e == 0.0) return 1.0;
  return std::pow(d, e);
}

struct NormalForce {
  double force{0.0};          ///< F ≥ 0 [N]
  double d_penetration{0.0};  ///< ∂F/∂δ [N/m]
  double d_rate{0.0};         ///< ∂F/∂δ̇ [N·s/m]
  double d_state{0.0};        ///< ∂F/∂x_d [N/m] (differential-state laws; else 0)
};

/// F(δ, δ̇; v₀, state). approach_velocity v₀ is δ̇ at onset (only the hysteresis family uses it,
/// floored at min_approach_velocity).
NormalForce CalcNormalForce(const NormalLaw& law, double penetration, double rate,
                            double approach_velocity, const LawState& state);

struct LawStateRate {
  double rate{0.0};           ///< ẋ_d [m/s]
  double d_penetration{0.0};  ///< ∂ẋ_d/∂δ [1/s]
  double d_state{0.0};        ///< ∂ẋ_d/∂x_d [1/s]
};
/// Derivative of the differential state (zero for laws without one).
LawStateRate CalcLawStateRate(const NormalLaw& law, double penetration, const LawState& state);

/// Elasto-plastic history update, called after each accepted step (and at a located maximum of
/// δ, which a caller should find with a root function on δ̇): if δ > δ_max then δ_max = δ,
/// F_max = K δⁿ. No-op for other laws. Within a step the state is frozen; δ above the stored
/// δ_max follows the loading curve, which is exact on the loading branch.
void UpdateLawHistory(const NormalLaw& law, double penetration, LawState* state);

/// For the line-contact laws: the explicit δ(F) [m] the force is solved from (tests, records).
/// Throws std::logic_error for other laws.
double LineLawPenetration(const NormalLaw& law, double force);
/// Penetration beyond which a law has no valid elastic branch [m]: δ_lim of the line-contact
/// laws, +∞ otherwise.
double ValidPenetrationLimit(const NormalLaw& law);

// ---------------------------------------------------------------------------------------------
// Restitution relations used to derive damping

/// Restitution of a mass on a Kelvin–Voigt wall whose force cannot pull (contact ends when
/// kδ + dδ̇ = 0), ζ = d/(2√(km)): cₑ = exp(−2ζ·arccos(ζ)/√(1−ζ²)) for ζ < 1,
/// exp(−2ζ·arccosh(ζ)/√(ζ²−1)) for ζ > 1 (derived in normal_law.cc; cf. Schwager & Pöschel,
/// Granular Matter 9 (2007) 465). The textbook exp(−πζ/√(1−ζ²)) assumes a wall that pulls;
/// the two agree to O(ζ²) for light damping.
double KelvinVoigtRestitution(double damping_ratio);
/// Textbook linear-oscillator restitution exp(−πζ/√(1−ζ²)) (0 for ζ ≥ 1): exact for a mass on a
/// Kelvin–Voigt wall that may pull, and for the Maxwell law with ζ = √(km)/(2d).
double LinearOscillatorRestitution(double damping_ratio);

}  // namespace flexrod::contact
