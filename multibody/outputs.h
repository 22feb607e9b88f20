// multibody/outputs.h — what an observer can ask about a state: marker kinematics and
// accelerations, joint reaction forces from the multipliers λ, driver angle/speed/torque,
// force-element forces, and the energy balance. Every function here reads the body and
// marker quantities that UpdateKinematics(model, data, y) left in `data` for the same y
// (SampleView in simulate.h does that once per sample). What does not live here: the
// equations (dae.h), the run loop (simulate.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "common/eigen.h"
#include "multibody/force_element.h"
#include "multibody/mechanism.h"
#include "multibody/run_data.h"

namespace flexrod::multibody {

/// Constraint force and moment a joint exerts ON the body of each marker, at the marker point
/// (world axes), from its multipliers: generalized constraint force = −Gᵀλ. For a ground
/// joint the force acts on the body at its frame origin (force_j, moment_j).
struct JointReaction {
  Vec2 force_i{0.0, 0.0};  ///< [N]
  double moment_i{0.0};    ///< [N m]
  Vec2 force_j{0.0, 0.0};  ///< [N]
  double moment_j{0.0};    ///< [N m]
};

struct DriverState {
  double angle{0.0};   ///< body angle θ [rad]
  double speed{0.0};   ///< θ̇ [rad/s]
  double torque{0.0};  ///< torque applied by the driver to the body [N m] (−λ, or the motor line)
  double power{0.0};   ///< torque · θ̇ [W]
};

struct ElementReport {
  Vec2 force_i{0.0, 0.0};
  double moment_i{0.0};
  Vec2 force_j{0.0, 0.0};
  double moment_j{0.0};
  double dissipation{0.0};       ///< [W]
  double potential_energy{0.0};  ///< [J]
};

/// Energy terms [J]. Balance: mechanical + dissipated − driver_work − stiffening_work is
/// constant; balance_error is its drift from the start of the run.
struct EnergyReport {
  double kinetic{0.0};              ///< ½ vᵀ M v
  double strain{0.0};               ///< ½ qᵀ K q over flexible bodies
  double gravity{0.0};              ///< −gᵀ Σ (m R + A s) (zero at the world origin)
  double element_potential{0.0};    ///< Σ ForceElement::PotentialEnergy
  double dissipated_elements{0.0};  ///< ∫ element dissipation (incl. prismatic guides)
  double dissipated_damping{0.0};   ///< ∫ q̇ᵀ D q̇
  double driver_work{0.0};          ///< ∫ driver torque · θ̇
  double stiffening_work{0.0};      ///< ∫ q̇ᵀ(−N(q) K_g q)
  double balance_error{0.0};
  double mechanical() const { return kinetic + strain + gravity + element_potential; }
  /// mechanical + dissipated − work: constant for an exact solution.
  double total() const {
    return mechanical() + dissipated_elements + dissipated_damping - driver_work - stiffening_work;
  }
};

const MarkerKinematics& MarkerState(const RunData& data, MarkerId marker);
/// r̈ = Jr v̇ + a_v (needs ẏ).
Vec2 MarkerAcceleration(const Mechanism& model, const RunData& data, MarkerId marker,
                        const double* yp);
JointReaction CalcJointReaction(const Mechanism& model, const RunData& data, JointId joint,
                                const double* y);
DriverState CalcDriverState(const Mechanism& model, DriverId driver, const double* y);
ElementReport CalcElementReport(const Mechanism& model, RunData* data, ElementId element, double t,
                                const double* y);
/// One element's potential energy [J] already evaluated at the state (index −1: none).
struct KnownPotential {
  int element{-1};
  double energy{0.0};  ///< [J]
};
/// Uses data->reference_energy for balance_error. The `known` element's potential energy is
/// taken as given instead of evaluated again.
EnergyReport CalcEnergies(const Mechanism& model, RunData* data, const double* y,
                          KnownPotential known = {});
/// Largest |g_k(p, t)| over all position constraints [m or rad].
double MaxConstraintViolation(const Mechanism& model, RunData* data, double t, const double* y);

}  // namespace flexrod::multibody
