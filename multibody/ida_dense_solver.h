// multibody/ida_dense_solver.h — the dense direct linear solver for IDA: LU with partial
// pivoting, factored in place in a SUNDIALS dense matrix. Internal to multibody/ (used by
// ida_integrator.cc; IntegratorOptions::dense_fill_threshold says when).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

namespace flexrod::multibody {

/// Factors P R A = L U in place (a: n × n, column-major, leading dimension n), R the row
/// equilibration diag(1 / max_j |a_ij|) (stored in row_scale, n), by Gaussian elimination
/// with partial pivoting, right-looking, row swaps applied to whole rows (LAPACK's dgetf2
/// convention: pivot[k] is the row exchanged with row k at step k). The equilibration is
/// KLU's default (scale = 2); without it the iteration matrix's rows, each in its own unit and
/// with entries from 1 to 4e10, choose pivots by unit, not by size (componentwise backward
/// error 1e-8 instead of 5e-16 on the exudyn-match clearance Jacobians). A later column whose
/// entry in the pivot row is zero is not updated, so a sparse iteration matrix costs less than
/// n³/3. The factors are kept as DenseLuSolve takes them: L's 4 × 4 diagonal blocks from
/// column 0 on and U's from column n − 1 back hold their inverses, U's remaining first n mod 4
/// diagonal entries their reciprocals. Returns 0, or k + 1 if row k is zero or column k has no
/// non-zero pivot.
int DenseLuFactor(double* a, int n, int* pivot, double* row_scale);
/// Solves A x = b in place (b in, x out) with the factors of DenseLuFactor.
void DenseLuSolve(const double* lu, int n, const int* pivot, const double* row_scale, double* b);

/// A SUNDIALS direct linear solver (SUNLINEARSOLVER_DIRECT) on the square SUNDenseMatrix A:
/// set-up factors the matrix in place (DenseLuFactor; a zero pivot is SUNLS_LUFACT_FAIL,
/// recoverable), solve applies the factors. It also gives A a zeroing operation that clears
/// its data in one pass (IDA zeroes the matrix before every Jacobian; SUNDIALS' own indexes
/// each entry: 16 700 instructions at n = 41, callgrind; IdaIntegrator, which zeroes the
/// matrix itself only when it evaluates a Jacobian, replaces it by a no-op). In place of
/// SUNLinSol_Dense, whose row-by-row substitutions cost about fifteen times the instructions at
/// the mechanism's sizes. NumericalError if A is not a square dense matrix or SUNDIALS cannot
/// allocate the solver.
SUNLinearSolver MakeDenseLuSolver(SUNMatrix A, SUNContext ctx);

}  // namespace flexrod::multibody
