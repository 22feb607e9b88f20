// fem/reduction_detail.h — what the reductions of fem/reduced_rod.cc and the Craig–Bampton basis
// of fem/craig_bampton.cc share. Internal to fem/.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <optional>
#include <set>
#include <vector>

#include "common/eigen.h"
#include "fem/eigensolver.h"
#include "fem/reduced_rod.h"
#include "fem/rod_mesh.h"

namespace flexrod::fem::reduction_detail {

/// Above this many dofs ARPACK is used instead of a dense eigen-solution.
inline constexpr int kDenseEigenLimit = 600;

/// The `count` lowest modes of (K, M), or all below cutoff_hz if it is > 0; ascending.
EigenResult LowestModes(const SpMat& K, const SpMat& M, int count, double cutoff_hz);
/// The sub-block A(rows, cols) of a sparse matrix.
SpMat SubMatrix(const SpMat& A, const std::vector<int>& rows, const std::vector<int>& cols);
/// Dense generalised eigen-decomposition of a small reduced pair, ascending.
EigenResult SmallEigen(const Mat& K, const Mat& M);
/// The number of rigid-body (near-zero) eigenvalues.
int CountRigid(const Vec& eigenvalues);

/// The Craig–Bampton basis (constraint modes at the interface nodes, fixed-interface normal
/// modes, optionally the axial-load static modes; orthonormalised for that method) into
/// `basis`; `structured_K`: the reduced stiffness where it is known without projection.
void CraigBamptonBasis(const RodSpec& rod, const ReductionSpec& spec, const AssembledRod& A,
                       const std::vector<int>& free, const std::set<int>& fixed, Mat* basis,
                       std::optional<Mat>* structured_K);

}  // namespace flexrod::fem::reduction_detail
