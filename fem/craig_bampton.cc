// fem/craig_bampton.cc — the Craig–Bampton basis (Craig & Bampton, AIAA J. 6 (1968)
// 1313–1319): Φ = [ I 0 ; Ψ Φ_k ] on (interface, interior) dofs, Ψ = −K_II⁻¹ K_IB the static
// constraint modes, Φ_k the k lowest fixed-interface modes of (K_II, M_II); optionally the
// fixed-interface static responses to the axial inertia loads, and the orthonormalised variant.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <vector>

#include "common/error.h"
#include "fem/eigensolver.h"
#include "fem/reduction_detail.h"
#include "fem/sparse_solver.h"

namespace flexrod::fem::reduction_detail {
namespace {

/// X = A⁻¹ B for a symmetric positive definite banded A, by a band Cholesky factorisation in
/// long double (x87 extended precision, ε ≈ 1.1e-19). Returns false if A's half-bandwidth
/// exceeds `max_band` (the caller then uses the sparse solver). A beam's interior stiffness has
/// cond ~ (number of elements)⁴ (≈1e16 at 10 000 elements): solved in double, the constraint
/// modes Ψ lose enough digits to put the reduced fundamental frequency 3e-3 off there.
constexpr int kExtendedBandLimit = 64;  // node-wise dof numbering: 2 × 6 dofs per node at most

bool SolveBandedExtended(const SpMat& A, const Mat& B, Mat* X, int max_band) {
  const int n = static_cast<int>(A.rows());
  int band = 0;
  for (int c = 0; c < A.outerSize(); ++c) {
    for (SpMat::InnerIterator it(A, c); it; ++it)
      band = std::max(band, static_cast<int>(std::abs(it.row() - c)));
  }
  if (band > max_band) return false;
  const int w = band + 1;  // L(i, j), j in [i − band, i], stored at i·w + (j − i + band)
  std::vector<long double> L(static_cast<size_t>(n) * w, 0.0L);
  auto at = [&](int i, int j) -> long double& {
    return L[static_cast<size_t>(i) * w + (j - i + band)];
  };
  for (int c = 0; c < A.outerSize(); ++c) {
    for (SpMat::InnerIterator it(A, c); it; ++it) {
      if (it.row() >= c) at(static_cast<int>(it.row()), c) = it.value();
    }
  }
  for (int j = 0; j < n; ++j) {
    long double d = at(j, j);
    for (int k = std::max(0, j - band); k < j; ++k) d -= at(j, k) * at(j, k);
    if (!(d > 0.0L))
      throw NumericalError("constraint modes: the interior stiffness is not positive definite");
    const long double ljj = std::sqrt(d);
    at(j, j) = ljj;
    for (int i = j + 1; i <= std::min(n - 1, j + band); ++i) {
      long double v = at(i, j);
      for (int k = std::max(0, i - band); k < j; ++k) v -= at(i, k) * at(j, k);
      at(i, j) = v / ljj;
    }
  }
  X->resize(n, B.cols());
  std::vector<long double> y(n);
  for (int c = 0; c < B.cols(); ++c) {
    for (int i = 0; i < n; ++i) {  // L y = b
      long double v = B(i, c);
      for (int k = std::max(0, i - band); k < i; ++k) v -= at(i, k) * y[k];
      y[i] = v / at(i, i);
    }
    for (int i = n - 1; i >= 0; --i) {  // Lᵀ x = y
      long double v = y[i];
      for (int k = i + 1; k <= std::min(n - 1, i + band); ++k) v -= at(k, i) * y[k];
      y[i] = v / at(i, i);
    }
    for (int i = 0; i < n; ++i) (*X)(i, c) = static_cast<double>(y[i]);
  }
  return true;
}

/// The fixed-interface static responses of a planar rod to the axial inertia loads of a
/// rigid motion: f₁ = M r_u (uniform axial acceleration) and f₂ = M (x r_u) (the centripetal
/// load θ̇² x), with the frame's and the interface's dofs held, so that together with the
/// interface's axial constraint mode the basis carries an axial force linear, then quadratic
/// in x. Each is made M-orthogonal to `basis` (Gram–Schmidt, twice) and M-normalised; one
/// that the basis already spans (to 1e-8 of its norm) is dropped.
Mat AxialLoadModes(const RodSpec& rod, const AssembledRod& A, const std::vector<int>& interior,
                   const Mat& basis) {
  const int ndof = rod.num_dofs();
  const int ni = static_cast<int>(interior.size());
  Mat loads = Mat::Zero(ndof, 2);
  for (int i = 0; i < rod.num_nodes(); ++i) {
    loads(3 * i, 0) = 1.0;
    loads(3 * i, 1) = rod.node_x(i);
  }
  const Mat f = A.M * loads;
  Mat rhs(ni, 2);
  for (int i = 0; i < ni; ++i) rhs.row(i) = f.row(interior[i]);
  Mat x(ni, 2);
  auto chol = MakeSparseSolver(SparseSolverKind::kCholmod);
  chol->Factorize(SubMatrix(A.K, interior, interior));
  chol->Solve(rhs, &x);
  Mat out = Mat::Zero(ndof, 2);
  int kept = 0;
  Mat accepted = basis;
  for (int c = 0; c < 2; ++c) {
    Vec psi = Vec::Zero(ndof);
    for (int i = 0; i < ni; ++i) psi(interior[i]) = x(i, c);
    const double norm0 = std::sqrt(psi.dot(A.M * psi));
    for (int pass = 0; pass < 2; ++pass) {
      const Mat MB = A.M * accepted;
      const Mat G = accepted.transpose() * MB;
      const Vec coeff = G.ldlt().solve(MB.transpose() * psi);
      psi -= accepted * coeff;
    }
    const double norm = std::sqrt(psi.dot(A.M * psi));
    if (!(norm > 1e-8 * norm0)) continue;
    psi /= norm;
    out.col(kept++) = psi;
    accepted.conservativeResize(Eigen::NoChange, accepted.cols() + 1);
    accepted.rightCols(1) = psi;
  }
  return out.leftCols(kept);
}

/// The free dofs of the interface nodes (`boundary`, ascending) and the other free dofs
/// (`interior`, in the order of `free`).
void SplitInterfaceDofs(const std::vector<int>& interface_nodes, int dofs_per_node,
                        const std::vector<int>& free, const std::set<int>& fixed,
                        std::vector<int>* boundary, std::vector<int>* interior) {
  std::set<int> bset;
  for (int k : interface_nodes) {
    for (int d = 0; d < dofs_per_node; ++d) {
      if (!fixed.count(k * dofs_per_node + d)) bset.insert(k * dofs_per_node + d);
    }
  }
  boundary->assign(bset.begin(), bset.end());
  for (int d : free) {
    if (!bset.count(d)) interior->push_back(d);
  }
}

/// The static constraint modes Ψ = −K_ii⁻¹ K_ib (ni × nb): by the band solver in extended
/// precision where K_ii's band allows, else by the sparse Cholesky solver.
Mat ConstraintModes(const SpMat& Kii, const SpMat& Kib, int ni, int nb) {
  Mat Psi(ni, nb);
  if (ni > 0 && nb > 0) {
    const Mat rhs = -(Kib * Mat::Identity(nb, nb));
    if (!SolveBandedExtended(Kii, rhs, &Psi, kExtendedBandLimit)) {
      auto chol = MakeSparseSolver(SparseSolverKind::kCholmod);
      chol->Factorize(Kii);
      chol->Solve(rhs, &Psi);
    }
  }
  return Psi;
}

/// Φ = [ I 0 ; Ψ Φ_k ] (ndof × (nb + k)) scattered to the rod's dofs: the unit constraint
/// columns at `boundary`, Ψ and the k fixed-interface modes at `interior`.
Mat CraigBamptonColumns(int ndof, const std::vector<int>& boundary,
                        const std::vector<int>& interior, const Mat& Psi,
                        const EigenResult& fixed_interface, int k) {
  const int nb = static_cast<int>(boundary.size());
  const int ni = static_cast<int>(interior.size());
  Mat basis = Mat::Zero(ndof, nb + k);
  for (int i = 0; i < nb; ++i) basis(boundary[i], i) = 1.0;
  for (int i = 0; i < ni; ++i) {
    basis.row(interior[i]).head(nb) = Psi.row(i);
    if (k > 0) basis.row(interior[i]).tail(k) = fixed_interface.eigenvectors.row(i);
  }
  return basis;
}

/// Reduced stiffness from the Craig–Bampton block structure (Craig & Bampton 1968):
/// K_r = diag(K_bb + K_bi Ψ, Λ), symmetrised; the coupling Φ_mᵀ(K_ii Ψ + K_ib) is zero and Φ_m
/// is M-orthonormal. The projection Φᵀ K Φ forms the same matrix from products of K's largest
/// entries (12EI/h³ ≈ 6e12 N/m at 10 000 elements) with smooth shapes, and its cancellation
/// alone puts the reduced fundamental frequency 1e-2 below the full model's there; the Schur
/// complement cancels once, against the boundary entries only.
Mat StructuredStiffness(const SpMat& K, const std::vector<int>& boundary, const SpMat& Kib,
                        const Mat& Psi, const Vec& eigenvalues, int ni, int k) {
  const int nb = static_cast<int>(boundary.size());
  Mat Kcb = Mat::Zero(nb + k, nb + k);
  if (nb > 0) {
    Kcb.topLeftCorner(nb, nb) = Mat(SubMatrix(K, boundary, boundary));
    if (ni > 0) Kcb.topLeftCorner(nb, nb) += Mat(SpMat(Kib.transpose())) * Psi;
  }
  for (int j = 0; j < k; ++j) Kcb(nb + j, nb + j) = eigenvalues(j);
  Kcb = (0.5 * (Kcb + Kcb.transpose())).eval();
  return Kcb;
}

/// Appends the fixed-interface static responses to the axial inertia loads of a rigid motion
/// (uniform axial acceleration, and the centripetal load growing with x): ψ = K_ii⁻¹ f_i,
/// M-orthogonalised against the basis (AxialLoadModes). Returns whether any was appended.
bool AppendAxialLoadModes(const RodSpec& rod, const AssembledRod& A,
                          const std::vector<int>& interior, Mat* basis) {
  const Mat psi = AxialLoadModes(rod, A, interior, *basis);
  if (psi.cols() == 0) return false;
  const int ndof = static_cast<int>(basis->rows()), n = static_cast<int>(basis->cols());
  const int na = static_cast<int>(psi.cols());
  Mat widened = Mat::Zero(ndof, n + na);
  widened.leftCols(n) = *basis;
  widened.rightCols(na) = psi;
  *basis = std::move(widened);
  return true;
}

/// Diagonalises the reduced pair; the basis becomes M-orthonormal with K diagonal, and
/// *structured_K that diagonal K. `drop_rigid`: the frame carries rigid-body motion (no dofs
/// fixed), so the rigid-body modes are dropped.
void Orthonormalise(const AssembledRod& A, bool drop_rigid, Mat* basis,
                    std::optional<Mat>* structured_K) {
  const Mat Mr = basis->transpose() * (A.M * *basis);
  const Mat Kr = *structured_K ? **structured_K : Mat(basis->transpose() * (A.K * *basis));
  const EigenResult er = SmallEigen(0.5 * (Kr + Kr.transpose()), 0.5 * (Mr + Mr.transpose()));
  const int rigid = drop_rigid ? CountRigid(er.eigenvalues) : 0;
  const Mat E = er.eigenvectors.rightCols(er.eigenvalues.size() - rigid);
  *basis = *basis * E;
  *structured_K = (E.transpose() * Kr * E).eval();
}

}  // namespace

/// The Craig–Bampton basis (constraint modes at the interface nodes, fixed-interface normal
/// modes, optionally the axial-load static modes; orthonormalised for that method) into
/// `basis`; `structured_K`: the reduced stiffness where it is known without projection.
void CraigBamptonBasis(const RodSpec& rod, const ReductionSpec& spec, const AssembledRod& A,
                       const std::vector<int>& free, const std::set<int>& fixed, Mat* basis_out,
                       std::optional<Mat>* structured_K) {
  const int ndof = rod.num_dofs(), dpn = rod.dofs_per_node();
  std::vector<int> boundary, interior;
  SplitInterfaceDofs(spec.interface_nodes, dpn, free, fixed, &boundary, &interior);
  const int nb = static_cast<int>(boundary.size());
  const int ni = static_cast<int>(interior.size());
  Require(spec.cutoff_hz > 0.0 || spec.num_modes <= ni, "reduction.modes", spec.num_modes,
          "more modes than the " + std::to_string(ni) +
              " interior dofs of the rod's mesh (rod.elements = " +
              std::to_string(rod.num_elements) + ")");
  const SpMat Kii = SubMatrix(A.K, interior, interior);
  const SpMat Mii = SubMatrix(A.M, interior, interior);
  const SpMat Kib = SubMatrix(A.K, interior, boundary);
  const Mat Psi = ConstraintModes(Kii, Kib, ni, nb);
  EigenResult fixed_interface;
  if (ni > 0) fixed_interface = LowestModes(Kii, Mii, spec.num_modes, spec.cutoff_hz);
  const int k = ni > 0 ? static_cast<int>(fixed_interface.eigenvalues.size()) : 0;
  *basis_out = CraigBamptonColumns(ndof, boundary, interior, Psi, fixed_interface, k);
  *structured_K = StructuredStiffness(A.K, boundary, Kib, Psi, fixed_interface.eigenvalues, ni, k);
  if (spec.axial_load_modes && dpn == 3 && ni > 0 &&
      AppendAxialLoadModes(rod, A, interior, basis_out)) {
    structured_K->reset();  // K_r by projection: the static modes couple to the boundary
  }
  if (spec.method == ReductionMethod::kOrthonormalCraigBampton) {
    Orthonormalise(A, fixed.empty(), basis_out, structured_K);
  }
}

}  // namespace flexrod::fem::reduction_detail
