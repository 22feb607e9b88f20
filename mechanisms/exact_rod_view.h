// mechanisms/exact_rod_view.h — what a run reads off an exact rod (multibody/exact_rod.h) at a
// sample: node positions, the deflection from the chord, surface strains at gauge positions
// (from the elements' exact strains), the strain energy, and the elastic state that a steady
// start compares between revolutions. The reduced rod's counterparts are rows of its basis
// (fem/reduced_rod.h); this is the exact rod's, read from the node bodies' coordinates.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "common/eigen.h"
#include "multibody/exact_rod.h"
#include "multibody/mechanism.h"

namespace flexrod::study {

class ExactRodView {
 public:
  ExactRodView(const multibody::Mechanism& m, const multibody::ExactRod& rod);
  int num_nodes() const { return static_cast<int>(x_.size()); }
  /// Node k's position in the world [m].
  Vec2 NodePosition(const double* y, int k) const { return Vec2(y[x_[k]], y[y_[k]]); }
  /// Node k's section angle [rad].
  double NodeAngle(const double* y, int k) const { return y[theta_[k]]; }
  /// Signed distance of node k from the chord of the end nodes [m] (left of the chord > 0).
  double Deflection(const double* y, int k) const;
  /// Surface strain ε − y_f κ at axial position x [m] on fibre y_f [m]: the element strains
  /// (constant per element, superconvergent at its midpoint) interpolated linearly between
  /// element midpoints, extrapolated from the two end elements beyond the outer midpoints.
  double Strain(const double* y, double x, double fibre) const;
  /// Σ of the elements' strain energies [J].
  double StrainEnergy(const double* y) const;
  /// The deflections of all nodes from the chord (num_nodes) [m].
  void ElasticState(const double* y, double* out) const;

 private:
  fem::ReissnerStrains ElementStrains(const double* y, int e) const;
  const multibody::ExactRod* rod_;
  std::vector<int> x_, y_, theta_;
};

}  // namespace flexrod::study
