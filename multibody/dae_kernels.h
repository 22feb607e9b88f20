// multibody/dae_kernels.h — the body, marker, joint and element kernels that the mechanism
// DAE's residual (multibody/dae.cc) and Jacobian (multibody/dae_jacobian.cc) are assembled
// from. Internal to multibody/; the notation is dae.cc's (ffrf-planar.md).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cmath>
#include <limits>

#include "common/eigen.h"
#include "multibody/mechanism.h"
#include "multibody/run_data.h"

namespace flexrod::multibody::dae_kernels {

using CMap = Eigen::Map<const Vec>;
using VMap = Eigen::Map<Vec>;
using JacMap = Eigen::Map<Mat, 0, Eigen::OuterStride<>>;

// cbrt(machine epsilon): optimal relative step of a central difference.
inline const double kFdStep = std::cbrt(std::numeric_limits<double>::epsilon());

// `dynamics` false skips D q̇ and S̃ q̇, which only the residual and the Jacobian read (each
// refreshes them itself): output samples at 100 kHz need the kinematics and the energies only.
void UpdateBody(const Body& b, const double* pb, const double* vb, BodyScratch* s,
                bool dynamics = true);

// The second-order strain's Jacobian pieces at (q, q̇) (after UpdateBody): BodyScratch::Jg =
// ∂(F_g + F_d)/∂q, Jkv_qd = ∂F_d/∂q̇ − D, and the power rows q̇ᵀ ∂F_g/∂q (stiffening_row) and
// q̇ᵀ ∂F_d/∂q (damping_row); F_d, Jkv_qd and damping_row with strain damping only.
void AddSecondOrderStrainJacobian(const Body& b, const CMap& q, const CMap& qd, BodyScratch* s);

// M(θ, q), ffrf-planar.md "Mass matrix".
void FillMassMatrix(const Body& b, const BodyScratch& s, const double* pb, Mat* M);

// Q_v, ffrf-planar.md "Quadratic-velocity vector".
void FillQuadraticVelocity(const Body& b, const BodyScratch& s, const double* vb, Vec* Qv);

// Bodies (UpdateBody) and markers at the state (p, v).
void UpdateAll(const Mechanism& model, RunData* data, const double* p, const double* v,
               bool dynamics = true);

// One marker's kinematics at (p, v), its body's orientation refreshed first and nothing else
// (UpdateMarker reads only A(θ) of the body): a query of one marker (SampleView::Marker) does
// not need every body's modal products and every marker. A ground marker's are set once.
void UpdateMarkerAlone(const Mechanism& model, int mi, RunData* data, const double* p,
                       const double* v);

// Jr, Jφ, C = ∂(Jr v)/∂p and A S_u of a body marker at the current state.
void FillMarkerJacobian(const Mechanism& model, int mi, RunData* data, const double* v);

// H += scale · ∂(Jrᵀ f)/∂p for a fixed world vector f (symmetric, only θ row/column).
void AddMarkerHessian(const Mechanism& model, int mi, const RunData& data, const Vec2& f,
                      double scale, Eigen::Ref<Mat> H);

// target[body rows] += Jrᵀ F + Jφᵀ moment.
void AddMarkerForce(const Mechanism& model, int mi, const RunData& data, const Vec2& F,
                    double moment, double* target);

// g and G v + g_t of one joint (rows jt.row ...).
void EvalJoint(const Mechanism& model, const RunData& data, const Joint& jt, const double* p,
               const double* v, double* g, double* gv);

// target += Gᵀ w for one joint (w = λ or −μ rows of the joint).
void AddJointTransposeProduct(const Mechanism& model, const RunData& data, const Joint& jt,
                              const double* w, double* target);

inline int BodyOf(const Mechanism& model, int marker) { return model.markers()[marker].body; }

// The bodies a, b of a joint (a = −1 for a ground joint, whose body is b), and its markers'
// Jacobians at velocity v (FillMarkerJacobian) where it has markers.
void FillJointMarkers(const Mechanism& model, RunData* data, const Joint& jt, const double* v,
                      int* a, int* b);

// Ga, Gb of one joint (requires FillMarkerJacobian of its markers).
void FillJointJacobian(const Mechanism& model, RunData* data, const Joint& jt, JointScratch* js);

// Haa, Hab, Hba, Hbb = Σ_k w_k ∂²g_k/∂p² of one (non-ground) joint.
void FillJointHessian(const Mechanism& model, RunData* data, const Joint& jt, const double* w,
                      JointScratch* js);

// Rows of a joint whose equation is non-linear in p (has a Hessian).
bool RowHasHessian(const Joint& jt, int k);

// ha = Haa va + Hab vb, hb = Hba va + Hbb vb (Hessian times velocity).
void HessianTimesVelocity(const Mechanism& model, const Joint& jt, const double* v,
                          JointScratch* js);

// ---- element finite differences -----------------------------------------------------------------
// Component c of a marker's kinematics as the element Jacobian columns order them
// (x, y, vx, vy, φ, ω), and its finite-difference scale.
double& Component(MarkerKinematics& k, int c);
double ComponentScale(const FiniteDifferenceScales& s, int c);

// The element's outputs stacked in o (forces, moments, dissipation, state rates); false if it
// reports a problem.
bool EvalElementStacked(const ElementSlot& e, ElementScratch* es, double t,
                        const MarkerKinematics& ki, const MarkerKinematics& kj, const double* z,
                        const double* memory, Vec* o);

// The chain matrices from an element's marker kinematics to its bodies' coordinates
// (Kp, Kv) and its generalized-force maps (Gen) for the Jacobian.
void FillElementChainMatrices(const Mechanism& model, const ElementSlot& e, RunData* data,
                              ElementScratch* es);

}  // namespace flexrod::multibody::dae_kernels
