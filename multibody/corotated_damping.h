// multibody/corotated_damping.h — modal damping of a chain of rigid bodies (the exact rod's node
// bodies) on their deformation rates in a frame that turns with the first body: the equations
// of Mechanism::corotated_dampings() in the residual, the Jacobian and its pattern, and the rate
// map the modal fit needs (mechanisms/mechanism_model.cc). What does not live here: choosing
// the modes and coefficients (FitCorotatedModalDamping, multibody/mechanism_modes.h).
//
// Bodies k = 0 … n−1 with (r_k, θ_k); the frame is body 0's: origin r_0, angle θ_0, R = R(θ_0),
// J = [[0, −1], [1, 0]]. Deformation rates, k = 1 … n−1:
//   ḋ_k = [Rᵀ(ṙ_k − ṙ_0 − θ̇_0 J (r_k − r_0)); θ̇_k − θ̇_0]   (3(n−1); ḋ = B(p) v)
// zero for every rigid motion of the chain. They are the time derivatives of the co-rotated
// displacements d_k = [Rᵀ(r_k − r_0); θ_k − θ_0] (minus their reference), the deformation a
// floating frame clamped at body 0 sees — the reduced rod's elastic coordinates play this part.
// Modal rates w = Yᵀ ḋ (r), generalized forces Q_d = −Bᵀ Y diag(c) w, power −Q_d·v = Σ c_i w_i².
// The modes Y are dense over the chain, so the forces are realised through r states η with
// η̇ = w (rows η̇ − Yᵀ B v of F5) and Q_d = −Bᵀ Y diag(c) η̇: the iteration matrix then holds
// r dense columns and rows (a bordered sparse matrix KLU factors cheaply) instead of a dense
// (3n)² block. η itself enters nothing; its tolerance scale (kCorotatedStateScale) keeps it
// out of the error test. The dissipation Σ c_i η̇_i² goes to the damping quadrature.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <vector>

#include "common/eigen.h"
#include "multibody/mechanism.h"

namespace flexrod::multibody {

/// Absolute-tolerance multiplier of the modal states η: they integrate the modal rates for
/// nothing but the force's η̇, so their own error is not controlled.
inline constexpr double kCorotatedStateScale = 1e6;

/// B(p): ḋ = B v for the chain `bodies` (3(n−1) × np).
Mat CorotatedRateMap(const Mechanism& m, const std::vector<BodyId>& bodies, const Vec& p);

/// Scratch of one co-rotated damping (RunData::corotated), sized once.
struct CorotatedScratch {
  Vec rates;   ///< ḋ (3(n−1))
  Vec stress;  ///< σ = Y diag(c) η̇ (3(n−1))
  Mat forces;  ///< Bᵀ Y: column i is the generalized force of mode i (3n × r)
};
void ResizeCorotatedScratch(const CorotatedDamping& d, CorotatedScratch* s);

/// Residual: adds Q_d to Q (np), writes the rows η̇ − Yᵀ B v at r5 + state_offset, adds the
/// dissipation Σ c_i η̇_i² to *dissipation. zd: ż (the z block of ẏ). Does not allocate.
void AddCorotatedDampingResidual(const Mechanism& m, const CorotatedDamping& d, CorotatedScratch* s,
                                 const double* p, const double* v, const double* zd, double* Q,
                                 double* r5, double* dissipation);

/// Jacobian: adds ∂F/∂y + c_j ∂F/∂ẏ of the terms above to jac (column-major, leading
/// dimension ld) and, if given, ∂F/∂ẏ to dfdyp. Does not allocate.
void AddCorotatedDampingJacobian(const Mechanism& m, const CorotatedDamping& d, CorotatedScratch* s,
                                 double cj, const double* p, const double* v, const double* zd,
                                 double* jac, int ld, double* dfdyp);

/// The Jacobian's structural non-zeros of the terms above: mark(row, column).
template <typename Mark>
void MarkCorotatedDamping(const Mechanism& m, const CorotatedDamping& d, Mark mark) {
  const int np = m.num_coordinates(), F5 = m.z_offset() + d.state_offset;
  const int QD = m.quadrature_offset() + kDissipatedDamping;
  const int th0 = m.bodies()[d.bodies[0]].coordinate_offset + kTheta;
  for (const int b : d.bodies) {
    const int o = m.bodies()[b].coordinate_offset;
    for (int k = 0; k < 3; ++k) {
      mark(np + o + k, th0);  // the forces turn with the frame
      mark(np + th0, o + k);  // the frame's moment has arms r_k − r_0
      for (int i = 0; i < d.num_states(); ++i) {
        mark(np + o + k, F5 + i);
        mark(F5 + i, o + k);
        mark(F5 + i, np + o + k);
      }
    }
  }
  for (int i = 0; i < d.num_states(); ++i) mark(QD, F5 + i);
}

}  // namespace flexrod::multibody
