// contact/impact.h — a single impact of a point mass against a rigid wall through one normal law
// (with its internal states), integrated to high accuracy: GSL gsl_odeiv2 with the embedded
// Runge–Kutta–Prince–Dormand 8(9) pair at tight tolerance; the maximum penetration, every drop of
// the force to zero and the exit through δ = 0 are located by bisection in time, re-integrating
// from the start of the step that contains them. Used to check laws against their restitution
// relations and for the `flexrod contact` command. What does not live here: the laws themselves
// (contact/normal_law.h) and anything about mechanisms (multibody/).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <vector>

#include "contact/normal_law.h"

namespace flexrod::contact {

struct ImpactOptions {
  double rel_tol{1e-12};            ///< relative tolerance of the RK8(9) error control [-]
  int num_samples{400};             ///< at least this many loop samples over the contact [-]
  int max_steps{2000000};           ///< give up (NumericalError) after this many steps [-]
  double max_duration_factor{1e4};  ///< give up if contact outlasts this × the elastic estimate
  /// Throws InputError("impact.<field>", ...) for invalid values.
  void Validate() const;
};

/// One point of the force–penetration loop.
struct LoopSample {
  double time;         ///< since onset [s]
  double penetration;  ///< δ [m]
  double rate;         ///< δ̇ [m/s]
  double force;        ///< F [N]
};

struct ImpactResult {
  double incoming_speed{0.0};            ///< v₀ [m/s]
  double outgoing_speed{0.0};            ///< |δ̇| when the mass leaves the wall (δ = 0) [m/s]
  double achieved_restitution{0.0};      ///< outgoing/incoming speed [-]
  double peak_force{0.0};                ///< max F [N]
  double peak_penetration{0.0};          ///< max δ [m]
  double time_of_peak_penetration{0.0};  ///< [s]
  /// Time from onset until the force last drops to zero [s]. For laws whose force vanishes
  /// before δ returns to 0 (clipped damping, permanent set), the mass then flies freely.
  double contact_duration{0.0};
  double exit_time{0.0};          ///< time at which δ returns to 0 [s]
  double dissipated_energy{0.0};  ///< ½m(v₀² − v_out²) [J], energy lost by the mass
  std::vector<LoopSample> loop;   ///< onset → exit, in time order
};

/// Mass m [kg] > 0 arrives at δ = 0 with approach speed v₀ [m/s] > 0 (InputError otherwise);
/// law states start at InitialLawState. Throws NumericalError if the integrator fails or the mass
/// does not leave the wall (an over-damped law can hold it).
ImpactResult SimulateImpact(const NormalLaw& law, double mass, double approach_speed,
                            const ImpactOptions& options = {});

}  // namespace flexrod::contact
