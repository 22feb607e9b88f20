// multibody/clearance_joint.cc — the clearance joint force element (see clearance_joint.h for
// the contact logic and the energy bookkeeping of every law).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/clearance_joint.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <variant>

#include "multibody/simulate.h"

namespace flexrod::multibody {
namespace {

using contact::LawState;

// Elastic energy stored in the contact and its partial derivatives.
struct ElasticEnergy {
  double energy{0.0};         ///< E [J]
  double d_penetration{0.0};  ///< ∂E/∂δ [N]
  double d_state{0.0};        ///< ∂E/∂x_d [N]
};

/// E = Kδⁿ⁺¹/(n+1), ∂E/∂δ = Kδⁿ (scaled by `factor`).
ElasticEnergy PowerLawEnergy(double stiffness, double exponent, double penetration,
                             double factor = 1.0) {
  const double p = factor * stiffness * contact::PenetrationPower(penetration, exponent);
  return {p * penetration / (exponent + 1.0), p, 0.0};
}

/// Line-contact laws δ(F) = aF[ln(b/F) + c₀]: E = ∫₀^δ F dδ = Fδ − ∫₀^F δ(f) df = ½Fδ − ¼aF²
/// on the elastic branch; beyond δ_lim = aF_lim the force is continued linearly with slope 1/a
/// (normal_law.h), so E = ¼aF_lim² + F_lim Δ + Δ²/(2a), Δ = δ − δ_lim.
ElasticEnergy LineLawEnergy(const contact::LogLineCurve& curve, double penetration, double force) {
  const double a = curve.coefficient;
  const double limit_force = curve.force_scale * std::exp(curve.constant - 1.0);
  const double limit_penetration = a * limit_force;
  if (penetration <= limit_penetration) {
    return {0.5 * force * penetration - 0.25 * a * force * force, force, 0.0};
  }
  const double excess = penetration - limit_penetration;
  return {0.25 * a * limit_force * limit_force + limit_force * excess + 0.5 * excess * excess / a,
          force, 0.0};
}

/// The stored energy of the law. `in_contact`: flag on and δ > 0; `force` is the law's F.
ElasticEnergy CalcElasticEnergy(const contact::NormalLaw& law, bool in_contact, double penetration,
                                const LawState& s, double force) {
  const double d = penetration;
  return std::visit(
      [&](const auto& l) -> ElasticEnergy {
        using L = std::decay_t<decltype(l)>;
        if constexpr (std::is_same_v<L, contact::StandardLinearSolidLaw>) {
          // The free wall (force clipped or contact open) holds ½κx².
          const double x = s[0];
          const double kappa = l.stiffness * l.arm_stiffness / (l.stiffness + l.arm_stiffness);
          const double f = l.stiffness * d + l.arm_stiffness * (d - x);
          if (in_contact && f > 0.0) {
            return {0.5 * l.stiffness * d * d + 0.5 * l.arm_stiffness * (d - x) * (d - x), f,
                    -l.arm_stiffness * (d - x)};
          }
          return {0.5 * kappa * x * x, 0.0, kappa * x};
        } else {
          if (!in_contact) return {};
          if constexpr (std::is_same_v<L, contact::LinearSpringLaw> ||
                        std::is_same_v<L, contact::KelvinVoigtLaw>) {
            return {0.5 * l.stiffness * d * d, l.stiffness * d, 0.0};
          } else if constexpr (std::is_same_v<L, contact::MaxwellLaw>) {
            const double stretch = std::max(0.0, d - s[0]);
            return {0.5 * l.stiffness * stretch * stretch, l.stiffness * stretch,
                    -l.stiffness * stretch};
          } else if constexpr (std::is_same_v<L, contact::HertzLaw> ||
                               std::is_same_v<L, contact::ImpactFunctionLaw>) {
            return PowerLawEnergy(l.stiffness, l.exponent, d);
          } else if constexpr (std::is_same_v<L, contact::Esdu78035Law> ||
                               std::is_same_v<L, contact::JohnsonLaw> ||
                               std::is_same_v<L, contact::DubowskyFreudensteinLaw>) {
            return LineLawEnergy(l.curve, d, force);
          } else if constexpr (std::is_same_v<L, contact::ElastoPlasticLaw>) {
            const double max_penetration = s[0], max_force = s[1];
            const double e2 = l.restitution * l.restitution;
            if (d >= max_penetration) return PowerLawEnergy(l.stiffness, l.exponent, d, e2);
            const double set = max_penetration * (1.0 - e2);  // δ_p
            if (d <= set) return {};
            const double span = max_penetration - set;
            const double ratio = (d - set) / span;
            const double p = max_force * contact::PenetrationPower(ratio, l.exponent);
            return {p * (d - set) / (l.exponent + 1.0), p, 0.0};
          } else {  // hysteresis family: elastic part K δⁿ
            return PowerLawEnergy(l.hysteresis.stiffness, l.hysteresis.exponent, d);
          }
        }
      },
      law);
}

/// ẋ_d of the normal law's differential state and its partial derivatives. Maxwell: the law's
/// rate in contact, at rest otherwise. Standard linear solid: the arm relaxes towards the wall
/// surface δ_eff = max(δ, δ_w) in contact and δ_w when open, δ_w = k₂x/(k₁+k₂) (force-free
/// wall), so where δ_w wins the rate depends on x alone.
contact::LawStateRate NormalStateRate(const contact::NormalLaw& law, bool in_contact,
                                      double penetration, const LawState& s) {
  if (const auto* l = std::get_if<contact::StandardLinearSolidLaw>(&law)) {
    const double wall_per_state = l->arm_stiffness / (l->stiffness + l->arm_stiffness);
    const double wall = wall_per_state * s[0];
    if (in_contact && penetration >= wall) return contact::CalcLawStateRate(law, penetration, s);
    contact::LawStateRate r = contact::CalcLawStateRate(law, wall, s);
    r.d_state += r.d_penetration * wall_per_state;
    r.d_penetration = 0.0;
    return r;
  }
  if (!in_contact) return {};
  return contact::CalcLawStateRate(law, penetration, s);
}

/// The regularisation velocity of a friction law [m/s] (where its force changes fastest).
double FrictionVelocityScale(const contact::FrictionLaw& law) {
  return std::visit(
      [](const auto& l) -> double {
        using L = std::decay_t<decltype(l)>;
        if constexpr (std::is_same_v<L, contact::CoulombFrictionLaw>) {
          return l.stick_velocity;
        } else if constexpr (std::is_same_v<L, contact::ThrelfallFrictionLaw>) {
          return l.velocity_scale;
        } else {
          return l.stribeck_velocity;
        }
      },
      law);
}

double HysteresisFloor(const contact::NormalLaw& law) {
  return std::visit(
      [](const auto& l) -> double {
        if constexpr (requires { l.hysteresis; }) {
          return l.hysteresis.min_approach_velocity;
        } else {
          return 0.0;
        }
      },
      law);
}

/// Columns of κ (ForceElement) that the joint's Jacobian rows use: positions, velocities and
/// angular velocities of the bush (B) and the pin (P).
enum KinematicColumn : int { kPB = 0, kVB = 2, kWB = 5, kPP = 6, kVP = 8, kWP = 11 };

contact::ClearanceKinematics Kinematics(const contact::ContactGeometry& g,
                                        const MarkerKinematics& bush, const MarkerKinematics& pin) {
  contact::ClearanceMotion motion;
  motion.bush_centre = bush.position;
  motion.bush_velocity = bush.velocity;
  motion.bush_angular_velocity = bush.angular_velocity;
  motion.pin_centre = pin.position;
  motion.pin_velocity = pin.velocity;
  motion.pin_angular_velocity = pin.angular_velocity;
  return contact::CalcClearanceKinematics(g, motion);
}

}  // namespace

ClearanceJoint::ClearanceJoint(const contact::ContactGeometry& geometry,
                               contact::NormalLaw normal_law,
                               std::optional<contact::FrictionLaw> friction_law)
    : geometry_(geometry),
      normal_law_(std::move(normal_law)),
      friction_law_(std::move(friction_law)) {
  geometry_.Validate();
  const contact::LawStateKind kind = contact::StateKind(normal_law_);
  history_law_ = kind == contact::LawStateKind::kHistory;
  if (kind == contact::LawStateKind::kDifferential) normal_state_ = num_states_++;
  if (friction_law_ && contact::NumFrictionStates(*friction_law_) > 0) {
    friction_state_ = num_states_++;
  }
  FLEXROD_ASSERT(num_states_ <= kMaxClearanceStates);
  min_approach_velocity_ = HysteresisFloor(normal_law_);
}

LawState ClearanceJoint::LawStateOf(const double* z, const double* memory) const {
  LawState s{0.0, 0.0};
  if (history_law_) {
    s[0] = memory[kMaxPenetration];
    s[1] = memory[kMaxForce];
  } else if (normal_state_ >= 0) {
    s[0] = z[normal_state_] - memory[kStatesAtOnset + normal_state_];
  }
  return s;
}

bool ClearanceJoint::InContact(const contact::ClearanceKinematics& k, const double* memory) const {
  return memory[kContactFlag] > 0.5 && k.normal_defined && k.penetration > 0.0;
}

ClearanceJoint::LawValues ClearanceJoint::EvaluateLaws(const contact::ClearanceKinematics& k,
                                                       const double* z,
                                                       const double* memory) const {
  LawValues v;
  const double delta = k.penetration, rate = k.penetration_rate;
  const LawState s = LawStateOf(z, memory);
  v.in_contact = InContact(k, memory);
  if (v.in_contact) {
    v.normal = contact::CalcNormalForce(normal_law_, delta, rate, memory[kApproachVelocity], s);
  }
  if (normal_state_ >= 0) v.normal_rate = NormalStateRate(normal_law_, v.in_contact, delta, s);
  const ElasticEnergy e = CalcElasticEnergy(normal_law_, v.in_contact, delta, s, v.normal.force);
  v.potential_energy = e.energy;
  v.normal_dissipation = (v.normal.force - e.d_penetration) * rate - e.d_state * v.normal_rate.rate;
  // Friction (only while in contact: an open joint transmits nothing).
  if (friction_law_ && v.in_contact) {
    const double zf =
        friction_state_ >= 0 ? z[friction_state_] - memory[kStatesAtOnset + friction_state_] : 0.0;
    v.friction = contact::CalcFrictionForce(*friction_law_, k.slip_velocity, v.normal.force, zf);
    if (friction_state_ >= 0) {
      v.friction_rate = contact::CalcFrictionStateRate(*friction_law_, k.slip_velocity, zf);
    }
  }
  v.friction_dissipation = -v.friction.force * k.slip_velocity;
  return v;
}

ClearanceResponse ClearanceJoint::CalcResponse(const MarkerKinematics& bush,
                                               const MarkerKinematics& pin, const double* z,
                                               const double* memory) const {
  ClearanceResponse r;
  r.kinematics = Kinematics(geometry_, bush, pin);
  r.approach_velocity = memory[kApproachVelocity];
  r.contact_flag = memory[kContactFlag] > 0.5;
  r.onsets = std::lround(memory[kOnsetCount]);
  r.onset_time = memory[kOnsetTime];
  const LawValues v = EvaluateLaws(r.kinematics, z, memory);
  r.in_contact = v.in_contact;
  r.normal_force = v.normal.force;
  r.friction_force = v.friction.force;
  if (normal_state_ >= 0) r.state_rates[normal_state_] = v.normal_rate.rate;
  if (friction_state_ >= 0) r.state_rates[friction_state_] = v.friction_rate.rate;
  r.potential_energy = v.potential_energy;
  r.normal_dissipation = v.normal_dissipation;
  r.friction_dissipation = v.friction_dissipation;
  r.loads = contact::CalcContactLoads(geometry_, r.kinematics, r.normal_force, r.friction_force);
  return r;
}

void ClearanceJoint::Initialize(const MarkerKinematics& bush, const MarkerKinematics& pin,
                                double* /*z*/, double* memory) const {
  const contact::ClearanceKinematics k = Kinematics(geometry_, bush, pin);
  if (k.normal_defined && k.penetration > 0.0) {
    memory[kContactFlag] = 1.0;
    memory[kApproachVelocity] = std::max({k.penetration_rate, min_approach_velocity_, 0.0});
    memory[kOnsetCount] = 1.0;
  }
}

bool ClearanceJoint::Evaluate(double /*t*/, const MarkerKinematics& bush,
                              const MarkerKinematics& pin, const double* z, const double* memory,
                              ElementOutput* out) const {
  const ClearanceResponse r = CalcResponse(bush, pin, z, memory);
  if (!(std::isfinite(r.normal_force) && std::isfinite(r.friction_force) &&
        std::isfinite(r.normal_dissipation) && std::isfinite(r.friction_dissipation))) {
    return false;
  }
  out->force_i = r.loads.force_on_bush;
  out->moment_i = r.loads.moment_on_bush;
  out->force_j = r.loads.force_on_pin;
  out->moment_j = r.loads.moment_on_pin;
  out->dissipation = r.dissipation();
  for (int k = 0; k < num_states_; ++k) {
    if (!std::isfinite(r.state_rates[k])) return false;
    out->state_rates[k] = r.state_rates[k];
  }
  return true;
}

// Rows o = [F_bush (2), M_bush, F_pin (2), M_pin, D, ż]; columns κ = [p_B, v_B, φ_B, ω_B, p_P,
// v_P, φ_P, ω_P] (ForceElement). With e = p_P − p_B, ė = v_P − v_B, r = |e|, n = e/r, t = Jn:
//   dn = t tᵀ de / r,  dt = −n tᵀ de / r,  dδ = nᵀ de,
//   dδ̇ = (tᵀė / r) tᵀ de + nᵀ dė,  dv_t = −(δ̇ / r) tᵀ de + tᵀ dė + R_pin dω_P − R_bush dω_B,
// and F_pin = −F_n n + F_t t = −F_bush, M_pin = R_pin F_t, M_bush = −R_bush F_t, with the laws'
// own derivatives ∂F_n/∂(δ, δ̇, x), ∂F_t/∂(v_t, F_n, z), ∂ẋ/∂(δ, x), ∂ż/∂(v_t, z). The
// dissipation row (energy bookkeeping; no force depends on it) is differenced in the law
// variables (δ, δ̇, v_t, z): its closed form would need every law's second energy derivatives.
bool ClearanceJoint::EvaluateJacobian(double /*t*/, const MarkerKinematics& bush,
                                      const MarkerKinematics& pin, const double* z,
                                      const double* memory, Mat* d_kinematics,
                                      Mat* d_states) const {
  const contact::ClearanceKinematics k = Kinematics(geometry_, bush, pin);
  const LawValues v = EvaluateLaws(k, z, memory);
  // Open: every output is zero, and so every derivative (both matrices arrive zeroed), except
  // for the standard linear solid, whose arm relaxes (and dissipates) while the joint is open.
  if (!v.in_contact && !std::holds_alternative<contact::StandardLinearSolidLaw>(normal_law_)) {
    return true;
  }
  const LawVariableRows rows = CalcLawVariableRows(k, bush, pin);
  FillForceAndRateRows(k, v, rows, d_kinematics, d_states);
  FillDissipationRow(k, v, rows, z, memory, d_kinematics, d_states);
  return d_kinematics->allFinite() && d_states->allFinite();
}

ClearanceJoint::LawVariableRows ClearanceJoint::CalcLawVariableRows(
    const contact::ClearanceKinematics& k, const MarkerKinematics& bush,
    const MarkerKinematics& pin) const {
  const Vec2 n = k.normal, tg = k.tangent;
  const Vec2 edot = pin.velocity - bush.velocity;
  LawVariableRows rows;
  rows.r = std::max(k.eccentricity_norm, contact::kMinEccentricity);
  rows.d_delta.segment<2>(kPP) = n.transpose();
  rows.d_rate.segment<2>(kPP) = (tg.dot(edot) / rows.r) * tg.transpose();
  rows.d_rate.segment<2>(kVP) = n.transpose();
  rows.d_slip.segment<2>(kPP) = (-k.penetration_rate / rows.r) * tg.transpose();
  rows.d_slip.segment<2>(kVP) = tg.transpose();
  for (KinematicRow* row : {&rows.d_delta, &rows.d_rate, &rows.d_slip}) {
    row->segment<2>(kPB) = -row->segment<2>(kPP);
  }
  rows.d_slip.segment<2>(kVB) = -tg.transpose();
  rows.d_rate.segment<2>(kVB) = -n.transpose();
  rows.d_slip(kWP) = geometry_.pin_radius;
  rows.d_slip(kWB) = -geometry_.bush_radius;
  return rows;
}

void ClearanceJoint::FillForceAndRateRows(const contact::ClearanceKinematics& k, const LawValues& v,
                                          const LawVariableRows& rows, Mat* d_kinematics,
                                          Mat* d_states) const {
  Mat& D = *d_kinematics;
  Mat& Dz = *d_states;
  const Vec2 n = k.normal, tg = k.tangent;
  const double r = rows.r;
  // Normal and friction forces: rows over κ and columns over z.
  const KinematicRow d_fn = v.normal.d_penetration * rows.d_delta + v.normal.d_rate * rows.d_rate;
  const KinematicRow d_ft = v.friction.d_slip * rows.d_slip + v.friction.d_normal * d_fn;
  std::array<double, kMaxClearanceStates> fn_z{}, ft_z{};
  if (normal_state_ >= 0) {
    fn_z[normal_state_] = v.normal.d_state;
    ft_z[normal_state_] = v.friction.d_normal * v.normal.d_state;
  }
  if (friction_state_ >= 0) ft_z[friction_state_] = v.friction.d_state;
  // F_pin = −F_n n + F_t t: the direction terms act through de only.
  for (int a = 0; a < 2; ++a) {
    D.row(3 + a) = -n(a) * d_fn + tg(a) * d_ft;
    const double dir = (-v.normal.force * tg(a) - v.friction.force * n(a)) / r;  // ·tᵀ de
    D.block<1, 2>(3 + a, kPP) += dir * tg.transpose();
    D.block<1, 2>(3 + a, kPB) -= dir * tg.transpose();
    D.row(a) = -D.row(3 + a);
  }
  D.row(5) = geometry_.pin_radius * d_ft;
  D.row(2) = -geometry_.bush_radius * d_ft;
  for (int s = 0; s < num_states_; ++s) {
    for (int a = 0; a < 2; ++a) {
      Dz(3 + a, s) = -n(a) * fn_z[s] + tg(a) * ft_z[s];
      Dz(a, s) = -Dz(3 + a, s);
    }
    Dz(5, s) = geometry_.pin_radius * ft_z[s];
    Dz(2, s) = -geometry_.bush_radius * ft_z[s];
  }
  // State rates.
  if (normal_state_ >= 0) {
    D.row(7 + normal_state_) = v.normal_rate.d_penetration * rows.d_delta;
    Dz(7 + normal_state_, normal_state_) = v.normal_rate.d_state;
  }
  if (friction_state_ >= 0 && v.in_contact) {
    D.row(7 + friction_state_) = v.friction_rate.d_slip * rows.d_slip;
    Dz(7 + friction_state_, friction_state_) = v.friction_rate.d_state;
  }
}

void ClearanceJoint::FillDissipationRow(const contact::ClearanceKinematics& k, const LawValues& v,
                                        const LawVariableRows& rows, const double* z,
                                        const double* memory, Mat* d_kinematics,
                                        Mat* d_states) const {
  Mat& D = *d_kinematics;
  Mat& Dz = *d_states;
  // Central differences in the law variables.
  const double step = std::cbrt(std::numeric_limits<double>::epsilon());
  const FiniteDifferenceScales sc = fd_scales();
  auto dissipation_slope = [&](double contact::ClearanceKinematics::*u, double scale) {
    contact::ClearanceKinematics kp = k, km = k;
    const double x0 = k.*u;
    const volatile double xh = x0 + step * scale;
    const double h = xh - x0;
    kp.*u = x0 + h;
    km.*u = x0 - h;
    const LawValues vp = EvaluateLaws(kp, z, memory), vm = EvaluateLaws(km, z, memory);
    return (vp.dissipation() - vm.dissipation()) / (2.0 * h);
  };
  D.row(6) =
      dissipation_slope(&contact::ClearanceKinematics::penetration, sc.length) * rows.d_delta +
      dissipation_slope(&contact::ClearanceKinematics::penetration_rate, sc.speed) * rows.d_rate;
  if (friction_law_ && v.in_contact) {
    D.row(6) +=
        dissipation_slope(&contact::ClearanceKinematics::slip_velocity, sc.speed) * rows.d_slip;
  }
  for (int s = 0; s < num_states_; ++s) {
    std::array<double, kMaxClearanceStates> zp{}, zm{};
    for (int q = 0; q < num_states_; ++q) zp[q] = zm[q] = z[q];
    const volatile double xh = z[s] + step * StateScale(s);
    const double h = xh - z[s];
    zp[s] = z[s] + h;
    zm[s] = z[s] - h;
    Dz(6, s) = (EvaluateLaws(k, zp.data(), memory).dissipation() -
                EvaluateLaws(k, zm.data(), memory).dissipation()) /
               (2.0 * h);
  }
}

double ClearanceJoint::PotentialEnergy(const MarkerKinematics& bush, const MarkerKinematics& pin,
                                       const double* z, const double* memory) const {
  return EvaluateLaws(Kinematics(geometry_, bush, pin), z, memory).potential_energy;
}

void ClearanceJoint::Roots(double /*t*/, const MarkerKinematics& bush, const MarkerKinematics& pin,
                           const double* /*z*/, const double* memory, double* g) const {
  const contact::ClearanceKinematics k = Kinematics(geometry_, bush, pin);
  const bool on = memory[kContactFlag] > 0.5;
  g[0] = on ? k.penetration + EventBand() : k.penetration - EventBand();
  if (history_law_) g[1] = on ? k.penetration_rate : 1.0;
}

bool ClearanceJoint::OnRoot(int index, int direction, double t, const MarkerKinematics& bush,
                            const MarkerKinematics& pin, const double* z, double* memory) const {
  const contact::ClearanceKinematics k = Kinematics(geometry_, bush, pin);
  if (index == 0) {
    const bool on = memory[kContactFlag] > 0.5;
    if (on == (direction > 0)) return false;  // g₀ back through its own side: no change of state
    if (!on) {                                // onset
      memory[kContactFlag] = 1.0;
      memory[kApproachVelocity] = std::max({k.penetration_rate, min_approach_velocity_, 0.0});
      memory[kMaxPenetration] = 0.0;
      memory[kMaxForce] = 0.0;
      memory[kOnsetTime] = t;
      memory[kOnsetCount] += 1.0;
      for (int s = 0; s < num_states_; ++s) memory[kStatesAtOnset + s] = z[s];
      return true;
    }
    memory[kContactFlag] = 0.0;  // separation
    return num_states_ > 0;
  }
  if (index == 1 && direction < 0 && memory[kContactFlag] > 0.5) {  // maximum penetration
    LawState s{memory[kMaxPenetration], memory[kMaxForce]};
    contact::UpdateLawHistory(normal_law_, k.penetration, &s);
    memory[kMaxPenetration] = s[0];
    memory[kMaxForce] = s[1];
    return true;
  }
  return false;
}

double ClearanceJoint::EventBand() const { return 1e-6 * geometry_.clearance(); }

FiniteDifferenceScales ClearanceJoint::fd_scales() const {
  FiniteDifferenceScales s;
  s.length = 1e-3 * geometry_.clearance();
  s.speed = 1e-3;
  if (friction_law_) s.speed = std::min(s.speed, FrictionVelocityScale(*friction_law_));
  s.angle = 1e-3;  // the joint does not depend on the marker angles
  s.angular_speed = s.speed / geometry_.bush_radius;
  return s;
}

double ClearanceJoint::StateScale(int k) const {
  if (k == normal_state_) return 1e-2 * geometry_.clearance();
  if (k == friction_state_) {
    const auto& l = std::get<contact::LuGreFrictionLaw>(*friction_law_);
    return l.static_coefficient / l.bristle_stiffness;
  }
  return 1.0;
}

ClearanceResponse CalcClearanceResponse(const SampleView& sample, ElementId element) {
  const Mechanism& m = sample.model();
  const ElementSlot& slot = m.element(element);
  // ClearanceJoint is final: an exact type test, cheaper than dynamic_cast at every sample.
  const ForceElement& element_ref = *slot.element;
  if (typeid(element_ref) != typeid(ClearanceJoint)) {
    throw std::invalid_argument("CalcClearanceResponse: element '" + slot.name + "' is a " +
                                slot.element->type_name() + ", not a clearance joint");
  }
  const MarkerKinematics bush = sample.Marker(MarkerId{slot.marker_i});
  const MarkerKinematics pin = sample.Marker(MarkerId{slot.marker_j});
  const double* z = sample.y() + m.z_offset() + slot.state_offset;
  const double* memory = sample.data().element_memory.data() + slot.memory_offset;
  const ClearanceResponse r =
      static_cast<const ClearanceJoint&>(element_ref).CalcResponse(bush, pin, z, memory);
  sample.NotePotentialEnergy(element, r.potential_energy);
  return r;
}

}  // namespace flexrod::multibody
