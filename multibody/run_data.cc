// multibody/run_data.cc — sizing of the per-run workspace.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/run_data.h"

#include <algorithm>

namespace flexrod::multibody {

void ResizeBodyScratch(const Body& b, BodyScratch* s) {
  const int n = b.num_modes, nb = b.num_coordinates();
  s->A.setIdentity();
  s->s.setZero();
  s->w = Vec::Zero(n);
  s->c = Vec::Zero(n);
  s->Kq = Vec::Zero(n);
  s->Fg = Vec::Zero(n);
  const bool gs = b.geometric_stiffening;
  const int ne = gs && !b.modal_strain_kernel ? b.num_strain_elements : 0;
  const int nw = ne > 0 ? 2 * (ne + 1) : 0;
  const int r = gs ? static_cast<int>(b.element_strain_basis.cols()) : 0;
  const int nj = gs ? n : 0;
  s->strain_h = Mat::Zero(n, r);
  s->strain_coef = Vec::Zero(r);
  s->strain_force = Vec::Zero(r);
  s->node_w = Vec::Zero(nw);
  s->element_kgw = Vec::Zero(4 * ne);
  s->element_short = Vec::Zero(ne);
  s->element_force = Vec::Zero(ne);
  s->node_force = Vec::Zero(nw);
  s->node_wd = Vec::Zero(nw);
  s->element_short_rate = Vec::Zero(ne);
  s->strain_rate = Vec::Zero(r);
  s->strain_velocity = Vec::Zero(n);
  s->damping_g = Vec::Zero(n);
  s->damping_eta = Vec::Zero(r);
  s->strain_hd = Mat::Zero(n, r);
  s->kg_weights = Vec::Zero(r);
  s->Jg = Mat::Zero(nj, nj);
  s->stiffening_row = RowVec::Zero(nj);
  s->strain_map = Mat::Zero(nj, nj);
  s->dmap = Mat::Zero(nj, nj);
  s->bsd = Mat::Zero(nj, nj);
  s->Jkv_q = Mat::Zero(nj, nj);
  s->Jkv_qd = Mat::Zero(nj, nj);
  s->damping_row = RowVec::Zero(nj);
  s->Dqd = Vec::Zero(n);
  s->Sqd = Vec::Zero(n);
  s->q_products = Vec::Zero(b.q_products.rows());
  s->qd_products = Vec::Zero(b.qd_products.rows());
  s->M = Mat::Zero(nb, nb);
  s->Qv = Vec::Zero(nb);
  s->tmp = Vec::Zero(nb);
  s->AS = Mat2X::Zero(2, n);
}

RunData::RunData(const Mechanism& m) : model(&m) {
  const auto& bs = m.bodies();
  bodies.resize(bs.size());
  for (size_t i = 0; i < bs.size(); ++i) ResizeBodyScratch(bs[i], &bodies[i]);
  auto nb_of = [&m](int body) { return body < 0 ? 0 : m.bodies()[body].num_coordinates(); };
  markers.resize(m.markers().size());
  for (size_t i = 0; i < markers.size(); ++i) {
    const Marker& mk = m.markers()[i];
    const int nb = nb_of(mk.body);
    const int n = mk.body < 0 ? 0 : m.bodies()[mk.body].num_modes;
    if (mk.body < 0) {  // fixed in the world (the scratch's vectors start at zero)
      markers[i].kin.position = mk.position;
      markers[i].kin.angle = mk.angle;
    } else {
      body_markers.push_back(static_cast<int>(i));
    }
    markers[i].Jr = Mat2X::Zero(2, nb);
    markers[i].Jphi = RowVec::Zero(nb);
    markers[i].C = Mat2X::Zero(2, nb);
    markers[i].AS = Mat2X::Zero(2, n);
  }
  corotated.resize(m.corotated_dampings().size());
  for (size_t i = 0; i < corotated.size(); ++i)
    ResizeCorotatedScratch(m.corotated_dampings()[i], &corotated[i]);
  joints.resize(m.joints().size());
  for (size_t i = 0; i < joints.size(); ++i) {
    const Joint& jt = m.joints()[i];
    int na = 0, nb = 0;
    if (jt.kind == JointKind::kGround) {
      nb = nb_of(jt.body);
    } else {
      na = nb_of(m.markers()[jt.marker_i].body);
      nb = nb_of(m.markers()[jt.marker_j].body);
    }
    JointScratch& js = joints[i];
    js.Ga = Mat::Zero(jt.num_rows, na);
    js.Gb = Mat::Zero(jt.num_rows, nb);
    js.Haa = Mat::Zero(na, na);
    js.Hab = Mat::Zero(na, nb);
    js.Hba = Mat::Zero(nb, na);
    js.Hbb = Mat::Zero(nb, nb);
    js.va = Vec::Zero(na);
    js.vb = Vec::Zero(nb);
    js.ha = Vec::Zero(na);
    js.hb = Vec::Zero(nb);
  }
  elements.resize(m.elements().size());
  const int nbmax = m.max_body_coordinates();
  for (size_t i = 0; i < elements.size(); ++i) {
    const ElementSlot& e = m.elements()[i];
    ElementScratch& es = elements[i];
    const int ns = e.num_states;
    const int ni = nb_of(m.markers()[e.marker_i].body), nj = nb_of(m.markers()[e.marker_j].body);
    es.zdot = Vec::Zero(ns);
    es.z_fd = Vec::Zero(ns);
    es.zdot_fd = Vec::Zero(ns);
    es.o_plus = Vec::Zero(7 + ns);
    es.o_minus = Vec::Zero(7 + ns);
    es.Do = Mat::Zero(7 + ns, 12);
    es.Dz = Mat::Zero(7 + ns, ns);
    es.Kp_i = Mat::Zero(6, ni);
    es.Kv_i = Mat::Zero(6, ni);
    es.Kp_j = Mat::Zero(6, nj);
    es.Kv_j = Mat::Zero(6, nj);
    es.Gen_i = Mat::Zero(3, ni);
    es.Gen_j = Mat::Zero(3, nj);
    es.T = Mat::Zero(7 + ns, nbmax);
  }
  Q = Vec::Zero(m.num_coordinates());
  element_memory.assign(m.num_element_memory(), 0.0);
}

}  // namespace flexrod::multibody
