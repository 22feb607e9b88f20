// SPDX-License-Identifier: GPL-3.0-or-later
// ParaView output of one run (run/vtk.h): frames from output samples, VTU/PVD writer.
#include "run/vtk.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "common/error.h"
#include "common/files.h"
#include "multibody/clearance_joint.h"

namespace flexrod::study {
namespace {

/// Segments of a drawn joint circle: 64 keeps the chord error below R(1 − cos(π/64)) ≈ 1.2e-3 R.
constexpr int kCirclePoints = 64;
/// Slider rectangle around the journal, in bush radii (a drawing size, not physics): long
/// enough along the guide to read as a block, high enough to enclose the pin circle.
constexpr double kSliderHalfLengthInBushRadii = 2.0;
constexpr double kSliderHalfHeightInBushRadii = 1.25;
/// One-sided limits of the element strain rows at a node are taken this fraction of an
/// element length away from it (the rows are polynomials in x inside an element, so the
/// limit is approached to O(1e-6) of their variation over an element).
constexpr double kNodeLimitOffset = 1e-6;

void AppendNumber(std::string* out, double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
  out->append(buf, res.ptr);
}

void AppendNumber(std::string* out, long v) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  out->append(buf, res.ptr);
}

std::string NumberText(double v) {
  std::string s;
  AppendNumber(&s, v);
  return s;
}

template <typename T>  // double or long
void AppendArray(std::string* out, const char* type, const std::string& name,
                 const std::vector<T>& v, const char* indent) {
  *out += indent;
  *out += "<DataArray type=\"";
  *out += type;
  *out += "\" Name=\"" + name + "\" format=\"ascii\">\n";
  *out += indent;
  *out += "  ";
  for (size_t i = 0; i < v.size(); ++i) {
    if (i) *out += ' ';
    AppendNumber(out, v[i]);
  }
  *out += '\n';
  *out += indent;
  *out += "</DataArray>\n";
}

void AppendFieldScalar(std::string* out, const std::string& name, double v) {
  *out += "      <DataArray type=\"Float64\" Name=\"" + name +
          "\" NumberOfTuples=\"1\" format=\"ascii\">";
  AppendNumber(out, v);
  *out += "</DataArray>\n";
}

std::string FrameVtu(const VtkSeries& series, const VtkFrame& f) {
  const VtkLayout& L = series.layout;
  std::string s;
  s.reserve(static_cast<size_t>(L.num_points) * 120 + 2048);
  s += "<?xml version=\"1.0\"?>\n";
  s += "<!-- flexrod run frame: t = " + NumberText(f.time) + " s; rod deflection drawn " +
       NumberText(series.options.scale) +
       " times (deflection from the chord of the rod's end nodes); point data unscaled, SI units "
       "-->\n";
  s += "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  s += "  <UnstructuredGrid>\n";
  s += "    <FieldData>\n";
  AppendFieldScalar(&s, "time [s]", f.time);
  if (std::isfinite(f.crank_angle)) AppendFieldScalar(&s, "crank_angle [rad]", f.crank_angle);
  AppendFieldScalar(&s, "deformation_scale [1]", series.options.scale);
  s += "    </FieldData>\n";
  s += "    <Piece NumberOfPoints=\"" + std::to_string(L.num_points) + "\" NumberOfCells=\"" +
       std::to_string(L.cells.size()) + "\">\n";
  s += "      <PointData Scalars=\"deflection [m]\">\n";
  AppendArray(&s, "Float64", "deflection [m]", f.displacement, "        ");
  AppendArray(&s, "Float64", "bending_stress [Pa]", f.bending_stress, "        ");
  AppendArray(&s, "Float64", "axial_stress [Pa]", f.axial_stress, "        ");
  s += "      </PointData>\n";
  // Per cell: part, offset of its end in the connectivity, VTK type.
  std::vector<long> part, offsets, types;
  long offset = 0;
  for (const VtkCell& c : L.cells) {
    part.push_back(static_cast<long>(c.part));
    offsets.push_back(offset += static_cast<long>(c.points.size()));
    types.push_back(static_cast<long>(c.type));
  }
  s += "      <CellData Scalars=\"part\">\n";
  AppendArray(&s, "Int32", "part", part, "        ");
  s += "      </CellData>\n";
  s += "      <Points>\n";
  s += "        <DataArray type=\"Float64\" Name=\"position [m]\" NumberOfComponents=\"3\" "
       "format=\"ascii\">\n";
  for (const Vec2& p : f.points) {
    s += "          ";
    AppendNumber(&s, p.x());
    s += ' ';
    AppendNumber(&s, p.y());
    s += " 0\n";
  }
  s += "        </DataArray>\n";
  s += "      </Points>\n";
  s += "      <Cells>\n";
  s += "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const VtkCell& c : L.cells) {
    s += "          ";
    for (size_t i = 0; i < c.points.size(); ++i) {
      if (i) s += ' ';
      AppendNumber(&s, static_cast<long>(c.points[i]));
    }
    s += '\n';
  }
  s += "        </DataArray>\n";
  AppendArray(&s, "Int32", "offsets", offsets, "        ");
  AppendArray(&s, "UInt8", "types", types, "        ");
  s += "      </Cells>\n";
  s += "    </Piece>\n";
  s += "  </UnstructuredGrid>\n";
  s += "</VTKFile>\n";
  return s;
}

}  // namespace

// ---- options
// -------------------------------------------------------------------------------------
void VtkOptions::Validate() const {
  Require(rate > 0.0 && std::isfinite(rate), "vtk.rate", rate,
          "must be a finite frame rate > 0 Hz");
  Require(scale >= 0.0 && std::isfinite(scale), "vtk.scale", scale, "must be a finite factor >= 0");
  Require(duration >= 0.0 && std::isfinite(duration), "vtk.duration", duration,
          "must be >= 0 s (0 = the whole capture)");
}

VtkOptions VtkOptions::FromConfig(const Config& cfg) {
  VtkOptions o;
  o.rate = cfg.Quantity("vtk.rate");
  o.scale = cfg.Quantity("vtk.scale");
  o.duration = cfg.Quantity("vtk.duration");
  o.Validate();
  return o;
}

// ---- recorder
// ------------------------------------------------------------------------------------
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
  int next = 0;
  // Rod centre line: FE nodes of a flexible rod, the two clamp nodes of a rigid one.
  L.rod_first = next;
  if (model.rod) {
    LayOutReducedRod(cfg, &next);
  } else if (model.exact) {
    LayOutExactRod(&next);
  } else {
    const double length = cfg.Quantity("rod.length");
    carried_.push_back({next++, Vec2::Zero(), Mat2X(2, 0)});
    carried_.push_back({next++, Vec2(length, 0.0), Mat2X(2, 0)});
  }
  L.rod_count = next - L.rod_first;
  chord_first_ = 0;  // carried_ holds the rod's centre-line points first
  chord_last_ = static_cast<size_t>(L.rod_count - 1);
  const multibody::Marker& big = m.marker(model.big_end);
  L.big_end = next++;
  carried_.push_back({L.big_end, big.position, big.S_u});
  std::vector<int> rod_line(L.rod_count);
  for (int k = 0; k < L.rod_count; ++k) rod_line[k] = L.rod_first + k;
  L.cells.push_back({kVtkPolyLine, VtkPart::kRod, rod_line});
  L.cells.push_back({kVtkLine, VtkPart::kClamp, {L.big_end, L.rod_first}});
  // crank, slider, joint; a mechanism without a slider (the pendulum, the four-bar) draws its rod
  if (!model.crank.is_ground() && !model.slider.is_ground()) LayOutSliderCrank(cfg, &next);
  L.num_points = next;
}

/// The reduced rod's FE nodes, carried by its frame and shape rows, with their stress rows.
void VtkRecorder::LayOutReducedRod(const Config& cfg, int* next_point) {
  int& next = *next_point;
  const fem::ReducedRod& rod = *model_.rod;
  for (const fem::MarkerShape& node : rod.nodes)
    carried_.push_back({next++, node.position, node.S_u});
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
void VtkRecorder::LayOutExactRod(int* next_point) {
  int& next = *next_point;
  const fem::RodSpec& rod = model_.exact->rod;
  for (int k = 0; k < rod.num_nodes(); ++k)
    carried_.push_back({next++, Vec2(rod.node_x(k), 0.0), Mat2X(2, 0)});
  exact_ = std::make_shared<const ExactRodView>(model_.mechanism, *model_.exact);
  exact_E_ = rod.material.youngs_modulus;
  exact_fibre_ = rod.section.half_depth_in_plane();
}

/// A slider-crank's parts: the small-end clamp, the crank, the slider, and with a clearance
/// joint the bush and pin circles.
void VtkRecorder::LayOutSliderCrank(const Config& cfg, int* next_point) {
  int& next = *next_point;
  const multibody::Mechanism& m = model_.mechanism;
  VtkLayout& L = series_.layout;
  // Where the small-end clamp is a body of its own, Frame() draws the bush at its marker.
  const multibody::Marker& small = m.marker(model_.small_end);
  L.small_end = next++;
  carried_.push_back({L.small_end, small.position, small.S_u});
  L.cells.push_back({kVtkLine, VtkPart::kClamp, {L.rod_first + L.rod_count - 1, L.small_end}});
  L.crank_axis = next++;
  L.crank_pin = next++;
  L.cells.push_back({kVtkLine, VtkPart::kCrank, {L.crank_axis, L.crank_pin}});
  L.slider_first = next;
  next += 4;
  L.cells.push_back({kVtkQuad,
                     VtkPart::kSlider,
                     {L.slider_first, L.slider_first + 1, L.slider_first + 2, L.slider_first + 3}});
  const double bush = cfg.Quantity("joint.bush_radius");
  RequirePositive("joint.bush_radius", bush);
  slider_half_length_ = kSliderHalfLengthInBushRadii * bush;
  slider_half_height_ = kSliderHalfHeightInBushRadii * bush;
  if (model_.clearance.index >= 0) {
    const auto* joint =
        dynamic_cast<const multibody::ClearanceJoint*>(m.element(model_.clearance).element.get());
    FLEXROD_ASSERT(joint != nullptr);
    bush_radius_ = joint->geometry().bush_radius;
    pin_radius_ = joint->geometry().pin_radius;
    L.circle_points = kCirclePoints;
    for (auto [first, part] :
         {std::pair{&L.bush_first, VtkPart::kBush}, std::pair{&L.pin_first, VtkPart::kPin}}) {
      *first = next;
      std::vector<int> ring(kCirclePoints + 1);
      for (int i = 0; i < kCirclePoints; ++i) ring[i] = next + i;
      ring[kCirclePoints] = next;  // closed
      next += kCirclePoints;
      L.cells.push_back({kVtkPolyLine, part, ring});
    }
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
  if (L.small_end >= 0 && (model_.small_clamp.index >= 0 || exact_)) {  // laid out with a slider
    f.points[L.small_end] = s.Marker(model_.small_end).position;
  }
  if (exact_) DrawExactRod(y, &f);
  if (model_.crank.is_ground() || model_.slider.is_ground()) {  // the rod only (LayOutSliderCrank)
    f.crank_angle = std::numeric_limits<double>::quiet_NaN();
    return f;
  }
  DrawCrankAndSlider(s, &f);
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

void VtkRecorder::DrawCrankAndSlider(const multibody::SampleView& s, VtkFrame* f) const {
  const multibody::Mechanism& m = model_.mechanism;
  const VtkLayout& L = series_.layout;
  const double* y = s.y();
  f->crank_angle = y[m.coordinate(model_.crank, multibody::kTheta)];
  // The crank: axis (frame origin of the crank body) to the pin.
  f->points[L.crank_axis] = Vec2(y[m.coordinate(model_.crank, multibody::kX)],
                                 y[m.coordinate(model_.crank, multibody::kY)]);
  f->points[L.crank_pin] = s.Marker(model_.crank_pin).position;
  // The slider: a rectangle centred on the journal, aligned with the journal marker.
  const multibody::MarkerKinematics& journal = s.Marker(model_.journal);
  const Mat2 As = Rotation(journal.angle);
  const double a = slider_half_length_, b = slider_half_height_;
  const Vec2 corners[4] = {Vec2(-a, -b), Vec2(a, -b), Vec2(a, b), Vec2(-a, b)};
  for (int i = 0; i < 4; ++i) f->points[L.slider_first + i] = journal.position + As * corners[i];
  // Clearance joint: bush and pin circles at their true centres.
  if (L.bush_first >= 0) {
    const Vec2 bush_centre = s.Marker(model_.small_end).position;
    for (int i = 0; i < L.circle_points; ++i) {
      const double phi = 2.0 * std::numbers::pi * i / L.circle_points;
      const Vec2 u(std::cos(phi), std::sin(phi));
      f->points[L.bush_first + i] = bush_centre + bush_radius_ * u;
      f->points[L.pin_first + i] = journal.position + pin_radius_ * u;
    }
  }
}

void VtkRecorder::Offer(long k, const multibody::SampleView& sample) {
  if (k < 0 || k % series_.stride != 0) return;
  if (last_index_ >= 0 && k > last_index_) return;
  series_.frames.push_back(CalcFrame(sample));
}

// ---- writer
// --------------------------------------------------------------------------------------
std::string VtkFrameFileName(const std::string& stem, size_t i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "_%06zu.vtu", i);
  return stem + buf;
}

std::string WriteVtkSeries(const std::string& dir, const VtkSeries& series,
                           const std::string& stem) {
  EnsureDirectory("--vtk", dir);
  std::string pvd;
  pvd += "<?xml version=\"1.0\"?>\n";
  pvd +=
      "<!-- flexrod run: " + std::to_string(series.frames.size()) + " frames at " +
      NumberText(series.frame_rate) + " Hz; timestep = time [s]; rod deflection drawn " +
      NumberText(series.options.scale) +
      " times from the chord of the rod's end nodes (deformation_scale [1] in each frame's field "
      "data) -->\n";
  pvd += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  pvd += "  <Collection>\n";
  for (size_t i = 0; i < series.frames.size(); ++i) {
    const std::string name = VtkFrameFileName(stem, i);
    WriteFileAtomic(dir + "/" + name, FrameVtu(series, series.frames[i]));
    pvd += "    <DataSet timestep=\"" + NumberText(series.frames[i].time) +
           "\" group=\"\" part=\"0\" file=\"" + name + "\"/>\n";
  }
  pvd += "  </Collection>\n";
  pvd += "</VTKFile>\n";
  const std::string path = dir + "/" + stem + ".pvd";
  WriteFileAtomic(path, pvd);
  return path;
}

}  // namespace flexrod::study
