// multibody/clearance_joint.h — the planar revolute joint with radial clearance (a pin in a
// bush) as a force element of the multibody engine: contact detection by root functions, the
// per-run contact memory (flag, approach velocity at onset, elasto-plastic history, state
// offsets), the contact forces from contact::CalcClearanceKinematics, a normal law and an
// optional friction law, their internal states (Maxwell / standard-linear-solid dashpot, LuGre
// bristle) as element states, and the energy bookkeeping (stored elastic energy and dissipation
// rate) that closes the run's energy balance. CalcClearanceResponse evaluates the joint at an
// output sample or an integrator step, for the report channels and the impact log. What does not
// live here: the laws and the geometry (contact/), the resolution of laws from input keys
// (mechanisms/joint_config.h), the impact log (mechanisms/impact_log.h, built from the located
// events).
//
// Markers: i = the bush centre B (on the rod's small-end clamp: node marker of a flexible rod or
// a rigid-body marker), j = the pin (journal) centre P (on the slider). Both marker points are
// the circle centres, so the loads of contact::CalcContactLoads (force at the contact point
// Q, moment about the centre) are exactly force-at-marker + moment-about-marker: moving a force
// F from Q to the centre adds (Q − centre) × F, which is the ±R F_t of CalcContactLoads.
//
// Contact logic. Contact is "on" between a located onset (root δ = +b crossed upwards) and a
// located separation (δ = −b crossed downwards); the flag lives in the run memory. The event
// band b = 1e-6·clearance (EventBand; 0.5 nm at 0.5 mm) is a hysteresis on the root function,
// g₀ = δ − b with the flag off and δ + b with it on, so a root just found cannot be found again
// from round-off. Without it (g₀ = δ) a restart at an onset left g₀ at ±1e-16 m of either sign
// (the round-off of δ = |r_P − r_B| − c at |r| ≈ 0.3 m), IDA reported a "separation" at the
// same instant while the pin still approached, and the alternation could end with the flag off
// and δ growing without force: the pin went through the bush (every normal law with LuGre
// friction on both rigs; the restart at separation is what LuGre's state adds). A band of
// 1e-9·clearance stopped the round-off but not the Kelvin–Voigt micro-bounces at onset (its
// damping force d·δ̇ acts at δ = 0): the pin left by 2b within the first step a thousand times
// over. 1e-6·clearance leaves one such bounce. It is far below loaded penetrations (µm): the
// force at δ = b is 5e-2 N for a linear 1e8 N/m contact, and the energy skipped is (b/δ_max)²
// of an impact's. The force needs δ > 0 as well, so it is zero inside the band. While the
// flag is off the force is exactly zero even if δ > 0 inside the step that overshoots the onset,
// so every integrator step sees one smooth law. At onset OnRoot stores the approach velocity
// v₀ = max(δ̇, law floor), resets the law states and asks for a restart. Differential states are
// reset without writing z (OnRoot receives z read-only): the memory keeps z at onset and the
// laws see z − z_onset. Elasto-plastic laws get a second root, δ̇ = 0 while in contact
// (maximum penetration), at which the history {δ_max, F_max} is updated (UpdateLawHistory) and
// the integrator restarted. With the flag off the states are frozen (ż = 0), except the
// standard-linear-solid arm, which relaxes as the free wall does (see below).
//
// Energy. PotentialEnergy is the elastic energy E stored in the contact and the reported
// dissipation is D = F_n δ̇ − dE/dt (normal) + (−F_t v_t) (friction), with dE/dt evaluated
// analytically from ∂E/∂δ and ∂E/∂x_d, so the run's energy balance closes for every law:
//  * linear-spring, kelvin-voigt: E = ½kδ²;
//  * hertz and the hysteresis family (lankarani-nikravesh, hunt-crossley, flores, gonthier,
//    pereira, hybrid) and impact: E = Kδⁿ⁺¹/(n+1), the integral of the elastic part Kδⁿ;
//    D = (F − Kδⁿ)δ̇ ≥ 0 (the damping term, or −Kδⁿδ̇ > 0 while the force is clipped);
//  * esdu-78035, johnson, dubowsky-freudenstein (elastic, implicit): E = ∫₀^δ F dδ in closed
//    form from δ(F) = aF[ln(b/F) + c₀]: E = ½Fδ − ¼aF² (integration by parts); D = 0;
//  * maxwell: E = ½k·max(0, δ − x_d)², D = F ẋ_d = F²/d ≥ 0;
//  * standard-linear-solid: E = ½k₁δ² + ½k₂(δ − x_d)² while the force is positive, else the
//    energy of the free wall ½κx_d² (κ = k₁k₂/(k₁+k₂)), whose surface then sits at
//    δ_w = k₂x_d/(k₁+k₂); the arm relaxes with ẋ_d = k₂(max(δ, δ_w) − x_d)/d, so D = d ẋ_d² ≥ 0.
//    At the next onset the states are reset: the remainder of ½κx_d² still held then (it decays
//    as exp(−2t/τ), τ = d(k₁+k₂)/(k₁k₂), between impacts) leaves the balance — the one law
//    whose balance is not exact;
//  * elasto-plastic (Lankarani & Nikravesh 1994): on the loading curve E = cₑ²Kδⁿ⁺¹/(n+1), the
//    energy the unloading curve from the current δ would return, so D = (1 − cₑ²)Kδⁿδ̇ ≥ 0
//    while loading; on the unloading curve E = F_max(δ − δ_p)ⁿ⁺¹/((n+1)(δ_max − δ_p)ⁿ), D = 0.
//    E is continuous where the history changes.
// Friction: D_t = −F_t v_t, ≥ 0 for coulomb, threlfall, stribeck; lugre's bristles store and
// return energy, so its D_t can be briefly negative (the balance still closes).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <array>
#include <optional>
#include <string>

#include "contact/friction_law.h"
#include "contact/geometry.h"
#include "contact/normal_law.h"
#include "multibody/force_element.h"
#include "multibody/mechanism.h"

namespace flexrod::multibody {

class SampleView;  // multibody/simulate.h

/// At most one normal-law state and one friction state.
inline constexpr int kMaxClearanceStates = 2;

/// Slots of the joint's per-run memory.
enum ClearanceMemorySlot : int {
  kContactFlag = 0,       ///< 1 between a located onset and the next separation, else 0
  kApproachVelocity = 1,  ///< v₀ = max(δ̇ at onset, law floor) [m/s]
  kMaxPenetration = 2,    ///< elasto-plastic history δ_max [m] (0 on the loading curve)
  kMaxForce = 3,          ///< elasto-plastic history F_max [N]
  kOnsetTime = 4,         ///< time of the last onset [s]
  kOnsetCount = 5,        ///< number of onsets in the run [-]
  kStatesAtOnset = 6,     ///< z at the last onset, num_states() entries (laws see z − z_onset)
};

/// Everything the joint computes at one instant.
struct ClearanceResponse {
  contact::ClearanceKinematics kinematics;  ///< δ, δ̇, n, t, slip, eccentricity (contact/geometry.h)
  bool in_contact{false};                   ///< contact flag on and δ > 0
  bool contact_flag{false};                 ///< on from a located onset to the located separation
  long onsets{0};                  ///< onsets located so far in the run (incl. a start in contact)
  double onset_time{0.0};          ///< time of the last located onset [s]
  double approach_velocity{0.0};   ///< v₀ in use [m/s]
  double normal_force{0.0};        ///< F_n ≥ 0 [N]
  double friction_force{0.0};      ///< F_t on the pin along t [N]
  contact::ContactLoads loads;     ///< force on pin/bush, moments about the centres
  double potential_energy{0.0};    ///< elastic energy stored in the contact E [J]
  double normal_dissipation{0.0};  ///< F_n δ̇ − dE/dt [W]
  double friction_dissipation{0.0};                       ///< −F_t v_t [W]
  std::array<double, kMaxClearanceStates> state_rates{};  ///< ż (num_states() entries)
  /// Total dissipation rate [W].
  double dissipation() const { return normal_dissipation + friction_dissipation; }
};

/// Pin (journal) in a bush with radial clearance, between marker i = bush centre and marker
/// j = pin centre. Immutable and thread-safe; all run data is in z and the memory.
class ClearanceJoint final : public ForceElement {
 public:
  /// `friction_law` = std::nullopt: frictionless. Throws InputError if the geometry is invalid
  /// (contact::ContactGeometry::Validate).
  ClearanceJoint(const contact::ContactGeometry& geometry, contact::NormalLaw normal_law,
                 std::optional<contact::FrictionLaw> friction_law);

  int num_states() const override { return num_states_; }
  int num_memory() const override { return kStatesAtOnset + num_states_; }
  /// δ (onset/separation); elasto-plastic laws also δ̇ while in contact (maximum penetration).
  int num_roots() const override { return history_law_ ? 2 : 1; }

  /// Contact flag on if the joint starts penetrated (δ > 0), with v₀ = max(δ̇, floor).
  void Initialize(const MarkerKinematics& bush, const MarkerKinematics& pin, double* z,
                  double* memory) const override;
  bool Evaluate(double t, const MarkerKinematics& bush, const MarkerKinematics& pin,
                const double* z, const double* memory, ElementOutput* out) const override;
  /// Forces, moments and state rates analytic from the laws' derivatives; the dissipation
  /// row differenced in the law variables (see the definition).
  bool EvaluateJacobian(double t, const MarkerKinematics& bush, const MarkerKinematics& pin,
                        const double* z, const double* memory, Mat* d_kinematics,
                        Mat* d_states) const override;
  double PotentialEnergy(const MarkerKinematics& bush, const MarkerKinematics& pin, const double* z,
                         const double* memory) const override;
  /// g[0] = δ − b with the flag off, δ + b with it on [m] (b = EventBand()); g[1] = δ̇ [m/s]
  /// while in contact, 1 otherwise (elasto-plastic only).
  void Roots(double t, const MarkerKinematics& bush, const MarkerKinematics& pin, const double* z,
             const double* memory, double* g) const override;
  /// Root 0 upwards with the flag off: onset (flag on, v₀, state reset, count) → restart. Root 0
  /// downwards with the flag on: separation (flag off) → restart if the joint has states (their
  /// rates switch law). Root 0 in the other direction changes nothing.
  /// Root 1 downwards in contact: maximum penetration, history update → restart.
  bool OnRoot(int index, int direction, double t, const MarkerKinematics& bush,
              const MarkerKinematics& pin, const double* z, double* memory) const override;
  /// length = 1e-3·clearance; speed = min(1e-3 m/s, the friction law's regularisation velocity);
  /// angular speed = speed / R_bush.
  FiniteDifferenceScales fd_scales() const override;
  /// Hysteresis of the contact root function, b = 1e-6·clearance [m] (see the file comment).
  double EventBand() const;
  bool relative_kinematics() const override { return true; }
  /// Normal-law state x_d: 1e-2·clearance [m]; LuGre z: μ_s/σ̂₀ [m].
  double StateScale(int k) const override;
  /// The radial clearance: the pin's motion inside the bush.
  double ResolvedLength() const override { return geometry_.clearance(); }
  std::string type_name() const override { return "clearance-joint"; }

  /// The joint's response for given marker kinematics, states z and memory (pure function;
  /// Evaluate, PotentialEnergy and the report channels all use it). Allocation-free.
  ClearanceResponse CalcResponse(const MarkerKinematics& bush, const MarkerKinematics& pin,
                                 const double* z, const double* memory) const;

  const contact::ContactGeometry& geometry() const { return geometry_; }
  const contact::NormalLaw& normal_law() const { return normal_law_; }
  const std::optional<contact::FrictionLaw>& friction_law() const { return friction_law_; }
  /// Index in z of the normal-law state / the friction state, −1 if none.
  int normal_state_index() const { return normal_state_; }
  int friction_state_index() const { return friction_state_; }
  /// Floor on v₀ used by the law [m/s] (0 for laws without v₀).
  double min_approach_velocity() const { return min_approach_velocity_; }

 private:
  /// The laws at given kinematics (δ, δ̇ and v_t are all they read), with their derivatives.
  struct LawValues {
    bool in_contact{false};
    contact::NormalForce normal;               ///< F_n and ∂F_n/∂(δ, δ̇, x) (zero when open)
    contact::LawStateRate normal_rate;         ///< ẋ of the normal law's state
    contact::FrictionForce friction;           ///< F_t and ∂F_t/∂(v_t, F_n, z) (zero when open)
    contact::FrictionStateRate friction_rate;  ///< ż of LuGre (zero when open)
    double potential_energy{0.0};              ///< E [J]
    double normal_dissipation{0.0};            ///< F_n δ̇ − dE/dt [W]
    double friction_dissipation{0.0};          ///< −F_t v_t [W]
    double dissipation() const { return normal_dissipation + friction_dissipation; }
  };
  LawValues EvaluateLaws(const contact::ClearanceKinematics& k, const double* z,
                         const double* memory) const;
  using KinematicRow = Eigen::Matrix<double, 1, kElementKinematicColumns>;
  /// The law variables' derivatives ∂δ/∂κ, ∂δ̇/∂κ, ∂v_t/∂κ (EvaluateJacobian), with the
  /// eccentricity r = max(|e|, contact::kMinEccentricity) [m] they divide by.
  struct LawVariableRows {
    double r{0.0};
    KinematicRow d_delta{KinematicRow::Zero()};
    KinematicRow d_rate{KinematicRow::Zero()};
    KinematicRow d_slip{KinematicRow::Zero()};
  };
  LawVariableRows CalcLawVariableRows(const contact::ClearanceKinematics& k,
                                      const MarkerKinematics& bush,
                                      const MarkerKinematics& pin) const;
  /// EvaluateJacobian's force and moment rows (0–5) and state-rate rows (7…), analytic.
  void FillForceAndRateRows(const contact::ClearanceKinematics& k, const LawValues& v,
                            const LawVariableRows& rows, Mat* d_kinematics, Mat* d_states) const;
  /// EvaluateJacobian's dissipation row (6), by central differences in δ, δ̇, v_t and z.
  void FillDissipationRow(const contact::ClearanceKinematics& k, const LawValues& v,
                          const LawVariableRows& rows, const double* z, const double* memory,
                          Mat* d_kinematics, Mat* d_states) const;
  contact::LawState LawStateOf(const double* z, const double* memory) const;
  bool InContact(const contact::ClearanceKinematics& k, const double* memory) const;

  contact::ContactGeometry geometry_;
  contact::NormalLaw normal_law_;
  std::optional<contact::FrictionLaw> friction_law_;
  int num_states_{0};
  int normal_state_{-1};
  int friction_state_{-1};
  bool history_law_{false};
  double min_approach_velocity_{0.0};
};

/// The response of the clearance joint `element` at an output sample: marker kinematics from
/// the sample, z from its state vector, memory from the run data. Throws std::invalid_argument
/// if the element is not a ClearanceJoint.
ClearanceResponse CalcClearanceResponse(const SampleView& sample, ElementId element);

}  // namespace flexrod::multibody
