// SPDX-License-Identifier: GPL-3.0-or-later
// ParaView output of a run (run/vtk.h): the drawn geometry is the mechanism's (joints hold,
// the rigid placement is exact, the scale scales only the elastic part, the rod's own
// deflection channel and curvature agree with the drawn shape), the frame grid follows
// vtk.rate / vtk.duration, the files are well-formed VTU/PVD, bad keys are rejected.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "common/error.h"
#include "input/presets.h"
#include "run/run.h"

namespace flexrod {
namespace {

namespace fs = std::filesystem;
using study::VtkFrame;
using study::VtkLayout;

/// Short captures from the index angle at t = 0: 500 samples at 10 kHz.
std::vector<std::string> Short(std::vector<std::string> more) {
  more.insert(more.begin(), {"sim.settle=0 s", "sim.capture=0.05 s", "sim.sample_rate=10 kHz"});
  return more;
}

RunResult RunWithFrames(const Config& cfg) {
  RunOutputOptions o;
  o.record_vtk = true;
  RunResult r = RunSimulation(cfg, nullptr, false, o);
  EXPECT_TRUE(r.ok()) << r.status.Summary();
  EXPECT_TRUE(r.vtk.has_value());
  EXPECT_FALSE(r.vtk->frames.empty());
  return r;
}

Vec2 Mean(const VtkFrame& f, int first, int count) {
  Vec2 m = Vec2::Zero();
  for (int i = 0; i < count; ++i) m += f.points[first + i];
  return m / count;
}

/// Signed distance of p from the line a→b (positive on the left).
double SignedDistance(const Vec2& a, const Vec2& b, const Vec2& p) {
  const Vec2 u = (b - a).normalized();
  return u.x() * (p - a).y() - u.y() * (p - a).x();
}

constexpr double kRodLength = 0.280;  // flexible-rig preset [m]
constexpr int kRodElements = 40;

TEST(VtkGeometry, ZeroScaleDrawsAStraightRodOnTheDeformedChord) {
  const RunResult r0 =
      RunWithFrames(LoadRunInput("flexible-rig", Short({"joint.type=ideal", "vtk.scale=0"})));
  const RunResult r1 =
      RunWithFrames(LoadRunInput("flexible-rig", Short({"joint.type=ideal", "vtk.scale=1"})));
  const VtkLayout& L = r0.vtk->layout;
  ASSERT_EQ(L.rod_count, kRodElements + 1);
  ASSERT_EQ(r0.vtk->frames.size(), r1.vtk->frames.size());
  const int last = L.rod_first + L.rod_count - 1;
  double max_deflection = 0.0;
  for (size_t i = 0; i < r0.vtk->frames.size(); ++i) {
    const VtkFrame &f = r0.vtk->frames[i], &t = r1.vtk->frames[i];
    const Vec2 a = f.points[L.rod_first], b = f.points[last];
    // The end nodes are drawn where they truly are (s = 1), to round-off of 0.3 m coordinates.
    EXPECT_LT((a - t.points[L.rod_first]).norm(), 1e-15);
    EXPECT_LT((b - t.points[last]).norm(), 1e-15);
    // The chord is the undeformed length up to the axial strain (measured up to 2.5e-5 here;
    // bound 1e-4 = 20 MPa of axial stress in steel).
    EXPECT_NEAR((b - a).norm(), kRodLength, 1e-4 * kRodLength);
    // Equal segments on the chord: the nodes are equally spaced along the undeformed rod.
    const double le = (b - a).norm() / kRodElements;
    double length = 0.0;
    for (int k = 0; k + 1 < L.rod_count; ++k) {
      const double seg = (f.points[L.rod_first + k + 1] - f.points[L.rod_first + k]).norm();
      EXPECT_NEAR(seg, le, 1e-12);
      length += seg;
      EXPECT_NEAR(SignedDistance(a, b, f.points[L.rod_first + k]), 0.0, 1e-12);
    }
    EXPECT_NEAR(length, (b - a).norm(), 1e-12);
    for (int k = 0; k < L.rod_count; ++k)
      max_deflection = std::max(max_deflection, f.displacement[L.rod_first + k]);
  }
  // The rod did bend (deflection from the chord reaches tens of µm in this window): scale 0
  // removed something.
  EXPECT_GT(max_deflection, 1e-5);
}

TEST(VtkGeometry, RodJointPointsSitOnTheCrankPinAndTheJournal) {
  // Tight tolerances: position constraints then hold to ~1e-11 m (summary
  // max_constraint_violation).
  const std::vector<std::string> tight = {"joint.type=ideal", "sim.rel_tol=1e-9",
                                          "sim.abs_tol=1e-11"};
  for (const std::string preset : {"flexible-rig", "rigid-rig"}) {
    std::vector<std::string> sets = Short(tight);
    sets.push_back("vtk.scale=1");
    const RunResult r = RunWithFrames(LoadRunInput(preset, sets));
    const double violation = r.summary["max_constraint_violation [m]"].get<double>();
    EXPECT_LT(violation, 1e-10) << preset;
    const VtkLayout& L = r.vtk->layout;
    for (const VtkFrame& f : r.vtk->frames) {
      // Big end: the rod's joint point on the crank pin; small end: on the journal (the centre of
      // the slider rectangle). Both rod points are computed from the rod's frame and q_f, the
      // crank pin and the journal from the other bodies: they agree to the constraint violation.
      EXPECT_LT((f.points[L.big_end] - f.points[L.crank_pin]).norm(), 2 * violation + 1e-14)
          << preset;
      EXPECT_LT((f.points[L.small_end] - Mean(f, L.slider_first, 4)).norm(), 2 * violation + 1e-14)
          << preset;
      // The crank is drawn from the axis at the origin with its length.
      EXPECT_NEAR(f.points[L.crank_axis].norm(), 0.0, 1e-12);
      EXPECT_NEAR((f.points[L.crank_pin] - f.points[L.crank_axis]).norm(),
                  preset == "rigid-rig" ? 0.05 : 0.03, 1e-12);
    }
  }
}

TEST(VtkGeometry, ScaleMultipliesOnlyTheElasticDisplacement) {
  // Three identical (deterministic) runs drawn at s = 0, 1, 37.
  auto run = [](const char* scale) {
    return RunWithFrames(LoadRunInput(
        "flexible-rig", Short({"joint.type=ideal", std::string("vtk.scale=") + scale})));
  };
  const RunResult r0 = run("0"), r1 = run("1"), r37 = run("37");
  const VtkLayout& L = r0.vtk->layout;
  ASSERT_EQ(r0.vtk->frames.size(), r37.vtk->frames.size());
  const int mid = L.rod_first + kRodElements / 2;
  double max_mid = 0.0;
  for (size_t i = 0; i < r0.vtk->frames.size(); ++i) {
    const VtkFrame &f0 = r0.vtk->frames[i], &f1 = r1.vtk->frames[i], &f37 = r37.vtk->frames[i];
    EXPECT_LT((f37.points[L.small_end] - f0.points[L.small_end]).norm(), 1e-15);
    for (int k = L.rod_first; k < L.rod_first + L.rod_count; ++k) {
      const Vec2 d1 = f1.points[k] - f0.points[k];
      // p_s − p_0 = s A (d − d_c): exactly s times the unscaled deflection (round-off ~1e-16 m).
      EXPECT_LT((f37.points[k] - f0.points[k] - 37.0 * d1).norm(), 1e-13);
      // The deflection data is the unscaled |d − d_c|.
      EXPECT_NEAR(d1.norm(), f37.displacement[k], 1e-14);
    }
    max_mid = std::max(max_mid, (f1.points[mid] - f0.points[mid]).norm());
    // Only the centre line's deflection from its chord is scaled: the rod's end nodes and the
    // joint points on the clamp arms do not move with s.
    EXPECT_LT((f37.points[L.big_end] - f0.points[L.big_end]).norm(), 1e-15);
    EXPECT_LT((f37.points[L.rod_first] - f0.points[L.rod_first]).norm(), 1e-15);
    EXPECT_LT((f37.points[L.rod_first + L.rod_count - 1] - f0.points[L.rod_first + L.rod_count - 1])
                  .norm(),
              1e-15);
  }
  EXPECT_GT(max_mid, 1e-5);  // midspan moved by more than 10 µm in B: the check has teeth
}

TEST(VtkGeometry, MidspanDeflectionEqualsTheRodDeflectionChannel) {
  // rod_deflection (run/run.cc) is the midspan node's signed distance from the chord of the
  // end nodes, computed from the rod coordinates alone; the drawn rod at s = 1 must agree.
  const RunResult r =
      RunWithFrames(LoadRunInput("flexible-rig", Short({"joint.type=ideal", "vtk.scale=1"})));
  const VtkLayout& L = r.vtk->layout;
  const auto defl = r.channels.values("rod_deflection");
  const long stride = r.vtk->stride;
  ASSERT_EQ(stride, 10);  // 10 kHz samples, 1 kHz frames
  double peak = 0.0;
  for (size_t i = 0; i < r.vtk->frames.size(); ++i) {
    const VtkFrame& f = r.vtk->frames[i];
    const size_t k = i * stride;
    EXPECT_NEAR(f.time, r.channels.time(k), 1e-12);
    const double d = SignedDistance(f.points[L.rod_first], f.points[L.rod_first + L.rod_count - 1],
                                    f.points[L.rod_first + kRodElements / 2]);
    EXPECT_NEAR(d, defl[k], 1e-13);
    peak = std::max(peak, std::abs(d));
  }
  EXPECT_GT(peak, 1e-6);
}

// The geometrically exact rod (rod.type = exact): its node bodies drawn where they are (s = 1):
// the midspan node's distance from the end nodes' chord is the rod_deflection channel, the
// joint points sit on the crank pin and the journal, and the nodal stresses are E times the
// surface strains the gauges read (fibre 0: axial; ± half depth: bending).
TEST(VtkGeometry, ExactRodIsDrawnFromItsNodeBodies) {
  const RunResult r = RunWithFrames(LoadRunInput(
      "flexible-rig", Short({"rod.type=exact", "joint.type=ideal", "vtk.scale=1",
                             "sim.rel_tol=1e-9", "sim.abs_tol=1e-11", "output.gauges=0.14"})));
  ASSERT_TRUE(r.ok()) << r.status.Summary();
  const VtkLayout& L = r.vtk->layout;
  ASSERT_EQ(L.rod_count, kRodElements + 1);
  const double violation = r.summary["max_constraint_violation [m]"].get<double>();
  const auto defl = r.channels.values("rod_deflection");
  const auto stress = r.channels.values("stress_gauge1");  // at x = 0.14 m: node 20, midspan
  double peak = 0.0;
  for (size_t i = 0; i < r.vtk->frames.size(); ++i) {
    const VtkFrame& f = r.vtk->frames[i];
    const size_t k = i * r.vtk->stride;
    const int mid = L.rod_first + kRodElements / 2;
    const double d = SignedDistance(f.points[L.rod_first], f.points[L.rod_first + L.rod_count - 1],
                                    f.points[mid]);
    EXPECT_NEAR(d, defl[k], 1e-13);
    EXPECT_NEAR(f.axial_stress[mid] + f.bending_stress[mid], stress[k],
                1e-9 * std::abs(stress[k]) + 1e-6);
    EXPECT_LT((f.points[L.big_end] - f.points[L.crank_pin]).norm(), 2 * violation + 1e-14);
    EXPECT_LT((f.points[L.small_end] - Mean(f, L.slider_first, 4)).norm(), 2 * violation + 1e-14);
    peak = std::max(peak, std::abs(d));
  }
  EXPECT_GT(peak, 1e-6);
}

TEST(VtkGeometry, NodalStressesMatchTheDrawnRodsStrainAndCurvature) {
  // Axial: linear axial shape functions make u' constant per element, so the nodal mean of the
  // two element values is E (u_{k+1} − u_{k−1}) / (2 le) exactly. Bending: σ = −E y κ with κ
  // from the second difference of the lateral displacement (O(le²) accurate: measured 0.04 %
  // of the peak on the rig's 40-element rod; bound 0.2 %). Axial measured 2e-9 relative.
  // The displacement in frame B is recovered from the true (s = 1) drawing: node 0 is the
  // frame origin R_B, and the big-end joint point is R_B + A(θ_B) ū_big with ū_big = (−15, −8)
  // mm (rod.big_end_x/y defaults) on the clamp, which the clamped-interface rod keeps rigid
  // in B; ū₀_k = (k le, 0). Linear strain (rod.geometric_stiffening = false): the second-order
  // membrane strain is the gauges' (fem::StrainGaugeRows::membrane), projected on the basis's
  // elongation fields, which the drawing cannot show node by node.
  const RunResult r1 = RunWithFrames(
      LoadRunInput("flexible-rig",
                   Short({"joint.type=ideal", "vtk.scale=1", "rod.geometric_stiffening=false"})));
  const VtkLayout& L = r1.vtk->layout;
  const Vec2 big_offset(-15e-3, -8e-3);
  const double E = 200e9;           // steel (fem/material.cc)
  const double y = 0.5 * 3.175e-3;  // weak axis: half the thickness in the plane
  const double le = kRodLength / kRodElements;
  double worst_bending = 0.0, peak_bending = 0.0, worst_axial = 0.0, peak_axial = 0.0;
  for (size_t i = 1; i < r1.vtk->frames.size(); ++i) {
    const VtkFrame& f1 = r1.vtk->frames[i];
    const Vec2 origin = f1.points[L.rod_first];
    const Vec2 arm = f1.points[L.big_end] - origin;
    ASSERT_NEAR(arm.norm(), big_offset.norm(), 1e-12);
    const double th = std::atan2(arm.y(), arm.x()) - std::atan2(big_offset.y(), big_offset.x());
    const Vec2 ex(std::cos(th), std::sin(th)), ey(-std::sin(th), std::cos(th));
    std::vector<double> u(L.rod_count), v(L.rod_count);
    for (int k = 0; k < L.rod_count; ++k) {
      const Vec2 d = f1.points[L.rod_first + k] - origin;
      u[k] = d.dot(ex) - k * le;
      v[k] = d.dot(ey);
    }
    for (int k = 1; k + 1 < L.rod_count; ++k) {
      const double axial = E * (u[k + 1] - u[k - 1]) / (2 * le);
      worst_axial = std::max(worst_axial, std::abs(axial - f1.axial_stress[L.rod_first + k]));
      peak_axial = std::max(peak_axial, std::abs(axial));
      const double bending = -E * y * (v[k - 1] - 2 * v[k] + v[k + 1]) / (le * le);
      worst_bending =
          std::max(worst_bending, std::abs(bending - f1.bending_stress[L.rod_first + k]));
      peak_bending = std::max(peak_bending, std::abs(f1.bending_stress[L.rod_first + k]));
    }
  }
  ASSERT_GT(peak_bending, 1e6);  // MPa-level bending stress
  ASSERT_GT(peak_axial, 1e4);
  EXPECT_LT(worst_bending, 2e-3 * peak_bending);
  EXPECT_LT(worst_axial, 1e-7 * peak_axial);
}

TEST(VtkGeometry, ClearanceJointCirclesSitOnTheRodAndTheSlider) {
  const RunResult r = RunWithFrames(LoadRunInput("flexible-rig", Short({"vtk.scale=1"})));
  const VtkLayout& L = r.vtk->layout;
  ASSERT_GE(L.bush_first, 0);
  ASSERT_EQ(L.circle_points, 64);
  const double R_bush = 9.525e-3, R_pin = R_bush - 0.5e-3;  // preset: bush radius and clearance
  const auto ecc = r.channels.values("journal_eccentricity");
  for (size_t i = 0; i < r.vtk->frames.size(); ++i) {
    const VtkFrame& f = r.vtk->frames[i];
    const Vec2 bush = Mean(f, L.bush_first, L.circle_points),
               pin = Mean(f, L.pin_first, L.circle_points);
    for (int j = 0; j < L.circle_points; ++j) {
      EXPECT_NEAR((f.points[L.bush_first + j] - bush).norm(), R_bush, 1e-12);
      EXPECT_NEAR((f.points[L.pin_first + j] - pin).norm(), R_pin, 1e-12);
    }
    // The bush circle is drawn at the multibody marker kinematics of the small end; the rod's
    // small-end point at s = 1 is computed here from frame B and q_f: the same point.
    EXPECT_LT((bush - f.points[L.small_end]).norm(), 1e-14);
    EXPECT_LT((pin - Mean(f, L.slider_first, 4)).norm(), 1e-14);
    EXPECT_NEAR((pin - bush).norm(), ecc[i * r.vtk->stride], 1e-14);
  }
}

TEST(VtkGeometry, PendulumDrawsTheRodAboutItsPivot) {
  const RunResult r =
      RunWithFrames(LoadRunInput("flexible-pendulum", {"sim.capture=0.05 s", "vtk.scale=1"}));
  const VtkLayout& L = r.vtk->layout;
  EXPECT_EQ(L.crank_axis, -1);
  EXPECT_EQ(L.slider_first, -1);
  EXPECT_EQ(L.num_points, L.rod_count + 2);  // the rod and its two joint points
  for (const VtkFrame& f : r.vtk->frames) {
    EXPECT_TRUE(std::isnan(f.crank_angle));
    EXPECT_LT(f.points[L.big_end].norm(), 1e-9);  // pinned at the world origin (rel_tol 1e-8)
  }
  // It fell: the free end went down under gravity.
  EXPECT_LT(r.vtk->frames.back().points[L.rod_first + L.rod_count - 1].y(), -1e-3);
}

// Every rod draws both joint points, at the small end's marker where it sits on a body of its
// own (the exact rod's last node body; the exact pendulum once wrote a point past the frame's
// array). The four-bar draws its crank and its rocker (MechanismRecipe::LayOutParts): the rod's
// joint points on the crank pin and on the rocker's tip, the rocker's axis on its pivot.
TEST(VtkGeometry, EveryMechanismDrawsBothRodEndsAndItsOwnParts) {
  const Config exact = LoadRunInput("flexible-pendulum", {"sim.capture=0.02 s", "rod.type=exact"});
  const RunResult pendulum = RunWithFrames(exact);
  const VtkLayout& P = pendulum.vtk->layout;
  EXPECT_EQ(P.num_points, P.rod_count + 2);
  ASSERT_GE(P.small_end, 0);
  // The small-end point rides rigidly on the exact rod's last node body at the preset's offset.
  const double offset =
      Vec2(exact.Quantity("rod.small_end_x"), exact.Quantity("rod.small_end_y")).norm();
  ASSERT_GT(offset, 0.0);
  for (const VtkFrame& f : pendulum.vtk->frames) {
    ASSERT_EQ(f.points.size(), size_t(P.num_points));
    EXPECT_NEAR((f.points[P.small_end] - f.points[P.rod_first + P.rod_count - 1]).norm(), offset,
                1e-12);
  }
  const RunResult four_bar = RunWithFrames(LoadRunInput(
      "flexible-rig",
      Short({"mechanism.type=four-bar", "joint.type=ideal", "sim.start=rigid", "vtk.scale=1"})));
  const VtkLayout& L = four_bar.vtk->layout;
  ASSERT_GE(L.crank_axis, 0);
  ASSERT_GE(L.rocker_axis, 0);
  ASSERT_GE(L.rocker_tip, 0);
  EXPECT_EQ(L.slider_first, -1);
  EXPECT_EQ(L.bush_first, -1);
  const Config cfg = LoadRunInput("flexible-rig", {});
  const Vec2 pivot(cfg.Quantity("rocker.pivot_x"), cfg.Quantity("rocker.pivot_y"));
  const double c = cfg.Quantity("rocker.length");
  int rocker_cells = 0;
  for (const study::VtkCell& cell : L.cells) rocker_cells += cell.part == study::VtkPart::kRocker;
  EXPECT_EQ(rocker_cells, 1);
  for (const VtkFrame& f : four_bar.vtk->frames) {
    ASSERT_EQ(f.points.size(), size_t(L.num_points));
    EXPECT_TRUE(std::isfinite(f.crank_angle));
    EXPECT_LT((f.points[L.big_end] - f.points[L.crank_pin]).norm(), 1e-6);
    EXPECT_LT((f.points[L.small_end] - f.points[L.rocker_tip]).norm(), 1e-6);
    EXPECT_LT((f.points[L.rocker_axis] - pivot).norm(), 1e-9);
    EXPECT_NEAR((f.points[L.rocker_tip] - f.points[L.rocker_axis]).norm(), c, 1e-12);
  }
}

TEST(VtkFrames, GridFollowsRateAndDuration) {
  auto frames = [](std::vector<std::string> sets) {
    const RunResult r = RunWithFrames(LoadRunInput("rigid-rig", Short(std::move(sets))));
    return std::make_tuple(r.vtk->frames.size(), r.vtk->stride, r.vtk->frame_rate, r.vtk->frames);
  };
  {  // 500 samples at 10 kHz, a frame every 10th: k = 0, 10, …, 490.
    const auto [n, stride, rate, f] = frames({"joint.type=ideal"});
    EXPECT_EQ(n, 50u);
    EXPECT_EQ(stride, 10);
    EXPECT_DOUBLE_EQ(rate, 1000.0);
    for (size_t i = 1; i < f.size(); ++i) EXPECT_NEAR(f[i].time - f[i - 1].time, 1e-3, 1e-12);
  }
  {  // 20 ms window: k = 0 … 200 → 21 frames.
    const auto [n, stride, rate, f] = frames({"joint.type=ideal", "vtk.duration=20 ms"});
    EXPECT_EQ(n, 21u);
    EXPECT_NEAR(f.back().time - f.front().time, 0.02, 1e-12);
  }
  {  // 3 kHz does not divide 10 kHz: nearest stride 3, 3333.3 Hz, ceil(500 / 3) = 167 frames.
    const auto [n, stride, rate, f] = frames({"joint.type=ideal", "vtk.rate=3 kHz"});
    EXPECT_EQ(stride, 3);
    EXPECT_NEAR(rate, 1e4 / 3, 1e-9);
    EXPECT_EQ(n, 167u);
  }
  {  // Faster than the samples: every sample.
    const auto [n, stride, rate, f] = frames({"joint.type=ideal", "vtk.rate=50 kHz"});
    EXPECT_EQ(stride, 1);
    EXPECT_EQ(n, 500u);
  }
  // Without a request (the sweep's call) nothing is recorded or written.
  const RunResult plain = RunSimulation(LoadRunInput("rigid-rig", Short({"joint.type=ideal"})));
  EXPECT_FALSE(plain.vtk.has_value());
}

TEST(VtkInput, BadValuesNameTheKey) {
  auto expect_error = [](const std::vector<std::string>& sets, const std::string& key) {
    RunOutputOptions o;
    o.record_vtk = true;
    try {
      RunSimulation(LoadRunInput("rigid-rig", Short(sets)), nullptr, false, o);
      ADD_FAILURE() << "no InputError for " << key;
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
    }
  };
  expect_error({"vtk.rate=0"}, "vtk.rate");
  expect_error({"vtk.rate=-1 kHz"}, "vtk.rate");
  expect_error({"vtk.scale=-2"}, "vtk.scale");
  expect_error({"vtk.duration=-1 s"}, "vtk.duration");
  EXPECT_THROW(LoadRunInput("rigid-rig", {"vtk.rate=3 m"}), InputError);  // wrong dimension
  EXPECT_THROW(LoadRunInput("rigid-rig", {"vtk.scale=big"}), InputError);
}

}  // namespace
}  // namespace flexrod
