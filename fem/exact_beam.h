// fem/exact_beam.h — the planar geometrically exact (Simo–Reissner) beam, flexrod's reference
// for everything flexible: the pure element kernel (strains, internal forces with
// Kelvin–Voigt damping, analytic tangents), the lumped node inertia that a multibody body per
// node carries, a static nonlinear solver for a whole rod (Newton with load stepping), and
// the linearised frequencies about the straight reference.
//
// Element (two nodes, linear interpolation of the centreline x(s) ∈ R² and the section angle
// θ(s), one-point midpoint integration, which is free of shear locking): with the element
// dofs d = [x_a, y_a, θ_a, x_b, y_b, θ_b] and reference length L0,
//   x' = (x_b − x_a)/L0,  θ_m = (θ_a + θ_b)/2,  Γ = R(θ_m)ᵀ x' − e1 = [ε, γ],  κ = (θ_b − θ_a)/L0,
//   U = L0/2 (EA ε² + GA γ² + EI κ²)
// (Simo & Vu-Quoc 1986, "A three-dimensional finite-strain rod model. Part II", planar case;
// Crisfield 1991, "Non-linear Finite Element Analysis of Solids and Structures", vol. 1 §7.4).
// Strains are objective: any rigid motion (translation and finite rotation) leaves them
// unchanged, and the straight reference along x with θ = 0 is stress-free.
//
// What does not live here: the small-displacement frame elements (fem/beam_element.h), the
// rod mesh and its linear assembly (fem/rod_mesh.h), and any multibody coupling.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <Eigen/Dense>
#include <utility>
#include <vector>

#include "common/eigen.h"
#include "fem/material.h"
#include "fem/rod_mesh.h"
#include "fem/section.h"

namespace flexrod::fem {

using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// Section resultant stiffnesses of the planar Reissner beam.
struct ReissnerStiffness {
  double EA;  ///< axial stiffness [N]
  double GA;  ///< shear stiffness k G A with Cowper's k [N]
  double EI;  ///< in-plane bending stiffness [N m^2]
};

/// EA, k G A (RectSection::CowperShearFactor) and E I_in_plane. Validates both inputs
/// (InputError).
ReissnerStiffness ReissnerStiffnessOf(const Material& material, const RectSection& section);

/// Strain measures of one element (constant over it: one-point integration).
struct ReissnerStrains {
  double axial;      ///< ε [-]
  double shear;      ///< γ [-]
  double curvature;  ///< κ [1/m]
};

/// Strains of the element with reference length L0 [m] > 0 and dofs d [m, m, rad, m, m, rad].
ReissnerStrains CalcReissnerStrains(double L0, const Vec6& d);

/// Internal nodal forces f = ∂U/∂d + damping forces (generalised: forces [N] and moments
/// [N m] ON the element's nodes as the element resists, i.e. the nodes receive −f), and
/// optionally the tangents K = ∂f/∂d and C = ∂f/∂ḋ (6×6, may be null); returns the elastic
/// energy U [J]. Damping is stiffness-proportional on the strain rates (Kelvin–Voigt
/// resultants N = EA(ε + β ε̇), Q = GA(γ + β γ̇), M = EI(κ + β κ̇)), β [s] >= 0. K is symmetric
/// when β ḋ = 0. Analytic, no allocation, no throw. d_dot [m/s, m/s, rad/s, ...].
double CalcReissnerElement(const ReissnerStiffness& s, double L0, double beta, const Vec6& d,
                           const Vec6& d_dot, Vec6* f, Mat6* K, Mat6* C);

/// The same element with a stress-free reference that is not straight: the strains are
/// measured from `reference` (e.g. CalcReissnerStrains of the initial, crooked geometry), so
/// U = L0/2 (EA (ε − ε0)² + GA (γ − γ0)² + EI (κ − κ0)²). Rigid motions of that reference
/// remain strain-free.
double CalcReissnerElement(const ReissnerStiffness& s, double L0, double beta,
                           const ReissnerStrains& reference, const Vec6& d, const Vec6& d_dot,
                           Vec6* f, Mat6* K, Mat6* C);

/// Rigid-body inertia lumped at one node.
struct NodeInertia {
  double mass;     ///< [kg]
  Vec2 com;        ///< centre of mass relative to the node, rod frame [m]
  double inertia;  ///< rotational inertia about the centre of mass [kg m^2]
};

/// Lumped inertia of each node (rod.num_nodes() entries): node k carries the rigid segment of
/// rod around it (interior: [x_k − L0/2, x_k + L0/2]; ends: the half segment on the rod
/// side) with mass ρA·len, centroid on the rod axis and inertia ρA len³/12 + ρ I_in_plane len
/// about it, combined with every RigidAttachment at that node (parallel-axis theorem). The
/// nodes together reproduce the rigid rod's mass, centre of mass and inertia exactly.
/// rod.theory, rod.mass_kind and rod.dim are not used. Throws InputError (rod.Validate).
std::vector<NodeInertia> ExactBeamNodeInertia(const RodSpec& rod);

/// The 3×3 mass matrix of a node body expressed at the node, planar dofs (x, y, θ), rod frame
/// aligned with the world: [[m, 0, −m c_y], [0, m, m c_x], [−m c_y, m c_x, J + m|c|²]].
Eigen::Matrix3d NodeMassMatrix(const NodeInertia& node);

/// A static problem on the whole rod. The element reference length is rod.element_length().
struct ExactBeamStaticProblem {
  RodSpec rod;  ///< straight along x, node k at (node_x(k), 0), θ = 0
  /// Optional per-node offset [m] of the stress-free reference (an initial crookedness such as
  /// a dy imperfection): the reference node k is at (node_x(k), 0) + initial_offset[k] with
  /// θ = 0 and every element is stress-free there. Empty, or rod.num_nodes() entries.
  std::vector<Vec2> initial_offset;
  /// (node, dof) held at the reference value; dof 0: x, 1: y, 2: θ.
  std::vector<std::pair<int, int>> fixed;
  /// (node, [Fx [N], Fy [N], M [N m]]) dead loads in world axes, scaled by the load factor.
  std::vector<std::pair<int, Vec3>> loads;
  int load_steps{20};  ///< equal load increments, >= 1

  /// Throws InputError naming exact_beam.<key> (and rod.<key> via rod.Validate()).
  void Validate() const;
};

struct ExactBeamStaticSolution {
  std::vector<Vec3> nodes;  ///< x [m], y [m], θ [rad] per node
  int newton_iterations;    ///< total over all load steps
};

/// Equilibrium under the loads times load_factor: Newton with load stepping (factors
/// 1/load_steps … 1 of load_factor), analytic tangent, sparse Cholesky (Eigen SimplicialLLT).
/// Dead loads are conservative, so each step minimises the total potential: where the
/// tangent is not positive definite (past a bifurcation) it is shifted until it is, and every
/// step is accepted by a backtracking line search on the potential; the iteration therefore
/// follows stable equilibria (e.g. the buckled branch selected by an imperfection). Throws
/// InputError for an invalid problem before any work, NumericalError naming the load factor,
/// the iteration and the residual if a step does not converge.
ExactBeamStaticSolution SolveExactBeamStatic(const ExactBeamStaticProblem& p,
                                             double load_factor = 1.0);

/// The lowest `count` linearised frequencies [Hz] about the straight, unloaded reference,
/// ascending: K_T(ref) with the lumped node inertia (NodeMassMatrix of ExactBeamNodeInertia),
/// fixed (node, dof) removed. Rigid-body modes appear at ≈ 0 Hz. Throws InputError.
std::vector<double> ExactBeamFrequencies(const RodSpec& rod,
                                         const std::vector<std::pair<int, int>>& fixed, int count);

}  // namespace flexrod::fem
