// multibody/dae_jacobian.cc — the iteration Jacobian of the mechanism DAE, ∂r/∂y + c_j ∂r/∂ẏ,
// analytic for bodies, drivers and joints and chained from each force element's own Jacobian
// (or central differences in its inputs); and its structural sparsity.
// Notation (ffrf-planar.md): as multibody/dae.cc.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <algorithm>
#include <optional>
#include <set>

#include "common/error.h"
#include "common/scope_timer.h"
#include "multibody/dae.h"
#include "multibody/dae_kernels.h"

namespace flexrod::multibody {

using dae_kernels::AddMarkerHessian;
using dae_kernels::AddSecondOrderStrainJacobian;
using dae_kernels::BodyOf;
using dae_kernels::CMap;
using dae_kernels::Component;
using dae_kernels::ComponentScale;
using dae_kernels::EvalElementStacked;
using dae_kernels::FillElementChainMatrices;
using dae_kernels::FillJointHessian;
using dae_kernels::FillJointJacobian;
using dae_kernels::FillJointMarkers;
using dae_kernels::FillMarkerJacobian;
using dae_kernels::FillMassMatrix;
using dae_kernels::HessianTimesVelocity;
using dae_kernels::JacMap;
using dae_kernels::kFdStep;
using dae_kernels::RowHasHessian;
using dae_kernels::UpdateAll;

// ---- public: Jacobian ---------------------------------------------------------------------------
/// Body rows: c_j M, −∂Q/∂v, ∂(M v̇ − Q)/∂p (closed form), and the damping and stiffening power
/// rows of the energy quadratures.
void AddBodyJacobian(const Mechanism& model, RunData* data, size_t bi, double cj, const double* p,
                     const double* v, const double* vd, JacMap& J, JacMap* dfdyp) {
  const int np = model.num_coordinates();
  const int F2 = np, QD = model.quadrature_offset();
  const Vec2& g = model.gravity();
  const auto& bodies = model.bodies();
  const Body& b = bodies[bi];
  BodyScratch& s = data->bodies[bi];
  const int o = b.coordinate_offset, nb = b.num_coordinates(), n = b.num_modes;
  FillMassMatrix(b, s, p + o, &s.M);
  const int R = F2 + o, P = o, V = np + o;
  J.block(R, V, nb, nb) += cj * s.M;
  if (dfdyp != nullptr) dfdyp->block(R, V, nb, nb) += s.M;

  const double thd = v[o + kTheta];
  const double alpha = vd[o + kTheta];
  const Vec2 aR(vd[o + kX], vd[o + kY]);
  const Vec2 bb = s.A.transpose() * (aR - g);  // Aᵀ(a_R − g)
  Vec2 u1 = Vec2::Zero(), u2 = Vec2::Zero();
  if (n > 0) {
    u1.noalias() = b.Sbar * CMap(vd + o + kFirstMode, n);  // S̄ q̈
    u2.noalias() = b.Sbar * CMap(v + o + kFirstMode, n);   // S̄ q̇
  }
  // ∂/∂θ̇.
  J.block(R, V + kTheta, 2, 1) += s.A * (Jm(2.0 * u2) - 2.0 * thd * s.s);
  // ∂/∂θ.
  J.block(R, P + kTheta, 2, 1) +=
      s.A * (-(s.s * alpha + 2.0 * thd * u2) - thd * thd * Jm(s.s) + Jm(u1));
  J(R + kTheta, P + kTheta) += -s.s.dot(bb);
  if (n > 0) {
    CMap q(p + o + kFirstMode, n), qd(v + o + kFirstMode, n), qdd(vd + o + kFirstMode, n);
    s.AS.noalias() = s.A * b.Sbar;
    // Velocity derivatives.
    J(R + kTheta, V + kTheta) += 2.0 * s.w.dot(qd);
    J.block(R + kFirstMode, V + kTheta, n, 1) += -2.0 * thd * s.w + 2.0 * s.Sqd;
    J.block(R, V + kFirstMode, 1, n) += -2.0 * thd * s.AS.row(1);  // 2θ̇ J A S̄
    J.block(R + 1, V + kFirstMode, 1, n) += 2.0 * thd * s.AS.row(0);
    J.block(R + kTheta, V + kFirstMode, 1, n) += 2.0 * thd * s.w.transpose();
    J.block(R + kFirstMode, V + kFirstMode, n, n) += 2.0 * thd * b.Stilde + b.D;
    // Position derivatives.
    J.block(R + kFirstMode, P + kTheta, n, 1).noalias() += b.Sbar.transpose() * JTm(bb);
    J.block(R, P + kFirstMode, 1, n) += -alpha * s.AS.row(1) - thd * thd * s.AS.row(0);
    J.block(R + 1, P + kFirstMode, 1, n) += alpha * s.AS.row(0) - thd * thd * s.AS.row(1);
    s.tmp.head(n).noalias() = b.Sbar.transpose() * JTm(bb);
    J.block(R + kTheta, P + kFirstMode, 1, n) += s.tmp.head(n).transpose();
    J.block(R + kTheta, P + kFirstMode, 1, n) += 2.0 * alpha * s.w.transpose();
    s.tmp.head(n).noalias() = b.Stilde.transpose() * qdd;  // (q̈ᵀ S̃)ᵀ
    J.block(R + kTheta, P + kFirstMode, 1, n) += s.tmp.head(n).transpose();
    s.tmp.head(n).noalias() = b.Mff * qd;
    J.block(R + kTheta, P + kFirstMode, 1, n) += 2.0 * thd * s.tmp.head(n).transpose();
    J.block(R + kFirstMode, P + kFirstMode, n, n) += alpha * b.Stilde - thd * thd * b.Mff + b.K;
    // Quadrature: damping power q̇ᵀDq̇.
    J.block(QD + kDissipatedDamping, V + kFirstMode, 1, n) -= 2.0 * s.Dqd.transpose();
    if (b.geometric_stiffening) {
      AddSecondOrderStrainJacobian(b, q, qd, &s);
      J.block(R + kFirstMode, P + kFirstMode, n, n) += s.Jg;
      if (b.strain_damping) {
        J.block(R + kFirstMode, V + kFirstMode, n, n) += s.Jkv_qd;
        // Damping power q̇ᵀ F_d: F_d is linear in q̇ (Cᵀ D C q̇), so ∂/∂q̇ is 2 F_d above.
        J.block(QD + kDissipatedDamping, P + kFirstMode, 1, n) -= s.damping_row;
      }
      // Stiffening power P_s = −q̇ᵀ F_g(q).
      J.block(QD + kStiffeningWork, V + kFirstMode, 1, n) += s.Fg.transpose();
      J.block(QD + kStiffeningWork, P + kFirstMode, 1, n) += s.stiffening_row;
    }
  }
}

/// Driver rows: a constraint driver's Jacobian rows and multiplier columns, a motor's torque
/// slope; the driver-work quadrature.
void AddDriverJacobian(const Mechanism& model, const double* v, const double* lam, JacMap& J) {
  const int np = model.num_coordinates();
  const int F1 = 0, F2 = np, F3 = model.lambda_offset(), F4 = model.mu_offset();
  const int QD = model.quadrature_offset();
  const auto& bodies = model.bodies();
  for (const Driver& d : model.drivers()) {
    const int ith = bodies[d.body].coordinate(kTheta);
    const double thd = v[ith];
    if (d.is_constraint()) {
      J(F3 + d.row, ith) += 1.0;
      J(F4 + d.row, np + ith) += 1.0;
      J(F2 + ith, model.lambda_offset() + d.row) += 1.0;
      J(F1 + ith, model.mu_offset() + d.row) -= 1.0;
      J(QD + kDriverWork, model.lambda_offset() + d.row) += thd;  // r = ż + λθ̇
      J(QD + kDriverWork, np + ith) += lam[d.row];
    } else {
      const double slope = d.MotorTorqueSlope();
      J(F2 + ith, np + ith) -= slope;
      J(QD + kDriverWork, np + ith) -= d.MotorTorque(thd) + thd * slope;
    }
  }
}

/// Joint ji's rows: G and Gᵀ in the constraint and multiplier blocks, the Hessians of Gᵀλ,
/// Gᵀμ and G v.
void AddJointJacobian(const Mechanism& model, RunData* data, size_t ji, const double* v,
                      const double* lam, const double* mu, JacMap& J) {
  const int np = model.num_coordinates();
  const int F1 = 0, F2 = np, F3 = model.lambda_offset(), F4 = model.mu_offset();
  const auto& bodies = model.bodies();
  const auto& joints = model.joints();
  const Joint& jt = joints[ji];
  JointScratch& js = data->joints[ji];
  int a = -1, b = -1;
  FillJointMarkers(model, data, jt, v, &a, &b);
  FillJointJacobian(model, data, jt, &js);
  const int nr = jt.num_rows;
  const int L = model.lambda_offset() + jt.row, Mu = model.mu_offset() + jt.row;
  auto put_G = [&](int body, const Mat& G) {
    const int o = bodies[body].coordinate_offset, nb = bodies[body].num_coordinates();
    J.block(F3 + jt.row, o, nr, nb) += G;
    J.block(F4 + jt.row, np + o, nr, nb) += G;
    J.block(F2 + o, L, nb, nr) += G.transpose();
    J.block(F1 + o, Mu, nb, nr) -= G.transpose();
  };
  if (a >= 0) put_G(a, js.Ga);
  if (b >= 0) put_G(b, js.Gb);
  if (jt.kind == JointKind::kGround) return;
  const int oa = a >= 0 ? bodies[a].coordinate_offset : 0;
  const int ob = b >= 0 ? bodies[b].coordinate_offset : 0;
  const int na = a >= 0 ? bodies[a].num_coordinates() : 0;
  const int nbb = b >= 0 ? bodies[b].num_coordinates() : 0;
  auto put_H = [&](int row0, double scale) {
    if (a >= 0) J.block(row0 + oa, oa, na, na) += scale * js.Haa;
    if (b >= 0) J.block(row0 + ob, ob, nbb, nbb) += scale * js.Hbb;
    if (a >= 0 && b >= 0) {
      J.block(row0 + oa, ob, na, nbb) += scale * js.Hab;
      J.block(row0 + ob, oa, nbb, na) += scale * js.Hba;
    }
  };
  FillJointHessian(model, data, jt, lam + jt.row, &js);  // ∂(Gᵀλ)/∂p in F2
  put_H(F2, 1.0);
  FillJointHessian(model, data, jt, mu + jt.row, &js);  // −∂(Gᵀμ)/∂p in F1
  put_H(F1, -1.0);
  for (int k = 0; k < nr; ++k) {  // ∂(G_k v)/∂p = (Hess_k v)ᵀ in F4
    if (!RowHasHessian(jt, k)) continue;
    double e[3] = {0.0, 0.0, 0.0};
    e[k] = 1.0;
    FillJointHessian(model, data, jt, e, &js);
    HessianTimesVelocity(model, jt, v, &js);
    if (a >= 0) J.block(F4 + jt.row + k, oa, 1, na) += js.ha.transpose();
    if (b >= 0) J.block(F4 + jt.row + k, ob, 1, nbb) += js.hb.transpose();
  }
}

/// The element's ∂o/∂κ (es->Do) and ∂o/∂z (es->Dz) by central differences in its marker
/// kinematics and states, where it gives no analytic Jacobian; false if an evaluation fails.
bool DifferenceElement(const ElementSlot& e, ElementScratch* es, double t,
                       const MarkerKinematics (&k0)[2], const int (&body)[2], const double* ze,
                       const double* mem) {
  const int ns = e.num_states;
  const FiniteDifferenceScales sc = e.element->fd_scales();
  // Relative-kinematics elements: positions and velocities are differenced on one side
  // (j if it is on a body), the other side's columns are their negatives, angles are skipped.
  const bool relative = e.element->relative_kinematics();
  const int fd_side = body[1] >= 0 ? 1 : 0;
  for (int pass = 0; pass < 2; ++pass) {
    const int side = pass == 0 ? fd_side : 1 - fd_side;
    if (body[side] < 0) continue;
    for (int c = 0; c < 6; ++c) {
      if (relative && c == 4) continue;  // ∂/∂φ = 0
      if (relative && c < 4 && side != fd_side) {
        es->Do.col(6 * side + c) = -es->Do.col(6 * fd_side + c);
        continue;
      }
      MarkerKinematics kp[2] = {k0[0], k0[1]}, km[2] = {k0[0], k0[1]};
      const double x0 = Component(kp[side], c);
      const volatile double xh = x0 + kFdStep * ComponentScale(sc, c);
      const double h = xh - x0;
      Component(kp[side], c) = x0 + h;
      Component(km[side], c) = x0 - h;
      if (!EvalElementStacked(e, es, t, kp[0], kp[1], ze, mem, &es->o_plus)) return false;
      if (!EvalElementStacked(e, es, t, km[0], km[1], ze, mem, &es->o_minus)) return false;
      es->Do.col(6 * side + c) = (es->o_plus - es->o_minus) / (2.0 * h);
    }
  }
  for (int k = 0; k < ns; ++k) {
    es->z_fd = CMap(ze, ns);
    const double x0 = ze[k];
    const volatile double xh = x0 + kFdStep * e.element->StateScale(k);
    const double h = xh - x0;
    es->z_fd(k) = x0 + h;
    if (!EvalElementStacked(e, es, t, k0[0], k0[1], es->z_fd.data(), mem, &es->o_plus))
      return false;
    es->z_fd(k) = x0 - h;
    if (!EvalElementStacked(e, es, t, k0[0], k0[1], es->z_fd.data(), mem, &es->o_minus))
      return false;
    es->Dz.col(k) = (es->o_plus - es->o_minus) / (2.0 * h);
  }
  return true;
}

/// Chains an element's ∂o/∂κ and ∂o/∂z with its marker Jacobians into the force rows of its
/// bodies, its state rows and the dissipation quadrature; F0: its forces on the two markers.
void ChainElementJacobian(const Mechanism& model, const RunData& data, const ElementSlot& e,
                          ElementScratch& es, const int (&body)[2], const Vec2 (&F0)[2],
                          JacMap& J) {
  const int np = model.num_coordinates();
  const int F2 = np, F5 = model.z_offset(), QD = model.quadrature_offset();
  const int ns = e.num_states;
  const int marker[2] = {e.marker_i, e.marker_j};
  const auto& bodies = model.bodies();
  const int zcol = F5 + e.state_offset;
  for (int so = 0; so < 2; ++so) {  // output side: generalized forces on its body
    if (body[so] < 0) continue;
    const Body& bo = bodies[body[so]];
    const int ro = F2 + bo.coordinate_offset, nbo = bo.num_coordinates();
    const Mat& Gen = so == 0 ? es.Gen_i : es.Gen_j;
    for (int si = 0; si < 2; ++si) {  // input side
      if (body[si] < 0) continue;
      const Body& bi = bodies[body[si]];
      const int nbi = bi.num_coordinates();
      const Mat& Kp = si == 0 ? es.Kp_i : es.Kp_j;
      const Mat& Kv = si == 0 ? es.Kv_i : es.Kv_j;
      // Coefficient-wise products (lazyProduct): at 3 × 6 × (3 + n) Eigen's size heuristic
      // takes the blocked matrix-matrix path, whose packing costs more than the 18 (3 + n)
      // multiply-adds.
      es.T.topLeftCorner(3, nbi).noalias() = es.Do.block(3 * so, 6 * si, 3, 6).lazyProduct(Kp);
      J.block(ro, bi.coordinate_offset, nbo, nbi).noalias() -=
          Gen.transpose().lazyProduct(es.T.topLeftCorner(3, nbi));
      es.T.topLeftCorner(3, nbi).noalias() = es.Do.block(3 * so, 6 * si, 3, 6).lazyProduct(Kv);
      J.block(ro, np + bi.coordinate_offset, nbo, nbi).noalias() -=
          Gen.transpose().lazyProduct(es.T.topLeftCorner(3, nbi));
    }
    if (ns > 0) {
      J.block(ro, zcol, nbo, ns).noalias() -=
          Gen.transpose().lazyProduct(es.Dz.block(3 * so, 0, 3, ns));
    }
    AddMarkerHessian(model, marker[so], data, F0[so], -1.0,
                     J.block(ro, bo.coordinate_offset, nbo, nbo));
  }
  // Element state rows and the dissipation quadrature row.
  for (int si = 0; si < 2; ++si) {
    if (body[si] < 0) continue;
    const Body& bi = bodies[body[si]];
    const int nbi = bi.num_coordinates();
    const Mat& Kp = si == 0 ? es.Kp_i : es.Kp_j;
    const Mat& Kv = si == 0 ? es.Kv_i : es.Kv_j;
    es.T.topLeftCorner(1 + ns, nbi).noalias() = es.Do.block(6, 6 * si, 1 + ns, 6) * Kp;
    J.block(QD + kDissipatedElements, bi.coordinate_offset, 1, nbi) -= es.T.topLeftCorner(1, nbi);
    if (ns > 0) J.block(zcol, bi.coordinate_offset, ns, nbi) -= es.T.block(1, 0, ns, nbi);
    es.T.topLeftCorner(1 + ns, nbi).noalias() = es.Do.block(6, 6 * si, 1 + ns, 6) * Kv;
    J.block(QD + kDissipatedElements, np + bi.coordinate_offset, 1, nbi) -=
        es.T.topLeftCorner(1, nbi);
    if (ns > 0) J.block(zcol, np + bi.coordinate_offset, ns, nbi) -= es.T.block(1, 0, ns, nbi);
  }
  if (ns > 0) {
    J.block(QD + kDissipatedElements, zcol, 1, ns) -= es.Dz.block(6, 0, 1, ns);
    J.block(zcol, zcol, ns, ns) -= es.Dz.block(7, 0, ns, ns);
  }
}

/// Element ei's rows: its analytic ∂o/∂κ (ForceElement::EvaluateJacobian) or finite differences
/// in its kinematic inputs, chained analytically with the marker Jacobians; false if an
/// evaluation fails.
bool AddElementJacobian(const Mechanism& model, RunData* data, size_t ei, double t, const double* y,
                        JacMap& J) {
  const ElementSlot& e = model.elements()[ei];
  ElementScratch& es = data->elements[ei];
  const ScopeTimer timer(data->time_elements ? &es.seconds : nullptr);
  const double* v = y + model.num_coordinates();
  const int body[2] = {BodyOf(model, e.marker_i), BodyOf(model, e.marker_j)};
  FillMarkerJacobian(model, e.marker_i, data, v);
  FillMarkerJacobian(model, e.marker_j, data, v);
  FillElementChainMatrices(model, e, data, &es);
  const double* ze = y + model.z_offset() + e.state_offset;
  const double* mem = data->element_memory.data() + e.memory_offset;
  const MarkerKinematics k0[2] = {data->markers[e.marker_i].kin, data->markers[e.marker_j].kin};
  if (!EvalElementStacked(e, &es, t, k0[0], k0[1], ze, mem, &es.o_plus)) return false;
  const Vec2 F0[2] = {Vec2(es.o_plus(0), es.o_plus(1)), Vec2(es.o_plus(3), es.o_plus(4))};
  es.Do.setZero();
  es.Dz.setZero();
  const bool analytic = e.element->EvaluateJacobian(t, k0[0], k0[1], ze, mem, &es.Do, &es.Dz);
  if (!analytic && !DifferenceElement(e, &es, t, k0, body, ze, mem)) return false;
  ChainElementJacobian(model, *data, e, es, body, F0, J);
  return true;
}

int AddJacobian(const Mechanism& model, RunData* data, double t, double cj, const double* y,
                const double* yp, double* jac, int ld, double* dfdyp) {
  const int np = model.num_coordinates();
  const int N = model.size();
  JacMap J(jac, N, N, Eigen::OuterStride<>(ld));
  std::optional<JacMap> B;  // dF/dẏ alone, if asked for
  if (dfdyp != nullptr) B.emplace(dfdyp, N, N, Eigen::OuterStride<>(ld));
  const double* p = y;
  const double* v = y + np;
  const double* lam = y + model.lambda_offset();
  const double* mu = y + model.mu_offset();
  const double* vd = yp + np;
  const int F1 = 0, F5 = model.z_offset();

  UpdateAll(model, data, p, v);

  // Identity blocks: F1 = ṗ − v …, F5 = ż − ….
  for (int i = 0; i < np; ++i) {
    J(F1 + i, i) += cj;
    J(F1 + i, np + i) -= 1.0;
  }
  for (int i = F5; i < N; ++i) J(i, i) += cj;
  if (B) {
    for (int i = 0; i < np; ++i) (*B)(F1 + i, i) += 1.0;
    for (int i = F5; i < N; ++i) (*B)(i, i) += 1.0;
  }
  for (size_t bi = 0; bi < model.bodies().size(); ++bi)
    AddBodyJacobian(model, data, bi, cj, p, v, vd, J, B ? &*B : nullptr);
  AddDriverJacobian(model, v, lam, J);
  for (size_t ji = 0; ji < model.joints().size(); ++ji)
    AddJointJacobian(model, data, ji, v, lam, mu, J);
  for (size_t ei = 0; ei < model.elements().size(); ++ei) {
    if (!AddElementJacobian(model, data, ei, t, y, J)) return 1;
  }
  for (size_t di = 0; di < model.corotated_dampings().size(); ++di) {
    AddCorotatedDampingJacobian(model, model.corotated_dampings()[di], &data->corotated[di], cj, p,
                                v, yp + model.z_offset(), jac, ld, dfdyp);
  }
  ++data->jacobian_evaluations;
  return 0;
}

namespace {

/// The structural non-zeros of the iteration Jacobian, column by column, block by block in the
/// order AddJacobian fills them.
class PatternBuilder {
 public:
  explicit PatternBuilder(const Mechanism& model)
      : model_(model),
        bodies_(model.bodies()),
        N(model.size()),
        np(model.num_coordinates()),
        F2(np),
        F3(model.lambda_offset()),
        F4(model.mu_offset()),
        F5(model.z_offset()),
        QD(model.quadrature_offset()),
        cols_(N) {
    for (int i = 0; i < np; ++i) {
      mark(i, i);
      mark(i, np + i);
    }
    for (int i = F5; i < N; ++i) mark(i, i);
  }

  void MarkBodies() {
    const auto& bodies = bodies_;
    for (const Body& b : bodies) {
      const int o = b.coordinate_offset, nb = b.num_coordinates(), n = b.num_modes;
      for (int r = 0; r < nb; ++r) {
        for (int c = 0; c < nb; ++c) {
          const bool frame = r < 3 || c < 3;
          if (frame || b.qq_mask[r - 3][c - 3]) {
            mark(F2 + o + r, o + c);
            mark(F2 + o + r, np + o + c);
          }
        }
      }
      for (int k = 0; k < n; ++k) {
        mark(QD + kDissipatedDamping, np + o + kFirstMode + k);
        if (b.strain_damping) mark(QD + kDissipatedDamping, o + kFirstMode + k);
        if (b.geometric_stiffening) {
          mark(QD + kStiffeningWork, o + kFirstMode + k);
          mark(QD + kStiffeningWork, np + o + kFirstMode + k);
        }
      }
    }
  }

  void MarkDrivers() {
    const auto& bodies = bodies_;
    const Mechanism& model = model_;
    for (const Driver& d : model.drivers()) {
      const int ith = bodies[d.body].coordinate(kTheta);
      mark(F2 + ith, np + ith);
      mark(QD + kDriverWork, np + ith);
      if (d.is_constraint()) {
        mark(F3 + d.row, ith);
        mark(F4 + d.row, np + ith);
        mark(F2 + ith, model.lambda_offset() + d.row);
        mark(ith, model.mu_offset() + d.row);
        mark(QD + kDriverWork, model.lambda_offset() + d.row);
      }
    }
  }

  void MarkJoints() {
    const auto& bodies = bodies_;
    const Mechanism& model = model_;
    for (const Joint& jt : model.joints()) {
      std::vector<int> idx;
      if (jt.kind == JointKind::kGround) {
        for (int k = 0; k < 3; ++k) idx.push_back(bodies[jt.body].coordinate_offset + k);
      } else {
        idx = active(jt.marker_i);
        for (int c : active(jt.marker_j)) idx.push_back(c);
      }
      for (int k = 0; k < jt.num_rows; ++k) {
        const int row = jt.row + k;
        for (int c : idx) {
          mark(F3 + row, c);
          mark(F4 + row, c);
          mark(F4 + row, np + c);
          mark(F2 + c, model.lambda_offset() + row);
          mark(c, model.mu_offset() + row);
        }
      }
      for (int r : idx) {
        for (int c : idx) {
          mark(F2 + r, c);
          mark(r, c);
        }
      }
    }
  }

  void MarkElements() {
    for (const ElementSlot& e : model_.elements()) {
      std::vector<int> idx = active(e.marker_i);
      for (int c : active(e.marker_j)) idx.push_back(c);
      const int zc = F5 + e.state_offset;
      for (int r : idx) {
        for (int c : idx) {
          mark(F2 + r, c);
          mark(F2 + r, np + c);
        }
        for (int k = 0; k < e.num_states; ++k) mark(F2 + r, zc + k);
      }
      for (int k = -1; k < e.num_states; ++k) {
        const int row = k < 0 ? QD + kDissipatedElements : zc + k;
        for (int c : idx) {
          mark(row, c);
          mark(row, np + c);
        }
        for (int kk = 0; kk < e.num_states; ++kk) mark(row, zc + kk);
      }
    }
  }

  void MarkCorotatedDampings() {
    for (const CorotatedDamping& d : model_.corotated_dampings())
      MarkCorotatedDamping(model_, d, [this](int r, int c) { mark(r, c); });
  }

  SparsityPattern Finish() const {
    SparsityPattern pat;
    pat.size = N;
    pat.col_ptr.assign(N + 1, 0);
    for (int c = 0; c < N; ++c) {
      pat.col_ptr[c + 1] = pat.col_ptr[c] + static_cast<int64_t>(cols_[c].size());
      for (int64_t r : cols_[c]) pat.row_index.push_back(r);
    }
    return pat;
  }

 private:
  void mark(int r, int c) { cols_[c].insert(r); }
  // Global coordinate indices a marker moves with.
  std::vector<int> active(int mi) const {
    std::vector<int> idx;
    const Marker& m = model_.markers()[mi];
    if (m.body < 0) return idx;
    for (int s : m.active_slots) idx.push_back(bodies_[m.body].coordinate_offset + s);
    return idx;
  }

  const Mechanism& model_;
  const std::vector<Body>& bodies_;
  const int N, np, F2, F3, F4, F5, QD;  // sizes and row-block offsets, as AddJacobian's
  std::vector<std::set<int64_t>> cols_;
};

}  // namespace

SparsityPattern JacobianPattern(const Mechanism& model) {
  PatternBuilder pattern(model);
  pattern.MarkBodies();
  pattern.MarkDrivers();
  pattern.MarkJoints();
  pattern.MarkElements();
  pattern.MarkCorotatedDampings();
  return pattern.Finish();
}

}  // namespace flexrod::multibody
