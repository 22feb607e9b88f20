// common/eigen.h — Eigen aliases used across flexrod. Only aliases live here.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>

namespace flexrod {
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;
using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;
using Mat2X = Eigen::Matrix<double, 2, Eigen::Dynamic>;
using RowVec = Eigen::RowVectorXd;
using SpMat = Eigen::SparseMatrix<double>;  // column-major, int indices
using Triplet = Eigen::Triplet<double>;
}  // namespace flexrod
