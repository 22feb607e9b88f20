// SPDX-License-Identifier: GPL-3.0-or-later
// benchmarks/radau_iia.h — the three-stage Radau IIA formula (order 5, L-stable; E. Hairer,
// G. Wanner, Solving Ordinary Differential Equations II, 2nd ed., 1996, §IV.5 and §IV.8 for the
// implementation RADAU5 follows), for the benchmarks that weigh it against IDA's BDF
// (bench_bdf_oscillator, bench_radau_vs_ida). A measuring instrument, not flexrod's integrator:
// no sampling, no projection at restarts, dense Eigen factorisations.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <stdexcept>
#include <vector>

#include "multibody/ida_integrator.h"

namespace flexrod::bench {

/// The tableau: a (the weights b are its last row: stiffly accurate) and the nodes c.
struct RadauTableau {
  Eigen::Matrix3d a;
  Eigen::Vector3d c;
  RadauTableau() {
    const double s6 = std::sqrt(6.0);
    c << (4.0 - s6) / 10.0, (4.0 + s6) / 10.0, 1.0;
    a << (88.0 - 7.0 * s6) / 360.0, (296.0 - 169.0 * s6) / 1800.0, (-2.0 + 3.0 * s6) / 225.0,
        (296.0 + 169.0 * s6) / 1800.0, (88.0 + 7.0 * s6) / 360.0, (-2.0 - 3.0 * s6) / 225.0,
        (16.0 - s6) / 36.0, (16.0 + s6) / 36.0, 1.0 / 9.0;
  }
  /// Largest defect of the conditions that make it Radau IIA of order 5: the weights integrate
  /// ξ^(q−1) exactly for q = 1..5 (Σ bᵢ cᵢ^(q−1) = 1/q), and the stages are of order 3
  /// (Σⱼ aᵢⱼ cⱼ^(q−1) = cᵢ^q / q, q = 1..3).
  double OrderDefect() const {
    double d = 0.0;
    for (int q = 1; q <= 5; ++q) {
      double sum = 0.0;
      for (int i = 0; i < 3; ++i) sum += a(2, i) * std::pow(c(i), q - 1);
      d = std::max(d, std::abs(sum - 1.0 / q));
    }
    for (int q = 1; q <= 3; ++q) {
      for (int i = 0; i < 3; ++i) {
        double sum = 0.0;
        for (int j = 0; j < 3; ++j) sum += a(i, j) * std::pow(c(j), q - 1);
        d = std::max(d, std::abs(sum - std::pow(c(i), q) / q));
      }
    }
    return d;
  }
};

struct RadauStats {
  long steps{0}, rejected{0}, newton_failures{0}, residuals{0}, newton_iterations{0}, jacobians{0},
      factorisations{0}, events{0};
};

/// Radau IIA on a DAE F(t, y, ẏ) = 0 given as a multibody::DaeSystem, as RADAU5 does it for
/// M ẏ = f (F_ẏ = M, F_y = −J):
/// - stage increments Z_i = Y_i − y_n, stage rates Y'_i = (1/h) Σ_k (A⁻¹)_ik Z_k;
/// - simplified Newton on F(t_n + c_i h, y_n + Z_i, Y'_i) = 0 with A⁻¹ = T Λ T⁻¹ (one real
///   eigenvalue γ, a complex pair α ± iβ): one real matrix F_y + (γ/h) F_ẏ and one complex
///   F_y + ((α − iβ)/h) F_ẏ, the Jacobian kept while Newton contracts by 0.1 or better, the
///   factorisation while the step stays within 20 %; starting values from the last step's
///   collocation polynomial;
/// - RADAU5's error estimate (F_y + (γ/h) F_ẏ)⁻¹ F_ẏ (ẏ_n + Σ dᵢ Z_i / h), d = (−(13 + 7√6)/3,
///   (−13 + 7√6)/3, −1/3), in the weighted RMS norm of the system's differential unknowns with
///   its tolerances (DaeSystem's scales and caps), and Gustafsson's predictive step control;
/// - roots located by bisection on the collocation polynomial; the caller's on_root handles
///   them and may ask for a restart (the next step starts from zero stage increments).
class RadauDae {
 public:
  using Vec = Eigen::VectorXd;
  /// Called at a located root with (t, y, ẏ, direction per root function); true: restart.
  std::function<bool(double, const Vec&, const Vec&, const std::vector<int>&)> on_root;
  RadauStats stats;

  RadauDae(multibody::DaeSystem* sys, double rel_tol, double abs_tol)
      : sys_(sys), n_(sys->size()), rel_tol_(rel_tol) {
    const RadauTableau tableau;
    c_ = tableau.c;
    W_ = tableau.a.inverse();
    Eigen::EigenSolver<Eigen::Matrix3d> es(W_);
    int ir = 0, ic = 0;
    for (int i = 0; i < 3; ++i) {
      if (std::abs(es.eigenvalues()(i).imag()) < 1e-12) {
        ir = i;
      } else if (es.eigenvalues()(i).imag() > 0.0) {
        ic = i;
      }
    }
    gamma_ = es.eigenvalues()(ir).real();
    lambda_ = es.eigenvalues()(ic);
    // W T = T Λ with T = [real eigenvector, Re v, Im v]: Λ's 2×2 block [[α, β], [−β, α]] acts on
    // (x₂, x₃) as (α − iβ) on x₂ + i x₃.
    T_.col(0) = es.eigenvectors().col(ir).real();
    T_.col(1) = es.eigenvectors().col(ic).real();
    T_.col(2) = es.eigenvectors().col(ic).imag();
    TI_ = T_.inverse();
    const double s6 = std::sqrt(6.0);
    d_ << -(13.0 + 7.0 * s6) / 3.0, (-13.0 + 7.0 * s6) / 3.0, -1.0 / 3.0;
    id_.resize(n_);
    sys->DifferentialMask(id_.data());
    step_scaled_.resize(n_);
    sys->StepScaledWeightMask(step_scaled_.data());
    atol_.resize(n_);
    sys->AbsoluteToleranceScales(atol_.data());
    atol_ *= abs_tol;
    caps_.resize(n_);
    sys->RelativeToleranceCaps(caps_.data());
  }

  void Initialize(double t, const Vec& y, const Vec& yp, double h0 = 1e-6) {
    t_ = t;
    y_ = y;
    yp_ = yp;
    h_ = h0;
    have_poly_ = false;
    need_jacobian_ = true;
    factored_h_ = -1.0;
    nroots_ = sys_->num_roots();
    g0_.assign(nroots_, 0.0);
    if (nroots_ > 0) sys_->Roots(t_, y_.data(), yp_.data(), g0_.data());
  }

  /// Integrates to t_end exactly (the last step shortened to land on it); a root on the way moves
  /// the state to it and calls on_root, and the integration goes on from there.
  void Advance(double t_end) {
    while (t_ < t_end - 1e-14 * std::max(1.0, std::abs(t_end))) {
      const double proposal = h_;
      double h = std::min(h_, t_end - t_);
      const bool cut = h < proposal;  // shortened to land on t_end
      for (int attempt = 0; !TryStep(h); ++attempt) {
        if (attempt > 60) throw std::runtime_error("Radau IIA: 60 rejected attempts in one step");
        h = h_;
      }
      if (cut) h_ = std::max(h_, proposal);
      if (nroots_ > 0) CheckRoots();
    }
  }

  double t() const { return t_; }
  const Vec& y() const { return y_; }
  const Vec& yp() const { return yp_; }

 private:
  using Cd = std::complex<double>;
  using MatC = Eigen::Matrix<Cd, Eigen::Dynamic, Eigen::Dynamic>;
  using VecC = Eigen::Matrix<Cd, Eigen::Dynamic, 1>;

  Vec Weights(const Vec& y, double h) const {
    Vec w(n_);
    for (int i = 0; i < n_; ++i) {
      const double d = rel_tol_ * std::min(std::abs(y(i)), caps_(i)) + atol_(i);
      w(i) = (step_scaled_(i) != 0.0 ? std::min(h, 1.0) : 1.0) / d;
    }
    return w;
  }
  double Norm(const Vec& v, const Vec& w, bool differential_only) const {
    double s = 0.0;
    int m = 0;
    for (int i = 0; i < n_; ++i) {
      if (differential_only && id_(i) == 0.0) continue;
      s += (v(i) * w(i)) * (v(i) * w(i));
      ++m;
    }
    return std::sqrt(s / std::max(m, 1));
  }

  void Factor(double h) {
    const double cj = gamma_ / h;
    if (need_jacobian_) {
      Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(n_, n_);
      dfdyp_.setZero(n_, n_);
      sys_->JacobianAndDerivativePart(t_, cj, y_.data(), yp_.data(), jac.data(), dfdyp_.data());
      fy_ = jac - cj * dfdyp_;
      ++stats.jacobians;
      need_jacobian_ = false;
    }
    lu_real_.compute(fy_ + cj * dfdyp_);
    lu_complex_.compute(fy_.cast<Cd>() + (std::conj(lambda_) / h) * dfdyp_.cast<Cd>());
    factored_h_ = h;
    ++stats.factorisations;
  }

  /// The last step's collocation polynomial at t_prev_ + s h_prev_ (s = 0: y_prev_, s = 1: y_).
  void Dense(double s, Vec* y, Vec* yp) const {
    const double nodes[4] = {0.0, c_(0), c_(1), c_(2)};
    *y = y_prev_;
    yp->setZero(n_);
    for (int j = 1; j <= 3; ++j) {
      double l = 1.0, dl = 0.0;
      for (int m = 0; m < 4; ++m) {
        if (m == j) continue;
        const double f = (s - nodes[m]) / (nodes[j] - nodes[m]);
        dl = dl * f + l / (nodes[j] - nodes[m]);
        l *= f;
      }
      *y += l * Z_.col(j - 1);
      *yp += (dl / h_prev_) * Z_.col(j - 1);
    }
  }

  /// One attempt at a step of h: true if accepted; either way h_ holds the next proposal.
  bool TryStep(double h) {
    const Vec w = Weights(y_, h);
    if (factored_h_ != h) Factor(h);
    Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(n_, 3);
    if (have_poly_) {  // the last collocation polynomial, extrapolated to the new nodes
      Vec u(n_), up(n_);
      for (int i = 0; i < 3; ++i) {
        Dense(1.0 + c_(i) * h / h_prev_, &u, &up);
        Z.col(i) = u - y_;
      }
    }
    Eigen::MatrixXd F(n_, 3), Yp(n_, 3);
    Vec r(n_);
    double dyno_old = 0.0, theta = 0.0;
    bool converged = false, failed = false;
    constexpr double kNewtonTol = 0.03;  // RADAU5's bound on the Newton error, weighted
    for (int it = 0; it < 7 && !failed; ++it) {
      Yp = Z * W_.transpose() / h;
      for (int i = 0; i < 3 && !failed; ++i) {
        const Vec yi = y_ + Z.col(i);
        const Vec ypi = Yp.col(i);
        failed = sys_->Residual(t_ + c_(i) * h, yi.data(), ypi.data(), r.data()) != 0;
        F.col(i) = r;
        ++stats.residuals;
      }
      if (failed) break;
      ++stats.newton_iterations;
      const Eigen::MatrixXd G = F * TI_.transpose();
      Eigen::MatrixXd dV(n_, 3);
      dV.col(0) = lu_real_.solve(-G.col(0));
      VecC rhs(n_);
      for (int i = 0; i < n_; ++i) rhs(i) = Cd(-G(i, 1), -G(i, 2));
      const VecC x = lu_complex_.solve(rhs);
      dV.col(1) = x.real();
      dV.col(2) = x.imag();
      const Eigen::MatrixXd dZ = dV * T_.transpose();
      Z += dZ;
      double s = 0.0;
      for (int i = 0; i < 3; ++i) s += std::pow(Norm(dZ.col(i), w, false), 2);
      const double dyno = std::sqrt(s / 3.0);
      if (it == 0) {
        converged = dyno <= 1e-3 * kNewtonTol;
      } else {
        theta = dyno / dyno_old;
        if (theta >= 0.99) break;
        converged = theta / (1.0 - theta) * dyno <= kNewtonTol;
      }
      if (converged) break;
      dyno_old = dyno;
    }
    if (!converged) {  // a fresh Jacobian and half the step
      ++stats.newton_failures;
      ++stats.rejected;
      need_jacobian_ = true;
      factored_h_ = -1.0;
      h_ = 0.5 * h;
      last_rejected_ = true;
      return false;
    }
    const Vec e = lu_real_.solve(dfdyp_ * (yp_ + (Z * d_) / h));
    const double err = std::max(Norm(e, Weights(y_ + Z.col(2), h).cwiseMin(w), true), 1e-10);
    double quot = std::clamp(std::pow(err, 0.25) / 0.9, 1.0 / 8.0, 5.0);
    if (err < 1.0 && h_accepted_ > 0.0) {  // Gustafsson's predictive control
      quot = std::max(
          quot, std::clamp((h_accepted_ / h) * std::pow(err * err / err_accepted_, 0.25) / 0.9,
                           1.0 / 8.0, 5.0));
    }
    double h_new = h / quot;
    if (err >= 1.0) {
      ++stats.rejected;
      last_rejected_ = true;
      h_ = h_new;
      return false;
    }
    if (last_rejected_) h_new = std::min(h_new, h);
    last_rejected_ = false;
    h_accepted_ = h;
    err_accepted_ = std::max(err, 1e-2);
    t_prev_ = t_;
    y_prev_ = y_;
    h_prev_ = h;
    Z_ = Z;
    t_ += h;
    y_ += Z.col(2);
    yp_ = Yp.col(2);
    have_poly_ = true;
    ++stats.steps;
    if (theta > 0.1) need_jacobian_ = true;
    h_ = std::abs(h_new / h - 1.0) < 0.2 && !need_jacobian_ ? h : h_new;
    return true;
  }

  /// After an accepted step: the earliest sign change of a root function inside it, located on
  /// the collocation polynomial; there the state moves to the root and on_root is called.
  void CheckRoots() {
    std::vector<double> g1(nroots_), g(nroots_);
    sys_->Roots(t_, y_.data(), yp_.data(), g1.data());
    auto changed = [&](int k, double v) { return v == 0.0 || (g0_[k] > 0.0) != (v > 0.0); };
    Vec yr(n_), ypr(n_);
    double s_root = 2.0;
    for (int k = 0; k < nroots_; ++k) {
      if (g0_[k] == 0.0 || !changed(k, g1[k])) continue;
      double lo = 0.0, hi = 1.0;
      for (int it = 0; it < 60 && hi - lo > 1e-13; ++it) {
        const double mid = 0.5 * (lo + hi);
        Dense(mid, &yr, &ypr);
        sys_->Roots(t_prev_ + mid * h_prev_, yr.data(), ypr.data(), g.data());
        (changed(k, g[k]) ? hi : lo) = mid;
      }
      s_root = std::min(s_root, hi);
    }
    if (s_root > 1.5) {
      g0_ = g1;
      return;
    }
    const double tr = t_prev_ + s_root * h_prev_;
    Dense(s_root, &yr, &ypr);
    sys_->Roots(tr, yr.data(), ypr.data(), g.data());
    std::vector<int> directions(nroots_, 0);
    for (int k = 0; k < nroots_; ++k) {
      if (g0_[k] != 0.0 && changed(k, g[k])) directions[k] = g0_[k] < 0.0 ? 1 : -1;
    }
    ++stats.events;
    t_ = tr;
    y_ = yr;
    yp_ = ypr;
    have_poly_ = false;  // the polynomial no longer ends at y_
    if (on_root && on_root(tr, y_, yp_, directions)) {
      need_jacobian_ = true;
      factored_h_ = -1.0;
      h_accepted_ = 0.0;
    }
    sys_->Roots(t_, y_.data(), yp_.data(), g0_.data());
  }

  multibody::DaeSystem* sys_;
  int n_;
  double rel_tol_;
  Eigen::Vector3d c_, d_;
  Eigen::Matrix3d W_, T_, TI_;
  double gamma_{0.0};
  std::complex<double> lambda_;
  Vec id_, step_scaled_, atol_, caps_;
  double t_{0.0}, h_{1e-6}, t_prev_{0.0}, h_prev_{0.0}, factored_h_{-1.0};
  double h_accepted_{0.0}, err_accepted_{1.0};
  Vec y_, yp_, y_prev_;
  Eigen::MatrixXd Z_;
  bool have_poly_{false}, need_jacobian_{true}, last_rejected_{false};
  Eigen::MatrixXd fy_, dfdyp_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_real_;
  Eigen::PartialPivLU<MatC> lu_complex_;
  int nroots_{0};
  std::vector<double> g0_;
};

}  // namespace flexrod::bench
