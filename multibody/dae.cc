// multibody/dae.cc — residual, Jacobian, roots and constraint pieces of the mechanism DAE.
// Notation (ffrf-planar.md): A = A(θ), J = [[0,−1],[1,0]], s = S̄₀ + S̄q, w = I₁ + M_ff q,
// c = Ī + S̃q, ū = ū₀ + S_u q (marker), Jr = [I, AJū, AS_u], Jφ = [0, 0, 1, S_φ].
// SPDX-License-Identifier: GPL-3.0-or-later
#define EIGEN_RUNTIME_NO_MALLOC  // the residual must not allocate (tests/multibody)
#include "multibody/dae.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "common/error.h"
#include "common/scope_timer.h"

namespace flexrod::multibody {
namespace {

using CMap = Eigen::Map<const Vec>;
using VMap = Eigen::Map<Vec>;
using JacMap = Eigen::Map<Mat, 0, Eigen::OuterStride<>>;

// cbrt(machine epsilon): optimal relative step of a central difference.
const double kFdStep = std::cbrt(std::numeric_limits<double>::epsilon());

// ---- body level -------------------------------------------------------------------------------
// The second-order axial strain (FlexibleBodySpec::geometric_stiffening). Element e's strain
// times its length is δ_e + (P s)_e: its elongation δ = E q and the projection P = V Vᵀ of the
// chords' shortenings s_e = ½ w_eᵀ K_G w_e on the elongation fields the basis carries, with
// w_e = T_e q its nodes' (v, θ). Its force N_e = k (δ_e + (P s)_e), k = EA/L_e, and
// F_g = Σ_e N_e T_eᵀ K_G w_e + k Eᵀ P s (the gradient of ½ k Σ_e (δ_e + (P s)_e)² less ½ qᵀKq's
// axial part, which K q already has). The element loops touch only the 2 (n_e + 1) nodal rows
// of T, each product with T or E is one matrix-vector product.
void UpdateSecondOrderStrain(const Body& b, const CMap& q, BodyScratch* s) {
  const double k = b.element_axial_stiffness;
  const int ne = b.num_elements();
  s->node_w.noalias() = b.transverse_rows * q;
  for (int e = 0; e < ne; ++e) {
    const auto w = s->node_w.segment<4>(2 * e);
    auto kw = s->element_kgw.segment<4>(4 * e);
    kw.noalias() = b.element_Kg * w;
    s->element_short(e) = 0.5 * w.dot(kw);  // ½ ∫_e v'² dx [m]
  }
  s->strain_coef.noalias() = b.element_strain_basis.transpose() * s->element_short;
  s->projected_short.noalias() = b.element_strain_basis * s->strain_coef;
  s->element_force.noalias() = b.elongation_rows * q;
  s->element_force = k * (s->element_force + s->projected_short);
  s->node_force.setZero();
  for (int e = 0; e < ne; ++e) {
    s->node_force.segment<4>(2 * e) += s->element_force(e) * s->element_kgw.segment<4>(4 * e);
  }
  s->Fg.noalias() = b.transverse_rows.transpose() * s->node_force;
  s->Fg.noalias() += k * (b.elongation_rows.transpose() * s->projected_short);
}

// Damping of the second-order strains (Body::strain_damping): D acts on the rates of the
// strain-consistent coordinates q̃ = q + B s(q), whose elongations are the strains, E q̃ = δ + P s,
// so the bent rod's shortening motion, which strains nothing, is not damped. With v = q̇ + B ṡ,
// ṡ_e = (K_G w_e)ᵀ ẇ_e, the force is (I + B ∂s/∂q)ᵀ D v = g + Σ_e T_eᵀ K_G w_e h_e, g = D v,
// h = Bᵀ g; with D = β K it is Kelvin–Voigt on the strains. Needs UpdateSecondOrderStrain's
// K_G w_e.
void UpdateStrainDamping(const Body& b, const CMap& qd, BodyScratch* s) {
  const int ne = b.num_elements();
  s->node_wd.noalias() = b.transverse_rows * qd;
  for (int e = 0; e < ne; ++e) {
    s->element_short_rate(e) = s->element_kgw.segment<4>(4 * e).dot(s->node_wd.segment<4>(2 * e));
  }
  s->strain_velocity = qd;
  s->strain_velocity.noalias() += b.shortening_to_q * s->element_short_rate;
  s->damping_g.noalias() = b.D * s->strain_velocity;
  s->damping_h.noalias() = b.shortening_to_q.transpose() * s->damping_g;
  s->node_damping.setZero();
  for (int e = 0; e < ne; ++e) {
    s->node_damping.segment<4>(2 * e) += s->damping_h(e) * s->element_kgw.segment<4>(4 * e);
  }
  s->Dqd = s->damping_g;
  s->Dqd.noalias() += b.transverse_rows.transpose() * s->node_damping;
}

// `dynamics` false skips D q̇ and S̃ q̇, which only the residual and the Jacobian read (each
// refreshes them itself): output samples at 100 kHz need the kinematics and the energies only.
void UpdateBody(const Body& b, const double* pb, const double* vb, BodyScratch* s,
                bool dynamics = true) {
  const double th = pb[kTheta];
  if (th != s->trig_theta) {  // a held or prescribed angle repeats: skip the trigonometry
    s->cos_theta = std::cos(th);
    s->sin_theta = std::sin(th);
    s->trig_theta = th;
  }
  s->A << s->cos_theta, -s->sin_theta, s->sin_theta, s->cos_theta;
  s->s = b.S0;
  const int n = b.num_modes;
  if (n == 0) return;
  CMap q(pb + kFirstMode, n), qd(vb + kFirstMode, n);
  s->s.noalias() += b.Sbar * q;
  s->w = b.I1;
  s->w.noalias() += b.Mff * q;
  s->c = b.Ibar;
  s->c.noalias() += b.Stilde * q;
  s->Kq.noalias() = b.K * q;
  s->Fg.setZero();
  // Output samples (dynamics false) need ½ qᵀKq only, not F_g.
  if (b.geometric_stiffening && dynamics) {
    UpdateSecondOrderStrain(b, q, s);
    s->Kq += s->Fg;
  }
  if (!dynamics) return;
  if (b.strain_damping) {
    UpdateStrainDamping(b, qd, s);
  } else {
    s->Dqd.noalias() = b.D * qd;
  }
  s->Sqd.noalias() = b.Stilde * qd;
}

// Σ_e c_e T_eᵀ K_G T_e (n × n): the nodal rows Σ_e c_e K_G T_e, then one product with Tᵀ.
void AddWeightedKg(const Body& b, const Vec& c, BodyScratch* s, Mat* out) {
  s->node_kgt.setZero();
  for (int e = 0; e < b.num_elements(); ++e) {
    s->node_kgt.middleRows<4>(2 * e).noalias() +=
        c(e) * (b.element_Kg * b.transverse_rows.middleRows<4>(2 * e));
  }
  out->noalias() += b.transverse_rows.transpose() * s->node_kgt;
}

// With S = ∂s/∂q (rows (K_G w_e)ᵀ T_e) and H = Sᵀ V:
//   ∂F_g/∂q = Σ_e N_e T_eᵀ K_G T_e + k (Sᵀ E + Eᵀ S) + k H Hᵀ;
// and with strain damping, C = I + B S, Ṡ (rows (K_G ẇ_e)ᵀ T_e):
//   ∂F_d/∂q̇ = Cᵀ D C,  ∂F_d/∂q = Cᵀ D B Ṡ + Σ_e h_e T_eᵀ K_G T_e.
void AddSecondOrderStrainJacobian(const Body& b, BodyScratch* s) {
  const double k = b.element_axial_stiffness;
  const int ne = b.num_elements();
  for (int e = 0; e < ne; ++e) {
    s->short_jac.row(e).noalias() =
        s->element_kgw.segment<4>(4 * e).transpose() * b.transverse_rows.middleRows<4>(2 * e);
  }
  s->dmap.noalias() = k * (s->short_jac.transpose() * b.elongation_rows);  // k Sᵀ E
  s->Jg = s->dmap + s->dmap.transpose();
  s->H.noalias() = s->short_jac.transpose() * b.element_strain_basis;
  s->Jg.noalias() += k * (s->H * s->H.transpose());
  AddWeightedKg(b, s->element_force, s, &s->Jg);
  if (!b.strain_damping) return;
  for (int e = 0; e < ne; ++e) {
    const Eigen::Vector4d kwd = b.element_Kg * s->node_wd.segment<4>(2 * e);
    s->short_rate_jac.row(e).noalias() = kwd.transpose() * b.transverse_rows.middleRows<4>(2 * e);
  }
  s->strain_map.setIdentity();
  s->strain_map.noalias() += b.shortening_to_q * s->short_jac;
  s->dmap.noalias() = b.D * s->strain_map;
  s->Jkv_qd.noalias() = s->strain_map.transpose() * s->dmap;
  s->Jkv_qd -= b.D;  // the residual's velocity block already has D
  s->bsd.noalias() = b.shortening_to_q * s->short_rate_jac;
  s->dmap.noalias() = b.D * s->bsd;
  s->Jkv_q.noalias() = s->strain_map.transpose() * s->dmap;
  AddWeightedKg(b, s->damping_h, s, &s->Jkv_q);
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
    CMap q(pb + kFirstMode, n), qd(vb + kFirstMode, n);
    ubar.noalias() += mk.S_u * q;
    Suqd.noalias() = mk.S_u * qd;
    phi += mk.S_phi.transpose().dot(q);
    omega += mk.S_phi.transpose().dot(qd);
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

void UpdateAll(const Mechanism& model, RunData* data, const double* p, const double* v,
               bool dynamics = true) {
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
    VMap tq(t + kFirstMode, n);
    const Vec2 Fl = data.bodies[mk.body].A.transpose() * F;
    tq.noalias() += mk.S_u.transpose() * Fl;
    tq += moment * mk.S_phi.transpose();
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

int BodyOf(const Mechanism& model, int marker) { return model.markers()[marker].body; }

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
    js->ha.noalias() = js->Haa * js->va;
    if (b >= 0) js->ha.noalias() += js->Hab * js->vb;
  }
  if (b >= 0) {
    js->hb.noalias() = js->Hbb * js->vb;
    if (a >= 0) js->hb.noalias() += js->Hba * js->va;
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

}  // namespace

// ---- public: kernels ----------------------------------------------------------------------------
Mat BodyMassMatrix(const Body& body, const Vec& pb) {
  const int nb = body.num_coordinates();
  FLEXROD_ASSERT(pb.size() == nb);
  BodyScratch s;
  ResizeBodyScratch(body, &s);
  const Vec vb = Vec::Zero(nb);
  UpdateBody(body, pb.data(), vb.data(), &s);
  Mat M(nb, nb);
  FillMassMatrix(body, s, pb.data(), &M);
  return M;
}

double BodyKineticEnergy(const Body& body, const Vec& pb, const Vec& vb) {
  FLEXROD_ASSERT(pb.size() == body.num_coordinates() && vb.size() == body.num_coordinates());
  BodyScratch s;
  ResizeBodyScratch(body, &s);
  UpdateBody(body, pb.data(), vb.data(), &s);
  return KineticEnergy(body, s, pb.data(), vb.data());
}

Vec BodyQuadraticVelocity(const Body& body, const Vec& pb, const Vec& vb) {
  const int nb = body.num_coordinates();
  FLEXROD_ASSERT(pb.size() == nb && vb.size() == nb);
  BodyScratch s;
  ResizeBodyScratch(body, &s);
  UpdateBody(body, pb.data(), vb.data(), &s);
  Vec Qv(nb);
  FillQuadraticVelocity(body, s, vb.data(), &Qv);
  return Qv;
}

void UpdateKinematics(const Mechanism& model, RunData* data, const double* y) {
  UpdateAll(model, data, y, y + model.num_coordinates(), /*dynamics=*/false);
}

double KineticEnergy(const Body& b, const BodyScratch& s, const double* pb, const double* vb) {
  // ½ vᵀ M v with the blocks of FillMassMatrix, without forming M (energies are sampled at the
  // output rate).
  const int n = b.num_modes;
  const Vec2 Rd(vb[kX], vb[kY]);
  const double thd = vb[kTheta];
  const Vec2 AJs = s.A * Jm(s.s);
  double mtt = b.J0;
  double twice = b.mass * Rd.squaredNorm() + 2.0 * thd * AJs.dot(Rd);
  if (n > 0) {
    CMap q(pb + kFirstMode, n), qd(vb + kFirstMode, n);
    mtt += b.I1.dot(q) + q.dot(s.w);
    const Vec2 ASqd = s.A * (b.Sbar * qd);
    twice += 2.0 * Rd.dot(ASqd) + 2.0 * thd * s.c.dot(qd) + qd.dot(b.Mff * qd);
  }
  return 0.5 * (twice + mtt * thd * thd);
}

void CalcJointConstraint(const Mechanism& model, const RunData& data, JointId joint,
                         const double* y, double* g) {
  double gv[3];
  EvalJoint(model, data, model.joint(joint), y, y + model.num_coordinates(), g, gv);
}

// ---- public: residual ---------------------------------------------------------------------------
int CalcResidual(const Mechanism& model, RunData* data, double t, const double* y, const double* yp,
                 double* r) {
  const int np = model.num_coordinates(), nc = model.num_constraints();
  const int N = model.size();
  const double* p = y;
  const double* v = y + np;
  const double* lam = y + model.lambda_offset();
  const double* mu = y + model.mu_offset();
  const double* z = y + model.z_offset();
  const double* pd = yp;
  const double* vd = yp + np;
  const double* zd = yp + model.z_offset();
  double* r1 = r;
  double* r2 = r + np;
  double* r3 = r + model.lambda_offset();
  double* r4 = r + model.mu_offset();
  double* r5 = r + model.z_offset();
  (void)nc;

  UpdateAll(model, data, p, v);
  for (int i = 0; i < np; ++i) r1[i] = pd[i] - v[i];
  data->Q.setZero();
  double diss_elements = 0.0, diss_damping = 0.0, driver_power = 0.0, stiffening_power = 0.0;

  // Bodies: M v̇ − Q_v − Q_e − Q_gravity.
  const Vec2& gravity = model.gravity();
  const bool has_gravity = gravity.squaredNorm() > 0.0;
  const auto& bodies = model.bodies();
  for (size_t bi = 0; bi < bodies.size(); ++bi) {
    const Body& b = bodies[bi];
    BodyScratch& s = data->bodies[bi];
    const int o = b.coordinate_offset, nb = b.num_coordinates(), n = b.num_modes;
    FillMassMatrix(b, s, p + o, &s.M);
    FillQuadraticVelocity(b, s, v + o, &s.Qv);
    VMap rb(r2 + o, nb);
    rb.noalias() = s.M * CMap(vd + o, nb);
    rb -= s.Qv;
    if (has_gravity) {
      rb.head<2>() -= b.mass * gravity;
      rb(kTheta) -= (s.A * Jm(s.s)).dot(gravity);
      if (n > 0) {
        const Vec2 gl = s.A.transpose() * gravity;
        rb.tail(n).noalias() -= b.Sbar.transpose() * gl;
      }
    }
    if (n > 0) {
      rb.tail(n) += s.Kq + s.Dqd;
      CMap qd(v + o + kFirstMode, n);
      diss_damping += qd.dot(s.Dqd);
      if (b.geometric_stiffening) stiffening_power -= qd.dot(s.Fg);
    }
  }

  // Drivers.
  for (const Driver& d : model.drivers()) {
    const int ith = bodies[d.body].coordinate(kTheta);
    const double thd = v[ith];
    if (d.is_constraint()) {
      r3[d.row] = p[ith] - d.PrescribedAngle(t);
      r4[d.row] = thd - d.PrescribedSpeed(t);
      r2[ith] += lam[d.row];
      r1[ith] -= mu[d.row];
      driver_power -= lam[d.row] * thd;  // driver torque = −λ
    } else {
      const double torque = d.MotorTorque(thd);
      data->Q(ith) += torque;
      driver_power += torque * thd;
    }
  }

  // Joints: g, G v, + Gᵀλ in F2, − Gᵀμ in F1.
  for (const Joint& jt : model.joints()) {
    EvalJoint(model, *data, jt, p, v, r3 + jt.row, r4 + jt.row);
    AddJointTransposeProduct(model, *data, jt, lam + jt.row, r2);
    double neg_mu[3];
    for (int k = 0; k < jt.num_rows; ++k) neg_mu[k] = -mu[jt.row + k];
    AddJointTransposeProduct(model, *data, jt, neg_mu, r1);
  }

  // Force elements.
  const auto& elements = model.elements();
  double* memory = data->element_memory.data();
  for (size_t ei = 0; ei < elements.size(); ++ei) {
    const ElementSlot& e = elements[ei];
    ElementScratch& es = data->elements[ei];
    es.out = ElementOutput{};
    if (e.num_states > 0) {
      es.zdot.setZero();
      es.out.state_rates = es.zdot.data();
    }
    const MarkerKinematics& ki = data->markers[e.marker_i].kin;
    const MarkerKinematics& kj = data->markers[e.marker_j].kin;
    const ScopeTimer timer(data->time_elements ? &es.seconds : nullptr);
    if (!e.element->Evaluate(t, ki, kj, z + e.state_offset, memory + e.memory_offset, &es.out)) {
      return 1;
    }
    AddMarkerForce(model, e.marker_i, *data, es.out.force_i, es.out.moment_i, data->Q.data());
    AddMarkerForce(model, e.marker_j, *data, es.out.force_j, es.out.moment_j, data->Q.data());
    for (int k = 0; k < e.num_states; ++k) {
      r5[e.state_offset + k] = zd[e.state_offset + k] - es.zdot(k);
    }
    diss_elements += es.out.dissipation;
  }
  for (int i = 0; i < np; ++i) r2[i] -= data->Q(i);

  // Energy quadratures.
  const int q0 = model.num_element_states();
  r5[q0 + kDissipatedElements] = zd[q0 + kDissipatedElements] - diss_elements;
  r5[q0 + kDissipatedDamping] = zd[q0 + kDissipatedDamping] - diss_damping;
  r5[q0 + kDriverWork] = zd[q0 + kDriverWork] - driver_power;
  r5[q0 + kStiffeningWork] = zd[q0 + kStiffeningWork] - stiffening_power;

  ++data->residual_evaluations;
  for (int i = 0; i < N; ++i) {
    if (!std::isfinite(r[i])) return 1;
  }
  return 0;
}

// ---- public: Jacobian ---------------------------------------------------------------------------
int AddJacobian(const Mechanism& model, RunData* data, double t, double cj, const double* y,
                const double* yp, double* jac, int ld) {
  const int np = model.num_coordinates();
  const int N = model.size();
  JacMap J(jac, N, N, Eigen::OuterStride<>(ld));
  const double* p = y;
  const double* v = y + np;
  const double* lam = y + model.lambda_offset();
  const double* mu = y + model.mu_offset();
  const double* z = y + model.z_offset();
  const double* vd = yp + np;
  const int F1 = 0, F2 = np, F3 = model.lambda_offset(), F4 = model.mu_offset();
  const int F5 = model.z_offset();
  const int QD = model.quadrature_offset();

  UpdateAll(model, data, p, v);

  // Identity blocks: F1 = ṗ − v …, F5 = ż − ….
  for (int i = 0; i < np; ++i) {
    J(F1 + i, i) += cj;
    J(F1 + i, np + i) -= 1.0;
  }
  for (int i = F5; i < N; ++i) J(i, i) += cj;

  // Bodies: c_j M, −∂Q/∂v, ∂(M v̇ − Q)/∂p (closed form).
  const Vec2& g = model.gravity();
  const auto& bodies = model.bodies();
  for (size_t bi = 0; bi < bodies.size(); ++bi) {
    const Body& b = bodies[bi];
    BodyScratch& s = data->bodies[bi];
    const int o = b.coordinate_offset, nb = b.num_coordinates(), n = b.num_modes;
    FillMassMatrix(b, s, p + o, &s.M);
    const int R = F2 + o, P = o, V = np + o;
    J.block(R, V, nb, nb) += cj * s.M;

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
        AddSecondOrderStrainJacobian(b, &s);
        J.block(R + kFirstMode, P + kFirstMode, n, n) += s.Jg;
        if (b.strain_damping) {
          J.block(R + kFirstMode, P + kFirstMode, n, n) += s.Jkv_q;
          J.block(R + kFirstMode, V + kFirstMode, n, n) += s.Jkv_qd;
          // Damping power q̇ᵀ F_d: F_d is linear in q̇ (Cᵀ D C q̇), so ∂/∂q̇ is 2 F_d above.
          J.block(QD + kDissipatedDamping, P + kFirstMode, 1, n).noalias() -=
              qd.transpose() * s.Jkv_q;
        }
        // Stiffening power P_s = −q̇ᵀ F_g(q).
        J.block(QD + kStiffeningWork, V + kFirstMode, 1, n) += s.Fg.transpose();
        J.block(QD + kStiffeningWork, P + kFirstMode, 1, n).noalias() += qd.transpose() * s.Jg;
      }
    }
  }

  // Drivers.
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

  // Joints.
  const auto& joints = model.joints();
  for (size_t ji = 0; ji < joints.size(); ++ji) {
    const Joint& jt = joints[ji];
    JointScratch& js = data->joints[ji];
    int a = -1, b = -1;
    if (jt.kind == JointKind::kGround) {
      b = jt.body;
    } else {
      a = BodyOf(model, jt.marker_i);
      b = BodyOf(model, jt.marker_j);
      FillMarkerJacobian(model, jt.marker_i, data, v);
      FillMarkerJacobian(model, jt.marker_j, data, v);
    }
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
    if (jt.kind == JointKind::kGround) continue;
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

  // Force elements: their analytic ∂o/∂κ (ForceElement::EvaluateJacobian) or finite
  // differences in their kinematic inputs, chained analytically with the marker Jacobians.
  const auto& elements = model.elements();
  const double* memory = data->element_memory.data();
  for (size_t ei = 0; ei < elements.size(); ++ei) {
    const ElementSlot& e = elements[ei];
    ElementScratch& es = data->elements[ei];
    const ScopeTimer timer(data->time_elements ? &es.seconds : nullptr);
    const int ns = e.num_states;
    const int marker[2] = {e.marker_i, e.marker_j};
    const int body[2] = {BodyOf(model, e.marker_i), BodyOf(model, e.marker_j)};
    for (int side = 0; side < 2; ++side) FillMarkerJacobian(model, marker[side], data, v);
    FillElementChainMatrices(model, e, data, &es);
    const double* ze = z + e.state_offset;
    const double* mem = memory + e.memory_offset;
    const MarkerKinematics k0[2] = {data->markers[e.marker_i].kin, data->markers[e.marker_j].kin};
    if (!EvalElementStacked(e, &es, t, k0[0], k0[1], ze, mem, &es.o_plus)) return 1;
    const Vec2 F0[2] = {Vec2(es.o_plus(0), es.o_plus(1)), Vec2(es.o_plus(3), es.o_plus(4))};
    const FiniteDifferenceScales sc = e.element->fd_scales();
    es.Do.setZero();
    es.Dz.setZero();
    const bool analytic = e.element->EvaluateJacobian(t, k0[0], k0[1], ze, mem, &es.Do, &es.Dz);
    // Relative-kinematics elements: positions and velocities are differenced on one side
    // (j if it is on a body), the other side's columns are their negatives, angles are skipped.
    const bool relative = e.element->relative_kinematics();
    const int fd_side = body[1] >= 0 ? 1 : 0;
    for (int pass = 0; pass < (analytic ? 0 : 2); ++pass) {
      const int side = pass == 0 ? fd_side : 1 - fd_side;
      if (body[side] < 0) continue;
      for (int c = 0; c < 6; ++c) {
        if (relative && c == 4) continue;  // ∂/∂φ = 0
        if (relative && c < 4 && side != fd_side) {
          es.Do.col(6 * side + c) = -es.Do.col(6 * fd_side + c);
          continue;
        }
        MarkerKinematics kp[2] = {k0[0], k0[1]}, km[2] = {k0[0], k0[1]};
        const double x0 = Component(kp[side], c);
        const volatile double xh = x0 + kFdStep * ComponentScale(sc, c);
        const double h = xh - x0;
        Component(kp[side], c) = x0 + h;
        Component(km[side], c) = x0 - h;
        if (!EvalElementStacked(e, &es, t, kp[0], kp[1], ze, mem, &es.o_plus)) return 1;
        if (!EvalElementStacked(e, &es, t, km[0], km[1], ze, mem, &es.o_minus)) return 1;
        es.Do.col(6 * side + c) = (es.o_plus - es.o_minus) / (2.0 * h);
      }
    }
    for (int k = 0; k < (analytic ? 0 : ns); ++k) {
      es.z_fd = CMap(ze, ns);
      const double x0 = ze[k];
      const volatile double xh = x0 + kFdStep * e.element->StateScale(k);
      const double h = xh - x0;
      es.z_fd(k) = x0 + h;
      if (!EvalElementStacked(e, &es, t, k0[0], k0[1], es.z_fd.data(), mem, &es.o_plus)) return 1;
      es.z_fd(k) = x0 - h;
      if (!EvalElementStacked(e, &es, t, k0[0], k0[1], es.z_fd.data(), mem, &es.o_minus)) return 1;
      es.Dz.col(k) = (es.o_plus - es.o_minus) / (2.0 * h);
    }
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
        es.T.topLeftCorner(3, nbi).noalias() = es.Do.block(3 * so, 6 * si, 3, 6) * Kp;
        J.block(ro, bi.coordinate_offset, nbo, nbi).noalias() -=
            Gen.transpose() * es.T.topLeftCorner(3, nbi);
        es.T.topLeftCorner(3, nbi).noalias() = es.Do.block(3 * so, 6 * si, 3, 6) * Kv;
        J.block(ro, np + bi.coordinate_offset, nbo, nbi).noalias() -=
            Gen.transpose() * es.T.topLeftCorner(3, nbi);
      }
      if (ns > 0) {
        J.block(ro, zcol, nbo, ns).noalias() -= Gen.transpose() * es.Dz.block(3 * so, 0, 3, ns);
      }
      AddMarkerHessian(model, marker[so], *data, F0[so], -1.0,
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
  ++data->jacobian_evaluations;
  return 0;
}

int CalcElementRoots(const Mechanism& model, RunData* data, double t, const double* y, double* g) {
  if (model.num_element_roots() == 0) return 0;
  UpdateKinematics(model, data, y);
  const double* z = y + model.z_offset();
  const double* memory = data->element_memory.data();
  for (const ElementSlot& e : model.elements()) {
    if (e.num_roots == 0) continue;
    e.element->Roots(t, data->markers[e.marker_i].kin, data->markers[e.marker_j].kin,
                     z + e.state_offset, memory + e.memory_offset, g + e.root_offset);
  }
  return 0;
}

Vec CalcResidual(const Mechanism& model, RunData* data, double t, const Vec& y, const Vec& yp) {
  FLEXROD_ASSERT(y.size() == model.size() && yp.size() == model.size());
  Vec r(model.size());
  if (CalcResidual(model, data, t, y.data(), yp.data(), r.data()) != 0) {
    throw NumericalError("residual evaluation failed (element failure or non-finite value)");
  }
  return r;
}

Mat CalcJacobian(const Mechanism& model, RunData* data, double t, double cj, const Vec& y,
                 const Vec& yp) {
  Mat Jm = Mat::Zero(model.size(), model.size());
  if (AddJacobian(model, data, t, cj, y.data(), yp.data(), Jm.data(), model.size()) != 0) {
    throw NumericalError("Jacobian evaluation failed (element failure)");
  }
  return Jm;
}

void DifferentialMask(const Mechanism& model, double* id) {
  const int N = model.size();
  for (int i = 0; i < N; ++i) {
    const bool multiplier = i >= model.lambda_offset() && i < model.z_offset();
    const bool driver_work = i == model.quadrature_offset() + kDriverWork;
    id[i] = (multiplier || driver_work) ? 0.0 : 1.0;
  }
}

void AbsoluteToleranceScales(const Mechanism& model, double velocity_scale, double energy_scale,
                             double* scales) {
  const int N = model.size(), np = model.num_coordinates();
  for (int i = 0; i < N; ++i) scales[i] = 1.0;
  for (int i = np; i < 2 * np; ++i) scales[i] = velocity_scale;
  for (const ElementSlot& e : model.elements()) {
    for (int k = 0; k < e.num_states; ++k) {
      scales[model.z_offset() + e.state_offset + k] = e.element->StateScale(k);
    }
  }
  for (int k = 0; k < kNumQuadratures; ++k) scales[model.quadrature_offset() + k] = energy_scale;
}

SparsityPattern JacobianPattern(const Mechanism& model) {
  const int N = model.size(), np = model.num_coordinates();
  std::vector<std::set<int64_t>> cols(N);
  auto mark = [&cols](int r, int c) { cols[c].insert(r); };
  const auto& bodies = model.bodies();
  const int F2 = np, F3 = model.lambda_offset(), F4 = model.mu_offset(), F5 = model.z_offset();
  const int QD = model.quadrature_offset();
  // Global coordinate indices a marker moves with.
  auto active = [&](int mi) {
    std::vector<int> idx;
    const Marker& m = model.markers()[mi];
    if (m.body < 0) return idx;
    for (int s : m.active_slots) idx.push_back(bodies[m.body].coordinate_offset + s);
    return idx;
  };
  for (int i = 0; i < np; ++i) {
    mark(i, i);
    mark(i, np + i);
  }
  for (int i = F5; i < N; ++i) mark(i, i);
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
  for (const ElementSlot& e : model.elements()) {
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
  SparsityPattern pat;
  pat.size = N;
  pat.col_ptr.assign(N + 1, 0);
  for (int c = 0; c < N; ++c) {
    pat.col_ptr[c + 1] = pat.col_ptr[c] + static_cast<int64_t>(cols[c].size());
    for (int64_t r : cols[c]) pat.row_index.push_back(r);
  }
  return pat;
}

// ---- constraint pieces --------------------------------------------------------------------------
void CalcConstraints(const Mechanism& model, RunData* data, double t, const Vec& p, Vec* g) {
  const int np = model.num_coordinates(), nc = model.num_constraints();
  FLEXROD_ASSERT(p.size() == np);
  const Vec v = Vec::Zero(np);
  UpdateAll(model, data, p.data(), v.data());
  g->resize(nc);
  double gv[3];
  for (const Joint& jt : model.joints()) {
    EvalJoint(model, *data, jt, p.data(), v.data(), g->data() + jt.row, gv);
  }
  for (const Driver& d : model.drivers()) {
    if (d.is_constraint()) {
      (*g)(d.row) = p(model.bodies()[d.body].coordinate(kTheta)) - d.PrescribedAngle(t);
    }
  }
}

void CalcConstraintJacobian(const Mechanism& model, RunData* data, double t, const Vec& p, Mat* G,
                            Vec* g_t) {
  const int np = model.num_coordinates(), nc = model.num_constraints();
  const Vec v = Vec::Zero(np);
  UpdateAll(model, data, p.data(), v.data());
  G->setZero(nc, np);
  g_t->setZero(nc);
  const auto& bodies = model.bodies();
  const auto& joints = model.joints();
  for (size_t ji = 0; ji < joints.size(); ++ji) {
    const Joint& jt = joints[ji];
    JointScratch& js = data->joints[ji];
    int a = -1, b = -1;
    if (jt.kind == JointKind::kGround) {
      b = jt.body;
    } else {
      a = BodyOf(model, jt.marker_i);
      b = BodyOf(model, jt.marker_j);
      FillMarkerJacobian(model, jt.marker_i, data, v.data());
      FillMarkerJacobian(model, jt.marker_j, data, v.data());
    }
    FillJointJacobian(model, data, jt, &js);
    if (a >= 0) {
      G->block(jt.row, bodies[a].coordinate_offset, jt.num_rows, bodies[a].num_coordinates()) +=
          js.Ga;
    }
    if (b >= 0) {
      G->block(jt.row, bodies[b].coordinate_offset, jt.num_rows, bodies[b].num_coordinates()) +=
          js.Gb;
    }
  }
  for (const Driver& d : model.drivers()) {
    if (!d.is_constraint()) continue;
    (*G)(d.row, bodies[d.body].coordinate(kTheta)) = 1.0;
    (*g_t)(d.row) = -d.PrescribedSpeed(t);
  }
}

void CalcConstraintAccelerationRhs(const Mechanism& model, RunData* data, double t, const Vec& p,
                                   const Vec& v, Vec* gamma) {
  const int nc = model.num_constraints();
  UpdateAll(model, data, p.data(), v.data());
  gamma->setZero(nc);
  const auto& joints = model.joints();
  for (size_t ji = 0; ji < joints.size(); ++ji) {
    const Joint& jt = joints[ji];
    if (jt.kind == JointKind::kGround) continue;
    JointScratch& js = data->joints[ji];
    FillMarkerJacobian(model, jt.marker_i, data, v.data());
    FillMarkerJacobian(model, jt.marker_j, data, v.data());
    const int a = BodyOf(model, jt.marker_i), b = BodyOf(model, jt.marker_j);
    for (int k = 0; k < jt.num_rows; ++k) {
      if (!RowHasHessian(jt, k)) continue;
      double e[3] = {0.0, 0.0, 0.0};
      e[k] = 1.0;
      FillJointHessian(model, data, jt, e, &js);
      HessianTimesVelocity(model, jt, v.data(), &js);
      double vhv = 0.0;
      if (a >= 0) vhv += js.va.dot(js.ha);
      if (b >= 0) vhv += js.vb.dot(js.hb);
      (*gamma)(jt.row + k) = -vhv;
    }
  }
  for (const Driver& d : model.drivers()) {
    if (d.is_constraint()) (*gamma)(d.row) = d.PrescribedAcceleration(t);
  }
}

void CalcMassMatrix(const Mechanism& model, RunData* data, const Vec& p, Mat* M) {
  const int np = model.num_coordinates();
  const Vec v = Vec::Zero(np);
  UpdateAll(model, data, p.data(), v.data());
  M->setZero(np, np);
  const auto& bodies = model.bodies();
  for (size_t bi = 0; bi < bodies.size(); ++bi) {
    const Body& b = bodies[bi];
    BodyScratch& s = data->bodies[bi];
    FillMassMatrix(b, s, p.data() + b.coordinate_offset, &s.M);
    M->block(b.coordinate_offset, b.coordinate_offset, b.num_coordinates(), b.num_coordinates()) =
        s.M;
  }
}

}  // namespace flexrod::multibody
