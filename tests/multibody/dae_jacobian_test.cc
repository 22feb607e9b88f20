// tests/multibody/dae_jacobian_test.cc — the iteration Jacobian dF/dy + c_j dF/dẏ agrees
// with a high-accuracy (Richardson-extrapolated central-difference) Jacobian of the
// residual for a mechanism that uses every feature, and so does its part dF/dẏ alone; its
// non-zeros lie inside the sparsity
// pattern given to KLU; and one residual evaluation performs no heap allocation.
//
// Allocation check: EIGEN_RUNTIME_NO_MALLOC is defined for every source (CMakeLists.txt),
// and Eigen::internal::set_is_malloc_allowed(false) guards the evaluation — Eigen turns a heap
// allocation into an assertion failure in builds with assertions. Because Release
// builds compile assertions out, this file also counts calls to malloc (glibc, forwarding to
// __libc_malloc) during the evaluation, which catches Eigen, operator new and std
// containers in every build type (not under AddressSanitizer, which owns malloc).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>

#include "mb_composite.h"
#include "multibody/dae.h"
#include "multibody/run_data.h"

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#define FLEXROD_COUNT_MALLOC 1
namespace {
bool g_count_malloc = false;
long g_malloc_calls = 0;
}  // namespace
extern "C" void* __libc_malloc(size_t size);
extern "C" void* malloc(size_t size) {
  if (g_count_malloc) ++g_malloc_calls;
  return __libc_malloc(size);
}
#endif

namespace flexrod::multibody {
namespace {

using testing::BuildComposite;
using testing::RandomState;

// Central differences with Richardson extrapolation: error O(h⁴) + O(ε/h).
Mat FiniteDifferenceJacobian(const Mechanism& m, RunData* data, double t, double cj, const Vec& y,
                             const Vec& yp) {
  const int N = m.size();
  Mat J(N, N);
  auto central = [&](int i, double h, bool derivative_of_yp) {
    Vec y1 = y, y2 = y, yp1 = yp, yp2 = yp;
    if (derivative_of_yp) {
      yp1(i) += h;
      yp2(i) -= h;
    } else {
      y1(i) += h;
      y2(i) -= h;
    }
    return Vec((CalcResidual(m, data, t, y1, yp1) - CalcResidual(m, data, t, y2, yp2)) / (2 * h));
  };
  for (int i = 0; i < N; ++i) {
    const double h = 1e-4 * std::max(1.0, std::abs(y(i)));
    const Vec dy = (4.0 * central(i, 0.5 * h, false) - central(i, h, false)) / 3.0;
    const double hp = 1e-4 * std::max(1.0, std::abs(yp(i)));
    const Vec dyp = (4.0 * central(i, 0.5 * hp, true) - central(i, hp, true)) / 3.0;
    J.col(i) = dy + cj * dyp;
  }
  return J;
}

struct Mismatch {
  double worst{0.0};  // max |J − J_fd| / (largest |J_fd| in the row)
  int row{-1}, col{-1};
};

Mismatch Compare(const Mat& J, const Mat& Jfd) {
  Mismatch w;
  for (int r = 0; r < J.rows(); ++r) {
    const double scale = std::max(Jfd.row(r).cwiseAbs().maxCoeff(), 1e-12);
    for (int col = 0; col < J.cols(); ++col) {
      const double e = std::abs(J(r, col) - Jfd(r, col)) / scale;
      if (e > w.worst) w = {e, r, col};
    }
  }
  return w;
}

using Kernel = FlexibleBodySpec::StrainKernel;

void ExpectJacobianMatches(double cj, unsigned seed,
                           DampingSpec damping = DampingSpec::ModalRatio({0.02, 0.05, 0.1, 0.3}),
                           Kernel kernel = Kernel::kAuto) {
  auto c = BuildComposite(true, damping, kernel);
  const Mechanism& m = c.model;
  RunData data(m);
  Vec y, yp;
  RandomState(m, seed, &y, &yp);
  const double t = 0.37;
  const Mat J = CalcJacobian(m, &data, t, cj, y, yp);
  const Mat Jfd = FiniteDifferenceJacobian(m, &data, t, cj, y, yp);
  const Mismatch w = Compare(J, Jfd);
  // Tolerance 1e-6 relative to the row's largest entry (brief requirement).
  EXPECT_LE(w.worst, 1e-6) << "worst entry d " << m.VariableName(w.row) << " / d "
                           << m.VariableName(w.col) << ": analytic " << J(w.row, w.col)
                           << ", finite difference " << Jfd(w.row, w.col);
  std::ostringstream os;
  os << std::scientific << w.worst;
  ::testing::Test::RecordProperty("worst_relative_error", os.str());
}

TEST(DaeJacobian, PositionAndVelocityPartsMatchFiniteDifferences) { ExpectJacobianMatches(0.0, 1); }

TEST(DaeJacobian, IterationMatrixMatchesFiniteDifferencesAtLargeCj) {
  ExpectJacobianMatches(1e3, 2);
}

TEST(DaeJacobian, MatchesFiniteDifferencesAtAnotherState) { ExpectJacobianMatches(37.0, 3); }

// dF/dẏ alone (AddJacobian's dfdyp: the identities of F1 and F5, the bodies' mass matrices in
// F2, flexible ones included), which the integrator saves to form the iteration matrix for
// another c_j without an evaluation: against central differences of the residual in ẏ, and
// the jac it fills alongside equal, bit for bit, to the Jacobian without it.
TEST(DaeJacobian, DerivativePartMatchesFiniteDifferencesInTheRates) {
  auto c = BuildComposite(true, DampingSpec::ModalRatio({0.02, 0.05, 0.1, 0.3}), Kernel::kAuto);
  const Mechanism& m = c.model;
  RunData data(m);
  Vec y, yp;
  RandomState(m, 10, &y, &yp);
  const double t = 0.37, cj = 2.5e3;
  const int N = m.size();
  Mat J = Mat::Zero(N, N), B = Mat::Zero(N, N);
  ASSERT_EQ(AddJacobian(m, &data, t, cj, y.data(), yp.data(), J.data(), N, B.data()), 0);
  EXPECT_EQ((J - CalcJacobian(m, &data, t, cj, y, yp)).cwiseAbs().maxCoeff(), 0.0);
  // F is affine in ẏ: a central difference is exact up to round-off, which a large step keeps
  // small against the residual's size.
  Mat B_fd(N, N);
  for (int i = 0; i < N; ++i) {
    const double h = std::max(1.0, std::abs(yp(i)));
    Vec yp1 = yp, yp2 = yp;
    yp1(i) += h;
    yp2(i) -= h;
    B_fd.col(i) = (CalcResidual(m, &data, t, y, yp1) - CalcResidual(m, &data, t, y, yp2)) / (2 * h);
  }
  const Mismatch w = Compare(B, B_fd);
  EXPECT_LE(w.worst, 1e-9) << "worst entry d " << m.VariableName(w.row) << " / d(rate of) "
                           << m.VariableName(w.col) << ": " << B(w.row, w.col) << " against "
                           << B_fd(w.row, w.col);
  EXPECT_GT(B.cwiseAbs().maxCoeff(), 0.0);
}

// The damping acts on the rates of the second-order strains (D on q̃̇, q̃ = q + E⁺P s(q)), a
// force nonlinear in q and q̇ with its own analytic Jacobian: the modal damping of the tests
// above, and Rayleigh damping here (Kelvin–Voigt on the strains).
TEST(DaeJacobian, MatchesFiniteDifferencesWithKelvinVoigtDamping) {
  ExpectJacobianMatches(0.0, 4, DampingSpec::Rayleigh(3.0, 2e-3));
  ExpectJacobianMatches(25.0, 5, DampingSpec::Rayleigh(0.0, 5e-3));
}

// Without damping the second-order strain has no strain damping: the stiffening power row's
// q̇ᵀ Σ_e N_e T_eᵀ K_G T_e then needs the nodes' rates T q̇ computed by the Jacobian itself.
TEST(DaeJacobian, MatchesFiniteDifferencesWithoutDamping) {
  ExpectJacobianMatches(0.0, 6, DampingSpec::None());
  ExpectJacobianMatches(25.0, 7, DampingSpec::None());
}

// The element kernel of the second-order strain (the full-FE rod's) against the same finite
// differences: the Jacobian is the modal one for both, the residual is not.
TEST(DaeJacobian, MatchesFiniteDifferencesWithTheElementStrainKernel) {
  ExpectJacobianMatches(0.0, 8, DampingSpec::Rayleigh(3.0, 2e-3), Kernel::kElements);
  ExpectJacobianMatches(25.0, 9, DampingSpec::ModalRatio({0.02, 0.05, 0.1, 0.3}),
                        Kernel::kElements);
}

// The two kernels compute the same residual by different sums (the modal tensors H_k q against
// T q, the elements' K_G w_e and Tᵀ): equal to round-off at a random state, with the damping of
// the strains, and both differ from the residual without the second-order strain.
TEST(DaeResidual, ModalAndElementStrainKernelsAgree) {
  const DampingSpec damping = DampingSpec::Rayleigh(3.0, 2e-3);
  auto modal = BuildComposite(true, damping, Kernel::kModal);
  auto elements = BuildComposite(true, damping, Kernel::kElements);
  auto linear = BuildComposite(false, damping);
  ASSERT_TRUE(modal.model.bodies()[1].modal_strain_kernel);
  ASSERT_FALSE(elements.model.bodies()[1].modal_strain_kernel);
  Vec y, yp;
  RandomState(modal.model, 10, &y, &yp);
  auto residual = [&](const Mechanism& m) {
    RunData data(m);
    return CalcResidual(m, &data, 0.3, y, yp);
  };
  const Vec rm = residual(modal.model), re = residual(elements.model);
  const Vec rl = residual(linear.model);
  EXPECT_LE((rm - re).lpNorm<Eigen::Infinity>(), 1e-12 * rm.lpNorm<Eigen::Infinity>());
  EXPECT_GT((rm - rl).lpNorm<Eigen::Infinity>(), 1e-3 * rm.lpNorm<Eigen::Infinity>());
}

// Negative control: the comparison does catch a Jacobian that is wrong by 1e-4 in one
// configuration-dependent entry (the prismatic-joint Hessian block of the rod).
TEST(DaeJacobian, ComparisonDetectsAWrongEntry) {
  auto c = BuildComposite();
  const Mechanism& m = c.model;
  RunData data(m);
  Vec y, yp;
  RandomState(m, 5, &y, &yp);
  Mat J = CalcJacobian(m, &data, 0.1, 0.0, y, yp);
  const Mat Jfd = FiniteDifferenceJacobian(m, &data, 0.1, 0.0, y, yp);
  const int row = m.v_offset() + m.coordinate(m.FindBody("rod"), kTheta);
  const int col = m.coordinate(m.FindBody("rod"), kTheta);
  J(row, col) += 1e-4 * std::max(1.0, Jfd.row(row).cwiseAbs().maxCoeff());
  EXPECT_GT(Compare(J, Jfd).worst, 1e-6);
}

TEST(DaeJacobian, NonZerosLieInsideTheSparsityPattern) {
  auto c = BuildComposite();
  const Mechanism& m = c.model;
  RunData data(m);
  const SparsityPattern pat = JacobianPattern(m);
  ASSERT_EQ(pat.size, m.size());
  std::vector<std::vector<bool>> in(m.size(), std::vector<bool>(m.size(), false));
  for (int col = 0; col < m.size(); ++col)
    for (int64_t k = pat.col_ptr[col]; k < pat.col_ptr[col + 1]; ++k)
      in[pat.row_index[k]][col] = true;
  for (unsigned seed = 10; seed < 13; ++seed) {
    Vec y, yp;
    RandomState(m, seed, &y, &yp);
    const Mat J = CalcJacobian(m, &data, 0.2, 11.0, y, yp);
    for (int r = 0; r < m.size(); ++r)
      for (int col = 0; col < m.size(); ++col)
        if (J(r, col) != 0.0) {
          EXPECT_TRUE(in[r][col]) << m.VariableName(r) << " / " << m.VariableName(col);
        }
  }
  EXPECT_LT(pat.nnz(), static_cast<int64_t>(m.size()) * m.size());  // genuinely sparse
}

// Runs f with Eigen's allocations forbidden and returns the heap allocations it made (0 where
// malloc cannot be counted: the Eigen guard then catches Eigen's own in assertion builds).
template <class F>
long HeapAllocationsDuring(F f) {
  Eigen::internal::set_is_malloc_allowed(false);
#ifdef FLEXROD_COUNT_MALLOC
  g_malloc_calls = 0;
  g_count_malloc = true;
#endif
  f();
#ifdef FLEXROD_COUNT_MALLOC
  g_count_malloc = false;
  const long calls = g_malloc_calls;
#else
  const long calls = 0;
#endif
  Eigen::internal::set_is_malloc_allowed(true);
  return calls;
}

// With either strain kernel (with strain damping).
TEST(DaeResidual, OneEvaluationDoesNotAllocate) {
  for (Kernel kernel : {Kernel::kModal, Kernel::kElements}) {
    auto c = BuildComposite(true, DampingSpec::Rayleigh(0.0, 2e-5), kernel);
    const Mechanism& m = c.model;
    RunData data(m);
    Vec y, yp;
    RandomState(m, 4, &y, &yp);
    Vec r(m.size());
    ASSERT_EQ(CalcResidual(m, &data, 0.1, y.data(), yp.data(), r.data()), 0);  // warm-up
    int rc = -1;
    EXPECT_EQ(HeapAllocationsDuring(
                  [&] { rc = CalcResidual(m, &data, 0.2, y.data(), yp.data(), r.data()); }),
              0)
        << "heap allocations during one residual evaluation";
    EXPECT_EQ(rc, 0);
    EXPECT_TRUE(r.allFinite());
  }
}

// The Jacobian too, with the second-order strain and its Kelvin–Voigt damping (Rayleigh β):
// its workspace lives in RunData.
TEST(DaeJacobian, OneEvaluationDoesNotAllocate) {
  auto c = BuildComposite(true, DampingSpec::Rayleigh(0.0, 2e-5));
  const Mechanism& m = c.model;
  RunData data(m);
  Vec y, yp;
  RandomState(m, 4, &y, &yp);
  Mat J = Mat::Zero(m.size(), m.size());
  ASSERT_EQ(AddJacobian(m, &data, 0.1, 11.0, y.data(), yp.data(), J.data(), m.size()), 0);
  J.setZero();
  int rc = -1;
  EXPECT_EQ(HeapAllocationsDuring([&] {
              rc = AddJacobian(m, &data, 0.2, 11.0, y.data(), yp.data(), J.data(), m.size());
            }),
            0)
      << "heap allocations during one Jacobian evaluation";
  EXPECT_EQ(rc, 0);
  EXPECT_TRUE(J.allFinite());
}

// The malloc counter itself works (otherwise the test above could not fail).
TEST(DaeResidual, AllocationCounterDetectsAnAllocation) {
#ifdef FLEXROD_COUNT_MALLOC
  g_malloc_calls = 0;
  g_count_malloc = true;
  Vec v(1000);
  v.setOnes();
  g_count_malloc = false;
  EXPECT_GE(g_malloc_calls, 1);
  EXPECT_EQ(v.sum(), 1000.0);
#else
  GTEST_SKIP() << "malloc counting needs glibc without AddressSanitizer";
#endif
}

}  // namespace
}  // namespace flexrod::multibody
