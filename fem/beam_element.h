// fem/beam_element.h — pure element kernels: stiffness, mass and geometric stiffness of 2-node
// frame elements, and the shape functions the inertia integrals and strain gauges use.
// Planar element dofs per node: (u, v, φ) = axial, transverse, rotation. Element vector
// [u1 v1 φ1 u2 v2 φ2]. Spatial element per node: (u, v, w, φx, φy, φz), 12 dofs; v/φz bend in
// the mechanism plane (in-plane second moment), w/φy out of plane, φx is torsion.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <Eigen/Dense>

#include "fem/material.h"
#include "fem/section.h"

namespace flexrod::fem {

enum class BeamTheory { kEulerBernoulli, kTimoshenko };
enum class MassKind { kConsistent, kLumped };

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;

Matrix6d PlanarFrameStiffness(const RectSection& s, const Material& m, double length, BeamTheory t);
Matrix6d PlanarFrameMass(const RectSection& s, const Material& m, double length, BeamTheory t,
                         MassKind kind);
/// Geometric stiffness for a unit axial tension N = 1 N (multiply by N) [1/m].
Matrix6d PlanarFrameGeometricStiffness(double length);

Matrix12d SpatialFrameStiffness(const RectSection& s, const Material& m, double length,
                                BeamTheory t);
Matrix12d SpatialFrameMass(const RectSection& s, const Material& m, double length, BeamTheory t,
                           MassKind kind);

/// Planar element interpolation at ξ = x/L ∈ [0, 1]: rows of the 3×6 matrix N(ξ) with
/// [u(x); v(x); ψ(x)] = N(ξ) d_e, where ψ is the section rotation (= v' for Euler–Bernoulli).
/// Also the 2×6 strain-displacement rows: [u'(x); κ(x)] with κ = ψ' (curvature, v'' for EB).
struct PlanarShape {
  Eigen::Matrix<double, 3, 6> N;  ///< u, v, ψ
  Eigen::Matrix<double, 2, 6> B;  ///< u' [1/m·m], κ [1/m]
};
PlanarShape PlanarFrameShape(const RectSection& s, const Material& m, double length, BeamTheory t,
                             double xi);

}  // namespace flexrod::fem
