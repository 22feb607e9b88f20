// SPDX-License-Identifier: GPL-3.0-or-later
// benchmarks/bdf_stability.h — where the constant-step BDF-k formulas (k = 1..5) keep the root
// condition on the test equation ẏ = λ y, for the benchmarks that ask whether IDA's steps are
// held by stability or by accuracy (bench_bdf_oscillator, bench_radau_vs_ida).
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <utility>

namespace flexrod::bench {

/// Whether BDF-k applied to ẏ = λ y at z = h λ keeps the root condition: every root of
/// ρ(ξ) − z ξᵏ inside the unit circle, ρ(ξ) = Σⱼ₌₁ᵏ (1/j) ξ^(k−j) (ξ − 1)ʲ (BDF-k in backward
/// differences).
inline bool BdfStable(int k, std::complex<double> z) {
  Eigen::VectorXcd c = Eigen::VectorXcd::Zero(k + 1);  // coefficients, ξ⁰ first
  for (int j = 1; j <= k; ++j) {
    double binomial = 1.0;  // C(j, i)
    for (int i = 0; i <= j; ++i) {
      c(k - j + i) += binomial * ((j - i) % 2 ? -1.0 : 1.0) / j;
      binomial = binomial * (j - i) / (i + 1);
    }
  }
  c(k) -= z;
  Eigen::MatrixXcd companion = Eigen::MatrixXcd::Zero(k, k);
  for (int i = 0; i < k; ++i) companion(0, i) = -c(k - 1 - i) / c(k);
  for (int i = 1; i < k; ++i) companion(i, i - 1) = 1.0;
  const Eigen::VectorXcd roots =
      Eigen::ComplexEigenSolver<Eigen::MatrixXcd>(companion).eigenvalues();
  return roots.cwiseAbs().maxCoeff() <= 1.0 + 1e-9;
}

/// The mode λ = ω (−ζ + i √(1 − ζ²)) of damping ratio ζ in [0, 1].
inline std::complex<double> ModeDirection(double zeta) {
  return {-zeta, std::sqrt(std::max(0.0, 1.0 - zeta * zeta))};
}

/// Smallest h ω in (0, 4] at which BDF-k is unstable on a mode of damping ratio ζ, in steps of
/// 0.01; 0 if never.
inline double BdfInstabilityOnset(int k, double zeta) {
  for (double hw = 0.01; hw <= 4.0; hw += 0.01) {
    if (!BdfStable(k, hw * ModeDirection(zeta))) return hw;
  }
  return 0.0;
}

/// The band of h ω over which BDF-k is unstable on a mode of damping ratio ζ, {first, last}
/// unstable h ω of a scan from 0.005 to 20 in steps of 1 %; {0, 0} if none. BDF-k is stable
/// again beyond it: the roots of ρ(ξ) − z ξᵏ tend to 0 as |z| grows.
inline std::pair<double, double> BdfInstabilityBand(int k, double zeta) {
  std::pair<double, double> band{0.0, 0.0};
  for (double hw = 0.005; hw <= 20.0; hw *= 1.01) {
    if (BdfStable(k, hw * ModeDirection(zeta))) continue;
    if (band.first == 0.0) band.first = hw;
    band.second = hw;
  }
  return band;
}

}  // namespace flexrod::bench
