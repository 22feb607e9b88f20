// multibody/dae.h — the mechanism's equations as functions of (model, data): the stabilised
// index-2 (GGL) DAE residual, its iteration Jacobian, root functions, the sparsity pattern,
// the FFRF body kernels (mass matrix, quadratic-velocity vector) and the constraint pieces
// the initial-condition solver needs. What does not live here: the integrator
// (ida_integrator.h), the run loop and initial conditions (simulate.h), output queries
// (outputs.h).
//
// Unknowns y = [p; v; λ; μ; z] (layout in Mechanism), residual
//   F1 = ṗ − v − Gᵀμ                       (np)  position equation with the GGL projection
//   F2 = M(p) v̇ − Q(t, p, v, z) + Gᵀλ      (np)  equations of motion
//   F3 = g(p, t)                           (nc)  position constraints
//   F4 = G v + g_t                         (nc)  velocity constraints
//   F5 = ż − f(t, p, v, z)                 (nz)  element states and energy quadratures
// with Q = Q_v + Q_e + Q_gravity + Q_elements + Q_motor (ffrf-planar.md).
//
// Jacobian dF/dy + c_j dF/dẏ: analytic for everything except force elements without an
// analytic ForceElement::EvaluateJacobian (the exact rod's beam elements and the clearance
// joint have one; the joint differences only its dissipation row, in the laws' variables).
// Analytic blocks: identities, c_j M, the velocity and position derivatives of M v̇ − Q_v − Q_e −
// Q_gravity (closed form from the shape integrals), G, Gᵀ, and the constraint Hessian terms
// ∂(Gᵀλ)/∂p, ∂(Gᵀμ)/∂p, ∂(G v)/∂p. Element outputs are chained analytically with the marker
// Jacobians (∂κ/∂p, ∂κ/∂v) and the geometric term ∂(Jrᵀ F)/∂p. Other force elements: central finite
// differences of the element outputs with respect to its kinematic inputs κ = (p_WM, v_WM, φ, ω) of
// both markers and its states z, with step h = cbrt(ε)·scale (ε = 2.2e-16, scale from
// ForceElement::fd_scales()/StateScale(); the realised step (x + h) − x is used). The test suite
// checks the whole matrix against a central-difference Jacobian of the residual.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <vector>

#include "common/eigen.h"
#include "multibody/ida_integrator.h"
#include "multibody/mechanism.h"
#include "multibody/run_data.h"

namespace flexrod::multibody {

// ---- body kernels (pure; one code path for rigid n = 0 and flexible bodies) ------------------
/// Mass matrix M(θ, q) of one body, nb × nb; pb = [x, y, θ, q].
Mat BodyMassMatrix(const Body& body, const Vec& pb);
/// Kinetic energy of one body at (pb, vb) [J], without forming M (KineticEnergy).
double BodyKineticEnergy(const Body& body, const Vec& pb, const Vec& vb);
/// Quadratic-velocity vector Q_v(θ, q, θ̇, q̇) of one body (nb).
Vec BodyQuadraticVelocity(const Body& body, const Vec& pb, const Vec& vb);

// ---- kinematics -------------------------------------------------------------------------------
/// Refreshes data->bodies (A, s, w, c, K q; not D q̇ and S̃ q̇, which only the residual and the
/// Jacobian use and refresh themselves) and data->markers (world kinematics, not the Jacobian
/// pieces) at the coordinates/velocities of y. Every query in outputs.h reads them.
void UpdateKinematics(const Mechanism& model, RunData* data, const double* y);

/// Kinetic energy ½ vᵀM v of one body [J] (after UpdateKinematics; pb, vb: its coordinates
/// and velocities [m, rad, 1; m/s, rad/s, 1/s]); M v goes through MassTimes into s->tmp.
double KineticEnergy(const Body& b, BodyScratch* s, const double* pb, const double* vb);
/// M(θ, q) a of one body into out[0, 3 + n) (after UpdateBody), without forming M: the
/// residual's M v̇.
void MassTimes(const Body& b, const BodyScratch& s, const double* pb, const double* a, double* out);
/// Position constraint values of one joint at the kinematics in data (num_rows values).
void CalcJointConstraint(const Mechanism& model, const RunData& data, JointId joint,
                         const double* y, double* g);

// ---- DAE ------------------------------------------------------------------------------------
/// Residual F(t, y, ẏ) (size model.size()). Returns 0, or 1 if an element reported a
/// recoverable failure or the result is not finite. Does not allocate.
int CalcResidual(const Mechanism& model, RunData* data, double t, const double* y, const double* yp,
                 double* r);
/// Adds dF/dy + cj·dF/dẏ to the column-major matrix jac (leading dimension ld >= N), which
/// the caller has zeroed, and, if dfdyp is given, dF/dẏ alone (the identities of F1 and F5 and
/// the bodies' mass matrices in F2) to dfdyp (zeroed, the same layout). Returns 0 or 1
/// (recoverable).
int AddJacobian(const Mechanism& model, RunData* data, double t, double cj, const double* y,
                const double* yp, double* jac, int ld, double* dfdyp = nullptr);
/// Element root functions g (model.num_element_roots()). Returns 0.
int CalcElementRoots(const Mechanism& model, RunData* data, double t, const double* y, double* g);

/// Convenience (allocating) forms for tests and tools.
Vec CalcResidual(const Mechanism& model, RunData* data, double t, const Vec& y, const Vec& yp);
Mat CalcJacobian(const Mechanism& model, RunData* data, double t, double cj, const Vec& y,
                 const Vec& yp);

/// 1 for unknowns under error control (p, v, element states z, the dissipation and
/// stiffening quadratures), 0 for the multipliers λ, μ and for the driver-work quadrature.
/// The driver work is integrated by the same BDF formula but kept out of the error test: its
/// rate −λθ̇ carries the round-off noise of the index-2 multiplier, which would otherwise
/// dictate the step (measured: one error-test failure per step on a flexible slider-crank).
/// The dissipation quadratures stay controlled so that sharp dissipation (friction reversal
/// on a kinematically driven slider) is resolved even where p and v are smooth.
void DifferentialMask(const Mechanism& model, double* id);
/// Absolute-tolerance multipliers: 1 for p, λ, μ; velocity_scale for v; StateScale(k) for
/// element states; energy_scale for the energy quadratures.
void AbsoluteToleranceScales(const Mechanism& model, double velocity_scale, double energy_scale,
                             double* scales);
/// Structural non-zero pattern of the iteration Jacobian (CSC), for the sparse solver.
SparsityPattern JacobianPattern(const Mechanism& model);

// ---- constraint pieces (initial conditions, diagnostics) -----------------------------------
/// Position constraints g(p, t) (nc).
void CalcConstraints(const Mechanism& model, RunData* data, double t, const Vec& p, Vec* g);
/// Constraint Jacobian G = ∂g/∂p (nc × np) and g_t = ∂g/∂t (nc).
void CalcConstraintJacobian(const Mechanism& model, RunData* data, double t, const Vec& p, Mat* G,
                            Vec* g_t);
/// Acceleration right-hand side γ with G v̇ = γ on the constraint manifold:
/// γ = −(∂(G v)/∂p) v − g_tt.
void CalcConstraintAccelerationRhs(const Mechanism& model, RunData* data, double t, const Vec& p,
                                   const Vec& v, Vec* gamma);
/// Full mass matrix M(p) (np × np, block diagonal over bodies).
void CalcMassMatrix(const Mechanism& model, RunData* data, const Vec& p, Mat* M);

}  // namespace flexrod::multibody
