// multibody/mechanism_modes.cc — linearised modes of the assembled mechanism and the body
// damping matrix that gives them prescribed ratios.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/mechanism_modes.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <numbers>
#include <string>

#include "common/error.h"
#include "multibody/corotated_damping.h"
#include "multibody/dae.h"
#include "multibody/run_data.h"

namespace flexrod::multibody {
namespace {

/// Singular values below this fraction of the largest count as zero: the rank of the stacked
/// constraint matrix (its entries are O(1)–O(lengths) in SI; round-off is ~1e-16 of them).
constexpr double kRankTolerance = 1e-10;
/// Smallest accepted reciprocal condition number of the modes' q rows Q (D is built from Q⁻¹;
/// its relative error is about cond(Q)·ε).
constexpr double kMinReciprocalCondition = 1e-10;

}  // namespace

MechanismModes CalcMechanismModes(const Mechanism& m, const Vec& p, const std::vector<int>& held,
                                  double t) {
  const int np = m.num_coordinates(), nc = m.num_constraints();
  if (p.size() != np) {
    throw InputError("mechanism_modes.p", std::to_string(p.size()) + " values",
                     "must have one value per coordinate (" + std::to_string(np) + ")");
  }
  if (!p.allFinite()) throw InputError("mechanism_modes.p", "non-finite", "must be finite");
  for (const int i : held) {
    if (i < 0 || i >= np) {
      throw InputError("mechanism_modes.held", std::to_string(i),
                       "must index a coordinate (0.." + std::to_string(np - 1) + ")");
    }
  }

  RunData data(m);
  Mat M;
  CalcMassMatrix(m, &data, p, &M);
  Mat G;
  Vec g_t;
  CalcConstraintJacobian(m, &data, t, p, &G, &g_t);
  Vec y = Vec::Zero(m.size());
  y.segment(m.p_offset(), np) = p;
  const Vec yp = Vec::Zero(m.size());
  const Mat jac = CalcJacobian(m, &data, t, 0.0, y, yp);
  const Mat K = jac.block(m.v_offset(), m.p_offset(), np, np);  // ∂F2/∂p

  // Tangent space: null space of [G; e_iᵀ (held)].
  const int nh = static_cast<int>(held.size());
  Mat C = Mat::Zero(nc + nh, np);
  C.topRows(nc) = G;
  for (int k = 0; k < nh; ++k) C(nc + k, held[k]) = 1.0;
  Mat N;
  if (C.rows() == 0) {
    N = Mat::Identity(np, np);
  } else {
    Eigen::JacobiSVD<Mat> svd(C, Eigen::ComputeFullV);
    const Vec& sigma = svd.singularValues();
    int rank = 0;
    while (rank < sigma.size() && sigma(rank) > kRankTolerance * sigma(0)) ++rank;
    N = svd.matrixV().rightCols(np - rank);
  }
  MechanismModes out;
  const int dof = static_cast<int>(N.cols());
  out.frequencies_hz = Vec::Zero(dof);
  out.shapes = Mat::Zero(np, dof);
  if (dof == 0) return out;

  const Mat Mp = N.transpose() * M * N;
  Mat Kp = N.transpose() * K * N;
  Kp = (0.5 * (Kp + Kp.transpose())).eval();
  if (Eigen::LLT<Mat>(0.5 * (Mp + Mp.transpose())).info() != Eigen::Success) {
    throw NumericalError(
        "mechanism modes: the mass matrix on the constraints' tangent space is not positive "
        "definite (a free coordinate without inertia; hold it or give it mass)");
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Mat> ges(Kp, 0.5 * (Mp + Mp.transpose()),
                                                    Eigen::ComputeEigenvectors | Eigen::Ax_lBx);
  if (ges.info() != Eigen::Success) {
    throw NumericalError(
        "mechanism modes: the eigensolver of the projected (K, M) did not converge");
  }
  out.frequencies_hz = ges.eigenvalues().cwiseMax(0.0).cwiseSqrt() / (2.0 * std::numbers::pi);
  out.shapes = N * ges.eigenvectors();  // Xᵀ Mp X = I ⇒ Ψᵀ M Ψ = I
  // Sign convention (reproducible shapes): the largest entry of each mode is positive.
  for (int i = 0; i < dof; ++i) {
    Eigen::Index k = 0;
    out.shapes.col(i).cwiseAbs().maxCoeff(&k);
    if (out.shapes(k, i) < 0.0) out.shapes.col(i) *= -1.0;
  }
  return out;
}

namespace {

/// Q⁻¹ for the modes' parts Q (n × n) that parametrise `what`, after checking the modes, the
/// ratios and Q's condition.
Mat InverseModalParts(const Mechanism& m, const MechanismModes& modes, const Mat& Q,
                      const Vec& zeta, const std::string& what) {
  const int n = static_cast<int>(Q.rows());
  if (modes.shapes.rows() != m.num_coordinates() ||
      modes.shapes.cols() != modes.frequencies_hz.size()) {
    throw InputError(
        "mechanism_modes.shapes",
        std::to_string(modes.shapes.rows()) + "x" + std::to_string(modes.shapes.cols()),
        "must be np x (number of frequencies) of this mechanism");
  }
  if (modes.num_modes() != n) {
    throw NumericalError("modal damping of " + what + ": the mechanism has " +
                         std::to_string(modes.num_modes()) + " modes but " + what + " has " +
                         std::to_string(n) +
                         " deformation coordinates; damping on them can set one ratio per "
                         "coordinate only (hold the mechanism's other degrees of freedom)");
  }
  if (zeta.size() != n) {
    throw InputError("zeta", std::to_string(zeta.size()) + " values",
                     "must give one ratio per mechanism mode (" + std::to_string(n) + ")");
  }
  for (int i = 0; i < n; ++i) {
    Require(std::isfinite(zeta(i)) && zeta(i) >= 0.0, "zeta[" + std::to_string(i) + "]", zeta(i),
            "must be >= 0");
  }
  const Vec sigma = Eigen::JacobiSVD<Mat>(Q).singularValues();
  if (!(sigma(n - 1) > kMinReciprocalCondition * sigma(0))) {
    throw NumericalError("modal damping of " + what +
                         ": the mechanism modes' deformation parts Q are singular (1/cond = " +
                         FormatValue(sigma(0) > 0.0 ? sigma(n - 1) / sigma(0) : 0.0) +
                         "): some mode does not deform it, so damping on its deformation cannot "
                         "damp that mode");
  }
  return Q.fullPivLu().inverse();
}

}  // namespace

Mat ModalDampingForBody(const Mechanism& m, const MechanismModes& modes, BodyId body,
                        const Vec& zeta) {
  const Body& b = m.body(body);
  const int n = b.num_modes;
  if (!b.flexible || n == 0) {
    throw InputError("body[" + b.name + "]", "rigid or without elastic coordinates",
                     "modal damping needs a flexible body");
  }
  const Mat Q = modes.shapes.middleRows(b.coordinate(kFirstMode), n);
  const Mat Qinv = InverseModalParts(m, modes, Q, zeta, "body " + b.name);
  const Vec two_zeta_omega = 2.0 * zeta.cwiseProduct(2.0 * std::numbers::pi * modes.frequencies_hz);
  const Mat D = Qinv.transpose() * two_zeta_omega.asDiagonal() * Qinv;
  return 0.5 * (D + D.transpose());
}

CorotatedModalFit FitCorotatedModalDamping(const Mechanism& m, const MechanismModes& modes,
                                           const std::vector<BodyId>& bodies, const Vec& p,
                                           const Vec& zeta, int exact_modes) {
  if (modes.shapes.rows() != m.num_coordinates()) {
    throw InputError("mechanism_modes.shapes", std::to_string(modes.shapes.rows()) + " rows",
                     "must be np of this mechanism");
  }
  const Mat Q = CorotatedRateMap(m, bodies, p) * modes.shapes;
  if (Q.rows() != Q.cols()) {
    throw NumericalError("modal damping of the chain of " + std::to_string(bodies.size()) +
                         " bodies: the mechanism has " + std::to_string(modes.num_modes()) +
                         " modes but the chain " + std::to_string(Q.rows()) +
                         " deformation coordinates (hold the mechanism's other degrees of "
                         "freedom)");
  }
  const Mat Qinv = InverseModalParts(m, modes, Q, zeta, "the chain");
  const int n = static_cast<int>(Q.rows());
  Require(exact_modes >= 1, "exact_modes", exact_modes, "must be >= 1");
  const int r = std::min(exact_modes, n);
  const Vec omega = 2.0 * std::numbers::pi * modes.frequencies_hz;
  CorotatedModalFit out;
  out.beta = r < n ? 2.0 * zeta(r) / omega(r) : 0.0;
  out.modes = Qinv.topRows(r).transpose();
  out.coefficients = 2.0 * zeta.head(r).cwiseProduct(omega.head(r)) -
                     out.beta * omega.head(r).cwiseProduct(omega.head(r));
  out.ratios = zeta;
  out.ratios.tail(n - r) = 0.5 * out.beta * omega.tail(n - r);
  return out;
}

}  // namespace flexrod::multibody
