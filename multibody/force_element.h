// multibody/force_element.h — the force-element interface between two markers and the
// built-in elements (translational spring-damper, rotational spring-damper, prismatic guide
// damper/friction). An element sees only the world kinematics of its two markers, its own
// extra ODE states z and a small per-run memory array; it returns forces and moments on the
// markers, ż, its dissipation rate, its stored energy and root functions. The clearance
// joint of the contact stage implements this interface. What does not live here: marker
// kinematics (multibody/dae.h computes them), contact laws (contact/).
//
// Contract for implementers: every method is const and must be thread-safe (the mechanism
// is shared between sweep threads; per-run mutable data lives in `memory`, owned by
// RunData). Evaluate() runs inside the DAE residual: it must not allocate and must not
// throw; it returns false for a recoverable problem (IDA then retries with a smaller step).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>

#include "common/eigen.h"

namespace flexrod::multibody {

/// World kinematics of a marker M: position p_WM, velocity, angle and angular velocity.
struct MarkerKinematics {
  Vec2 position{0.0, 0.0};       ///< p_WM [m]
  Vec2 velocity{0.0, 0.0};       ///< v_WM [m/s]
  double angle{0.0};             ///< marker angle in the world [rad]
  double angular_velocity{0.0};  ///< [rad/s]
};

/// What an element returns. Forces are in world axes and act ON the marker's body at the
/// marker point; moments are about the marker point (counter-clockwise positive).
struct ElementOutput {
  Vec2 force_i{0.0, 0.0};        ///< force on marker i's body at marker i [N]
  double moment_i{0.0};          ///< moment on marker i's body [N m]
  Vec2 force_j{0.0, 0.0};        ///< force on marker j's body at marker j [N]
  double moment_j{0.0};          ///< moment on marker j's body [N m]
  double dissipation{0.0};       ///< power removed from the mechanism [W] (>= 0 if passive)
  double* state_rates{nullptr};  ///< ż, num_states() entries, zeroed before Evaluate [unit/s]
};

/// Scales the Jacobian's finite differences use for this element: the central-difference
/// step of a kinematic input x is h = cbrt(machine epsilon) · scale (≈ 6e-6 · scale). Pick
/// the scale on which the force changes appreciably (for contact: a fraction of the
/// clearance; for regularised friction: the regularisation speed).
struct FiniteDifferenceScales {
  double length{1e-3};         ///< [m]
  double speed{1e-3};          ///< [m/s]
  double angle{1e-3};          ///< [rad]
  double angular_speed{1e-3};  ///< [rad/s]
};

/// Columns of an element's Jacobian with respect to its kinematic inputs: κ = [p_i (2), v_i (2),
/// φ_i, ω_i, p_j (2), v_j (2), φ_j, ω_j] (units as in MarkerKinematics). Rows: the stacked
/// outputs o = [F_i (2), M_i, F_j (2), M_j, dissipation, ż (num_states)].
inline constexpr int kElementKinematicColumns = 12;

/// A force element between markers i and j (either may be a ground marker).
class ForceElement {
 public:
  virtual ~ForceElement() = default;

  /// Extra ODE states z of this element (e.g. Maxwell force, LuGre bristle deflection).
  virtual int num_states() const { return 0; }
  /// Size of the per-run mutable memory (e.g. approach velocity at contact onset).
  virtual int num_memory() const { return 0; }
  /// Number of root functions g_k(t, y) whose zero crossings IDA locates.
  virtual int num_roots() const { return 0; }

  /// Initial z and memory at the start of a run (both arrays are zeroed before the call).
  virtual void Initialize(const MarkerKinematics& /*i*/, const MarkerKinematics& /*j*/,
                          double* /*z*/, double* /*memory*/) const {}

  /// Forces, ż and dissipation. Must not allocate or throw; false = recoverable failure.
  virtual bool Evaluate(double t, const MarkerKinematics& i, const MarkerKinematics& j,
                        const double* z, const double* memory, ElementOutput* out) const = 0;

  /// Energy stored in the element (springs, contact) [J]; enters the energy balance.
  virtual double PotentialEnergy(const MarkerKinematics& /*i*/, const MarkerKinematics& /*j*/,
                                 const double* /*z*/, const double* /*memory*/) const {
    return 0.0;
  }

  /// Root functions g[0..num_roots()).
  virtual void Roots(double /*t*/, const MarkerKinematics& /*i*/, const MarkerKinematics& /*j*/,
                     const double* /*z*/, const double* /*memory*/, double* /*g*/) const {}

  /// Called when IDA has located a zero of root `index` (direction +1: g increasing, −1:
  /// decreasing) at time t; may update `memory`. Return true if the element's law changed
  /// discontinuously so the integrator must be restarted (IDAReInit) at t.
  virtual bool OnRoot(int /*index*/, int /*direction*/, double /*t*/, const MarkerKinematics& /*i*/,
                      const MarkerKinematics& /*j*/, const double* /*z*/,
                      double* /*memory*/) const {
    return false;
  }

  /// Analytic derivatives of the stacked outputs o (kElementKinematicColumns): ∂o/∂κ into
  /// `d_kinematics` ((7 + num_states) × 12) and ∂o/∂z into `d_states` ((7 + num_states) ×
  /// num_states); both arrive zeroed. Return false (the default) to have the Jacobian
  /// difference the element instead. Must not allocate or throw.
  virtual bool EvaluateJacobian(double /*t*/, const MarkerKinematics& /*i*/,
                                const MarkerKinematics& /*j*/, const double* /*z*/,
                                const double* /*memory*/, Mat* /*d_kinematics*/,
                                Mat* /*d_states*/) const {
    return false;
  }

  virtual FiniteDifferenceScales fd_scales() const { return {}; }
  /// True if the outputs depend on the markers' positions and velocities only through
  /// r_j − r_i and ṙ_j − ṙ_i, and not on the marker angles (a pin in a bush, a spring between
  /// two points). The Jacobian then differences one side only: ∂/∂(r_i, ṙ_i) = −∂/∂(r_j, ṙ_j)
  /// and ∂/∂φ = 0, which halves the element evaluations per Jacobian.
  virtual bool relative_kinematics() const { return false; }
  /// Typical magnitude of state k: its finite-difference scale and its absolute-tolerance
  /// multiplier (abs_tol_z = abs_tol · StateScale(k)).
  virtual double StateScale(int /*k*/) const { return 1.0; }
  /// Length scale of the relative motion the element must resolve [m] (0: none). The
  /// relative tolerance of the coordinates that move its markers applies to this length, not
  /// to their absolute values (MechanismDae::RelativeToleranceCaps).
  virtual double ResolvedLength() const { return 0.0; }
  /// True for an element that is part of an elastic body (the exact rod's beam elements): its
  /// stiff modes then set the velocity tolerance scale as elastic coordinates do
  /// (AutoVelocityTolScale, multibody/simulate.h).
  virtual bool structural() const { return false; }
  /// Short type name for messages ("spring-damper", "clearance-joint", ...).
  virtual std::string type_name() const = 0;
};

/// Linear translational spring-damper between the two marker points. Tension positive:
/// f = k (L − L0) + c L̇ pulls the markers together when positive.
class SpringDamper final : public ForceElement {
 public:
  /// k [N/m] >= 0, c [N s/m] >= 0, L0 [m] >= 0. Throws InputError naming `key`.
  SpringDamper(const std::string& key, double stiffness, double damping, double free_length);
  bool Evaluate(double t, const MarkerKinematics& i, const MarkerKinematics& j, const double* z,
                const double* memory, ElementOutput* out) const override;
  double PotentialEnergy(const MarkerKinematics& i, const MarkerKinematics& j, const double* z,
                         const double* memory) const override;
  FiniteDifferenceScales fd_scales() const override;
  bool relative_kinematics() const override { return true; }
  std::string type_name() const override { return "spring-damper"; }

 private:
  double stiffness_, damping_, free_length_;
};

/// Linear rotational spring-damper on the relative angle Δ = φ_j − φ_i − Δ0: moment
/// M = k Δ + c Δ̇ acts +M on body i and −M on body j.
class RotationalSpringDamper final : public ForceElement {
 public:
  /// k [N m/rad] >= 0, c [N m s/rad] >= 0, Δ0 [rad].
  RotationalSpringDamper(const std::string& key, double stiffness, double damping,
                         double free_angle);
  bool Evaluate(double t, const MarkerKinematics& i, const MarkerKinematics& j, const double* z,
                const double* memory, ElementOutput* out) const override;
  double PotentialEnergy(const MarkerKinematics& i, const MarkerKinematics& j, const double* z,
                         const double* memory) const override;
  std::string type_name() const override { return "rotational-spring-damper"; }

 private:
  double stiffness_, damping_, free_angle_;
};

/// Viscous damper and regularised Coulomb friction along a prismatic joint's axis (axis a
/// fixed in marker i's frame). Sliding speed at the contact point j relative to body i:
/// s = uᵀ(v_j − v_i) − ω_i uᵀ J (p_j − p_i), u = R(φ_i) a; force on j: −(c s + F_c tanh(s/s_reg))
/// u, its reaction on i at the same point. Dissipation = (c s + F_c tanh(s/s_reg)) s >= 0.
class PrismaticGuide final : public ForceElement {
 public:
  /// axis: unit vector in marker i's frame; c [N s/m] >= 0; F_c [N] >= 0; s_reg [m/s] > 0.
  PrismaticGuide(const std::string& key, const Vec2& axis, double damping, double friction_force,
                 double regularisation_speed);
  bool Evaluate(double t, const MarkerKinematics& i, const MarkerKinematics& j, const double* z,
                const double* memory, ElementOutput* out) const override;
  FiniteDifferenceScales fd_scales() const override;
  std::string type_name() const override { return "prismatic-guide"; }

 private:
  Vec2 axis_;
  double damping_, friction_force_, regularisation_speed_;
};

}  // namespace flexrod::multibody
