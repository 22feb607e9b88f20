// multibody/exact_rod.h — the geometrically exact rod as part of a mechanism: one rigid body
// per FE node, carrying the rigid segment of rod around the node and the rigid attachments
// welded there (fem::ExactBeamNodeInertia), and a planar Simo–Reissner beam element
// (fem/exact_beam.h) between neighbouring nodes as a force element with an analytic Jacobian.
// No reduction and no small-rotation assumption: node positions and section angles are
// absolute coordinates, the strains are objective, rigid motions are exact. It is flexrod's
// internal reference for the reduced floating-frame rod (DESIGN.md, "The rod must be right
// under axial load").
//
// Node body k's frame: origin at node k, angle = the section angle θ_k (θ_k = θ_rod in the
// undeformed rod); a point at offset d from node k in the rod frame is a body marker at d.
// Damping: Kelvin–Voigt on the strain rates (stiffness-proportional, β [s]), the only
// Rayleigh part that does not damp rigid motion: mode i gets ζ_i = β ω_i / 2; and, for modal
// damping, a co-rotated modal damping of the node bodies (multibody/corotated_damping.h) with
// modes and coefficients from FitCorotatedModalDamping (multibody/mechanism_modes.h).
// What does not live here: the element kernel and the static solver (fem/exact_beam.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <string>
#include <vector>

#include "fem/exact_beam.h"
#include "fem/rod_mesh.h"
#include "multibody/force_element.h"
#include "multibody/mechanism.h"

namespace flexrod::multibody {

/// One Reissner beam element between two node markers (marker i at node a, marker j at node
/// b, both at their node body's origin with angle 0).
class ReissnerBeamElement final : public ForceElement {
 public:
  /// length L0 [m] > 0, beta [s] >= 0.
  ReissnerBeamElement(const fem::ReissnerStiffness& stiffness, double length, double beta);
  bool Evaluate(double t, const MarkerKinematics& i, const MarkerKinematics& j, const double* z,
                const double* memory, ElementOutput* out) const override;
  bool EvaluateJacobian(double t, const MarkerKinematics& i, const MarkerKinematics& j,
                        const double* z, const double* memory, Mat* d_kinematics,
                        Mat* d_states) const override;
  double PotentialEnergy(const MarkerKinematics& i, const MarkerKinematics& j, const double* z,
                         const double* memory) const override;
  /// The element length: positions of its nodes are resolved to rel_tol × L0, so that its
  /// strains (differences of node positions over L0) keep the relative tolerance.
  double ResolvedLength() const override { return length_; }
  bool structural() const override { return true; }
  std::string type_name() const override { return "reissner-beam"; }

  /// Strains (ε, γ, κ) of the element at the kinematics of its two markers.
  fem::ReissnerStrains Strains(const MarkerKinematics& i, const MarkerKinematics& j) const;
  double length() const { return length_; }

 private:
  fem::ReissnerStiffness stiffness_;
  double length_, beta_;
};

struct ExactRodSpec {
  std::string name;  ///< node bodies are "<name>.node<k>"
  fem::RodSpec rod;  ///< planar; material, section, length, elements, attachments
  double beta{0.0};  ///< Kelvin–Voigt damping of the strain rates [s], >= 0
  /// Co-rotated modal damping of the node bodies (none if empty): Y (3 num_elements × r) and
  /// c (r), MechanismBuilder::AddCorotatedDamping.
  Mat modal_damping_modes;
  Vec modal_damping_coefficients;
};

/// What AddExactRod added.
struct ExactRod {
  fem::RodSpec rod;
  std::vector<BodyId> nodes;           ///< node bodies, 0 … num_elements
  std::vector<MarkerId> node_markers;  ///< marker at each node (the elements' markers)
  std::vector<ElementId> elements;     ///< element e between node e and e + 1
  std::shared_ptr<const ReissnerBeamElement> element;  ///< the elements' common kernel
};

/// Adds the rod's node bodies and elements. Throws InputError naming <name>.<key>.
ExactRod AddExactRod(MechanismBuilder* builder, const ExactRodSpec& spec);

/// Node poses of the undeformed rod with frame origin R and angle θ (rod frame B: node 0 at
/// the origin, x along the rod): fills the node bodies' (x, y, θ) in p.
void SetExactRodPose(const Mechanism& m, const ExactRod& rod, const Vec2& R, double theta, Vec* p);

}  // namespace flexrod::multibody
