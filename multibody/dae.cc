// multibody/dae.cc — residual, roots, tolerance scales and constraint pieces of the mechanism
// DAE (its Jacobian: multibody/dae_jacobian.cc; the kernels: multibody/dae_kernels.h).
// Notation (ffrf-planar.md): A = A(θ), J = [[0,−1],[1,0]], s = S̄₀ + S̄q, w = I₁ + M_ff q,
// c = Ī + S̃q, ū = ū₀ + S_u q (marker), Jr = [I, AJū, AS_u], Jφ = [0, 0, 1, S_φ].
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/dae.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "common/error.h"
#include "common/scope_timer.h"
#include "multibody/dae_kernels.h"

namespace flexrod::multibody {

using dae_kernels::AddJointTransposeProduct;
using dae_kernels::AddMarkerForce;
using dae_kernels::BodyOf;
using dae_kernels::CMap;
using dae_kernels::EvalJoint;
using dae_kernels::FillJointHessian;
using dae_kernels::FillJointJacobian;
using dae_kernels::FillJointMarkers;
using dae_kernels::FillMarkerJacobian;
using dae_kernels::FillMassMatrix;
using dae_kernels::FillQuadraticVelocity;
using dae_kernels::HessianTimesVelocity;
using dae_kernels::RowHasHessian;
using dae_kernels::UpdateAll;
using dae_kernels::UpdateBody;
using dae_kernels::VMap;

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
  return KineticEnergy(body, &s, pb.data(), vb.data());
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

double KineticEnergy(const Body& b, BodyScratch* s, const double* pb, const double* vb) {
  // ½ vᵀ (M v), M v from MassTimes (M is not formed; energies are sampled at the output rate).
  const int nb = b.num_coordinates();
  MassTimes(b, *s, pb, vb, s->tmp.data());
  return 0.5 * CMap(vb, nb).dot(s->tmp.head(nb));
}

void MassTimes(const Body& b, const BodyScratch& s, const double* pb, const double* a,
               double* out) {
  // The blocks of FillMassMatrix applied to a without forming M: M_RR = m I, M_Rθ = A J s,
  // M_Rf = A S̄, M_θθ = J₀ + 2 I₁ᵀq + qᵀM_ff q, M_θf = cᵀ, M_ff.
  const int n = b.num_modes;
  const Vec2 aR(a[kX], a[kY]);
  const double ath = a[kTheta];
  const Vec2 AJs = s.A * Jm(s.s);
  Vec2 f = b.mass * aR + AJs * ath;
  double m = AJs.dot(aR);
  double mtt = b.J0;
  if (n > 0) {
    const double* pq = pb + kFirstMode;
    const double* af = a + kFirstMode;
    const Vec2 aRl = s.A.transpose() * aR;  // a_R in the body frame: (A S̄)ᵀ a_R = S̄ᵀ Aᵀ a_R
    Vec2 Saf = Vec2::Zero();
    double* tail = out + kFirstMode;
    for (int i = 0; i < n; ++i) {
      mtt += pq[i] * (b.I1(i) + s.w(i));
      m += s.c(i) * af[i];
      Saf += b.Sbar.col(i) * af[i];
      tail[i] = s.c(i) * ath + b.Sbar(0, i) * aRl.x() + b.Sbar(1, i) * aRl.y();
    }
    b.mass_ff.AddTermwise(af, tail);
    f += s.A * Saf;
  }
  out[kX] = f.x();
  out[kY] = f.y();
  out[kTheta] = m + mtt * ath;
}

void CalcJointConstraint(const Mechanism& model, const RunData& data, JointId joint,
                         const double* y, double* g) {
  double gv[3];
  EvalJoint(model, data, model.joint(joint), y, y + model.num_coordinates(), g, gv);
}

// ---- public: residual ---------------------------------------------------------------------------
namespace {

/// Body bi's rows of F2: M v̇ − Q_v − Q_gravity + K q + D q̇ (elastic rows); its damping and
/// stiffening powers added to *diss_damping and *stiffening_power.
void AddBodyResidual(const Mechanism& model, RunData* data, size_t bi, const double* p,
                     const double* v, const double* vd, double* r2, double* diss_damping,
                     double* stiffening_power) {
  const Vec2& gravity = model.gravity();
  const bool has_gravity = gravity.squaredNorm() > 0.0;
  const Body& b = model.bodies()[bi];
  BodyScratch& s = data->bodies[bi];
  const int o = b.coordinate_offset, nb = b.num_coordinates(), n = b.num_modes;
  FillQuadraticVelocity(b, s, v + o, &s.Qv);
  MassTimes(b, s, p + o, vd + o, r2 + o);
  VMap rb(r2 + o, nb);
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
    *diss_damping += qd.dot(s.Dqd);
    if (b.geometric_stiffening) *stiffening_power -= qd.dot(s.Fg);
  }
}

/// The drivers' rows: a constraint driver's g and G v rows and multiplier terms, a motor's
/// torque in Q; their power added to *driver_power.
void AddDriverResidual(const Mechanism& model, RunData* data, double t, const double* y, double* r,
                       double* driver_power) {
  const int np = model.num_coordinates();
  const double* p = y;
  const double* v = y + np;
  const double* lam = y + model.lambda_offset();
  const double* mu = y + model.mu_offset();
  double* r1 = r;
  double* r2 = r + np;
  double* r3 = r + model.lambda_offset();
  double* r4 = r + model.mu_offset();
  const auto& bodies = model.bodies();
  for (const Driver& d : model.drivers()) {
    const int ith = bodies[d.body].coordinate(kTheta);
    const double thd = v[ith];
    if (d.is_constraint()) {
      r3[d.row] = p[ith] - d.PrescribedAngle(t);
      r4[d.row] = thd - d.PrescribedSpeed(t);
      r2[ith] += lam[d.row];
      r1[ith] -= mu[d.row];
      *driver_power -= lam[d.row] * thd;  // driver torque = −λ
    } else {
      const double torque = d.MotorTorque(thd);
      data->Q(ith) += torque;
      *driver_power += torque * thd;
    }
  }
}

/// Element ei's generalized forces in Q and its state rows; its dissipation added to
/// *diss_elements. False if the element reports a problem.
bool AddElementResidual(const Mechanism& model, RunData* data, size_t ei, double t, const double* z,
                        const double* zd, double* r5, double* diss_elements) {
  double* memory = data->element_memory.data();
  const ElementSlot& e = model.elements()[ei];
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
    return false;
  }
  AddMarkerForce(model, e.marker_i, *data, es.out.force_i, es.out.moment_i, data->Q.data());
  AddMarkerForce(model, e.marker_j, *data, es.out.force_j, es.out.moment_j, data->Q.data());
  for (int k = 0; k < e.num_states; ++k) {
    r5[e.state_offset + k] = zd[e.state_offset + k] - es.zdot(k);
  }
  *diss_elements += es.out.dissipation;
  return true;
}

}  // namespace

int CalcResidual(const Mechanism& model, RunData* data, double t, const double* y, const double* yp,
                 double* r) {
  const int np = model.num_coordinates();
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

  UpdateAll(model, data, p, v);
  for (int i = 0; i < np; ++i) r1[i] = pd[i] - v[i];
  data->Q.setZero();
  double diss_elements = 0.0, diss_damping = 0.0, driver_power = 0.0, stiffening_power = 0.0;

  // Bodies: M v̇ − Q_v − Q_e − Q_gravity.
  for (size_t bi = 0; bi < model.bodies().size(); ++bi)
    AddBodyResidual(model, data, bi, p, v, vd, r2, &diss_damping, &stiffening_power);
  AddDriverResidual(model, data, t, y, r, &driver_power);

  // Joints: g, G v, + Gᵀλ in F2, − Gᵀμ in F1.
  for (const Joint& jt : model.joints()) {
    EvalJoint(model, *data, jt, p, v, r3 + jt.row, r4 + jt.row);
    AddJointTransposeProduct(model, *data, jt, lam + jt.row, r2);
    double neg_mu[3];
    for (int k = 0; k < jt.num_rows; ++k) neg_mu[k] = -mu[jt.row + k];
    AddJointTransposeProduct(model, *data, jt, neg_mu, r1);
  }

  // Force elements.
  for (size_t ei = 0; ei < model.elements().size(); ++ei) {
    if (!AddElementResidual(model, data, ei, t, z, zd, r5, &diss_elements)) return 1;
  }
  for (size_t di = 0; di < model.corotated_dampings().size(); ++di) {
    AddCorotatedDampingResidual(model, model.corotated_dampings()[di], &data->corotated[di], p, v,
                                zd, data->Q.data(), r5, &diss_damping);
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

int CalcElementRoots(const Mechanism& model, RunData* data, double t, const double* y, double* g) {
  if (model.num_element_roots() == 0) return 0;
  const double* z = y + model.z_offset();
  const double* memory = data->element_memory.data();
  for (const ElementSlot& e : model.elements()) {
    if (e.num_roots == 0) continue;
    // The root functions read the two markers' kinematics only: those, not every body's modal
    // products (IDA evaluates the roots at every step and inside every root search).
    dae_kernels::UpdateMarkerAlone(model, e.marker_i, data, y, y + model.num_coordinates());
    dae_kernels::UpdateMarkerAlone(model, e.marker_j, data, y, y + model.num_coordinates());
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
  for (const CorotatedDamping& d : model.corotated_dampings()) {
    for (int k = 0; k < d.num_states(); ++k)
      scales[model.z_offset() + d.state_offset + k] = kCorotatedStateScale;
  }
  for (int k = 0; k < kNumQuadratures; ++k) scales[model.quadrature_offset() + k] = energy_scale;
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
    FillJointMarkers(model, data, jt, v.data(), &a, &b);
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
