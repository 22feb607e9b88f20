// multibody/dae_kernels.cc — the kernels of the mechanism DAE (multibody/dae_kernels.h).
// Notation (ffrf-planar.md): A = A(θ), J = [[0,−1],[1,0]], s = S̄₀ + S̄q, w = I₁ + M_ff q,
// c = Ī + S̃q, ū = ū₀ + S_u q (marker), Jr = [I, AJū, AS_u], Jφ = [0, 0, 1, S_φ].
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/dae_kernels.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "common/error.h"
#include "common/matvec.h"
#include "common/scope_timer.h"
#include "multibody/dae.h"

namespace flexrod::multibody::dae_kernels {

// ---- body level -------------------------------------------------------------------------------
// The second-order axial strain (FlexibleBodySpec::geometric_stiffening). Element e's strain
// times its length is (P (δ + s))_e: the projection P = V Vᵀ on the elongation fields the basis
// carries of its elongation δ = E q and its chord's shortening s_e = ½ w_eᵀ K_G w_e = ½ qᵀ G_e q,
// w_e = T_e q, G_e = T_eᵀ K_G T_e. In the fields' coordinates the strains are a = W q + σ,
// W = Vᵀ E, σ = Vᵀ s (σ_k = ½ qᵀ H_k q, H_k = Σ_e V_ek G_e), the forces N = V c, c = k a,
// k = EA/L_e, and F_g = Σ_k c_k H_k q + k Wᵀ σ: the gradient of ½ k |a|² less ½ qᵀKq's axial
// part, which K q already has. The modal kernel forms the r vectors H_k q (r n² operations),
// the element kernel sums over the elements (T q, K_G w_e, Tᵀ).

namespace {

// [H_k x] (n × r) into h: Body::strain_tensors stacks the H_k (n r × n).
void StrainTensorProducts(const Body& b, const CMap& x, Mat* h) {
  b.strain_tensors.Apply(x.data(), h->data());
}

// out += Σ_k y_k H_k q for strain forces y (r): the modal kernel's [H_k q] y, or the
// elements' Tᵀ Σ_e (V y)_e K_G w_e (needs UpdateSecondOrderStrain at q).
void AddStrainGradient(const Body& b, const Vec& y, BodyScratch* s, Vec* out) {
  if (b.modal_strain_kernel) {
    MatVec<true>(s->strain_h, y.data(), out->data());
    return;
  }
  s->element_force.noalias() = b.element_strain_basis * y;
  s->node_force.setZero();
  for (int e = 0; e < b.num_strain_elements; ++e) {
    s->node_force.segment<4>(2 * e) += s->element_force(e) * s->element_kgw.segment<4>(4 * e);
  }
  out->noalias() += b.transverse_rows.transpose() * s->node_force;
}

void UpdateSecondOrderStrain(const Body& b, const CMap& q, BodyScratch* s) {
  const double k = b.element_axial_stiffness;
  if (b.modal_strain_kernel) {
    StrainTensorProducts(b, q, &s->strain_h);
    MatTVec(s->strain_h, q.data(), s->strain_coef.data());
    s->strain_coef *= 0.5;
  } else {
    s->node_w.noalias() = b.transverse_rows * q;
    for (int e = 0; e < b.num_strain_elements; ++e) {
      const auto w = s->node_w.segment<4>(2 * e);
      auto kw = s->element_kgw.segment<4>(4 * e);
      kw.noalias() = b.element_Kg * w;
      s->element_short(e) = 0.5 * w.dot(kw);  // ½ ∫_e v'² dx [m]
    }
    s->strain_coef.noalias() = b.element_strain_basis.transpose() * s->element_short;
  }
  s->strain_force =
      k * (s->q_products.tail(s->strain_coef.size()) + s->strain_coef);  // k (W q + σ)
  MatTVec(b.strain_elongation, s->strain_coef.data(), s->Fg.data());
  s->Fg *= k;
  AddStrainGradient(b, s->strain_force, s, &s->Fg);
}

// Damping of the second-order strains (Body::strain_damping): D acts on the rates of the
// strain-consistent coordinates q̃ = q + B σ(q), B = E⁺ V, whose elongations are the strains,
// E q̃ = V a, so the bent rod's shortening motion, which strains nothing, is not damped. With
// v = q̇ + B ρ, ρ = σ̇ = [H_k q]ᵀ q̇, the force is (I + B ∂σ/∂q)ᵀ D v = g + Σ_k η_k H_k q, g = D v,
// η = Bᵀ g; with D = β K it is Kelvin–Voigt on the strains. Needs UpdateSecondOrderStrain's.
void UpdateStrainDamping(const Body& b, const CMap& qd, BodyScratch* s) {
  if (b.modal_strain_kernel) {
    s->strain_rate.noalias() = s->strain_h.transpose() * qd;
  } else {
    s->node_wd.noalias() = b.transverse_rows * qd;
    for (int e = 0; e < b.num_strain_elements; ++e) {
      s->element_short_rate(e) = s->element_kgw.segment<4>(4 * e).dot(s->node_wd.segment<4>(2 * e));
    }
    s->strain_rate.noalias() = b.element_strain_basis.transpose() * s->element_short_rate;
  }
  s->strain_velocity = qd;
  s->strain_velocity.noalias() += b.strain_to_q * s->strain_rate;
  s->damping_g.noalias() = b.D * s->strain_velocity;
  s->damping_eta.noalias() = b.strain_to_q.transpose() * s->damping_g;
  s->Dqd = s->damping_g;
  AddStrainGradient(b, s->damping_eta, s, &s->Dqd);
}

// A(θ) of the body at pb.
void UpdateOrientation(const double* pb, BodyScratch* s) {
  const double th = pb[kTheta];
  if (th != s->trig_theta) {  // a held or prescribed angle repeats: skip the trigonometry
    s->cos_theta = std::cos(th);
    s->sin_theta = std::sin(th);
    s->trig_theta = th;
  }
  s->A << s->cos_theta, -s->sin_theta, s->sin_theta, s->cos_theta;
}

}  // namespace

// `dynamics` false skips D q̇ and S̃ q̇, which only the residual and the Jacobian read (each
// refreshes them itself): output samples at 100 kHz need the kinematics and the energies only.
void UpdateBody(const Body& b, const double* pb, const double* vb, BodyScratch* s, bool dynamics) {
  UpdateOrientation(pb, s);
  s->s = b.S0;
  const int n = b.num_modes;
  if (n == 0) return;
  CMap q(pb + kFirstMode, n), qd(vb + kFirstMode, n);
  // One product for S̄ q, M_ff q, S̃ q, K q (and W q): each row's sum in the same order as
  // separate products, one call instead of four or five.
  b.q_products.Apply(q.data(), s->q_products.data());
  s->s += s->q_products.head<2>();
  s->w = b.I1 + s->q_products.segment(2, n);
  s->c = b.Ibar + s->q_products.segment(2 + n, n);
  s->Kq = s->q_products.segment(2 + 2 * n, n);
  s->Fg.setZero();
  // Output samples (dynamics false) need ½ qᵀKq only, not F_g.
  if (b.geometric_stiffening && dynamics) {
    UpdateSecondOrderStrain(b, q, s);
    s->Kq += s->Fg;
  }
  if (!dynamics) return;
  b.qd_products.Apply(qd.data(), s->qd_products.data());
  s->Sqd = s->qd_products.head(n);
  if (b.strain_damping) {
    UpdateStrainDamping(b, qd, s);
  } else {
    s->Dqd = s->qd_products.tail(n);
  }
}

// With Hq = [H_k q], Hv = [H_k q̇] (n × r):
//   ∂F_g/∂q = Σ_k c_k H_k + k (Hq W + Wᵀ Hqᵀ + Hq Hqᵀ);
// and with strain damping, C = ∂v/∂q̇ = I + B Hqᵀ:
//   ∂F_d/∂q̇ = Cᵀ D C,  ∂F_d/∂q = Cᵀ D B Hvᵀ + Σ_k η_k H_k.
// The two weighted sums of the H_k are one (weights c + η), and q̇ᵀ Σ_k c_k H_k = (Hv c)ᵀ gives
// the power rows without them.
void AddSecondOrderStrainJacobian(const Body& b, const CMap& q, const CMap& qd, BodyScratch* s) {
  const double k = b.element_axial_stiffness;
  const int n = b.num_modes;
  if (!b.modal_strain_kernel) StrainTensorProducts(b, q, &s->strain_h);
  StrainTensorProducts(b, qd, &s->strain_hd);
  s->dmap.noalias() = k * (s->strain_h * b.strain_elongation);  // k Hq W
  s->Jg = s->dmap + s->dmap.transpose();
  s->Jg.noalias() += k * (s->strain_h * s->strain_h.transpose());
  s->stiffening_row.noalias() = qd.transpose() * s->Jg;
  s->stiffening_row.noalias() += s->strain_force.transpose() * s->strain_hd.transpose();
  s->kg_weights = s->strain_force;
  if (b.strain_damping) {
    s->strain_map.setIdentity();
    s->strain_map.noalias() += b.strain_to_q * s->strain_h.transpose();
    s->dmap.noalias() = b.D * s->strain_map;
    s->Jkv_qd.noalias() = s->strain_map.transpose() * s->dmap;
    s->Jkv_qd -= b.D;  // the residual's velocity block already has D
    s->bsd.noalias() = b.strain_to_q * s->strain_hd.transpose();
    s->dmap.noalias() = b.D * s->bsd;
    s->Jkv_q.noalias() = s->strain_map.transpose() * s->dmap;
    s->damping_row.noalias() = qd.transpose() * s->Jkv_q;
    s->damping_row.noalias() += s->damping_eta.transpose() * s->strain_hd.transpose();
    s->Jg += s->Jkv_q;
    s->kg_weights += s->damping_eta;
  }
  for (Eigen::Index k = 0; k < s->kg_weights.size(); ++k) {
    b.strain_tensors.AddScaledRows(k * n, s->kg_weights(k), &s->Jg);
  }
}

// M(θ, q), ffrf-planar.md "Mass matrix".
void FillMassMatrix(const Body& b, const BodyScratch& s, const double* pb, Mat* M) {
  const int n = b.num_modes;
  M->setZero();
  (*M)(0, 0) = b.mass;
  (*M)(1, 1) = b.mass;
  const Vec2 AJs = s.A * Jm(s.s);  // M_Rθ = A J (S̄₀ + S̄ q)
  (*M)(0, 2) = (*M)(2, 0) = AJs.x();
  (*M)(1, 2) = (*M)(2, 1) = AJs.y();
  double mtt = b.J0;
  if (n > 0) {
    CMap q(pb + kFirstMode, n);
    mtt += b.I1.dot(q) + q.dot(s.w);                // J₀ + 2 I₁ᵀq + qᵀM_ff q
    M->block(0, 3, 2, n).noalias() = s.A * b.Sbar;  // M_Rf = A S̄
    M->block(3, 0, n, 2) = M->block(0, 3, 2, n).transpose();
    M->block(2, 3, 1, n) = s.c.transpose();  // M_θf = Īᵀ + qᵀS̃ᵀ
    M->block(3, 2, n, 1) = s.c;
    M->block(3, 3, n, n) = b.Mff;
  }
  (*M)(2, 2) = mtt;
}

// Q_v, ffrf-planar.md "Quadratic-velocity vector".
void FillQuadraticVelocity(const Body& b, const BodyScratch& s, const double* vb, Vec* Qv) {
  const int n = b.num_modes;
  const double thd = vb[kTheta];
  Vec2 u2 = Vec2::Zero();
  if (n > 0) u2.noalias() = b.Sbar * CMap(vb + kFirstMode, n);
  Qv->head<2>() = s.A * (thd * thd * s.s - 2.0 * thd * Jm(u2));
  if (n > 0) {
    CMap qd(vb + kFirstMode, n);
    (*Qv)(2) = -2.0 * thd * s.w.dot(qd);
    Qv->tail(n) = thd * thd * s.w - 2.0 * thd * s.Sqd;
  } else {
    (*Qv)(2) = 0.0;
  }
}

// ---- marker level -----------------------------------------------------------------------------
// A marker on a body (ground markers' kinematics are constant: RunData sets them).
void UpdateMarker(const Mechanism& model, int mi, RunData* data, const double* p, const double* v) {
  const Marker& mk = model.markers()[mi];
  MarkerScratch& ms = data->markers[mi];
  const Body& b = model.bodies()[mk.body];
  const BodyScratch& s = data->bodies[mk.body];
  const double* pb = p + b.coordinate_offset;
  const double* vb = v + b.coordinate_offset;
  const int n = b.num_modes;
  Vec2 ubar = mk.position;
  Vec2 Suqd = Vec2::Zero();
  double phi = pb[kTheta] + mk.angle, omega = vb[kTheta];
  if (n > 0) {
    // S_u q, S_u q̇, S_φ q, S_φ q̇ in one pass over the columns (as in AddMarkerForce).
    const double* q = pb + kFirstMode;
    const double* qd = vb + kFirstMode;
    for (int i = 0; i < n; ++i) {
      ubar += mk.S_u.col(i) * q[i];
      Suqd += mk.S_u.col(i) * qd[i];
      phi += mk.S_phi(i) * q[i];
      omega += mk.S_phi(i) * qd[i];
    }
  }
  const double thd = vb[kTheta];
  ms.Au = s.A * ubar;
  ms.ASqd = s.A * Suqd;
  ms.kin.position = Vec2(pb[kX], pb[kY]) + ms.Au;
  ms.kin.velocity = Vec2(vb[kX], vb[kY]) + Jm(ms.Au) * thd + ms.ASqd;
  ms.kin.angle = phi;
  ms.kin.angular_velocity = omega;
  ms.conv_acc = -ms.Au * (thd * thd) + 2.0 * thd * Jm(ms.ASqd);  // a_v = A(−ūθ̇² + 2JS_uq̇θ̇)
}

void UpdateMarkerAlone(const Mechanism& model, int mi, RunData* data, const double* p,
                       const double* v) {
  const int body = model.markers().at(mi).body;  // a bad index throws, as MarkerState does
  if (body < 0) return;                          // a ground marker's kinematics are set once
  UpdateOrientation(p + model.bodies()[body].coordinate_offset, &data->bodies[body]);
  UpdateMarker(model, mi, data, p, v);
}

void UpdateAll(const Mechanism& model, RunData* data, const double* p, const double* v,
               bool dynamics) {
  FLEXROD_ASSERT(data->model == &model);
  const auto& bodies = model.bodies();
  for (size_t i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    UpdateBody(b, p + b.coordinate_offset, v + b.coordinate_offset, &data->bodies[i], dynamics);
  }
  for (int i : data->body_markers) UpdateMarker(model, i, data, p, v);
}

// Jr, Jφ, C = ∂(Jr v)/∂p and A S_u of a body marker at the current state.
void FillMarkerJacobian(const Mechanism& model, int mi, RunData* data, const double* v) {
  const Marker& mk = model.markers()[mi];
  if (mk.body < 0) return;
  const Body& b = model.bodies()[mk.body];
  const BodyScratch& s = data->bodies[mk.body];
  MarkerScratch& ms = data->markers[mi];
  const int n = b.num_modes;
  const double thd = v[b.coordinate(kTheta)];
  ms.Jr.setZero();
  ms.Jr(0, 0) = 1.0;
  ms.Jr(1, 1) = 1.0;
  ms.Jr.col(2) = Jm(ms.Au);
  ms.Jphi.setZero();
  ms.Jphi(2) = 1.0;
  ms.C.setZero();
  ms.C.col(2) = -ms.Au * thd + Jm(ms.ASqd);
  if (n > 0) {
    ms.AS.noalias() = s.A * mk.S_u;
    ms.Jr.rightCols(n) = ms.AS;
    ms.Jphi.tail(n) = mk.S_phi;
    ms.C.row(0).tail(n) = -thd * ms.AS.row(1);  // θ̇ J A S_u
    ms.C.row(1).tail(n) = thd * ms.AS.row(0);
  }
}

// H += scale · ∂(Jrᵀ f)/∂p for a fixed world vector f (symmetric, only θ row/column).
void AddMarkerHessian(const Mechanism& model, int mi, const RunData& data, const Vec2& f,
                      double scale, Eigen::Ref<Mat> H) {
  const Marker& mk = model.markers()[mi];
  if (mk.body < 0) return;
  const MarkerScratch& ms = data.markers[mi];
  const int n = model.bodies()[mk.body].num_modes;
  H(2, 2) += scale * (-ms.Au.dot(f));
  if (n > 0) {
    const Vec2 jf = JTm(f);
    for (int k = 0; k < n; ++k) {
      const double h = scale * ms.AS.col(k).dot(jf);
      H(2, 3 + k) += h;
      H(3 + k, 2) += h;
    }
  }
}

// target[body rows] += Jrᵀ F + Jφᵀ moment.
void AddMarkerForce(const Mechanism& model, int mi, const RunData& data, const Vec2& F,
                    double moment, double* target) {
  const Marker& mk = model.markers()[mi];
  if (mk.body < 0) return;
  const Body& b = model.bodies()[mk.body];
  const MarkerScratch& ms = data.markers[mi];
  double* t = target + b.coordinate_offset;
  t[kX] += F.x();
  t[kY] += F.y();
  t[kTheta] += Jm(ms.Au).dot(F) + moment;
  const int n = b.num_modes;
  if (n > 0) {
    // S_uᵀ Aᵀ F + S_φᵀ m, a loop over the columns of S_u (2 × n): Eigen's general product for
    // a transposed dynamic-width matrix costs more than the arithmetic at this size.
    const Vec2 Fl = data.bodies[mk.body].A.transpose() * F;
    double* tq = t + kFirstMode;
    for (int i = 0; i < n; ++i) {
      tq[i] += mk.S_u(0, i) * Fl.x() + mk.S_u(1, i) * Fl.y() + moment * mk.S_phi(i);
    }
  }
}

// ---- joints -----------------------------------------------------------------------------------
struct PrismaticFrame {
  Vec2 u, n, d;
};
PrismaticFrame PrismaticGeometry(const Joint& jt, const MarkerKinematics& ki,
                                 const MarkerKinematics& kj) {
  const double c = std::cos(ki.angle), s = std::sin(ki.angle);
  PrismaticFrame f;
  f.u = Vec2(c * jt.axis.x() - s * jt.axis.y(), s * jt.axis.x() + c * jt.axis.y());
  f.n = Jm(f.u);
  f.d = kj.position - ki.position;
  return f;
}

// g and G v + g_t of one joint (rows jt.row ...).
void EvalJoint(const Mechanism& model, const RunData& data, const Joint& jt, const double* p,
               const double* v, double* g, double* gv) {
  if (jt.kind == JointKind::kGround) {
    const Body& b = model.bodies()[jt.body];
    const int o = b.coordinate_offset;
    g[0] = p[o + kX] - jt.ground_position.x();
    g[1] = p[o + kY] - jt.ground_position.y();
    g[2] = p[o + kTheta] - jt.ground_angle;
    for (int k = 0; k < 3; ++k) gv[k] = v[o + k];
    return;
  }
  const MarkerKinematics& ki = data.markers[jt.marker_i].kin;
  const MarkerKinematics& kj = data.markers[jt.marker_j].kin;
  switch (jt.kind) {
    case JointKind::kWeld:
      g[2] = kj.angle - ki.angle - jt.relative_angle;
      gv[2] = kj.angular_velocity - ki.angular_velocity;
      [[fallthrough]];
    case JointKind::kRevolute: {
      const Vec2 dg = ki.position - kj.position;
      const Vec2 dv = ki.velocity - kj.velocity;
      g[0] = dg.x();
      g[1] = dg.y();
      gv[0] = dv.x();
      gv[1] = dv.y();
      break;
    }
    case JointKind::kPrismatic: {
      const PrismaticFrame f = PrismaticGeometry(jt, ki, kj);
      g[0] = kj.angle - ki.angle - jt.relative_angle;
      gv[0] = kj.angular_velocity - ki.angular_velocity;
      g[1] = f.n.dot(f.d);
      gv[1] = f.n.dot(kj.velocity - ki.velocity) - f.u.dot(f.d) * ki.angular_velocity;
      break;
    }
    case JointKind::kGround:
      break;
  }
}

// target += Gᵀ w for one joint (w = λ or −μ rows of the joint).
void AddJointTransposeProduct(const Mechanism& model, const RunData& data, const Joint& jt,
                              const double* w, double* target) {
  if (jt.kind == JointKind::kGround) {
    const int o = model.bodies()[jt.body].coordinate_offset;
    for (int k = 0; k < 3; ++k) target[o + k] += w[k];
    return;
  }
  switch (jt.kind) {
    case JointKind::kRevolute:
    case JointKind::kWeld: {
      const Vec2 f(w[0], w[1]);
      const double m = jt.kind == JointKind::kWeld ? w[2] : 0.0;
      AddMarkerForce(model, jt.marker_i, data, f, -m, target);
      AddMarkerForce(model, jt.marker_j, data, -f, m, target);
      break;
    }
    case JointKind::kPrismatic: {
      const PrismaticFrame fr =
          PrismaticGeometry(jt, data.markers[jt.marker_i].kin, data.markers[jt.marker_j].kin);
      AddMarkerForce(model, jt.marker_i, data, -w[1] * fr.n, -w[0] - w[1] * fr.u.dot(fr.d), target);
      AddMarkerForce(model, jt.marker_j, data, w[1] * fr.n, w[0], target);
      break;
    }
    case JointKind::kGround:
      break;
  }
}

void FillJointMarkers(const Mechanism& model, RunData* data, const Joint& jt, const double* v,
                      int* a, int* b) {
  if (jt.kind == JointKind::kGround) {
    *a = -1;
    *b = jt.body;
    return;
  }
  *a = BodyOf(model, jt.marker_i);
  *b = BodyOf(model, jt.marker_j);
  FillMarkerJacobian(model, jt.marker_i, data, v);
  FillMarkerJacobian(model, jt.marker_j, data, v);
}

// Ga, Gb of one joint (requires FillMarkerJacobian of its markers).
void FillJointJacobian(const Mechanism& model, RunData* data, const Joint& jt, JointScratch* js) {
  js->Ga.setZero();
  js->Gb.setZero();
  if (jt.kind == JointKind::kGround) {
    js->Gb.leftCols(3).setIdentity();
    return;
  }
  const int a = BodyOf(model, jt.marker_i), b = BodyOf(model, jt.marker_j);
  const MarkerScratch& mi = data->markers[jt.marker_i];
  const MarkerScratch& mj = data->markers[jt.marker_j];
  switch (jt.kind) {
    case JointKind::kWeld:
      if (a >= 0) js->Ga.row(2) = -mi.Jphi;
      if (b >= 0) js->Gb.row(2) = mj.Jphi;
      [[fallthrough]];
    case JointKind::kRevolute:
      if (a >= 0) js->Ga.topRows(2) = mi.Jr;
      if (b >= 0) js->Gb.topRows(2) = -mj.Jr;
      break;
    case JointKind::kPrismatic: {
      const PrismaticFrame f = PrismaticGeometry(jt, mi.kin, mj.kin);
      if (a >= 0) {
        js->Ga.row(0) = -mi.Jphi;
        js->Ga.row(1).noalias() = -f.n.transpose() * mi.Jr;
        js->Ga.row(1) -= f.u.dot(f.d) * mi.Jphi;
      }
      if (b >= 0) {
        js->Gb.row(0) = mj.Jphi;
        js->Gb.row(1).noalias() = f.n.transpose() * mj.Jr;
      }
      break;
    }
    case JointKind::kGround:
      break;
  }
}

// Haa, Hab, Hba, Hbb = Σ_k w_k ∂²g_k/∂p² of one (non-ground) joint.
void FillJointHessian(const Mechanism& model, RunData* data, const Joint& jt, const double* w,
                      JointScratch* js) {
  js->Haa.setZero();
  js->Hab.setZero();
  js->Hba.setZero();
  js->Hbb.setZero();
  if (jt.kind == JointKind::kGround) return;
  const int a = BodyOf(model, jt.marker_i), b = BodyOf(model, jt.marker_j);
  switch (jt.kind) {
    case JointKind::kRevolute:
    case JointKind::kWeld: {
      const Vec2 f(w[0], w[1]);  // g = r_i − r_j (rows 0, 1); the angle row is linear
      if (a >= 0) AddMarkerHessian(model, jt.marker_i, *data, f, 1.0, js->Haa);
      if (b >= 0) AddMarkerHessian(model, jt.marker_j, *data, f, -1.0, js->Hbb);
      break;
    }
    case JointKind::kPrismatic: {
      // g₂ = nᵀd, d = r_j − r_i, u = R(φ_i)a, n = Ju; ∂n/∂φ = −u, ∂u/∂φ = n. Gradient:
      // G₂,a = −nᵀJr_i − (uᵀd)Jφ_i, G₂,b = nᵀJr_j. Differentiating once more:
      //   H_aa = −H_i(n) + Jr_iᵀuJφ_i + Jφ_iᵀuᵀJr_i − (nᵀd)Jφ_iᵀJφ_i,
      //   H_ab = −Jφ_iᵀuᵀJr_j = H_baᵀ,  H_bb = H_j(n),
      // with H_m(f) = ∂(Jr_mᵀ f)/∂p (AddMarkerHessian). Checked against finite differences
      // in tests/multibody/dae_jacobian_test.cc.
      const double w1 = w[1];
      const MarkerScratch& mi = data->markers[jt.marker_i];
      const MarkerScratch& mj = data->markers[jt.marker_j];
      const PrismaticFrame f = PrismaticGeometry(jt, mi.kin, mj.kin);
      if (a >= 0) {
        AddMarkerHessian(model, jt.marker_i, *data, f.n, -w1, js->Haa);
        js->ha.noalias() = mi.Jr.transpose() * f.u;  // Jr_iᵀ u
        js->Haa.noalias() += w1 * (js->ha * mi.Jphi);
        js->Haa.noalias() += w1 * (mi.Jphi.transpose() * js->ha.transpose());
        js->Haa.noalias() -= (w1 * f.n.dot(f.d)) * (mi.Jphi.transpose() * mi.Jphi);
        if (b >= 0) {
          js->hb.noalias() = mj.Jr.transpose() * f.u;  // Jr_jᵀ u
          js->Hab.noalias() = -w1 * (mi.Jphi.transpose() * js->hb.transpose());
          js->Hba = js->Hab.transpose();
        }
      }
      if (b >= 0) AddMarkerHessian(model, jt.marker_j, *data, f.n, w1, js->Hbb);
      break;
    }
    case JointKind::kGround:
      break;
  }
}

// Rows of a joint whose equation is non-linear in p (has a Hessian).
bool RowHasHessian(const Joint& jt, int k) {
  switch (jt.kind) {
    case JointKind::kRevolute:
      return true;
    case JointKind::kWeld:
      return k < 2;
    case JointKind::kPrismatic:
      return k == 1;
    case JointKind::kGround:
      return false;
  }
  return false;
}

// ha = Haa va + Hab vb, hb = Hba va + Hbb vb (Hessian times velocity).
void HessianTimesVelocity(const Mechanism& model, const Joint& jt, const double* v,
                          JointScratch* js) {
  const int a = BodyOf(model, jt.marker_i), b = BodyOf(model, jt.marker_j);
  if (a >= 0) {
    const Body& ba = model.bodies()[a];
    js->va = CMap(v + ba.coordinate_offset, ba.num_coordinates());
  }
  if (b >= 0) {
    const Body& bb = model.bodies()[b];
    js->vb = CMap(v + bb.coordinate_offset, bb.num_coordinates());
  }
  if (a >= 0) {
    MatVec(js->Haa, js->va.data(), js->ha.data());
    if (b >= 0) MatVec<true>(js->Hab, js->vb.data(), js->ha.data());
  }
  if (b >= 0) {
    MatVec(js->Hbb, js->vb.data(), js->hb.data());
    if (a >= 0) MatVec<true>(js->Hba, js->va.data(), js->hb.data());
  }
}

// ---- element finite differences -----------------------------------------------------------------
double& Component(MarkerKinematics& k, int c) {
  switch (c) {
    case 0:
      return k.position.x();
    case 1:
      return k.position.y();
    case 2:
      return k.velocity.x();
    case 3:
      return k.velocity.y();
    case 4:
      return k.angle;
    default:
      return k.angular_velocity;
  }
}

double ComponentScale(const FiniteDifferenceScales& s, int c) {
  return c < 2 ? s.length : c < 4 ? s.speed : c == 4 ? s.angle : s.angular_speed;
}

bool EvalElementStacked(const ElementSlot& e, ElementScratch* es, double t,
                        const MarkerKinematics& ki, const MarkerKinematics& kj, const double* z,
                        const double* memory, Vec* o) {
  ElementOutput out;
  if (e.num_states > 0) {
    es->zdot_fd.setZero();
    out.state_rates = es->zdot_fd.data();
  }
  if (!e.element->Evaluate(t, ki, kj, z, memory, &out)) return false;
  (*o)(0) = out.force_i.x();
  (*o)(1) = out.force_i.y();
  (*o)(2) = out.moment_i;
  (*o)(3) = out.force_j.x();
  (*o)(4) = out.force_j.y();
  (*o)(5) = out.moment_j;
  (*o)(6) = out.dissipation;
  if (e.num_states > 0) o->tail(e.num_states) = es->zdot_fd;
  return true;
}

void FillElementChainMatrices(const Mechanism& model, const ElementSlot& e, RunData* data,
                              ElementScratch* es) {
  for (int side = 0; side < 2; ++side) {
    const int mi = side == 0 ? e.marker_i : e.marker_j;
    if (BodyOf(model, mi) < 0) continue;
    const MarkerScratch& ms = data->markers[mi];
    Mat& Kp = side == 0 ? es->Kp_i : es->Kp_j;
    Mat& Kv = side == 0 ? es->Kv_i : es->Kv_j;
    Mat& Gen = side == 0 ? es->Gen_i : es->Gen_j;
    Kp.setZero();
    Kv.setZero();
    Kp.topRows(2) = ms.Jr;        // ∂r/∂p
    Kp.middleRows(2, 2) = ms.C;   // ∂ṙ/∂p
    Kp.row(4) = ms.Jphi;          // ∂φ/∂p
    Kv.middleRows(2, 2) = ms.Jr;  // ∂ṙ/∂v
    Kv.row(5) = ms.Jphi;          // ∂ω/∂v
    Gen.topRows(2) = ms.Jr;
    Gen.row(2) = ms.Jphi;
  }
}

}  // namespace flexrod::multibody::dae_kernels
