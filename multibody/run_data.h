// multibody/run_data.h — the mutable per-run workspace (Pinocchio's Data, Drake's Context):
// every scratch array the residual, the Jacobian, the initial-condition solver and the output
// queries need, sized once from the Mechanism so the hot path never allocates; plus the
// per-run element memory and the reference energy of the run. One RunData per thread and
// run; the Mechanism is shared read-only. What does not live here: the model (mechanism.h),
// the equations (dae.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <vector>

#include "common/eigen.h"
#include "multibody/corotated_damping.h"
#include "multibody/force_element.h"
#include "multibody/mechanism.h"

namespace flexrod::multibody {

/// Per-body quantities at the current configuration (refreshed by every evaluation).
struct BodyScratch {
  double cos_theta{1.0}, sin_theta{0.0};
  double trig_theta{0.0};  ///< θ that cos_theta, sin_theta belong to (reused when θ repeats)
  Mat2 A;                  ///< A(θ)
  Vec2 s;                  ///< S̄₀ + S̄ q [kg m]
  Vec w;                   ///< I₁ + M_ff q (n) [kg m]
  Vec c;                   ///< Ī + S̃ q (n) [kg m]
  Vec Kq;                  ///< K q + F_g(q) (n) [N]
  Vec Fg;                  ///< F_g(q), the geometric-stiffness force (n) [N]
  // The second-order axial strain (Body::geometric_stiffening; dae_kernels.cc
  // UpdateSecondOrderStrain): strain coordinates σ, a and their forces c, r of them.
  Mat strain_h;      ///< [H_k q] (n × r) [m]: the residual's (modal kernel) or the Jacobian's
  Vec strain_coef;   ///< σ = Vᵀ s, σ_k = ½ qᵀ H_k q (r) [m]
  Vec strain_force;  ///< c = k (W q + σ): the elements' axial forces are N = V c (r) [N]
  // The element kernel (Body::modal_strain_kernel false).
  Vec node_w;              ///< T q: (v, θ) of every node (2 (n_e + 1)) [m, rad]
  Vec element_kgw;         ///< K_G w_e stacked (4 n_e) [-]
  Vec element_short;       ///< s_e = ½ w_eᵀ K_G w_e (n_e) [m]
  Vec element_force;       ///< V c (or V η for the damping) (n_e) [N]
  Vec node_force;          ///< Σ_e element_force_e K_G w_e on the nodes' (v, θ) (2 (n_e + 1)) [N]
  Vec node_wd;             ///< T q̇ (2 (n_e + 1)) [m/s, rad/s]
  Vec element_short_rate;  ///< ṡ_e (n_e) [m/s]
  // Damping of the second-order strains (Body::strain_damping).
  Vec strain_rate;      ///< ρ = σ̇ = [H_k q]ᵀ q̇ (r) [m/s]
  Vec strain_velocity;  ///< v = q̇ + B ρ (n)
  Vec damping_g;        ///< D v (n) [N]
  Vec damping_eta;      ///< η = Bᵀ D v (r) [N]
  // Jacobian only.
  Mat strain_hd;                ///< [H_k q̇] (n × r) [m/s]
  Vec kg_weights;               ///< c + η, the weights of Σ_k H_k (r) [N]
  Mat Jg;                       ///< ∂(F_g + F_d)/∂q (n × n)
  RowVec stiffening_row;        ///< q̇ᵀ ∂F_g/∂q (1 × n) [N/s]
  Mat strain_map;               ///< C = I + B [H_k q]ᵀ (n × n)
  Mat dmap, bsd;                ///< n × n work
  Mat Jkv_q, Jkv_qd;            ///< ∂F_d/∂q, ∂F_d/∂q̇ − D (n × n)
  RowVec damping_row;           ///< q̇ᵀ ∂F_d/∂q (1 × n) [N/s]
  Vec Dqd;                      ///< D q̇ (n) [N]
  Vec Sqd;                      ///< S̃ q̇ (n)
  Vec q_products, qd_products;  ///< Body::q_products q, Body::qd_products q̇
  Mat M;                        ///< mass matrix (nb × nb)
  Vec Qv;                       ///< quadratic-velocity vector (nb)
  Vec tmp;                      ///< nb
  Mat2X AS;                     ///< A S̄ (2×n), Jacobian only
};

/// World kinematics of a marker at the current state plus its Jacobian pieces.
struct MarkerScratch {
  MarkerKinematics kin;     ///< position, velocity, angle, angular velocity
  Vec2 Au{0.0, 0.0};        ///< A ū (world offset from the frame origin) [m]
  Vec2 ASqd{0.0, 0.0};      ///< A S_u q̇ [m/s]
  Vec2 conv_acc{0.0, 0.0};  ///< convective acceleration a_v = r̈ − L p̈ [m/s^2]
  Mat2X Jr;                 ///< ∂r/∂p_b (2 × nb)
  RowVec Jphi;              ///< ∂φ/∂p_b (1 × nb)
  Mat2X C;                  ///< ∂(Jr v_b)/∂p_b (2 × nb)
  Mat2X AS;                 ///< A S_u (2 × n)
};

struct JointScratch {
  Mat Ga, Gb;              ///< constraint Jacobian blocks (rows × nb_i, rows × nb_j)
  Mat Haa, Hab, Hba, Hbb;  ///< weighted constraint Hessian blocks
  Vec va, vb, ha, hb;      ///< velocities of the two bodies and Hessian-vector products
};

struct ElementScratch {
  ElementOutput out;  ///< last evaluation
  Vec zdot;           ///< ż (num_states)
  Vec z_fd;           ///< perturbed states
  Vec zdot_fd;
  Vec o_plus, o_minus;  ///< stacked outputs [F_i, M_i, F_j, M_j, diss, ż] (7 + ns)
  Mat Do;               ///< ∂o/∂κ, κ = [r_i, ṙ_i, φ_i, ω_i, r_j, ṙ_j, φ_j, ω_j]
  Mat Dz;               ///< ∂o/∂z
  Mat Kp_i, Kv_i, Kp_j, Kv_j;  ///< ∂κ_m/∂p_b, ∂κ_m/∂v_b (6 × nb)
  Mat Gen_i, Gen_j;            ///< [Jr; Jφ] (3 × nb)
  Mat T;                       ///< scratch (7 + ns) × nb_max
  /// Wall time spent in this element in residuals and Jacobians (RunData::time_elements) [s].
  double seconds{0.0};
};

/// Sizes a body's scratch for body b (used by RunData and the stand-alone kernels).
void ResizeBodyScratch(const Body& b, BodyScratch* s);

class RunData {
 public:
  explicit RunData(const Mechanism& model);

  const Mechanism* model{nullptr};  ///< the model this workspace was sized for
  std::vector<BodyScratch> bodies;
  std::vector<MarkerScratch> markers;  ///< ground markers' kinematics are set here, once
  std::vector<int> body_markers;       ///< the markers on bodies, which UpdateAll refreshes
  std::vector<JointScratch> joints;
  std::vector<ElementScratch> elements;
  std::vector<CorotatedScratch> corotated;  ///< one per Mechanism::corotated_dampings()
  Vec Q;                                    ///< applied generalized forces (np)
  /// Per-run element memory (ForceElement::num_memory each, at ElementSlot::memory_offset).
  std::vector<double> element_memory;
  /// Mechanical energy + dissipated − work at the start of the run: the energy balance
  /// error is measured against it [J].
  double reference_energy{0.0};
  /// Count of residual evaluations through CalcResidual (for statistics).
  long residual_evaluations{0};
  long jacobian_evaluations{0};
  /// Time each element's evaluations in CalcResidual and AddJacobian into
  /// ElementScratch::seconds (off by default: two clock reads per element per call).
  bool time_elements{false};
};

}  // namespace flexrod::multibody
