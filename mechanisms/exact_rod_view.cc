// SPDX-License-Identifier: GPL-3.0-or-later
#include "mechanisms/exact_rod_view.h"

#include <algorithm>
#include <cmath>

namespace flexrod::study {

ExactRodView::ExactRodView(const multibody::Mechanism& m, const multibody::ExactRod& rod)
    : rod_(&rod) {
  for (multibody::BodyId b : rod.nodes) {
    x_.push_back(m.coordinate(b, multibody::kX));
    y_.push_back(m.coordinate(b, multibody::kY));
    theta_.push_back(m.coordinate(b, multibody::kTheta));
  }
}

double ExactRodView::Deflection(const double* y, int k) const {
  const Vec2 a = NodePosition(y, 0), b = NodePosition(y, num_nodes() - 1), c = NodePosition(y, k);
  const Vec2 chord = (b - a).normalized();
  return chord.x() * (c - a).y() - chord.y() * (c - a).x();
}

fem::ReissnerStrains ExactRodView::ElementStrains(const double* y, int e) const {
  fem::Vec6 d;
  d << y[x_[e]], y[y_[e]], y[theta_[e]], y[x_[e + 1]], y[y_[e + 1]], y[theta_[e + 1]];
  return fem::CalcReissnerStrains(rod_->element->length(), d);
}

double ExactRodView::Strain(const double* y, double x, double fibre) const {
  const int ne = num_nodes() - 1;
  auto surface = [&](int e) {
    const fem::ReissnerStrains s = ElementStrains(y, e);
    return s.axial - fibre * s.curvature;
  };
  if (ne == 1) return surface(0);
  const double le = rod_->element->length();
  // Between the midpoints of elements e and e + 1 (clamped to the outer pairs: extrapolation).
  const int e = std::clamp(static_cast<int>(std::floor(x / le - 0.5)), 0, ne - 2);
  const double xi = (x - (e + 0.5) * le) / le;
  return (1.0 - xi) * surface(e) + xi * surface(e + 1);
}

double ExactRodView::StrainEnergy(const double* y) const {
  double u = 0.0;
  for (int e = 0; e + 1 < num_nodes(); ++e) {
    multibody::MarkerKinematics a, b;
    a.position = NodePosition(y, e);
    a.angle = NodeAngle(y, e);
    b.position = NodePosition(y, e + 1);
    b.angle = NodeAngle(y, e + 1);
    u += rod_->element->PotentialEnergy(a, b, nullptr, nullptr);
  }
  return u;
}

void ExactRodView::ElasticState(const double* y, double* out) const {
  for (int k = 0; k < num_nodes(); ++k) out[k] = Deflection(y, k);
}

}  // namespace flexrod::study
