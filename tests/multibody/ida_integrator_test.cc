// tests/multibody/ida_integrator_test.cc — the IDA wrapper on a generic DAE, without any
// mechanism: a harmonic oscillator written as an index-1 DAE (x' = v, v' = a, 0 = a + ω²x)
// follows cos ωt; its root function locates x = 0 at (k + ½)π/ω; the cached step polynomial
// reproduces IDAGetDky; re-initialisation keeps the statistics; the sparse (KLU) path gives
// the dense result; a reused Jacobian keeps a pendulum on its elliptic-integral period; a cap on
// the magnitude the relative tolerance applies to resolves a small motion at a large offset; bad
// options are rejected. SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/ida_integrator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

#include "common/error.h"

namespace flexrod::multibody {
namespace {

constexpr double kOmega = 3.0;  // [rad/s]

// y = [x, v, a]; F = [x' − v, v' − a, a + ω² x]; root g = x of the first copy. `copies`
// independent copies side by side (y = [x₁, v₁, a₁, x₂, ...]) make a larger system. As a
// pendulum, x is the angle θ and F₃ = a + ω² sin θ: its Jacobian changes with the state.
class Oscillator final : public DaeSystem {
 public:
  explicit Oscillator(int copies = 1, bool pendulum = false)
      : copies_(copies), pendulum_(pendulum) {}
  int size() const override { return 3 * copies_; }
  int num_roots() const override { return 1; }
  void DifferentialMask(double* id) const override {
    for (int m = 0; m < copies_; ++m) {
      id[3 * m + 0] = 1.0;
      id[3 * m + 1] = 1.0;
      id[3 * m + 2] = 0.0;
    }
  }
  int Residual(double, const double* y, const double* yp, double* r) override {
    ++residuals;
    for (int o = 0; o < 3 * copies_; o += 3) {
      r[o + 0] = yp[o + 0] - y[o + 1];
      r[o + 1] = yp[o + 1] - y[o + 2];
      r[o + 2] = y[o + 2] + kOmega * kOmega * (pendulum_ ? std::sin(y[o + 0]) : y[o + 0]);
    }
    return 0;
  }
  int Jacobian(double, double cj, const double* y, const double*, double* J) override {
    ++evaluations;
    // Column-major n×n: J(r, c) = J[c*n + r].
    const int n = size();
    for (int o = 0; o < n; o += 3) {
      J[(o + 0) * n + o + 0] = cj;
      J[(o + 1) * n + o + 0] = -1.0;
      J[(o + 1) * n + o + 1] = cj;
      J[(o + 2) * n + o + 1] = -1.0;
      J[(o + 0) * n + o + 2] = kOmega * kOmega * (pendulum_ ? std::cos(y[o + 0]) : 1.0);
      J[(o + 2) * n + o + 2] = 1.0;
    }
    return 0;
  }
  SparsityPattern JacobianPattern() const override {
    SparsityPattern p;
    p.size = size();
    p.col_ptr = {0};
    for (int o = 0; o < size(); o += 3) {
      for (int c = 0; c < 3; ++c) p.col_ptr.push_back(p.col_ptr.back() + 2);
      for (int r : {0, 2, 0, 1, 1, 2}) p.row_index.push_back(o + r);
    }
    return p;
  }
  int Roots(double, const double* y, const double*, double* g) override {
    g[0] = y[0];
    return 0;
  }
  long residuals{0};
  long evaluations{0};  // calls of Jacobian (the default JacobianAndDerivativePart makes two)

 private:
  int copies_;
  bool pendulum_;
};

// x' = A ω cos ωt, x(0) = X: x = X + A sin ωt, a small motion at a large offset (a pin moving
// inside a bush far from the origin). `x_cap` caps |x| for the relative tolerance.
class OffsetMotion final : public DaeSystem {
 public:
  static constexpr double kAmplitude = 1e-3, kOffset = 1.0;
  int size() const override { return 1; }
  void DifferentialMask(double* id) const override { id[0] = 1.0; }
  void RelativeToleranceCaps(double* caps) const override { caps[0] = x_cap; }
  int Residual(double t, const double*, const double* yp, double* r) override {
    r[0] = yp[0] - kAmplitude * kOmega * std::cos(kOmega * t);
    return 0;
  }
  int Jacobian(double, double cj, const double*, const double*, double* J) override {
    J[0] = cj;
    return 0;
  }
  double x_cap{std::numeric_limits<double>::infinity()};
};

IntegratorOptions Tight(LinearSolverKind kind = LinearSolverKind::kDense) {
  IntegratorOptions o;
  o.rel_tol = 1e-10;
  o.abs_tol = 1e-12;
  o.linear_solver = kind;
  return o;
}

// Consistent start of x = cos ωt at t = 0: (x, v, a) = (1, 0, −ω²) and their rates.
void StartOnCosine(IdaIntegrator* ida, int copies = 1) {
  std::vector<double> y0, yp0;
  for (int m = 0; m < copies; ++m) {
    y0.insert(y0.end(), {1.0, 0.0, -kOmega * kOmega});
    yp0.insert(yp0.end(), {0.0, -kOmega * kOmega, 0.0});
  }
  ida->Initialize(0.0, y0.data(), yp0.data());
}

// Integrates to t_end, returning the max |x − cos ωt| over steps and the root times.
double RunOscillator(LinearSolverKind kind, double t_end, std::vector<double>* roots,
                     IntegratorStats* stats, bool time_calls = false) {
  Oscillator dae;
  IntegratorOptions options = Tight(kind);
  options.time_calls = time_calls;
  IdaIntegrator ida(&dae, options);
  EXPECT_EQ(ida.linear_solver(), kind);
  StartOnCosine(&ida);
  ida.SetStopTime(t_end);
  double worst = 0.0;
  for (;;) {
    const StepResult r = ida.Step(t_end);
    worst = std::max(worst, std::abs(ida.y()[0] - std::cos(kOmega * r.t)));
    if (r.outcome == StepOutcome::kRoot) roots->push_back(r.t);
    if (r.outcome == StepOutcome::kStopTime) break;
  }
  *stats = ida.stats();
  return worst;
}

TEST(IdaIntegrator, HarmonicOscillatorDaeFollowsCosine) {
  std::vector<double> roots;
  IntegratorStats stats;
  const double err = RunOscillator(LinearSolverKind::kDense, 5.0, &roots, &stats);
  EXPECT_LE(err, 1e-7);
  EXPECT_GT(stats.steps, 10);
  EXPECT_GT(stats.residual_evaluations, stats.steps);
}

TEST(IdaIntegrator, TimesItsCallsOnlyWhenAsked) {
  std::vector<double> roots;
  IntegratorStats plain, timed;
  RunOscillator(LinearSolverKind::kDense, 1.0, &roots, &plain);
  EXPECT_EQ(plain.residual_seconds, 0.0);
  EXPECT_EQ(plain.jacobian_seconds, 0.0);
  EXPECT_EQ(plain.linear_solve_seconds, 0.0);
  RunOscillator(LinearSolverKind::kDense, 1.0, &roots, &timed, /*time_calls=*/true);
  EXPECT_GT(timed.residual_seconds, 0.0);
  EXPECT_GT(timed.jacobian_seconds, 0.0);
  EXPECT_GT(timed.linear_solve_seconds, 0.0);
}

// x = cos ωt vanishes at t_k = (k + ½)π/ω.
TEST(IdaIntegrator, RootFindingLocatesTheZeroCrossings) {
  std::vector<double> roots;
  IntegratorStats stats;
  RunOscillator(LinearSolverKind::kDense, 5.0, &roots, &stats);
  const double period = std::numbers::pi / kOmega;
  ASSERT_EQ(roots.size(), static_cast<size_t>(std::floor(5.0 / period - 0.5)) + 1);
  for (size_t k = 0; k < roots.size(); ++k) {
    EXPECT_NEAR(roots[k], (k + 0.5) * period, 1e-8) << "root " << k;
  }
  EXPECT_EQ(stats.roots_found, static_cast<long>(roots.size()));
}

TEST(IdaIntegrator, KluPathGivesTheDenseResult) {
  std::vector<double> r1, r2;
  IntegratorStats s1, s2;
  const double e1 = RunOscillator(LinearSolverKind::kDense, 2.0, &r1, &s1);
  const double e2 = RunOscillator(LinearSolverKind::kKlu, 2.0, &r2, &s2);
  EXPECT_NEAR(e1, e2, 1e-12);
  EXPECT_EQ(s1.steps, s2.steps);
}

// The oscillator with a pattern that misses the entry ω² at (0, 2): a model bug.
class PatternMissesAnEntry final : public DaeSystem {
 public:
  int size() const override { return inner_.size(); }
  void DifferentialMask(double* id) const override { inner_.DifferentialMask(id); }
  int Residual(double t, const double* y, const double* yp, double* r) override {
    return inner_.Residual(t, y, yp, r);
  }
  int Jacobian(double t, double cj, const double* y, const double* yp, double* J) override {
    return inner_.Jacobian(t, cj, y, yp, J);
  }
  SparsityPattern JacobianPattern() const override {
    SparsityPattern p = inner_.JacobianPattern();  // column 0 holds rows 0 and 2
    p.row_index.erase(p.row_index.begin() + 1);
    for (std::size_t c = 1; c < p.col_ptr.size(); ++c) --p.col_ptr[c];
    return p;
  }

 private:
  Oscillator inner_;
};

// The sparse path gathers only the pattern's entries; an entry the system writes outside the
// pattern is reported as the model bug it is, naming the entry, at the first Jacobian.
TEST(IdaIntegrator, KluPathReportsAJacobianEntryOutsideThePattern) {
  PatternMissesAnEntry dae;
  IdaIntegrator ida(&dae, Tight(LinearSolverKind::kKlu));
  const double y0[3] = {1.0, 0.0, -kOmega * kOmega}, yp0[3] = {0.0, -kOmega * kOmega, 0.0};
  ida.Initialize(0.0, y0, yp0);
  ida.SetStopTime(1.0);
  try {
    for (int k = 0; k < 10; ++k) (void)ida.Step(1.0);
    ADD_FAILURE() << "no error for an entry outside the pattern";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("Jacobian entry (2, 0) lies outside the sparsity pattern"),
              std::string::npos)
        << e.what();
  }
}

// x = X + A sin ωt with X = 1000 A: IDA's relative tolerance on |x| ≈ X allows an error of
// rel_tol·X = 1e-3 A per step. Capping |x| at A (DaeSystem::RelativeToleranceCaps) refers the
// tolerance to the motion, not to the offset, and the error drops by orders of magnitude.
TEST(IdaIntegrator, ARelativeToleranceCapResolvesASmallMotionAtALargeOffset) {
  constexpr double kAmplitude = OffsetMotion::kAmplitude, kOffset = OffsetMotion::kOffset;
  auto worst_error = [&](double cap, long* steps) {
    OffsetMotion dae;
    dae.x_cap = cap;
    IntegratorOptions o;
    o.rel_tol = 1e-6;
    o.abs_tol = 1e-12;
    IdaIntegrator ida(&dae, o);
    const double y0[1] = {kOffset};
    const double yp0[1] = {kAmplitude * kOmega};
    ida.Initialize(0.0, y0, yp0);
    ida.SetStopTime(4.0);
    double worst = 0.0;
    for (;;) {
      const StepResult r = ida.Step(4.0);
      worst = std::max(worst, std::abs(ida.y()[0] - kOffset - kAmplitude * std::sin(kOmega * r.t)));
      if (r.outcome == StepOutcome::kStopTime) break;
    }
    *steps = ida.stats().steps;
    return worst / kAmplitude;
  };
  long steps_plain = 0, steps_capped = 0;
  const double plain = worst_error(std::numeric_limits<double>::infinity(), &steps_plain);
  const double capped = worst_error(kAmplitude, &steps_capped);
  std::printf("offset motion: error / amplitude %.3g plain (%ld steps), %.3g capped (%ld steps)\n",
              plain, steps_plain, capped, steps_capped);
  EXPECT_GT(plain, 1e-4);
  EXPECT_LT(capped, 5e-5);  // observed 5.75e-3 plain, 1.13e-5 capped
  EXPECT_GT(steps_capped, steps_plain);
}

// The cached interpolant of the last step, in both its forms (from IDA's divided differences,
// and the power form of a step with many samples), equals IDAGetDky, value and derivative, also
// when written through an index map and when only the values of some components are asked for.
// Measured: 8.7e-17 and 2.0e-16 relative at worst; at t_n both give φ₀ exactly.
TEST(IdaIntegrator, CachedStepPolynomialReproducesIdaGetDky) {
  // 3 unknowns, and 9 (the evaluation takes four components at a time, then the rest); an
  // evaluation interval of 0 (few evaluations: the divided differences) and 1e-12 s (every step
  // holds many: the power form).
  for (const auto& [copies, interval] :
       {std::pair{1, 0.0}, std::pair{3, 0.0}, std::pair{1, 1e-12}, std::pair{3, 1e-12}}) {
    SCOPED_TRACE(std::to_string(copies) + " copies, interval " + std::to_string(interval));
    Oscillator dae(copies);
    const int n = dae.size();
    IdaIntegrator ida(&dae, Tight());
    StartOnCosine(&ida, copies);
    // A larger layout for the index map: component i goes to slot 2i + 1 (even slots untouched).
    std::vector<int> into(n);
    for (int i = 0; i < n; ++i) into[i] = 2 * i + 1;
    std::vector<double> y(n), yp(n), yd(n), ypd(n), ys(2 * n + 1), yps(2 * n + 1);
    double worst = 0.0;
    for (int step = 0; step < 200; ++step) {
      ida.Step(10.0);
      ida.CacheStepPolynomial(interval);
      const double t0 = ida.polynomial_start(), t1 = ida.polynomial_end();
      for (int k = 0; k <= 4; ++k) {
        const double t = t0 + (t1 - t0) * k / 4.0;
        ida.EvaluateStepPolynomial(t, y.data(), yp.data());
        ida.DenseOutput(t, 0, yd.data());
        ida.DenseOutput(t, 1, ypd.data());
        // Written through the index map: the same numbers, in their slots, nothing else touched.
        std::fill(ys.begin(), ys.end(), -7.0);
        std::fill(yps.begin(), yps.end(), -7.0);
        ida.EvaluateStepPolynomial(t, ys.data(), yps.data(), into.data());
        for (int i = 0; i < n; ++i) {
          EXPECT_EQ(ys[into[i]], y[i]);
          EXPECT_EQ(yps[into[i]], yp[i]);
        }
        for (int slot = 0; slot <= 2 * n; slot += 2) {
          EXPECT_EQ(ys[slot], -7.0);
          EXPECT_EQ(yps[slot], -7.0);
        }
        // The values alone over a range of components (the impact-peak search's evaluation):
        // the same numbers, nothing outside the range touched.
        for (const auto& [begin, end] : {std::pair{0, n}, std::pair{1, n}, std::pair{2, n - 1}}) {
          std::fill(ys.begin(), ys.end(), -7.0);
          ida.EvaluateStepPolynomialValues(t, begin, end, ys.data(), into.data());
          for (int i = 0; i < n; ++i) EXPECT_EQ(ys[into[i]], i >= begin && i < end ? y[i] : -7.0);
        }
        for (int i = 0; i < n; ++i) {
          // x, v, a and their rates are of order 1, ω, ω², ω³: relative to that scale.
          const double scale = std::pow(kOmega, i % 3);
          worst = std::max(worst, std::abs(y[i] - yd[i]) / (scale + std::abs(yd[i])));
          worst = std::max(worst, std::abs(yp[i] - ypd[i]) / (kOmega * scale + std::abs(ypd[i])));
          // At t_n the value is φ₀ itself (taken from IDASolve's return after a step, from
          // IDAGetDky after a root return inside the step): exactly IDA's.
          if (k == 4) {
            EXPECT_EQ(y[i], yd[i]) << "step " << step;
          }
        }
      }
    }
    std::printf("%d copies, interval %g s: worst difference from IDAGetDky %.3g\n", copies,
                interval, worst);
    EXPECT_LE(worst, 1e-15);
  }
}

// Complete elliptic integral of the first kind K(k) = π / (2 AGM(1, √(1 − k²)))
// (Abramowitz & Stegun 17.6), by the arithmetic-geometric mean.
double EllipticK(double k) {
  double a = 1.0, b = std::sqrt(1.0 - k * k);
  while (std::abs(a - b) > 1e-16 * a) {
    const double an = 0.5 * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  return std::numbers::pi / (2.0 * a);
}

struct PendulumRun {
  std::vector<double> roots;  // [s]
  IntegratorStats stats;
  long system_evaluations{0};
};

// The pendulum released at rest from θ₀ = 2.5 rad (143°) over 5 s, at 1e-10, with the given
// Jacobian reuse.
PendulumRun RunPendulum(LinearSolverKind kind, int reuse_steps, int copies = 1) {
  Oscillator dae(copies, /*pendulum=*/true);
  IntegratorOptions options = Tight(kind);
  options.jacobian_reuse_steps = reuse_steps;
  IdaIntegrator ida(&dae, options);
  constexpr double kTheta0 = 2.5;
  std::vector<double> y0, yp0;
  for (int m = 0; m < copies; ++m) {
    const double a0 = -kOmega * kOmega * std::sin(kTheta0);
    y0.insert(y0.end(), {kTheta0, 0.0, a0});
    yp0.insert(yp0.end(), {0.0, a0, 0.0});
  }
  ida.Initialize(0.0, y0.data(), yp0.data());
  ida.SetStopTime(5.0);
  PendulumRun out;
  for (;;) {
    const StepResult r = ida.Step(5.0);
    if (r.outcome == StepOutcome::kRoot) out.roots.push_back(r.t);
    if (r.outcome == StepOutcome::kStopTime) break;
  }
  out.stats = ida.stats();
  out.system_evaluations = dae.evaluations;
  return out;
}

// A set-up within jacobian_reuse_steps of the last evaluation forms the iteration matrix for
// the new c_j from the saved dF/dy and dF/dẏ. The solution is the residual's, not the
// matrix's: the zero crossings of the large-amplitude pendulum fall on the closed form
// t_k = (2k + 1) K(sin(θ₀/2)) / ω (the period 4K/ω) with and without reuse, dense and KLU,
// while the reuse evaluates the Jacobian at a fraction of the set-ups.
TEST(IdaIntegrator, ReusedJacobianKeepsTheSolutionAndEvaluatesLess) {
  const double quarter = EllipticK(std::sin(0.5 * 2.5)) / kOmega;  // T/4 [s]
  const PendulumRun fresh = RunPendulum(LinearSolverKind::kDense, 0);
  const PendulumRun reused = RunPendulum(LinearSolverKind::kDense, 20);
  const PendulumRun reused_klu = RunPendulum(LinearSolverKind::kKlu, 20, 2);
  for (const PendulumRun* run : {&fresh, &reused, &reused_klu}) {
    ASSERT_EQ(run->roots.size(), 3u);  // T = 3.46 s: crossings at T/4, 3T/4, 5T/4
    for (size_t k = 0; k < run->roots.size(); ++k) {
      // The global error at 1e-10 grows to 7.2e-9 s by the third crossing (measured).
      EXPECT_NEAR(run->roots[k], (2.0 * k + 1.0) * quarter, 2e-8) << "crossing " << k;
      // Reuse moves them by the Newton remainder, well within that error: 6e-11 s measured,
      // and 1.0e-9 s once the dense solve's last bits changed (reciprocal pivots), which moved
      // the fresh run's third crossing from 7.2e-9 to 5.9e-9 s and the reused run's to 6.9e-9.
      EXPECT_NEAR(run->roots[k], fresh.roots[k], 2.5e-9) << "crossing " << k;
    }
  }
  // Without reuse every set-up evaluates, as IDA does.
  EXPECT_EQ(fresh.stats.jacobian_evaluations, fresh.stats.matrix_setups);
  EXPECT_EQ(fresh.system_evaluations, fresh.stats.matrix_setups);
  // With reuse most set-ups do not; each evaluation costs the system two Jacobians here (the
  // default JacobianAndDerivativePart).
  EXPECT_LT(2 * reused.stats.jacobian_evaluations, reused.stats.matrix_setups);
  EXPECT_EQ(reused.system_evaluations, 2 * reused.stats.jacobian_evaluations);
  EXPECT_LT(2 * reused_klu.stats.jacobian_evaluations, reused_klu.stats.matrix_setups);
  std::printf("pendulum set-ups / evaluations: fresh %ld / %ld, reused %ld / %ld, KLU %ld / %ld\n",
              fresh.stats.matrix_setups, fresh.stats.jacobian_evaluations,
              reused.stats.matrix_setups, reused.stats.jacobian_evaluations,
              reused_klu.stats.matrix_setups, reused_klu.stats.jacobian_evaluations);
}

TEST(IdaIntegrator, ReinitialisationRestartsAndKeepsCountingSteps) {
  Oscillator dae;
  IdaIntegrator ida(&dae, Tight());
  StartOnCosine(&ida);
  for (int i = 0; i < 20; ++i) ida.Step(10.0);
  const long before = ida.stats().steps;
  const double t = ida.current_time();
  const double y1[3] = {std::cos(kOmega * t), -kOmega * std::sin(kOmega * t),
                        -kOmega * kOmega * std::cos(kOmega * t)};
  const double yp1[3] = {y1[1], y1[2], kOmega * kOmega * kOmega * std::sin(kOmega * t)};
  ida.Initialize(t, y1, yp1);
  for (int i = 0; i < 5; ++i) ida.Step(10.0);
  const IntegratorStats s = ida.stats();
  EXPECT_EQ(s.reinitialisations, 1);
  EXPECT_EQ(s.steps, before + 5);
  EXPECT_NEAR(ida.y()[0], std::cos(kOmega * ida.current_time()), 1e-8);
}

TEST(IntegratorOptions, RejectsInvalidValuesNamingTheKey) {
  IntegratorOptions o;
  o.max_order = 6;
  EXPECT_THROW(o.Validate(), InputError);
  o = IntegratorOptions{};
  o.abs_tol = -1.0;
  try {
    o.Validate();
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "integrator.abs_tol");
  }
}

}  // namespace
}  // namespace flexrod::multibody
