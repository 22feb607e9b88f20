// multibody/outputs.cc — observer queries on a state.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/outputs.h"

#include <algorithm>
#include <cmath>

#include "multibody/dae.h"

namespace flexrod::multibody {
namespace {
using CMap = Eigen::Map<const Vec>;
}  // namespace

const MarkerKinematics& MarkerState(const RunData& data, MarkerId marker) {
  return data.markers.at(marker.index).kin;
}

Vec2 MarkerAcceleration(const Mechanism& model, const RunData& data, MarkerId marker,
                        const double* yp) {
  const Marker& mk = model.marker(marker);
  if (mk.body < 0) return Vec2::Zero();
  const Body& b = model.bodies()[mk.body];
  const MarkerScratch& ms = data.markers[marker.index];
  const double* ab = yp + model.num_coordinates() + b.coordinate_offset;  // v̇ of the body
  Vec2 acc = Vec2(ab[kX], ab[kY]) + Jm(ms.Au) * ab[kTheta] + ms.conv_acc;
  if (b.num_modes > 0) {
    const Vec2 local = mk.S_u * CMap(ab + kFirstMode, b.num_modes);
    acc += data.bodies[mk.body].A * local;
  }
  return acc;
}

JointReaction CalcJointReaction(const Mechanism& model, const RunData& data, JointId joint,
                                const double* y) {
  const Joint& jt = model.joint(joint);
  const double* lam = y + model.lambda_offset() + jt.row;
  JointReaction r;
  switch (jt.kind) {
    case JointKind::kRevolute:
      r.force_i = -Vec2(lam[0], lam[1]);
      r.force_j = Vec2(lam[0], lam[1]);
      break;
    case JointKind::kWeld:
      r.force_i = -Vec2(lam[0], lam[1]);
      r.moment_i = lam[2];
      r.force_j = Vec2(lam[0], lam[1]);
      r.moment_j = -lam[2];
      break;
    case JointKind::kPrismatic: {
      const MarkerKinematics& ki = data.markers[jt.marker_i].kin;
      const MarkerKinematics& kj = data.markers[jt.marker_j].kin;
      const double c = std::cos(ki.angle), s = std::sin(ki.angle);
      const Vec2 u(c * jt.axis.x() - s * jt.axis.y(), s * jt.axis.x() + c * jt.axis.y());
      const Vec2 n = Jm(u);
      const Vec2 d = kj.position - ki.position;
      r.force_i = lam[1] * n;
      r.moment_i = lam[0] + lam[1] * u.dot(d);
      r.force_j = -lam[1] * n;
      r.moment_j = -lam[0];
      break;
    }
    case JointKind::kGround:
      r.force_j = -Vec2(lam[0], lam[1]);
      r.moment_j = -lam[2];
      break;
  }
  return r;
}

DriverState CalcDriverState(const Mechanism& model, DriverId driver, const double* y) {
  const Driver& d = model.driver(driver);
  const int ith = model.bodies()[d.body].coordinate(kTheta);
  DriverState s;
  s.angle = y[ith];
  s.speed = y[model.num_coordinates() + ith];
  s.torque = d.is_constraint() ? -y[model.lambda_offset() + d.row] : d.MotorTorque(s.speed);
  s.power = s.torque * s.speed;
  return s;
}

ElementReport CalcElementReport(const Mechanism& model, RunData* data, ElementId element, double t,
                                const double* y) {
  const ElementSlot& e = model.element(element);
  ElementScratch& es = data->elements[element.index];
  const MarkerKinematics& ki = data->markers[e.marker_i].kin;
  const MarkerKinematics& kj = data->markers[e.marker_j].kin;
  const double* z = y + model.z_offset() + e.state_offset;
  const double* mem = data->element_memory.data() + e.memory_offset;
  ElementOutput out;
  if (e.num_states > 0) {
    es.zdot_fd.setZero();
    out.state_rates = es.zdot_fd.data();
  }
  ElementReport r;
  if (!e.element->Evaluate(t, ki, kj, z, mem, &out)) {
    const double nan = std::nan("");
    r.force_i = r.force_j = Vec2(nan, nan);
    r.moment_i = r.moment_j = r.dissipation = r.potential_energy = nan;
    return r;
  }
  r.force_i = out.force_i;
  r.moment_i = out.moment_i;
  r.force_j = out.force_j;
  r.moment_j = out.moment_j;
  r.dissipation = out.dissipation;
  r.potential_energy = e.element->PotentialEnergy(ki, kj, z, mem);
  return r;
}

EnergyReport CalcEnergies(const Mechanism& model, RunData* data, const double* y,
                          KnownPotential known) {
  EnergyReport e;
  const int np = model.num_coordinates();
  const Vec2& g = model.gravity();
  const auto& bodies = model.bodies();
  for (size_t bi = 0; bi < bodies.size(); ++bi) {
    const Body& b = bodies[bi];
    BodyScratch& s = data->bodies[bi];
    const int o = b.coordinate_offset, n = b.num_modes;
    e.kinetic += KineticEnergy(b, &s, y + o, y + np + o);
    const Vec2 R(y[o + kX], y[o + kY]);
    e.gravity -= g.dot(b.mass * R + s.A * s.s);
    if (n > 0) {
      CMap q(y + o + kFirstMode, n);
      e.strain += 0.5 * q.dot(s.Kq - s.Fg);  // ½ qᵀKq
    }
  }
  const double* z = y + model.z_offset();
  const double* mem = data->element_memory.data();
  const auto& elements = model.elements();
  for (size_t i = 0; i < elements.size(); ++i) {
    const ElementSlot& el = elements[i];
    e.element_potential += static_cast<int>(i) == known.element
                               ? known.energy
                               : el.element->PotentialEnergy(
                                     data->markers[el.marker_i].kin, data->markers[el.marker_j].kin,
                                     z + el.state_offset, mem + el.memory_offset);
  }
  const double* quad = y + model.quadrature_offset();
  e.dissipated_elements = quad[kDissipatedElements];
  e.dissipated_damping = quad[kDissipatedDamping];
  e.driver_work = quad[kDriverWork];
  e.stiffening_work = quad[kStiffeningWork];
  e.balance_error = e.total() - data->reference_energy;
  return e;
}

double MaxConstraintViolation(const Mechanism& model, RunData* data, double t, const double* y) {
  double worst = 0.0;
  double g[3];
  for (size_t j = 0; j < model.joints().size(); ++j) {
    const Joint& jt = model.joints()[j];
    CalcJointConstraint(model, *data, JointId{static_cast<int>(j)}, y, g);
    for (int k = 0; k < jt.num_rows; ++k) worst = std::max(worst, std::abs(g[k]));
  }
  for (const Driver& d : model.drivers()) {
    if (!d.is_constraint()) continue;
    const double th = y[model.bodies()[d.body].coordinate(kTheta)];
    worst = std::max(worst, std::abs(th - d.PrescribedAngle(t)));
  }
  return worst;
}

}  // namespace flexrod::multibody
