// SPDX-License-Identifier: GPL-3.0-or-later
// The ParaView frames of one run (run/vtk.h): frames from output samples.
#include "run/vtk.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "common/error.h"
#include "mechanisms/mechanism_recipe.h"
#include "multibody/clearance_joint.h"

namespace flexrod::study {
namespace {

/// Segments of a drawn joint circle: 64 keeps the chord error below R(1 − cos(π/64)) ≈ 1.2e-3 R.
constexpr int kCirclePoints = 64;
/// One-sided limits of the element strain rows at a node are taken this fraction of an
/// element length away from it (the rows are polynomials in x inside an element, so the
/// limit is approached to O(1e-6) of their variation over an element).
constexpr double kNodeLimitOffset = 1e-6;

}  // namespace

VtkRecorder::VtkRecorder(const Config& cfg, const MechanismModel& model, const VtkOptions& options,
                         double sample_rate)
    : model_(model) {
  options.Validate();
  RequirePositive("sim.sample_rate", sample_rate);
  series_.options = options;
  series_.stride = std::max(1L, std::lround(sample_rate / options.rate));
  series_.frame_rate = sample_rate / static_cast<double>(series_.stride);
  if (options.duration > 0.0)
    last_index_ = static_cast<long>(std::floor(options.duration * sample_rate + 1e-9));

  const multibody::Mechanism& m = model.mechanism;
  VtkLayout& L = series_.layout;
  // Rod centre line: FE nodes of a flexible rod, the two clamp nodes of a rigid one.
  L.rod_first = L.num_points;
  if (model.rod) {
    LayOutReducedRod(cfg);
  } else if (model.exact) {
    LayOutExactRod();
  } else {
    const double length = cfg.Quantity("rod.length");
    carried_.push_back({L.AddPoints(1), Vec2::Zero(), Mat2X(2, 0)});
    carried_.push_back({L.AddPoints(1), Vec2(length, 0.0), Mat2X(2, 0)});
  }
  L.rod_count = L.num_points - L.rod_first;
  chord_first_ = 0;  // carried_ holds the rod's centre-line points first
  chord_last_ = static_cast<size_t>(L.rod_count - 1);
  const multibody::Marker& big = m.marker(model.big_end);
  L.big_end = L.AddPoints(1);
  carried_.push_back({L.big_end, big.position, big.S_u});
  std::vector<int> rod_line(L.rod_count);
  for (int k = 0; k < L.rod_count; ++k) rod_line[k] = L.rod_first + k;
  L.cells.push_back({kVtkPolyLine, VtkPart::kRod, rod_line});
  L.cells.push_back({kVtkLine, VtkPart::kClamp, {L.big_end, L.rod_first}});
  LayOutEndsAndCrank();
  parts_ = model.recipe->LayOutParts(cfg, model, &L);
  LayOutClearanceJoint();
}

/// The reduced rod's FE nodes, carried by its frame and shape rows, with their stress rows.
void VtkRecorder::LayOutReducedRod(const Config& cfg) {
  const fem::ReducedRod& rod = *model_.rod;
  for (const fem::MarkerShape& node : rod.nodes)
    carried_.push_back({series_.layout.AddPoints(1), node.position, node.S_u});
  const int nn = rod.rod.num_nodes(), n = rod.num_coordinates();
  const double E = rod.rod.material.youngs_modulus;
  const double y = rod.rod.section.half_depth_in_plane();
  const double h = kNodeLimitOffset * rod.rod.element_length();
  axial_rows_ = Mat::Zero(nn, n);
  bending_rows_ = Mat::Zero(nn, n);
  // The second-order membrane strain (rod.geometric_stiffening), as the gauges read it.
  const bool membrane = cfg.Bool("rod.geometric_stiffening");
  if (membrane) axial_quadratic_.assign(nn, Mat::Zero(n, n));
  for (int k = 0; k < nn; ++k) {
    const double x = rod.rod.node_x(k);
    int sides = 0;
    for (const double xs : {x - h, x + h}) {
      if (xs < 0.0 || xs > rod.rod.length) continue;
      const fem::StrainGaugeRows g = rod.Gauge("node" + std::to_string(k), xs, y);
      axial_rows_.row(k) += E * g.axial;
      bending_rows_.row(k) += E * g.bending;
      if (membrane) axial_quadratic_[k] += E * g.membrane;
      ++sides;
    }
    axial_rows_.row(k) /= sides;
    bending_rows_.row(k) /= sides;
    if (membrane) axial_quadratic_[k] /= sides;
  }
}

/// The exact rod's node bodies: one layout point each; Frame() sets it from the body's
/// coordinates (u0 = the node's place on the undeformed rod, no shape rows).
void VtkRecorder::LayOutExactRod() {
  const fem::RodSpec& rod = model_.exact->rod;
  for (int k = 0; k < rod.num_nodes(); ++k)
    carried_.push_back({series_.layout.AddPoints(1), Vec2(rod.node_x(k), 0.0), Mat2X(2, 0)});
  exact_ = std::make_shared<const ExactRodView>(model_.mechanism, *model_.exact);
  exact_E_ = rod.material.youngs_modulus;
  exact_fibre_ = rod.section.half_depth_in_plane();
}

/// The small-end point and its clamp arm (every rod has both ends), and the crank where the
/// mechanism has one.
void VtkRecorder::LayOutEndsAndCrank() {
  VtkLayout& L = series_.layout;
  // Where the small-end clamp is a body of its own, Frame() draws the bush at its marker.
  const multibody::Marker& small = model_.mechanism.marker(model_.small_end);
  L.small_end = L.AddPoints(1);
  carried_.push_back({L.small_end, small.position, small.S_u});
  L.cells.push_back({kVtkLine, VtkPart::kClamp, {L.rod_first + L.rod_count - 1, L.small_end}});
  if (model_.crank.is_ground()) return;
  L.crank_axis = L.AddPoints(1);
  L.crank_pin = L.AddPoints(1);
  L.cells.push_back({kVtkLine, VtkPart::kCrank, {L.crank_axis, L.crank_pin}});
}

/// A clearance joint's bush and pin circles.
void VtkRecorder::LayOutClearanceJoint() {
  if (model_.clearance.index < 0) return;
  VtkLayout& L = series_.layout;
  const auto* joint = dynamic_cast<const multibody::ClearanceJoint*>(
      model_.mechanism.element(model_.clearance).element.get());
  FLEXROD_ASSERT(joint != nullptr);
  bush_radius_ = joint->geometry().bush_radius;
  pin_radius_ = joint->geometry().pin_radius;
  L.circle_points = kCirclePoints;
  for (auto [first, part] :
       {std::pair{&L.bush_first, VtkPart::kBush}, std::pair{&L.pin_first, VtkPart::kPin}}) {
    *first = L.AddPoints(kCirclePoints);
    std::vector<int> ring(kCirclePoints + 1);
    for (int i = 0; i < kCirclePoints; ++i) ring[i] = *first + i;
    ring[kCirclePoints] = *first;  // closed
    L.cells.push_back({kVtkPolyLine, part, ring});
  }
}

VtkFrame VtkRecorder::CalcFrame(const multibody::SampleView& s) const {
  const multibody::Mechanism& m = model_.mechanism;
  const VtkLayout& L = series_.layout;
  const double* y = s.y();
  VtkFrame f;
  f.time = s.t();
  f.points.assign(L.num_points, Vec2::Zero());
  f.displacement.assign(L.num_points, 0.0);
  f.bending_stress.assign(L.num_points, 0.0);
  f.axial_stress.assign(L.num_points, 0.0);

  // The rod: p_W = R_B + A(θ_B)(ū₀ + s S_u q_f).
  const Vec2 R(y[m.coordinate(model_.conrod, multibody::kX)],
               y[m.coordinate(model_.conrod, multibody::kY)]);
  const Mat2 A = Rotation(y[m.coordinate(model_.conrod, multibody::kTheta)]);
  const int n = model_.rod ? model_.rod->num_coordinates() : 0;
  Vec q = Vec::Zero(n);
  if (n > 0) q = Eigen::Map<const Vec>(y + m.coordinate(model_.conrod, multibody::kFirstMode), n);
  DrawCarriedPoints(R, A, q, &f);
  if (model_.small_clamp.index >= 0 || exact_) {  // the small end is on a body of its own
    f.points[L.small_end] = s.Marker(model_.small_end).position;
  }
  if (exact_) DrawExactRod(y, &f);
  DrawCrankAndJoint(s, &f);
  if (parts_) parts_->Draw(s, &f);
  return f;
}

void VtkRecorder::DrawCarriedPoints(const Vec2& R, const Mat2& A, const Vec& q, VtkFrame* f) const {
  const VtkLayout& L = series_.layout;
  const double scale = series_.options.scale;
  // Elastic displacement d = S_u q in B, split into the chord part d_c (linear between the
  // displacements of the rod's end nodes a and b, by the position along the undeformed chord)
  // and the deflection d − d_c; only the deflection is scaled, so both rod ends stay on their
  // joints at any scale.
  auto displacement = [&](const CarriedPoint& c) -> Vec2 {
    return c.S_u.cols() > 0 ? Vec2(c.S_u * q) : Vec2::Zero();
  };
  const CarriedPoint& end_a = carried_[chord_first_];
  const CarriedPoint& end_b = carried_[chord_last_];
  const Vec2 da = displacement(end_a), db = displacement(end_b), chord = end_b.u0 - end_a.u0;
  for (size_t i = 0; i < carried_.size(); ++i) {
    const CarriedPoint& c = carried_[i];
    const Vec2 d = displacement(c);
    const double xi = (c.u0 - end_a.u0).dot(chord) / chord.squaredNorm();
    const Vec2 dc = (1.0 - xi) * da + xi * db;
    // Centre-line nodes scaled; the joint points on the clamp arms drawn where they are.
    const double si = i >= chord_first_ && i <= chord_last_ ? scale : 1.0;
    f->points[c.index] = R + A * (c.u0 + dc + si * (d - dc));
    f->displacement[c.index] = (d - dc).norm();
  }
  if (q.size() > 0) {
    const Vec axial = axial_rows_ * q, bending = bending_rows_ * q;
    for (int k = 0; k < L.rod_count; ++k) {
      f->axial_stress[L.rod_first + k] = axial[k];
      if (!axial_quadratic_.empty())
        f->axial_stress[L.rod_first + k] += q.dot(axial_quadratic_[k] * q);
      f->bending_stress[L.rod_first + k] = bending[k];
    }
  }
}

void VtkRecorder::DrawExactRod(const double* y, VtkFrame* f) const {
  const VtkLayout& L = series_.layout;
  const double scale = series_.options.scale;
  // Node k drawn at its chord point (the end nodes' chord at k/N) plus `scale` times its
  // deflection from it; stresses from the elements' exact strains at the node.
  const int N = L.rod_count - 1;
  const Vec2 a = exact_->NodePosition(y, 0), b = exact_->NodePosition(y, N);
  for (int k = 0; k <= N; ++k) {
    const Vec2 p = exact_->NodePosition(y, k);
    const Vec2 c = a + (static_cast<double>(k) / N) * (b - a);
    f->points[L.rod_first + k] = c + scale * (p - c);
    f->displacement[L.rod_first + k] = (p - c).norm();
    const double x = model_.exact->rod.node_x(k);
    const double axial = exact_->Strain(y, x, 0.0);
    f->axial_stress[L.rod_first + k] = exact_E_ * axial;
    f->bending_stress[L.rod_first + k] = exact_E_ * (exact_->Strain(y, x, exact_fibre_) - axial);
  }
}

void VtkRecorder::DrawCrankAndJoint(const multibody::SampleView& s, VtkFrame* f) const {
  const multibody::Mechanism& m = model_.mechanism;
  const VtkLayout& L = series_.layout;
  const double* y = s.y();
  f->crank_angle = std::numeric_limits<double>::quiet_NaN();
  if (L.crank_axis >= 0) {
    f->crank_angle = y[m.coordinate(model_.crank, multibody::kTheta)];
    // The crank: axis (frame origin of the crank body) to the pin.
    f->points[L.crank_axis] = Vec2(y[m.coordinate(model_.crank, multibody::kX)],
                                   y[m.coordinate(model_.crank, multibody::kY)]);
    f->points[L.crank_pin] = s.Marker(model_.crank_pin).position;
  }
  // Clearance joint: bush and pin circles at their true centres.
  if (L.bush_first >= 0) {
    const Vec2 bush_centre = s.Marker(model_.small_end).position;
    const Vec2 pin_centre = s.Marker(model_.journal).position;
    for (int i = 0; i < L.circle_points; ++i) {
      const double phi = 2.0 * std::numbers::pi * i / L.circle_points;
      const Vec2 u(std::cos(phi), std::sin(phi));
      f->points[L.bush_first + i] = bush_centre + bush_radius_ * u;
      f->points[L.pin_first + i] = pin_centre + pin_radius_ * u;
    }
  }
}

void VtkRecorder::Offer(long k, const multibody::SampleView& sample) {
  if (k < 0 || k % series_.stride != 0) return;
  if (last_index_ >= 0 && k > last_index_) return;
  series_.frames.push_back(CalcFrame(sample));
}

}  // namespace flexrod::study
