// multibody/prescribed.cc — prescribed coordinates and the reduced DAE's index maps.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/prescribed.h"

#include <Eigen/Geometry>
#include <optional>

#include "common/error.h"

namespace flexrod::multibody {
namespace {

using Rotation = Eigen::Rotation2Dd;

/// The constraint rows of `jt` (into λ and μ).
std::vector<int> RowsOf(const Joint& jt) {
  std::vector<int> r;
  for (int k = 0; k < jt.num_rows; ++k) r.push_back(jt.row + k);
  return r;
}

/// Whether `body` is a body (not the ground) without modes.
bool IsRigid(const Mechanism& model, int body) {
  return body >= 0 && model.bodies()[body].num_modes == 0;
}

}  // namespace

PrescribedMotion::PrescribedMotion(const Mechanism& model, bool enabled)
    : model_(model), full_size_(model.size()) {
  std::vector<bool> used(model.bodies().size(), false);
  if (enabled) {
    for (const Joint& jt : model.joints()) {
      std::optional<Set> s;
      if (jt.kind == JointKind::kGround) {
        s = HeldSet(jt);
      } else if (jt.kind == JointKind::kRevolute) {
        s = DrivenSet(model, jt);
      } else if (jt.kind == JointKind::kPrismatic) {
        s = GuidedSet(model, jt);
      }
      if (!s || used[s->body]) continue;
      used[s->body] = true;
      FLEXROD_ASSERT(s->slots.size() == s->rows.size());
      num_prescribed_ += static_cast<int>(s->slots.size());
      sets_.push_back(std::move(*s));
    }
  }
  BuildIndexMaps();
}

PrescribedMotion::Set PrescribedMotion::HeldSet(const Joint& jt) {
  Set s;
  s.kind = Kind::kHeld;
  s.body = jt.body;
  s.held = jt.ground_position;
  s.angle = jt.ground_angle;
  s.slots = {kX, kY, kTheta};
  s.rows = RowsOf(jt);
  return s;
}

std::optional<PrescribedMotion::Set> PrescribedMotion::DrivenSet(const Mechanism& model,
                                                                 const Joint& jt) {
  const Marker& a = model.markers()[jt.marker_i];
  const Marker& b = model.markers()[jt.marker_j];
  const Marker* ground = a.body < 0 ? &a : (b.body < 0 ? &b : nullptr);
  const Marker* moving = a.body < 0 ? &b : &a;
  if (ground == nullptr || !IsRigid(model, moving->body)) return std::nullopt;
  int driver = -1;
  for (size_t d = 0; d < model.drivers().size(); ++d) {
    const Driver& dr = model.drivers()[d];
    if (dr.body == moving->body && dr.is_constraint()) driver = static_cast<int>(d);
  }
  if (driver < 0) return std::nullopt;
  Set s;
  s.kind = Kind::kDriven;
  s.body = moving->body;
  s.driver = driver;
  s.pivot = ground->position;
  s.marker = moving->position;
  s.slots = {kX, kY, kTheta};
  s.rows = RowsOf(jt);
  s.rows.push_back(model.drivers()[driver].row);
  return s;
}

std::optional<PrescribedMotion::Set> PrescribedMotion::GuidedSet(const Mechanism& model,
                                                                 const Joint& jt) {
  const Marker& guide = model.markers()[jt.marker_i];
  const Marker& slider = model.markers()[jt.marker_j];
  if (guide.body >= 0 || !IsRigid(model, slider.body)) return std::nullopt;
  const Vec2 u = Rotation(guide.angle) * jt.axis;         // guide direction (world)
  if (u.x() != 0.0 && u.y() != 0.0) return std::nullopt;  // not along a world axis
  Set s;
  s.kind = Kind::kGuided;
  s.body = slider.body;
  s.cross_slot = u.y() == 0.0 ? kY : kX;
  // n·(R + A ū − r_guide) = 0 with the normal n along the held world axis; θ held.
  s.angle = guide.angle + jt.relative_angle - slider.angle;
  const int axis = s.cross_slot == kX ? 0 : 1;
  s.cross = guide.position(axis) - (Rotation(s.angle) * slider.position)(axis);
  s.slots = {s.cross_slot, kTheta};
  s.rows = RowsOf(jt);
  return s;
}

void PrescribedMotion::BuildIndexMaps() {
  // Dropped unknowns: p_c, v_c, μ_k; dropped rows: F1_c, F3_k, F4_k.
  const int np = model_.num_coordinates();
  std::vector<bool> drop_unknown(full_size_, false), drop_row(full_size_, false);
  for (const Set& s : sets_) {
    for (int slot : s.slots) {
      const int c = model_.bodies()[s.body].coordinate(slot);
      drop_unknown[c] = drop_unknown[np + c] = true;
      drop_row[c] = true;
    }
    for (int k : s.rows) {
      drop_unknown[model_.mu_offset() + k] = true;
      drop_row[model_.lambda_offset() + k] = drop_row[model_.mu_offset() + k] = true;
    }
  }
  row_to_reduced_.assign(full_size_, -1);
  for (int i = 0; i < full_size_; ++i) {
    if (!drop_unknown[i]) kept_unknowns_.push_back(i);
    if (!drop_row[i]) {
      row_to_reduced_[i] = static_cast<int>(kept_rows_.size());
      kept_rows_.push_back(i);
    }
  }
  FLEXROD_ASSERT(kept_rows_.size() == kept_unknowns_.size());
}

void PrescribedMotion::Motion(const Set& s, double t, double* p, double* v, double* a) const {
  switch (s.kind) {
    case Kind::kHeld:
      p[0] = s.held.x();
      p[1] = s.held.y();
      p[2] = s.angle;
      for (int k = 0; k < 3; ++k) v[k] = a[k] = 0.0;
      return;
    case Kind::kDriven: {
      // r_marker = R + A(θ) ū = P: R = P − Aū, Ṙ = −θ̇ J A ū, R̈ = −θ̈ J A ū + θ̇² A ū.
      const Driver& d = model_.drivers()[s.driver];
      const double th = d.PrescribedAngle(t), w = d.PrescribedSpeed(t),
                   al = d.PrescribedAcceleration(segment_start_);
      // A pivot at the frame origin (ū = 0) needs no rotation: R = P.
      const Vec2 Au = s.marker.isZero() ? Vec2::Zero() : Vec2(Rotation(th) * s.marker);
      const Vec2 R = s.pivot - Au, Rd = -w * Jm(Au), Rdd = -al * Jm(Au) + (w * w) * Au;
      p[0] = R.x(), p[1] = R.y(), p[2] = th;
      v[0] = Rd.x(), v[1] = Rd.y(), v[2] = w;
      a[0] = Rdd.x(), a[1] = Rdd.y(), a[2] = al;
      return;
    }
    case Kind::kGuided:
      p[0] = s.cross;
      p[1] = s.angle;
      v[0] = v[1] = a[0] = a[1] = 0.0;
      return;
  }
}

void PrescribedMotion::Expand(double t, const double* y, const double* yp, double* y_full,
                              double* yp_full) const {
  const int n = size();
  for (int i = 0; i < n; ++i) {
    y_full[kept_unknowns_[i]] = y[i];
    yp_full[kept_unknowns_[i]] = yp[i];
  }
  ExpandPrescribed(t, y_full, yp_full);
}

// Inlined into both callers: ExpandPrescribed runs in every residual (PrescribedMotion::Expand).
[[gnu::always_inline]] inline void PrescribedMotion::ExpandSet(const Set& s, double t,
                                                               double* y_full,
                                                               double* yp_full) const {
  const int np = model_.num_coordinates();
  double p[3], v[3], a[3];
  Motion(s, t, p, v, a);
  const Body& b = model_.bodies()[s.body];
  for (size_t k = 0; k < s.slots.size(); ++k) {
    const int c = b.coordinate(s.slots[k]);
    y_full[c] = p[k];
    y_full[np + c] = v[k];
    yp_full[c] = v[k];
    yp_full[np + c] = a[k];
  }
  for (int k : s.rows) y_full[model_.mu_offset() + k] = yp_full[model_.mu_offset() + k] = 0.0;
}

void PrescribedMotion::ExpandPrescribed(double t, double* y_full, double* yp_full) const {
  for (const Set& s : sets_) ExpandSet(s, t, y_full, yp_full);
}

void PrescribedMotion::ExpandPrescribedBody(double t, int body, double* y_full,
                                            double* yp_full) const {
  for (const Set& s : sets_) {
    if (s.body == body) ExpandSet(s, t, y_full, yp_full);
  }
}

void PrescribedMotion::Reduce(const double* full, double* reduced) const {
  const int n = size();
  for (int i = 0; i < n; ++i) reduced[i] = full[kept_unknowns_[i]];
}

void PrescribedMotion::MoveReducedMatrix(const SparsityPattern& pattern, double* full,
                                         double* reduced) const {
  FLEXROD_ASSERT(pattern.size == full_size_);
  const int n = size();
  const size_t N = static_cast<size_t>(full_size_);
  for (int c = 0, kept = 0; c < full_size_; ++c) {
    double* col = full + static_cast<size_t>(c) * N;
    const bool keep = kept < n && kept_unknowns_[kept] == c;
    double* out = keep ? reduced + static_cast<size_t>(kept++) * n : nullptr;
    for (int64_t k = pattern.col_ptr[c]; k < pattern.col_ptr[c + 1]; ++k) {
      const int64_t r = pattern.row_index[k];
      if (out != nullptr && row_to_reduced_[r] >= 0) out[row_to_reduced_[r]] += col[r];
      col[r] = 0.0;
    }
  }
}

SparsityPattern PrescribedMotion::ReducePattern(const SparsityPattern& full) const {
  FLEXROD_ASSERT(full.size == full_size_);
  SparsityPattern out;
  out.size = size();
  out.col_ptr.push_back(0);
  for (int c : kept_unknowns_) {
    for (int64_t k = full.col_ptr[c]; k < full.col_ptr[c + 1]; ++k) {
      const int r = row_to_reduced_[full.row_index[k]];
      if (r >= 0) out.row_index.push_back(r);
    }
    out.col_ptr.push_back(out.nnz());
  }
  return out;
}

}  // namespace flexrod::multibody
