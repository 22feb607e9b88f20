// fem/rod_mesh.h — a straight rod meshed with 2-node frame elements along its local x axis,
// rigid attachments welded to nodes, and per-node per-dof boundary conditions; plus the one
// generic assembler for sparse K, M and the geometric stiffness.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "common/eigen.h"
#include "fem/beam_element.h"

namespace flexrod::fem {

enum class MeshDim { kPlanar, kSpatial };  // 3 or 6 dofs per node

/// A rigid body welded to an FE node (clamp, bush): it moves with the node's translation
/// and rotation (small rotations). Offsets are in the rod frame.
struct RigidAttachment {
  std::string name;
  int node;        ///< FE node index
  double mass;     ///< [kg], >= 0
  double inertia;  ///< rotational inertia about its own centre of mass, about z [kg m^2]
  Eigen::Vector2d com_offset{0.0, 0.0};  ///< centre of mass relative to the node, rod frame [m]
  void Validate(const std::string& prefix) const;
};

enum class DofFix { kFree, kFixed };

/// The rod: geometry, discretisation and everything needed to assemble it.
struct RodSpec {
  Material material;
  RectSection section;
  double length;         ///< free length [m], > 0
  int num_elements{40};  ///< >= 1
  BeamTheory theory{BeamTheory::kEulerBernoulli};
  MassKind mass_kind{MassKind::kConsistent};
  MeshDim dim{MeshDim::kPlanar};
  std::vector<RigidAttachment> attachments;
  void Validate() const;  ///< throws InputError naming rod.<key>

  int num_nodes() const { return num_elements + 1; }
  int dofs_per_node() const { return dim == MeshDim::kPlanar ? 3 : 6; }
  int num_dofs() const { return num_nodes() * dofs_per_node(); }
  double element_length() const { return length / num_elements; }
  double node_x(int i) const { return length * i / num_elements; }  ///< [m]
};

/// Assembled sparse matrices over all node dofs (no boundary conditions applied).
struct AssembledRod {
  SpMat K;   ///< stiffness [N/m, N, N m]
  SpMat M;   ///< mass incl. attachments [kg, kg m, kg m^2]
  SpMat Kg;  ///< geometric stiffness per newton of axial tension (planar only; empty otherwise)
};

AssembledRod AssembleRod(const RodSpec& spec);

/// Standard boundary conditions by name; returns the list of fixed dof indices.
/// names: "clamped-clamped", "clamped-free", "free-free", "pinned-pinned", "clamped-pinned".
/// Pinned fixes translations (u, v; and w, and torsion φx in 3-D) but not bending rotations.
std::vector<int> BoundaryDofs(const RodSpec& spec, const std::string& bc_name);

/// Removes fixed dofs: returns the selection matrix columns kept (free dof indices, ascending).
std::vector<int> FreeDofs(int num_dofs, const std::vector<int>& fixed);
SpMat Restrict(const SpMat& A, const std::vector<int>& keep);

/// Static solve K u = f on the free dofs with CHOLMOD; returns u over all dofs (zero on fixed).
Vec SolveStatic(const RodSpec& spec, const SpMat& K, const Vec& f, const std::vector<int>& fixed);

}  // namespace flexrod::fem
