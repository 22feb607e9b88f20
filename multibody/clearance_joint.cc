// multibody/clearance_joint.cc — the clearance joint force element (see clearance_joint.h for
// the contact logic and the energy bookkeeping of every law).
// SPDX-License-Identifier: GPL-3.0-or-later
#define EIGEN_RUNTIME_NO_MALLOC  // consistent Eigen configuration across multibody (see tests)
#include "multibody/clearance_joint.h"

#include <algorithm>
#include <cmath>
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
ElasticEnergy LineLawEnergy(const contact::LogLineCurve& curve, double penetration,
                            double force) {
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
ElasticEnergy CalcElasticEnergy(const contact::NormalLaw& law, bool in_contact,
                                double penetration, const LawState& s, double force) {
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

/// ẋ_d of the normal law's differential state. Maxwell: the law's rate in contact, at rest
/// otherwise. Standard linear solid: the arm relaxes towards the wall surface
/// δ_eff = max(δ, δ_w) in contact and δ_w when open, δ_w = k₂x/(k₁+k₂) (force-free wall).
double NormalStateRate(const contact::NormalLaw& law, bool in_contact, double penetration,
                       const LawState& s) {
  if (const auto* l = std::get_if<contact::StandardLinearSolidLaw>(&law)) {
    const double wall = l->arm_stiffness * s[0] / (l->stiffness + l->arm_stiffness);
    const double effective = in_contact ? std::max(penetration, wall) : wall;
    return contact::CalcLawStateRate(law, effective, s).rate;
  }
  if (!in_contact) return 0.0;
  return contact::CalcLawStateRate(law, penetration, s).rate;
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

contact::ClearanceKinematics Kinematics(const contact::ContactGeometry& g,
                                        const MarkerKinematics& bush,
                                        const MarkerKinematics& pin) {
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

double ClearanceJoint::NormalForce(const contact::ClearanceKinematics& k, bool in_contact,
                                   const LawState& s, const double* memory) const {
  if (!in_contact) return 0.0;
  return contact::CalcNormalForce(normal_law_, k.penetration, k.penetration_rate,
                                  memory[kApproachVelocity], s)
      .force;
}

ClearanceResponse ClearanceJoint::CalcResponse(const MarkerKinematics& bush,
                                               const MarkerKinematics& pin, const double* z,
                                               const double* memory) const {
  ClearanceResponse r;
  r.kinematics = Kinematics(geometry_, bush, pin);
  const contact::ClearanceKinematics& k = r.kinematics;
  const double delta = k.penetration, rate = k.penetration_rate;
  r.approach_velocity = memory[kApproachVelocity];
  r.contact_flag = memory[kContactFlag] > 0.5;
  r.onsets = std::lround(memory[kOnsetCount]);
  r.onset_time = memory[kOnsetTime];
  const LawState s = LawStateOf(z, memory);

  // Normal force, its state and its energy.
  r.in_contact = InContact(k, memory);
  r.normal_force = NormalForce(k, r.in_contact, s, memory);
  double state_rate = 0.0;
  if (normal_state_ >= 0) {
    state_rate = NormalStateRate(normal_law_, r.in_contact, delta, s);
    r.state_rates[normal_state_] = state_rate;
  }
  const ElasticEnergy e = CalcElasticEnergy(normal_law_, r.in_contact, delta, s, r.normal_force);
  r.potential_energy = e.energy;
  r.normal_dissipation = (r.normal_force - e.d_penetration) * rate - e.d_state * state_rate;

  // Friction (only while in contact: an open joint transmits nothing).
  if (friction_law_ && r.in_contact) {
    const double zf = friction_state_ >= 0
                          ? z[friction_state_] - memory[kStatesAtOnset + friction_state_]
                          : 0.0;
    r.friction_force =
        contact::CalcFrictionForce(*friction_law_, k.slip_velocity, r.normal_force, zf).force;
    if (friction_state_ >= 0) {
      r.state_rates[friction_state_] =
          contact::CalcFrictionStateRate(*friction_law_, k.slip_velocity, zf).rate;
    }
  }
  r.friction_dissipation = -r.friction_force * k.slip_velocity;
  r.loads = contact::CalcContactLoads(geometry_, k, r.normal_force, r.friction_force);
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

double ClearanceJoint::PotentialEnergy(const MarkerKinematics& bush, const MarkerKinematics& pin,
                                       const double* z, const double* memory) const {
  // The normal part of CalcResponse only: energies are sampled at the output rate.
  const contact::ClearanceKinematics k = Kinematics(geometry_, bush, pin);
  const bool in_contact = InContact(k, memory);
  const LawState s = LawStateOf(z, memory);
  const double force = NormalForce(k, in_contact, s, memory);
  return CalcElasticEnergy(normal_law_, in_contact, k.penetration, s, force).energy;
}

void ClearanceJoint::Roots(double /*t*/, const MarkerKinematics& bush,
                           const MarkerKinematics& pin, const double* /*z*/,
                           const double* memory, double* g) const {
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
    if (!on) {  // onset
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
    throw std::invalid_argument("CalcClearanceResponse: element '" + slot.name +
                                "' is a " + slot.element->type_name() +
                                ", not a clearance joint");
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
