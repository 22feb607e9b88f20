// multibody/flexible_body.cc — a flexible body from a reduced rod (MechanismBuilder::
// AddFlexibleBody): the rod's checks, its second-order strain data, its damping matrix from the
// damping specification (DampingSpec) and its own modal frequencies.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "common/error.h"
#include "multibody/mechanism.h"

namespace flexrod::multibody {
namespace {

bool AllFinite(const Mat& m) { return m.allFinite(); }

void MarkMask(const Mat& m, std::vector<std::vector<bool>>* mask) {
  for (int c = 0; c < m.cols(); ++c)
    for (int r = 0; r < m.rows(); ++r)
      if (m(r, c) != 0.0) (*mask)[r][c] = true;
}

/// The reduced rod of a flexible body: finite inertia and stiffness of matching sizes, a
/// positive mass, a positive definite M_ff, K_G on the transverse dofs, a valid damping.
void CheckFlexibleBodySpec(const FlexibleBodySpec& spec) {
  const std::string key = "body[" + spec.name + "]";
  if (!spec.rod) throw InputError(key + ".rod", "null", "a flexible body needs a reduced rod");
  const fem::ReducedRod& rod = *spec.rod;
  const fem::PlanarInertia& in = rod.inertia;
  const int n = rod.num_coordinates();
  auto check_shape = [&](const Mat& m, int r, int c, const std::string& what) {
    if (m.rows() != r || m.cols() != c || !AllFinite(m)) {
      throw InputError(
          key + ".rod." + what, std::to_string(m.rows()) + "x" + std::to_string(m.cols()),
          "must be a finite " + std::to_string(r) + "x" + std::to_string(c) + " matrix");
    }
  };
  check_shape(rod.K, n, n, "K");
  check_shape(in.Mff, n, n, "inertia.Mff");
  check_shape(in.Stilde, n, n, "inertia.Stilde");
  check_shape(in.S, 2, n, "inertia.S");
  check_shape(in.I1, n, 1, "inertia.I1");
  check_shape(in.Ibar, n, 1, "inertia.Ibar");
  RequirePositive(key + ".rod.inertia.mass", in.mass);
  RequirePositive(key + ".rod.inertia.J0", in.J0);
  if (spec.geometric_stiffening) {
    if (rod.rod.dim != fem::MeshDim::kPlanar) {
      throw InputError(key + ".geometric_stiffening", "true", "needs a planar rod");
    }
    RequirePositive(key + ".rod.element_axial_stiffness", rod.element_axial_stiffness);
    check_shape(rod.basis, rod.rod.num_dofs(), n, "basis");
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) {
        if ((i % 3 == 0 || j % 3 == 0) && rod.element_Kg(i, j) != 0.0) {
          throw InputError(key + ".rod.element_Kg",
                           "entry (" + std::to_string(i) + ", " + std::to_string(j) + ") non-zero",
                           "K_G acts on the transverse dofs (v, θ) only, not on u");
        }
      }
    }
  }
  if (n > 0) {
    Eigen::LLT<Mat> llt(0.5 * (in.Mff + in.Mff.transpose()));
    if (llt.info() != Eigen::Success) {
      throw InputError(key + ".rod.inertia.Mff", "not positive definite",
                       "the elastic mass matrix must be symmetric positive definite");
    }
  }
  spec.damping.Validate(key + ".damping", n);
}

/// The second-order axial strain's data (FlexibleBodySpec::geometric_stiffening).
void SetSecondOrderStrain(const fem::ReducedRod& rod, FlexibleBodySpec::StrainKernel kernel,
                          Body* b) {
  const int n = rod.num_coordinates();
  // Element e joins nodes e and e + 1 (dofs u, v, θ each): its elongation is a difference of
  // u rows, its K_G acts on the (v, θ) rows of its two nodes, shared with its neighbours.
  const int ne = rod.rod.num_elements;
  constexpr std::array<int, 4> kTransverse = {1, 2, 4, 5};
  b->num_strain_elements = ne;
  b->transverse_rows.resize(2 * (ne + 1), n);
  Mat E(ne, n);
  for (int e = 0; e < ne; ++e) {
    const auto rows = rod.ElementBasisRows(e);
    E.row(e) = rows.row(3) - rows.row(0);
    b->transverse_rows.middleRows(2 * e, 2) = rows.middleRows(1, 2);
    if (e == ne - 1) b->transverse_rows.middleRows(2 * e + 2, 2) = rows.middleRows(4, 2);
  }
  b->element_axial_stiffness = rod.element_axial_stiffness;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      b->element_Kg(i, j) = 0.5 * (rod.element_Kg(kTransverse[i], kTransverse[j]) +
                                   rod.element_Kg(kTransverse[j], kTransverse[i]));
    }
  }
  const fem::ElongationSpace space = rod.Elongation();
  const Mat& V = space.basis;
  const int r = static_cast<int>(V.cols());
  b->element_strain_basis = V;
  b->strain_elongation = V.transpose() * E;
  b->strain_to_q = space.shortening_to_q * V;
  Mat strain_tensors = Mat::Zero(static_cast<Eigen::Index>(n) * r, n);
  for (int e = 0; e < ne; ++e) {
    const auto Te = b->transverse_rows.middleRows<4>(2 * e);
    const Mat G = Te.transpose() * b->element_Kg * Te;
    for (int k = 0; k < r; ++k) strain_tensors.middleRows(k * n, n) += V(e, k) * G;
  }
  b->strain_tensors = ProductMatrix(std::move(strain_tensors));
  using Kernel = FlexibleBodySpec::StrainKernel;
  b->modal_strain_kernel =
      kernel == Kernel::kModal || (kernel == Kernel::kAuto && r * n <= 8 * (ne + 1));
}

/// Body::q_products and qd_products from S̄, M_ff, S̃, K, W and D.
void StackModalProducts(Body* b) {
  const int n = b->num_modes;
  if (n == 0) return;  // UpdateBody has no modal products to take
  const Eigen::Index r = b->geometric_stiffening ? b->strain_elongation.rows() : 0;
  Mat q_products(2 + 3 * n + r, n);
  q_products.topRows(2 + 3 * n) << b->Sbar, b->Mff, b->Stilde, b->K;
  if (r > 0) q_products.bottomRows(r) = b->strain_elongation;
  b->q_products = ProductMatrix(std::move(q_products));
  b->mass_ff = ProductMatrix(b->Mff);
  Mat qd_products(b->strain_damping ? n : 2 * n, n);
  if (b->strain_damping) {
    qd_products = b->Stilde;
  } else {
    qd_products << b->Stilde, b->D;
  }
  b->qd_products = ProductMatrix(std::move(qd_products));
}

/// D from the damping specification, and the body's own modal frequencies and damping ratios
/// (eigenproblem K φ = ω² M_ff φ of the reduced body).
void SetDamping(const FlexibleBodySpec& spec, Body* b) {
  const int n = b->num_modes;
  b->D = Mat::Zero(n, n);
  b->modal_frequencies_hz.resize(0);
  b->modal_damping_ratios.resize(0);
  if (n > 0) {
    Eigen::GeneralizedSelfAdjointEigenSolver<Mat> ges(b->K, b->Mff,
                                                      Eigen::ComputeEigenvectors | Eigen::Ax_lBx);
    if (ges.info() != Eigen::Success) {
      throw NumericalError("body " + spec.name + ": eigenproblem of (K, M_ff) did not converge");
    }
    const Vec omega = ges.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    b->modal_frequencies_hz = omega / (2.0 * std::numbers::pi);
    if (spec.damping.kind == DampingKind::kModalRatio ||
        spec.damping.kind == DampingKind::kFrequencyBand) {
      Vec zeta(n);
      for (int i = 0; i < n; ++i) {
        if (spec.damping.kind == DampingKind::kModalRatio) {
          zeta(i) = spec.damping.modal_ratios.size() == 1 ? spec.damping.modal_ratios[0]
                                                          : spec.damping.modal_ratios[i];
        } else {
          zeta(i) = spec.damping.BandRatio(b->modal_frequencies_hz(i));
        }
      }
      b->modal_damping_ratios = zeta;
      const Mat& phi = ges.eigenvectors();  // φᵀ M_ff φ = I
      const Mat mphi = b->Mff * phi;
      b->D = mphi * (2.0 * zeta.cwiseProduct(omega)).asDiagonal() * mphi.transpose();
      b->D = 0.5 * (b->D + b->D.transpose());
    } else if (spec.damping.kind == DampingKind::kRayleigh) {
      b->D = spec.damping.rayleigh_alpha * b->Mff + spec.damping.rayleigh_beta * b->K;
    } else if (spec.damping.kind == DampingKind::kMatrix) {
      b->D = 0.5 * (spec.damping.matrix + spec.damping.matrix.transpose());
    }
  }
}

}  // namespace

DampingSpec DampingSpec::ModalRatio(std::vector<double> ratios) {
  DampingSpec d;
  d.kind = DampingKind::kModalRatio;
  d.modal_ratios = std::move(ratios);
  return d;
}

DampingSpec DampingSpec::FrequencyBand() {
  DampingSpec d;
  d.kind = DampingKind::kFrequencyBand;
  return d;
}

DampingSpec DampingSpec::Rayleigh(double alpha, double beta) {
  DampingSpec d;
  d.kind = DampingKind::kRayleigh;
  d.rayleigh_alpha = alpha;
  d.rayleigh_beta = beta;
  return d;
}

DampingSpec DampingSpec::Matrix(Mat d) {
  DampingSpec spec;
  spec.kind = DampingKind::kMatrix;
  spec.matrix = std::move(d);
  return spec;
}

void DampingSpec::Validate(const std::string& key, int num_modes) const {
  switch (kind) {
    case DampingKind::kNone:
      break;
    case DampingKind::kModalRatio: {
      const int n = static_cast<int>(modal_ratios.size());
      if (!(n == 1 || n == num_modes)) {
        throw InputError(key + ".modal_ratios", std::to_string(n) + " values",
                         "must give one ratio or one per mode (" + std::to_string(num_modes) + ")");
      }
      for (int i = 0; i < n; ++i) {
        RequireNonNegative(key + ".modal_ratios[" + std::to_string(i) + "]", modal_ratios[i]);
      }
      break;
    }
    case DampingKind::kFrequencyBand:
      RequirePositive(key + ".band_low_limit_hz", band_low_limit_hz);
      // The transitions (an octave about each limit, BandRatio) must not overlap, and log ζ
      // must exist.
      Require(band_high_limit_hz >= 2.0 * band_low_limit_hz, key + ".band_high_limit_hz",
              band_high_limit_hz, "must be >= 2 band_low_limit_hz");
      RequirePositive(key + ".band_low_ratio", band_low_ratio);
      RequirePositive(key + ".band_mid_ratio", band_mid_ratio);
      RequirePositive(key + ".band_high_ratio", band_high_ratio);
      break;
    case DampingKind::kRayleigh:
      RequireNonNegative(key + ".rayleigh_alpha", rayleigh_alpha);
      RequireNonNegative(key + ".rayleigh_beta", rayleigh_beta);
      break;
    case DampingKind::kMatrix: {
      const std::string mkey = key + ".matrix";
      if (matrix.rows() != num_modes || matrix.cols() != num_modes) {
        throw InputError(mkey, std::to_string(matrix.rows()) + "x" + std::to_string(matrix.cols()),
                         "must be n x n with n = " + std::to_string(num_modes) +
                             " (the body's elastic coordinates)");
      }
      if (!matrix.allFinite()) throw InputError(mkey, "non-finite entries", "must be finite");
      if (num_modes == 0) break;
      // Relative tolerances: symmetric to round-off; eigenvalues >= 0 to round-off of the
      // largest (a matrix built as Q⁻ᵀ diag(2ζω) Q⁻¹ with some ζ = 0 has zero eigenvalues).
      constexpr double kSymmetryTol = 1e-12;
      constexpr double kDefinitenessTol = 1e-10;
      const double scale = matrix.cwiseAbs().maxCoeff();
      const double asym = (matrix - matrix.transpose()).cwiseAbs().maxCoeff();
      if (asym > kSymmetryTol * scale) {
        throw InputError(
            mkey,
            "max |D - D^T| = " + FormatValue(asym) + " (max |D| = " + FormatValue(scale) + ")",
            "must be symmetric (to 1e-12 of its largest entry)");
      }
      const Vec eig = Eigen::SelfAdjointEigenSolver<Mat>(0.5 * (matrix + matrix.transpose()),
                                                         Eigen::EigenvaluesOnly)
                          .eigenvalues();
      if (eig(0) < -kDefinitenessTol * std::max(eig.cwiseAbs().maxCoeff(), scale)) {
        throw InputError(mkey, "smallest eigenvalue " + FormatValue(eig(0)),
                         "must be positive semi-definite (damping must not add energy)");
      }
      break;
    }
  }
}

BodyId MechanismBuilder::AddFlexibleBody(const FlexibleBodySpec& spec) {
  CheckNotBuilt();
  CheckName("body", spec.name);
  CheckFlexibleBodySpec(spec);
  const fem::ReducedRod& rod = *spec.rod;
  const fem::PlanarInertia& in = rod.inertia;
  const int n = rod.num_coordinates();
  Body b;
  b.name = spec.name;
  b.flexible = true;
  b.num_modes = n;
  b.mass = in.mass;
  b.S0 = in.S0;
  b.Sbar = in.S;
  b.J0 = in.J0;
  b.I1 = in.I1;
  b.Ibar = in.Ibar;
  b.Mff = 0.5 * (in.Mff + in.Mff.transpose());
  b.Stilde = 0.5 * (in.Stilde - in.Stilde.transpose());
  b.K = 0.5 * (rod.K + rod.K.transpose());
  b.geometric_stiffening = spec.geometric_stiffening && n > 0;
  b.element_Kg.setZero();
  if (b.geometric_stiffening) SetSecondOrderStrain(rod, spec.strain_kernel, &b);
  b.damping = spec.damping;
  b.rod = spec.rod;

  SetDamping(spec, &b);
  b.strain_damping = b.geometric_stiffening && b.element_strain_basis.cols() > 0 &&
                     b.D.size() > 0 && b.D.cwiseAbs().maxCoeff() > 0.0;
  StackModalProducts(&b);
  b.qq_mask.assign(n, std::vector<bool>(n, false));
  MarkMask(b.Mff, &b.qq_mask);
  MarkMask(b.Stilde, &b.qq_mask);
  MarkMask(b.K, &b.qq_mask);
  MarkMask(b.D, &b.qq_mask);
  if (b.geometric_stiffening) b.qq_mask.assign(n, std::vector<bool>(n, true));
  m_.bodies_.push_back(std::move(b));
  return BodyId{static_cast<int>(m_.bodies_.size()) - 1};
}

}  // namespace flexrod::multibody
