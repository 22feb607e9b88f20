// fem/rod_mesh.cc — rod validation, the generic element assembler, rigid attachments,
// boundary conditions and the static solve.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "fem/rod_mesh.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/error.h"
#include "fem/sparse_solver.h"

namespace flexrod::fem {
namespace {

// Sanity bound on the discretisation: beyond this the dense oracle and the reduction make
// no sense and the user almost certainly mistyped.
constexpr int kMaxElements = 100000;

std::string AttachmentPrefix(const RigidAttachment& a, size_t index) {
  return a.name.empty() ? "rod.attachments[" + std::to_string(index) + "]"
                        : "rod.attachments." + a.name;
}

/// Element matrices of one element, in element dofs (2 × dofs per node).
template <int N>
struct ElementMatrices {
  Eigen::Matrix<double, N, N> K, M, Kg;
  bool has_geometric;
};

ElementMatrices<6> PlanarElement(const RodSpec& spec) {
  const double le = spec.element_length();
  return {PlanarFrameStiffness(spec.section, spec.material, le, spec.theory),
          PlanarFrameMass(spec.section, spec.material, le, spec.theory, spec.mass_kind),
          PlanarFrameGeometricStiffness(le), true};
}

ElementMatrices<12> SpatialElement(const RodSpec& spec) {
  const double le = spec.element_length();
  return {SpatialFrameStiffness(spec.section, spec.material, le, spec.theory),
          SpatialFrameMass(spec.section, spec.material, le, spec.theory, spec.mass_kind),
          Matrix12d::Zero(), false};
}

/// The one assembler: loops over elements once, scattering K, M and Kg (if the element type
/// has one) into triplet lists. `element(e)` returns the matrices of element e; element e
/// joins nodes e and e+1 and its dofs are the two nodes' dofs in order.
template <int N, typename ElementFn>
void AssembleElements(const RodSpec& spec, ElementFn element, std::vector<Triplet>* K,
                      std::vector<Triplet>* M, std::vector<Triplet>* Kg) {
  const int dpn = spec.dofs_per_node();
  FLEXROD_ASSERT(N == 2 * dpn);
  K->reserve(K->size() + static_cast<size_t>(spec.num_elements) * N * N);
  M->reserve(M->size() + static_cast<size_t>(spec.num_elements) * N * N);
  for (int e = 0; e < spec.num_elements; ++e) {
    const ElementMatrices<N> em = element(e);
    const int first = e * dpn;  // element dofs are contiguous: node e then node e+1
    for (int c = 0; c < N; ++c) {
      for (int r = 0; r < N; ++r) {
        if (em.K(r, c) != 0.0) K->emplace_back(first + r, first + c, em.K(r, c));
        if (em.M(r, c) != 0.0) M->emplace_back(first + r, first + c, em.M(r, c));
        if (em.has_geometric && em.Kg(r, c) != 0.0)
          Kg->emplace_back(first + r, first + c, em.Kg(r, c));
      }
    }
  }
}

// Attachment welded to node k, small rotations, rod frame. Its centre of mass is displaced by
// u_c = u_k + φ × d (d = com_offset, in the x–y plane). Kinetic energy
//   T = ½ m |u̇_k + φ̇ × d|² + ½ J_a φ̇_z²
// gives, with u_c = S [u; φ], S = [I, −[d]×], the nodal mass block m SᵀS + J_a e_z e_zᵀ:
//   translations m I;  translation–rotation −m [d]×;  rotation m(|d|² I − d dᵀ) + J_a e_z e_zᵀ.
// Planar restriction (u, v, φ): [[m, 0, −m d_y], [0, m, m d_x], [−m d_y, m d_x, J_a + m|d|²]],
// i.e. coupling m·(J d) with J the +90° rotation. In 3-D only the attachment's own inertia
// about z is known; its own inertia about x and y is taken as zero (document in the input).
void AddAttachment(const RodSpec& spec, const RigidAttachment& a, std::vector<Triplet>* M) {
  const double m = a.mass;
  const double dx = a.com_offset.x(), dy = a.com_offset.y();
  const int base = a.node * spec.dofs_per_node();
  if (spec.dim == MeshDim::kPlanar) {
    Eigen::Matrix3d block;
    block << m, 0.0, -m * dy,  //
        0.0, m, m * dx,        //
        -m * dy, m * dx, a.inertia + m * (dx * dx + dy * dy);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        if (block(r, c) != 0.0) M->emplace_back(base + r, base + c, block(r, c));
    return;
  }
  const Eigen::Vector3d d(dx, dy, 0.0);
  Eigen::Matrix3d dx_cross;        // [d]×, so [d]× φ = d × φ
  dx_cross << 0.0, -d.z(), d.y(),  //
      d.z(), 0.0, -d.x(),          //
      -d.y(), d.x(), 0.0;
  Eigen::Matrix<double, 6, 6> block;
  block.topLeftCorner<3, 3>() = m * Eigen::Matrix3d::Identity();
  block.topRightCorner<3, 3>() = -m * dx_cross;
  block.bottomLeftCorner<3, 3>() = m * dx_cross;  // (−m [d]×)ᵀ = m [d]×
  block.bottomRightCorner<3, 3>() =
      m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  block(5, 5) += a.inertia;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c)
      if (block(r, c) != 0.0) M->emplace_back(base + r, base + c, block(r, c));
}

SpMat FromTriplets(int n, const std::vector<Triplet>& t) {
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  return A;
}

}  // namespace

void RigidAttachment::Validate(const std::string& prefix) const {
  if (!(std::isfinite(mass) && mass >= 0.0))
    throw InputError(prefix + ".mass", FormatValue(mass) + " kg", "must be finite and >= 0");
  if (!(std::isfinite(inertia) && inertia >= 0.0))
    throw InputError(prefix + ".inertia", FormatValue(inertia) + " kg m^2",
                     "must be finite and >= 0");
  if (!com_offset.allFinite())
    throw InputError(prefix + ".com_offset",
                     "(" + FormatValue(com_offset.x()) + ", " + FormatValue(com_offset.y()) + ") m",
                     "must be finite");
  if (node < 0) throw InputError(prefix + ".node", std::to_string(node), "must be >= 0");
}

void RodSpec::Validate() const {
  material.Validate("rod");  // keys rod.E, rod.nu, rod.rho, rod.yield
  section.Validate("rod");
  if (!(std::isfinite(length) && length > 0.0))
    throw InputError("rod.length", FormatValue(length) + " m", "must be finite and > 0");
  // A beam is longer than its section is wide: a section larger than the rod (rod.thickness =
  // "3175 m") ran 200 s before failing, at steps of 1e-7 s.
  for (const auto& [key, size] :
       {std::pair<const char*, double>{"rod.thickness", section.thickness},
        std::pair<const char*, double>{"rod.height", section.height}}) {
    if (!(size < length)) {
      throw InputError(key, FormatValue(size) + " m",
                       "must be below rod.length = " + FormatValue(length) +
                           " m: a beam is longer than its section");
    }
  }
  if (num_elements < 1 || num_elements > kMaxElements)
    throw InputError("rod.elements", std::to_string(num_elements),
                     "must be in [1, " + std::to_string(kMaxElements) + "]");
  for (size_t i = 0; i < attachments.size(); ++i) {
    const RigidAttachment& a = attachments[i];
    const std::string prefix = AttachmentPrefix(a, i);
    a.Validate(prefix);
    if (a.node >= num_nodes())
      throw InputError(prefix + ".node", std::to_string(a.node),
                       "must be a node index in [0, " + std::to_string(num_nodes() - 1) +
                           "] (the rod has " + std::to_string(num_nodes()) + " nodes)");
  }
}

AssembledRod AssembleRod(const RodSpec& spec) {
  spec.Validate();
  const int n = spec.num_dofs();
  std::vector<Triplet> K, M, Kg;
  bool planar = spec.dim == MeshDim::kPlanar;
  // The rod is straight and uniform, so every element has the same matrices; the element
  // function still receives e so that graded meshes need no new assembler.
  if (planar) {
    const ElementMatrices<6> em = PlanarElement(spec);
    AssembleElements<6>(
        spec, [&](int) { return em; }, &K, &M, &Kg);
  } else {
    const ElementMatrices<12> em = SpatialElement(spec);
    AssembleElements<12>(
        spec, [&](int) { return em; }, &K, &M, &Kg);
  }
  for (const RigidAttachment& a : spec.attachments) AddAttachment(spec, a, &M);

  AssembledRod out;
  out.K = FromTriplets(n, K);
  out.M = FromTriplets(n, M);
  if (planar) out.Kg = FromTriplets(n, Kg);  // spatial: 0 × 0, no geometric stiffness
  return out;
}

std::vector<int> BoundaryDofs(const RodSpec& spec, const std::string& bc_name) {
  enum class End { kClamped, kPinned, kFree };
  End left, right;
  if (bc_name == "clamped-clamped") {
    left = End::kClamped, right = End::kClamped;
  } else if (bc_name == "clamped-free") {
    left = End::kClamped, right = End::kFree;
  } else if (bc_name == "free-free") {
    left = End::kFree, right = End::kFree;
  } else if (bc_name == "pinned-pinned") {
    left = End::kPinned, right = End::kPinned;
  } else if (bc_name == "clamped-pinned") {
    left = End::kClamped, right = End::kPinned;
  } else {
    throw InputError("boundary_conditions", bc_name,
                     "must be one of clamped-clamped, clamped-free, free-free, pinned-pinned, "
                     "clamped-pinned");
  }
  const int dpn = spec.dofs_per_node();
  // Pinned: translations, plus torsion in 3-D (a pin does not let the rod spin about its axis).
  const std::vector<int> pinned_local =
      spec.dim == MeshDim::kPlanar ? std::vector<int>{0, 1} : std::vector<int>{0, 1, 2, 3};
  std::vector<int> fixed;
  auto add_end = [&](End end, int node) {
    if (end == End::kFree) return;
    if (end == End::kClamped) {
      for (int k = 0; k < dpn; ++k) fixed.push_back(node * dpn + k);
    } else {
      for (int k : pinned_local) fixed.push_back(node * dpn + k);
    }
  };
  add_end(left, 0);
  add_end(right, spec.num_nodes() - 1);
  std::sort(fixed.begin(), fixed.end());
  fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
  return fixed;
}

std::vector<int> FreeDofs(int num_dofs, const std::vector<int>& fixed) {
  std::vector<char> is_fixed(static_cast<size_t>(num_dofs), 0);
  for (int d : fixed) {
    FLEXROD_ASSERT(d >= 0 && d < num_dofs);
    is_fixed[static_cast<size_t>(d)] = 1;
  }
  std::vector<int> free;
  free.reserve(static_cast<size_t>(num_dofs));
  for (int d = 0; d < num_dofs; ++d)
    if (!is_fixed[static_cast<size_t>(d)]) free.push_back(d);
  return free;
}

SpMat Restrict(const SpMat& A, const std::vector<int>& keep) {
  FLEXROD_ASSERT(A.rows() == A.cols());
  std::vector<int> new_index(static_cast<size_t>(A.rows()), -1);
  for (size_t i = 0; i < keep.size(); ++i) {
    FLEXROD_ASSERT(keep[i] >= 0 && keep[i] < A.rows());
    new_index[static_cast<size_t>(keep[i])] = static_cast<int>(i);
  }
  std::vector<Triplet> t;
  t.reserve(static_cast<size_t>(A.nonZeros()));
  for (int c = 0; c < A.outerSize(); ++c) {
    const int nc = new_index[static_cast<size_t>(c)];
    if (nc < 0) continue;
    for (SpMat::InnerIterator it(A, c); it; ++it) {
      const int nr = new_index[static_cast<size_t>(it.row())];
      if (nr >= 0) t.emplace_back(nr, nc, it.value());
    }
  }
  const int k = static_cast<int>(keep.size());
  SpMat out(k, k);
  out.setFromTriplets(t.begin(), t.end());
  out.makeCompressed();
  return out;
}

Vec SolveStatic(const RodSpec& spec, const SpMat& K, const Vec& f, const std::vector<int>& fixed) {
  const int n = spec.num_dofs();
  FLEXROD_ASSERT(K.rows() == n && K.cols() == n && f.size() == n);
  const std::vector<int> free = FreeDofs(n, fixed);
  Vec u = Vec::Zero(n);
  if (free.empty()) return u;
  Vec f_free(static_cast<Eigen::Index>(free.size()));
  for (size_t i = 0; i < free.size(); ++i) f_free[static_cast<Eigen::Index>(i)] = f[free[i]];
  // An unrestrained rigid-body mode makes K_ff singular: CHOLMOD reports it as not positive
  // definite and the wrapper throws NumericalError.
  std::unique_ptr<SparseSolver> solver = MakeSparseSolver(SparseSolverKind::kCholmod);
  solver->Factorize(Restrict(K, free));
  Vec u_free;
  solver->Solve(f_free, &u_free);
  for (size_t i = 0; i < free.size(); ++i) u[free[i]] = u_free[static_cast<Eigen::Index>(i)];
  return u;
}

}  // namespace flexrod::fem
