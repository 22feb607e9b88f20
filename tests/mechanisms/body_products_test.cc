// tests/mechanisms/body_products_test.cc — which rods' stacked modal products (Body::q_products,
// qd_products: S̄, M_ff, S̃, K, W, D) are kept by their non-zeros (common/matvec.h,
// ProductMatrix): the full FE rod's, which are banded, and not a Craig–Bampton rod's, which are
// dense. The products are the same bit for bit either way (tests/multibody/matvec_test.cc);
// this keeps the full FE rod on the fast path. SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <string>

#include "input/config.h"
#include "input/presets.h"
#include "mechanisms/mechanism_model.h"

namespace flexrod {
namespace {

double Fill(const Mat& A) {
  return static_cast<double>((A.array() != 0.0).count()) / static_cast<double>(A.size());
}

TEST(BodyProducts, TheFullFeRodsAreKeptByTheirNonZerosAndACraigBamptonRodsDense) {
  for (const std::string method : {"full", "craig-bampton"}) {
    SCOPED_TRACE(method);
    Config cfg;
    cfg.LoadToml(FindPreset("flexible-rig")->toml, "flexible-rig");
    cfg.SetAssignment("reduction.method=" + method);
    const MechanismModel mm = BuildMechanism(cfg, nullptr);
    const multibody::Body& rod = mm.mechanism.body(mm.conrod);
    const bool full = method == "full";
    EXPECT_EQ(rod.q_products.sparse(), full) << "fill " << Fill(rod.q_products.dense());
    EXPECT_EQ(rod.qd_products.sparse(), full) << "fill " << Fill(rod.qd_products.dense());
    if (full) {
      // 40 elements, 120 coordinates: banded, 3 to 7 % non-zero (common/matvec.h says so).
      for (const double fill : {Fill(rod.q_products.dense()), Fill(rod.qd_products.dense())}) {
        EXPECT_GT(fill, 0.03);
        EXPECT_LT(fill, 0.07);
      }
    }
  }
}

}  // namespace
}  // namespace flexrod
