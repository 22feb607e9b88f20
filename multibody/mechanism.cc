// multibody/mechanism.cc — the mechanism's lookups and layout, the builder's checks, markers,
// joints, drivers and elements (flexible bodies: multibody/flexible_body.cc; the drivers' laws:
// multibody/driver.cc).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/mechanism.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/error.h"

namespace flexrod::multibody {
namespace {

std::string BodyKey(const std::string& name) { return "body[" + name + "]"; }

std::vector<int> ActiveSlots(const Marker& m, int num_modes) {
  std::vector<int> slots{kX, kY, kTheta};
  for (int k = 0; k < num_modes; ++k) {
    if (m.S_u.col(k).squaredNorm() > 0.0 || m.S_phi(k) != 0.0) slots.push_back(kFirstMode + k);
  }
  return slots;
}

}  // namespace

// ---- small value types -----------------------------------------------------------------------
const char* ToString(JointKind kind) {
  switch (kind) {
    case JointKind::kRevolute:
      return "revolute";
    case JointKind::kPrismatic:
      return "prismatic";
    case JointKind::kWeld:
      return "weld";
    case JointKind::kGround:
      return "ground";
  }
  return "?";
}

// ---- Mechanism ------------------------------------------------------------------------------
int Mechanism::coordinate(BodyId body, int slot) const {
  const Body& b = bodies_.at(body.index);
  if (slot < 0 || slot >= b.num_coordinates()) {
    throw InputError(BodyKey(b.name) + ".slot", std::to_string(slot),
                     "must be in [0, " + std::to_string(b.num_coordinates()) + ")");
  }
  return b.coordinate_offset + slot;
}

template <typename T>
static int FindByName(const std::vector<T>& items, const std::string& kind,
                      const std::string& name) {
  for (size_t i = 0; i < items.size(); ++i)
    if (items[i].name == name) return static_cast<int>(i);
  throw InputError(kind, name, "unknown " + kind + " name");
}

BodyId Mechanism::FindBody(const std::string& name) const {
  return BodyId{FindByName(bodies_, "body", name)};
}
MarkerId Mechanism::FindMarker(const std::string& name) const {
  return MarkerId{FindByName(markers_, "marker", name)};
}
JointId Mechanism::FindJoint(const std::string& name) const {
  return JointId{FindByName(joints_, "joint", name)};
}
DriverId Mechanism::FindDriver(const std::string& name) const {
  return DriverId{FindByName(drivers_, "driver", name)};
}
ElementId Mechanism::FindElement(const std::string& name) const {
  return ElementId{FindByName(elements_, "element", name)};
}

std::string Mechanism::VariableName(int i) const {
  auto slot_name = [this](int k) {
    for (const Body& b : bodies_) {
      if (k >= b.coordinate_offset && k < b.coordinate_offset + b.num_coordinates()) {
        const int s = k - b.coordinate_offset;
        static const char* kFrame[] = {"x", "y", "theta"};
        return b.name + "." +
               (s < 3 ? std::string(kFrame[s]) : std::string("q") + std::to_string(s - 3));
      }
    }
    return std::string("?");
  };
  auto row_name = [this](int r) {
    for (const Joint& j : joints_)
      if (r >= j.row && r < j.row + j.num_rows) return j.name + "." + std::to_string(r - j.row);
    for (const Driver& d : drivers_)
      if (d.row == r) return d.name;
    return std::string("?");
  };
  const int np = num_coordinates_, nc = num_constraints_;
  if (i < 0 || i >= size()) return "out-of-range[" + std::to_string(i) + "]";
  if (i < np) return "p[" + slot_name(i) + "]";
  if (i < 2 * np) return "v[" + slot_name(i - np) + "]";
  if (i < 2 * np + nc) return "lambda[" + row_name(i - 2 * np) + "]";
  if (i < 2 * np + 2 * nc) return "mu[" + row_name(i - 2 * np - nc) + "]";
  if (i < quadrature_offset()) {
    const int k = i - z_offset();
    for (const ElementSlot& e : elements_)
      if (k >= e.state_offset && k < e.state_offset + e.num_states)
        return "z[" + e.name + "." + std::to_string(k - e.state_offset) + "]";
    for (const CorotatedDamping& d : corotated_)
      if (k >= d.state_offset && k < d.state_offset + d.num_states())
        return "z[" + d.name + "." + std::to_string(k - d.state_offset) + "]";
    return "z[?]";
  }
  static const char* kQuad[] = {"dissipated_elements", "dissipated_damping", "driver_work",
                                "stiffening_work"};
  return std::string("energy[") + kQuad[i - quadrature_offset()] + "]";
}

std::vector<double> Mechanism::Breakpoints(double t0, double t1) const {
  std::vector<double> out;
  for (const Driver& d : drivers_) {
    if (d.kind != DriverKind::kSpeedProfile) continue;
    for (double t : d.profile.times)
      if (t > t0 && t < t1) out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// ---- MechanismBuilder -----------------------------------------------------------------------
void MechanismBuilder::CheckNotBuilt() const {
  if (built_) throw std::logic_error("MechanismBuilder used after Build()");
}

void MechanismBuilder::CheckName(const std::string& kind, const std::string& name) const {
  if (name.empty()) throw InputError(kind + ".name", "\"\"", "must not be empty");
  auto taken = [&name](const auto& items) {
    return std::any_of(items.begin(), items.end(),
                       [&name](const auto& x) { return x.name == name; });
  };
  bool dup = false;
  if (kind == "body") dup = taken(m_.bodies_);
  if (kind == "marker") dup = taken(m_.markers_);
  if (kind == "joint") dup = taken(m_.joints_) || taken(m_.drivers_);
  if (kind == "driver") dup = taken(m_.drivers_) || taken(m_.joints_);
  if (kind == "element") dup = taken(m_.elements_);
  if (dup) throw InputError(kind + ".name", name, "must be unique among " + kind + "s");
}

void MechanismBuilder::CheckBody(BodyId body, const std::string& key) const {
  if (body.index < 0 || body.index >= static_cast<int>(m_.bodies_.size())) {
    throw InputError(key, std::to_string(body.index),
                     "must be a body of this builder (not ground)");
  }
}

void MechanismBuilder::CheckMarker(MarkerId marker, const std::string& key) const {
  if (marker.index < 0 || marker.index >= static_cast<int>(m_.markers_.size())) {
    throw InputError(key, std::to_string(marker.index), "must be a marker of this builder");
  }
}

BodyId MechanismBuilder::AddRigidBody(const RigidBodySpec& spec) {
  CheckNotBuilt();
  CheckName("body", spec.name);
  const std::string key = BodyKey(spec.name);
  RequirePositive(key + ".mass", spec.mass);
  RequireNonNegative(key + ".inertia", spec.inertia);
  Require(spec.com.allFinite(), key + ".com", spec.com.norm(), "must be finite");
  Body b;
  b.name = spec.name;
  b.flexible = false;
  b.num_modes = 0;
  b.mass = spec.mass;
  b.S0 = spec.mass * spec.com;
  b.Sbar.resize(2, 0);
  b.J0 = spec.inertia + spec.mass * spec.com.squaredNorm();  // parallel-axis theorem
  b.I1.resize(0);
  b.Ibar.resize(0);
  b.Mff.resize(0, 0);
  b.Stilde.resize(0, 0);
  b.K.resize(0, 0);
  b.D.resize(0, 0);
  m_.bodies_.push_back(std::move(b));
  return BodyId{static_cast<int>(m_.bodies_.size()) - 1};
}

int MechanismBuilder::AddMarkerImpl(Marker marker) {
  const int n = marker.body < 0 ? 0 : m_.bodies_[marker.body].num_modes;
  if (marker.S_u.cols() != n) marker.S_u = Mat2X::Zero(2, n);
  if (marker.S_phi.size() != n) marker.S_phi = RowVec::Zero(n);
  if (marker.body >= 0) marker.active_slots = ActiveSlots(marker, n);
  m_.markers_.push_back(std::move(marker));
  return static_cast<int>(m_.markers_.size()) - 1;
}

MarkerId MechanismBuilder::AddGroundMarker(const std::string& name, const Vec2& position,
                                           double angle) {
  CheckNotBuilt();
  CheckName("marker", name);
  Require(position.allFinite(), "marker[" + name + "].position", position.norm(), "must be finite");
  Require(std::isfinite(angle), "marker[" + name + "].angle", angle, "must be finite");
  Marker m;
  m.name = name;
  m.body = -1;
  m.position = position;
  m.angle = angle;
  return MarkerId{AddMarkerImpl(std::move(m))};
}

MarkerId MechanismBuilder::AddBodyMarker(BodyId body, const std::string& name, const Vec2& position,
                                         double angle) {
  CheckNotBuilt();
  CheckName("marker", name);
  CheckBody(body, "marker[" + name + "].body");
  Require(position.allFinite(), "marker[" + name + "].position", position.norm(), "must be finite");
  Require(std::isfinite(angle), "marker[" + name + "].angle", angle, "must be finite");
  Marker m;
  m.name = name;
  m.body = body.index;
  m.position = position;
  m.angle = angle;
  return MarkerId{AddMarkerImpl(std::move(m))};
}

MarkerId MechanismBuilder::AddNodeMarker(BodyId body, const std::string& name, int node,
                                         const Vec2& offset, double angle) {
  CheckNotBuilt();
  CheckBody(body, "marker[" + name + "].body");
  const Body& b = m_.bodies_[body.index];
  if (!b.flexible) {
    throw InputError("marker[" + name + "].body", b.name, "node markers need a flexible body");
  }
  const fem::MarkerShape shape = b.rod->Marker(node, offset);
  const MarkerId id = AddShapeMarker(body, name, shape, angle);
  m_.markers_[id.index].node = node;
  return id;
}

MarkerId MechanismBuilder::AddShapeMarker(BodyId body, const std::string& name,
                                          const fem::MarkerShape& shape, double angle) {
  CheckNotBuilt();
  CheckName("marker", name);
  CheckBody(body, "marker[" + name + "].body");
  const Body& b = m_.bodies_[body.index];
  const std::string key = "marker[" + name + "]";
  if (shape.S_u.cols() != b.num_modes || shape.S_phi.size() != b.num_modes) {
    throw InputError(key + ".shape", std::to_string(shape.S_u.cols()) + " columns",
                     "must have one column per elastic coordinate of " + b.name + " (" +
                         std::to_string(b.num_modes) + ")");
  }
  Require(shape.position.allFinite() && shape.S_u.allFinite() && shape.S_phi.allFinite(),
          key + ".shape", 0.0, "must be finite");
  Require(std::isfinite(angle), key + ".angle", angle, "must be finite");
  Marker m;
  m.name = name;
  m.body = body.index;
  m.position = shape.position;
  m.angle = angle;
  m.S_u = shape.S_u;
  m.S_phi = shape.S_phi;
  return MarkerId{AddMarkerImpl(std::move(m))};
}

static void CheckJointMarkers(const Mechanism& m, const std::string& key, MarkerId i, MarkerId j,
                              const std::vector<Marker>& markers) {
  (void)m;
  const int bi = markers[i.index].body, bj = markers[j.index].body;
  if (bi < 0 && bj < 0) {
    throw InputError(key + ".markers", markers[i.index].name + ", " + markers[j.index].name,
                     "a joint needs at least one marker on a body (both are ground markers)");
  }
  if (bi == bj) {
    throw InputError(key + ".markers", markers[i.index].name + ", " + markers[j.index].name,
                     "the two markers of a joint must be on different bodies");
  }
}

JointId MechanismBuilder::AddRevolute(const std::string& name, MarkerId i, MarkerId j) {
  CheckNotBuilt();
  CheckName("joint", name);
  const std::string key = "joint[" + name + "]";
  CheckMarker(i, key + ".marker_i");
  CheckMarker(j, key + ".marker_j");
  CheckJointMarkers(m_, key, i, j, m_.markers_);
  Joint jt;
  jt.name = name;
  jt.kind = JointKind::kRevolute;
  jt.marker_i = i.index;
  jt.marker_j = j.index;
  jt.num_rows = 2;
  m_.joints_.push_back(jt);
  return JointId{static_cast<int>(m_.joints_.size()) - 1};
}

JointId MechanismBuilder::AddPrismatic(const PrismaticSpec& spec) {
  CheckNotBuilt();
  CheckName("joint", spec.name);
  const std::string key = "joint[" + spec.name + "]";
  CheckMarker(spec.marker_i, key + ".marker_i");
  CheckMarker(spec.marker_j, key + ".marker_j");
  CheckJointMarkers(m_, key, spec.marker_i, spec.marker_j, m_.markers_);
  Require(spec.axis.allFinite() && spec.axis.norm() > 0.0, key + ".axis", spec.axis.norm(),
          "must be a finite non-zero vector");
  Require(std::isfinite(spec.relative_angle), key + ".relative_angle", spec.relative_angle,
          "must be finite");
  RequireNonNegative(key + ".damping", spec.damping);
  RequireNonNegative(key + ".friction_force", spec.friction_force);
  RequirePositive(key + ".friction_regularisation_speed", spec.friction_regularisation_speed);
  Joint jt;
  jt.name = spec.name;
  jt.kind = JointKind::kPrismatic;
  jt.marker_i = spec.marker_i.index;
  jt.marker_j = spec.marker_j.index;
  jt.axis = spec.axis.normalized();
  jt.relative_angle = spec.relative_angle;
  jt.num_rows = 2;
  m_.joints_.push_back(jt);
  const int joint_index = static_cast<int>(m_.joints_.size()) - 1;
  if (spec.damping > 0.0 || spec.friction_force > 0.0) {
    auto guide = std::make_shared<PrismaticGuide>(key, jt.axis, spec.damping, spec.friction_force,
                                                  spec.friction_regularisation_speed);
    const ElementId e =
        AddElementImpl(spec.name + ".guide", spec.marker_i, spec.marker_j, guide, joint_index);
    m_.joints_[joint_index].guide_element = e.index;
  }
  return JointId{joint_index};
}

JointId MechanismBuilder::AddWeld(const std::string& name, MarkerId i, MarkerId j,
                                  double relative_angle) {
  CheckNotBuilt();
  CheckName("joint", name);
  const std::string key = "joint[" + name + "]";
  CheckMarker(i, key + ".marker_i");
  CheckMarker(j, key + ".marker_j");
  CheckJointMarkers(m_, key, i, j, m_.markers_);
  Require(std::isfinite(relative_angle), key + ".relative_angle", relative_angle, "must be finite");
  Joint jt;
  jt.name = name;
  jt.kind = JointKind::kWeld;
  jt.marker_i = i.index;
  jt.marker_j = j.index;
  jt.relative_angle = relative_angle;
  jt.num_rows = 3;
  m_.joints_.push_back(jt);
  return JointId{static_cast<int>(m_.joints_.size()) - 1};
}

JointId MechanismBuilder::AddGroundJoint(const std::string& name, BodyId body, const Vec2& position,
                                         double angle) {
  CheckNotBuilt();
  CheckName("joint", name);
  const std::string key = "joint[" + name + "]";
  CheckBody(body, key + ".body");
  Require(position.allFinite(), key + ".position", position.norm(), "must be finite");
  Require(std::isfinite(angle), key + ".angle", angle, "must be finite");
  Joint jt;
  jt.name = name;
  jt.kind = JointKind::kGround;
  jt.body = body.index;
  jt.ground_position = position;
  jt.ground_angle = angle;
  jt.num_rows = 3;
  m_.joints_.push_back(jt);
  return JointId{static_cast<int>(m_.joints_.size()) - 1};
}

DriverId MechanismBuilder::AddConstantSpeedDriver(const std::string& name, BodyId body,
                                                  double initial_angle, double speed) {
  CheckNotBuilt();
  CheckName("driver", name);
  const std::string key = "driver[" + name + "]";
  CheckBody(body, key + ".body");
  Require(std::isfinite(initial_angle), key + ".initial_angle", initial_angle, "must be finite");
  Require(std::isfinite(speed), key + ".speed", speed, "must be finite");
  Driver d;
  d.name = name;
  d.kind = DriverKind::kConstantSpeed;
  d.body = body.index;
  d.initial_angle = initial_angle;
  d.speed = speed;
  m_.drivers_.push_back(std::move(d));
  return DriverId{static_cast<int>(m_.drivers_.size()) - 1};
}

DriverId MechanismBuilder::AddSpeedProfileDriver(const std::string& name, BodyId body,
                                                 double initial_angle,
                                                 const std::vector<double>& times,
                                                 const std::vector<double>& speeds) {
  CheckNotBuilt();
  CheckName("driver", name);
  const std::string key = "driver[" + name + "]";
  CheckBody(body, key + ".body");
  Require(std::isfinite(initial_angle), key + ".initial_angle", initial_angle, "must be finite");
  if (times.size() < 2 || times.size() != speeds.size()) {
    throw InputError(
        key + ".profile",
        std::to_string(times.size()) + " times, " + std::to_string(speeds.size()) + " speeds",
        "needs at least 2 (time, speed) pairs of equal length");
  }
  for (size_t k = 0; k < times.size(); ++k) {
    const std::string ik = std::string("[") + std::to_string(k) + "]";
    Require(std::isfinite(times[k]), key + ".times" + ik, times[k], "must be finite");
    Require(std::isfinite(speeds[k]), key + ".speeds" + ik, speeds[k], "must be finite");
    if (k > 0) {
      Require(times[k] > times[k - 1], key + ".times" + ik, times[k],
              "must be strictly increasing");
    }
  }
  Driver d;
  d.name = name;
  d.kind = DriverKind::kSpeedProfile;
  d.body = body.index;
  d.initial_angle = initial_angle;
  d.profile.times = times;
  d.profile.speeds = speeds;
  d.profile.cumulative.assign(times.size(), 0.0);
  for (size_t k = 1; k < times.size(); ++k) {
    d.profile.cumulative[k] =
        d.profile.cumulative[k - 1] + 0.5 * (speeds[k] + speeds[k - 1]) * (times[k] - times[k - 1]);
  }
  m_.drivers_.push_back(std::move(d));
  return DriverId{static_cast<int>(m_.drivers_.size()) - 1};
}

DriverId MechanismBuilder::AddDcMotorDriver(const std::string& name, BodyId body,
                                            const DcMotorSpec& motor) {
  CheckNotBuilt();
  CheckName("driver", name);
  const std::string key = "driver[" + name + "]";
  CheckBody(body, key + ".body");
  motor.Validate(key);
  Driver d;
  d.name = name;
  d.kind = DriverKind::kDcMotor;
  d.body = body.index;
  d.motor = motor;
  m_.drivers_.push_back(std::move(d));
  return DriverId{static_cast<int>(m_.drivers_.size()) - 1};
}

ElementId MechanismBuilder::AddElementImpl(const std::string& name, MarkerId i, MarkerId j,
                                           std::shared_ptr<const ForceElement> element, int joint) {
  CheckName("element", name);
  const std::string key = "element[" + name + "]";
  CheckMarker(i, key + ".marker_i");
  CheckMarker(j, key + ".marker_j");
  if (!element) throw InputError(key, "null", "needs a force element");
  if (m_.markers_[i.index].body < 0 && m_.markers_[j.index].body < 0) {
    throw InputError(key + ".markers", m_.markers_[i.index].name + ", " + m_.markers_[j.index].name,
                     "an element needs at least one marker on a body");
  }
  const int ns = element->num_states(), nm = element->num_memory(), nr = element->num_roots();
  if (ns < 0 || nm < 0 || nr < 0) {
    throw InputError(key, element->type_name(), "negative number of states, memory or roots");
  }
  for (int k = 0; k < ns; ++k) {
    RequirePositive(key + ".state_scale[" + std::to_string(k) + "]", element->StateScale(k));
  }
  const FiniteDifferenceScales s = element->fd_scales();
  RequirePositive(key + ".fd_scales.length", s.length);
  RequirePositive(key + ".fd_scales.speed", s.speed);
  RequirePositive(key + ".fd_scales.angle", s.angle);
  RequirePositive(key + ".fd_scales.angular_speed", s.angular_speed);
  ElementSlot slot;
  slot.name = name;
  slot.marker_i = i.index;
  slot.marker_j = j.index;
  slot.element = std::move(element);
  slot.state_offset = m_.num_element_states_;
  slot.num_states = ns;
  slot.memory_offset = m_.num_element_memory_;
  slot.num_memory = nm;
  slot.root_offset = m_.num_element_roots_;
  slot.num_roots = nr;
  slot.joint = joint;
  m_.num_element_states_ += ns;
  m_.num_element_memory_ += nm;
  m_.num_element_roots_ += nr;
  m_.elements_.push_back(std::move(slot));
  return ElementId{static_cast<int>(m_.elements_.size()) - 1};
}

ElementId MechanismBuilder::AddSpringDamper(const std::string& name, MarkerId i, MarkerId j,
                                            double stiffness, double damping, double free_length) {
  CheckNotBuilt();
  auto e = std::make_shared<SpringDamper>("element[" + name + "]", stiffness, damping, free_length);
  return AddElementImpl(name, i, j, std::move(e), -1);
}

ElementId MechanismBuilder::AddRotationalSpringDamper(const std::string& name, MarkerId i,
                                                      MarkerId j, double stiffness, double damping,
                                                      double free_angle) {
  CheckNotBuilt();
  auto e = std::make_shared<RotationalSpringDamper>("element[" + name + "]", stiffness, damping,
                                                    free_angle);
  return AddElementImpl(name, i, j, std::move(e), -1);
}

ElementId MechanismBuilder::AddForceElement(const std::string& name, MarkerId i, MarkerId j,
                                            std::shared_ptr<const ForceElement> element) {
  CheckNotBuilt();
  return AddElementImpl(name, i, j, std::move(element), -1);
}

void MechanismBuilder::SetGravity(const Vec2& gravity) {
  CheckNotBuilt();
  Require(gravity.allFinite(), "gravity", gravity.norm(), "must be finite");
  m_.gravity_ = gravity;
}

void MechanismBuilder::AddCorotatedDamping(const std::string& name,
                                           const std::vector<BodyId>& bodies, const Mat& modes,
                                           const Vec& coefficients) {
  CheckNotBuilt();
  const std::string key = "corotated_damping[" + name + "]";
  const int n = static_cast<int>(bodies.size());
  Require(n >= 2, key + ".bodies", n, "needs at least two bodies");
  CorotatedDamping d;
  d.name = name;
  for (const BodyId b : bodies) {
    CheckBody(b, key + ".bodies");
    if (m_.bodies_[b.index].num_modes != 0) {
      throw InputError(key + ".bodies", m_.bodies_[b.index].name,
                       "must be rigid (the chain's deformation is its bodies' relative motion)");
    }
    d.bodies.push_back(b.index);
  }
  Require(modes.rows() == 3 * (n - 1), key + ".modes.rows", static_cast<double>(modes.rows()),
          "must be 3 (bodies - 1)");
  Require(modes.cols() == coefficients.size() && coefficients.size() > 0, key + ".coefficients",
          static_cast<double>(coefficients.size()), "must give one value per mode (column)");
  Require(modes.allFinite() && coefficients.allFinite(), key, 0.0,
          "modes and coefficients must be finite");
  d.modes = modes;
  d.coefficients = coefficients;
  d.state_offset = m_.num_element_states_;
  m_.num_element_states_ += d.num_states();
  m_.corotated_.push_back(std::move(d));
}

Mechanism MechanismBuilder::Build() {
  CheckNotBuilt();
  if (m_.bodies_.empty()) throw InputError("mechanism.bodies", "0", "needs at least one body");
  // Coordinates.
  int offset = 0, max_nb = 0;
  for (Body& b : m_.bodies_) {
    b.coordinate_offset = offset;
    offset += b.num_coordinates();
    max_nb = std::max(max_nb, b.num_coordinates());
  }
  m_.num_coordinates_ = offset;
  m_.max_body_coordinates_ = max_nb;
  // Drivers: at most one per body; not on a grounded body; motor inertia goes into J0.
  std::vector<int> driven(m_.bodies_.size(), -1);
  for (size_t d = 0; d < m_.drivers_.size(); ++d) {
    Driver& dr = m_.drivers_[d];
    if (driven[dr.body] >= 0) {
      throw InputError(
          "driver[" + dr.name + "].body", m_.bodies_[dr.body].name,
          "is already driven by " + m_.drivers_[driven[dr.body]].name + " (one driver per body)");
    }
    driven[dr.body] = static_cast<int>(d);
    if (dr.kind == DriverKind::kDcMotor) {
      Body& b = m_.bodies_[dr.body];
      b.driver_inertia =
          dr.motor.flywheel_inertia + dr.motor.ratio * dr.motor.ratio * dr.motor.rotor_inertia;
      b.J0 += b.driver_inertia;
    }
  }
  std::vector<int> grounded(m_.bodies_.size(), -1);
  for (size_t j = 0; j < m_.joints_.size(); ++j) {
    const Joint& jt = m_.joints_[j];
    if (jt.kind != JointKind::kGround) continue;
    if (grounded[jt.body] >= 0) {
      throw InputError("joint[" + jt.name + "].body", m_.bodies_[jt.body].name,
                       "is already fixed by ground joint " + m_.joints_[grounded[jt.body]].name);
    }
    grounded[jt.body] = static_cast<int>(j);
    if (driven[jt.body] >= 0 && m_.drivers_[driven[jt.body]].is_constraint()) {
      throw InputError("joint[" + jt.name + "].body", m_.bodies_[jt.body].name,
                       "is both grounded and driven by " + m_.drivers_[driven[jt.body]].name +
                           " (redundant angle constraint)");
    }
  }
  // Constraint rows: joints, then constraint drivers.
  int row = 0;
  for (Joint& jt : m_.joints_) {
    jt.row = row;
    row += jt.num_rows;
  }
  for (Driver& dr : m_.drivers_) {
    if (dr.is_constraint()) dr.row = row++;
  }
  m_.num_constraints_ = row;
  if (m_.num_constraints_ > m_.num_coordinates_) {
    throw InputError("mechanism.constraints", std::to_string(m_.num_constraints_),
                     "more constraint equations than coordinates (" +
                         std::to_string(m_.num_coordinates_) + "): the model is over-constrained");
  }
  built_ = true;
  return std::move(m_);
}

}  // namespace flexrod::multibody
