// tests/multibody/serial_vector_ops_test.cc — the compiled serial-vector operations
// (multibody/serial_vector_ops.h) against SUNDIALS' own N_V*_Serial functions, bit for bit:
// every coefficient case of the linear sum (±1, equal, opposite, zero, general), every aliasing
// IDA uses (z = x, z = y), the fused and vector-array forms, the masked and unmasked norms.
// A result one rounding apart would change every trajectory in its last bits.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/serial_vector_ops.h"

#include <gtest/gtest.h>
#include <nvector/nvector_serial.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace flexrod::multibody {
namespace {

constexpr sunindextype kN = 37;  // odd: the vectorised loops' remainders run too

class SerialOpsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(SUNContext_Create(nullptr, &ctx_), 0);
    plain_ = N_VNew_Serial(kN, ctx_);
    N_VEnableFusedOps_Serial(plain_, SUNTRUE);
    compiled_ = N_VClone(plain_);
    UseCompiledSerialOps(compiled_);
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int k = 0; k < 8; ++k) {
      std::vector<double> v(kN);
      for (double& x : v) x = u(gen);
      data_.push_back(v);
    }
    mask_.resize(kN);
    for (sunindextype i = 0; i < kN; ++i) mask_[i] = (i % 3 == 0) ? 0.0 : 1.0;
  }
  void TearDown() override {
    for (N_Vector v : owned_) N_VDestroy(v);
    N_VDestroy(compiled_);
    N_VDestroy(plain_);
    SUNContext_Free(&ctx_);
  }

  /// A vector with SUNDIALS' operations (compiled = false) or the compiled ones, holding `v`.
  N_Vector Make(bool compiled, const std::vector<double>& v) {
    N_Vector x = N_VClone(compiled ? compiled_ : plain_);
    std::memcpy(NV_DATA_S(x), v.data(), sizeof(double) * kN);
    owned_.push_back(x);
    return x;
  }

  static void ExpectBitwiseEqual(N_Vector a, N_Vector b, const std::string& what) {
    EXPECT_EQ(std::memcmp(NV_DATA_S(a), NV_DATA_S(b), sizeof(double) * kN), 0) << what;
  }

  SUNContext ctx_{nullptr};
  N_Vector plain_{nullptr}, compiled_{nullptr};
  std::vector<N_Vector> owned_;
  std::vector<std::vector<double>> data_;
  std::vector<double> mask_;
};

TEST_F(SerialOpsTest, LinearSumMatchesEveryCoefficientCaseAndAliasing) {
  const std::vector<double> coefs = {1.0, -1.0, 0.0, 0.7, -0.7, 2.3};
  for (double a : coefs) {
    for (double b : coefs) {
      for (int alias = 0; alias < 3; ++alias) {  // z separate, z = x, z = y
        N_Vector r[2];
        for (int c = 0; c < 2; ++c) {
          N_Vector x = Make(c == 1, data_[0]), y = Make(c == 1, data_[1]);
          N_Vector z = alias == 0 ? Make(c == 1, data_[2]) : (alias == 1 ? x : y);
          N_VLinearSum(a, x, b, y, z);
          r[c] = z;
        }
        ExpectBitwiseEqual(r[0], r[1],
                           "a " + std::to_string(a) + " b " + std::to_string(b) + " alias " +
                               std::to_string(alias));
      }
    }
  }
}

TEST_F(SerialOpsTest, ScaleConstAndNormsMatch) {
  for (double c : {1.0, -1.0, 0.0, 1.7}) {
    for (int alias = 0; alias < 2; ++alias) {
      N_Vector r[2];
      for (int k = 0; k < 2; ++k) {
        N_Vector x = Make(k == 1, data_[0]);
        N_Vector z = alias == 0 ? Make(k == 1, data_[1]) : x;
        N_VScale(c, x, z);
        r[k] = z;
      }
      ExpectBitwiseEqual(r[0], r[1], "scale " + std::to_string(c));
    }
  }
  N_Vector z[2] = {Make(false, data_[0]), Make(true, data_[0])};
  N_VConst(0.25, z[0]);
  N_VConst(0.25, z[1]);
  ExpectBitwiseEqual(z[0], z[1], "const");

  N_Vector x[2], w[2], id[2];
  for (int k = 0; k < 2; ++k) {
    x[k] = Make(k == 1, data_[3]);
    w[k] = Make(k == 1, data_[4]);
    id[k] = Make(k == 1, mask_);
  }
  EXPECT_EQ(N_VWrmsNorm(x[0], w[0]), N_VWrmsNorm(x[1], w[1]));
  EXPECT_EQ(N_VWrmsNormMask(x[0], w[0], id[0]), N_VWrmsNormMask(x[1], w[1], id[1]));
  EXPECT_EQ(N_VWSqrSumLocal(x[0], w[0]), N_VWSqrSumLocal(x[1], w[1]));
  EXPECT_EQ(N_VWSqrSumMaskLocal(x[0], w[0], id[0]), N_VWSqrSumMaskLocal(x[1], w[1], id[1]));
  // The masked norm is not the unmasked one (the mask is applied).
  EXPECT_LT(N_VWrmsNormMask(x[1], w[1], id[1]), N_VWrmsNorm(x[1], w[1]));
}

TEST_F(SerialOpsTest, LinearCombinationMatchesForEveryLengthAndInPlace) {
  std::vector<double> c = {1.0, -0.3, 0.45, -1.25, 2.0, 0.125};
  for (int nvec = 1; nvec <= 6; ++nvec) {
    for (int in_place = 0; in_place < 2; ++in_place) {  // z = X₀ (IDA's φ updates)
      for (double c0 : {1.0, 0.6}) {
        c[0] = c0;
        N_Vector r[2];
        for (int k = 0; k < 2; ++k) {
          std::vector<N_Vector> X;
          for (int i = 0; i < nvec; ++i) X.push_back(Make(k == 1, data_[i]));
          N_Vector z = in_place ? X[0] : Make(k == 1, data_[7]);
          ASSERT_EQ(N_VLinearCombination(nvec, c.data(), X.data(), z), 0);
          r[k] = z;
        }
        ExpectBitwiseEqual(r[0], r[1],
                           "nvec " + std::to_string(nvec) + " in place " +
                               std::to_string(in_place) + " c0 " + std::to_string(c0));
      }
    }
  }
}

TEST_F(SerialOpsTest, VectorArrayOperationsMatch) {
  constexpr int kVec = 3;
  const std::vector<std::pair<double, double>> ab = {
      {1.0, 1.0},  {1.0, -1.0}, {-1.0, 1.0}, {0.4, 1.0}, {1.0, 0.4},  {-1.0, 0.4},
      {0.4, -1.0}, {0.4, 0.4},  {0.4, -0.4}, {0.4, 1.9}, {-1.0, -1.0}};
  for (const auto& [a, b] : ab) {
    for (int alias = 0; alias < 3; ++alias) {  // Z separate, Z = X, Z = Y
      std::vector<N_Vector> out[2];
      for (int k = 0; k < 2; ++k) {
        std::vector<N_Vector> X, Y, Z;
        for (int i = 0; i < kVec; ++i) {
          X.push_back(Make(k == 1, data_[i]));
          Y.push_back(Make(k == 1, data_[i + 3]));
          Z.push_back(Make(k == 1, data_[7]));
        }
        std::vector<N_Vector>& dst = alias == 0 ? Z : (alias == 1 ? X : Y);
        ASSERT_EQ(N_VLinearSumVectorArray(kVec, a, X.data(), b, Y.data(), dst.data()), 0);
        out[k] = dst;
      }
      for (int i = 0; i < kVec; ++i) {
        ExpectBitwiseEqual(out[0][i], out[1][i],
                           "array sum a " + std::to_string(a) + " b " + std::to_string(b) +
                               " alias " + std::to_string(alias));
      }
    }
  }
  double c[kVec] = {1.0, -1.0, 0.3};
  double a[kVec] = {1.0, -0.2, 3.0};
  std::vector<N_Vector> scaled[2], added[2], constant[2];
  for (int k = 0; k < 2; ++k) {
    std::vector<N_Vector> X, Z, Y, W;
    for (int i = 0; i < kVec; ++i) {
      X.push_back(Make(k == 1, data_[i]));
      Z.push_back(Make(k == 1, data_[7]));
      Y.push_back(Make(k == 1, data_[i + 3]));
      W.push_back(Make(k == 1, data_[7]));
    }
    ASSERT_EQ(N_VScaleVectorArray(kVec, c, X.data(), Z.data()), 0);
    scaled[k] = Z;
    N_Vector x = Make(k == 1, data_[6]);
    ASSERT_EQ(N_VScaleAddMulti(kVec, a, x, Y.data(), W.data()), 0);
    added[k] = W;
    ASSERT_EQ(N_VConstVectorArray(kVec, -2.5, X.data()), 0);
    constant[k] = X;
  }
  for (int i = 0; i < kVec; ++i) {
    ExpectBitwiseEqual(scaled[0][i], scaled[1][i], "scale array");
    ExpectBitwiseEqual(added[0][i], added[1][i], "scale-add multi");
    ExpectBitwiseEqual(constant[0][i], constant[1][i], "const array");
  }
}

}  // namespace
}  // namespace flexrod::multibody
