// SPDX-License-Identifier: GPL-3.0-or-later
// damping.type = ratio sets the damping ratio of the rod's modes in the assembled mechanism:
// a free decay of the flexible rig (crank held) shows the requested ratio; the clamped-frame
// modal damping of the rod's own modes does not.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "input/presets.h"
#include "mechanisms/mechanism_damping.h"
#include "mechanisms/mechanism_model.h"
#include "multibody/corotated_damping.h"
#include "multibody/mechanism_modes.h"
#include "multibody/simulate.h"

namespace flexrod {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kRequestedRatio = 0.02;

void Record(const std::string& key, double value) {
  std::ostringstream os;
  os << std::setprecision(6) << value;
  ::testing::Test::RecordProperty(key, os.str());
}

/// The flexible rig (steel 3.175 × 19.05 mm, Craig–Bampton 8 + 2 axial modes) with an ideal
/// small-end joint, ratio damping, no guide damping or friction (the rod's damping alone), and
/// the crank held: a constant drive at 1e-9 rad/s (drive.speed must be > 0) turns it by 1e-10
/// rad during the decay.
Config RigAtRest() {
  Config cfg;
  cfg.LoadToml(FindPreset("flexible-rig")->toml, "flexible-rig");
  for (const char* s :
       {"joint.type=ideal", "damping.type=ratio", "damping.ratio=0.02", "slider.damping=0",
        "slider.friction=0", "drive.type=constant", "drive.speed=1e-9 rad/s"}) {
    cfg.SetAssignment(s);
  }
  return cfg;
}

struct Decay {
  double zeta{0.0};          ///< fitted damping ratio [-]
  double frequency_hz{0.0};  ///< undamped frequency from the fit [Hz]
  int extrema{0};            ///< extrema used
};

/// The modes' deformation parts Q (n × n) and the map from p − p0 to the deformation: the
/// reduced rod's elastic coordinates q, or the exact rod's co-rotated node displacements
/// (linearised: B(p0) (p − p0), multibody/corotated_damping.h), which parametrise the motion.
struct Deformation {
  Mat map;  ///< n × np
  Mat Q;    ///< map Ψ
};
Deformation DeformationOf(const MechanismModel& mm, const multibody::MechanismModes& modes) {
  const multibody::Mechanism& m = mm.mechanism;
  Deformation out;
  if (mm.exact) {
    out.map = multibody::CorotatedRateMap(m, mm.exact->nodes, mm.p0);
  } else {
    const int n = m.body(mm.conrod).num_modes, q0 = m.coordinate(mm.conrod, multibody::kFirstMode);
    out.map = Mat::Zero(n, m.num_coordinates());
    out.map.middleCols(q0, n).setIdentity();
  }
  out.Q = out.map * modes.shapes;
  return out;
}

/// Free decay of mechanism mode k of `mm`: the rod starts at rest deflected along the mode
/// (ε Ψ_k; the position Newton puts the frame and slider on the constraints), is integrated
/// for `periods` periods, and the modal coordinate η_k = (Q⁻¹ d)_k — d the deformation
/// (DeformationOf) — is sampled at 64 points per period. Extrema of η_k (parabolic
/// interpolation) give the damped period and the decay rate σ (least squares on ln|η|),
/// ζ = σ / √(ω_d² + σ²).
Decay FreeDecay(const MechanismModel& mm, const multibody::MechanismModes& modes, int k,
                double periods) {
  const multibody::Mechanism& m = mm.mechanism;
  const Deformation def = DeformationOf(mm, modes);
  const Mat modal = def.Q.fullPivLu().inverse() * def.map;
  // Amplitude: the largest deformation coordinate 1e-6 (m / rad): deflections of micrometres,
  // far in the linear range of the P-delta terms.
  const double eps = 1e-6 / def.Q.col(k).cwiseAbs().maxCoeff();
  multibody::InitialConditionSpec ic;
  ic.coordinates = mm.p0 + eps * modes.shapes.col(k);
  const double f = modes.frequencies_hz(k);
  multibody::SimulationOptions opt;
  opt.t_end = periods / f;
  opt.sample_rate = 64.0 * f;
  opt.integrator.rel_tol = 1e-10;
  opt.integrator.abs_tol = 1e-14;
  std::vector<double> t, eta;
  multibody::SimulationCallbacks cb;
  cb.on_sample = [&](const multibody::SampleView& s) {
    double e = 0.0;
    for (int i = 0; i < m.num_coordinates(); ++i) e += modal(k, i) * (s.coordinate(i) - mm.p0(i));
    t.push_back(s.t());
    eta.push_back(e);
  };
  multibody::RunData data(m);
  const multibody::SimulationStatus st = multibody::Simulate(m, &data, ic, opt, cb);
  EXPECT_TRUE(st.ok()) << st.Summary();

  std::vector<double> te, ln_a;
  for (size_t i = 1; i + 1 < eta.size(); ++i) {
    const double a = std::abs(eta[i - 1]), b = std::abs(eta[i]), c = std::abs(eta[i + 1]);
    if (!(b > a && b >= c) || eta[i - 1] * eta[i + 1] <= 0.0) continue;
    const double denom = a - 2.0 * b + c;
    const double x = 0.5 * (a - c) / denom;  // vertex offset in samples, |x| <= 1/2
    te.push_back(t[i] + x * (t[i + 1] - t[i]));
    ln_a.push_back(std::log(b - 0.25 * (a - c) * x));
  }
  Decay out;
  out.extrema = static_cast<int>(te.size());
  if (out.extrema < 4) return out;
  // Least squares ln|η| = c − σ t; half-periods between successive extrema.
  const int ne = out.extrema;
  double st_ = 0, sl = 0, stt = 0, stl = 0;
  for (int i = 0; i < ne; ++i) {
    st_ += te[i];
    sl += ln_a[i];
    stt += te[i] * te[i];
    stl += te[i] * ln_a[i];
  }
  const double sigma = -(ne * stl - st_ * sl) / (ne * stt - st_ * st_);
  const double half_period = (te[ne - 1] - te[0]) / (ne - 1);
  const double omega_d = std::numbers::pi / half_period;
  const double omega_n = std::sqrt(omega_d * omega_d + sigma * sigma);
  out.zeta = sigma / omega_n;
  out.frequency_hz = omega_n / kTwoPi;
  return out;
}

/// Modes of the rig's undamped twin (ideal joint), as BuildMechanism computes them.
multibody::MechanismModes UndampedModes(const Config& cfg, const MechanismModel& mm) {
  const MechanismModel undamped =
      BuildMechanismWithRodDamping(cfg, mm.rod, true, multibody::DampingSpec::None());
  return multibody::CalcMechanismModes(undamped.mechanism, undamped.p0,
                                       HeldForMechanismModes(undamped));
}

/// First-order (light damping) ratio of mechanism mode k under the rod's damping matrix D:
/// (Ψᵀ D_full Ψ)_kk / (2 ω_k).
double PredictedRatio(const MechanismModel& mm, const multibody::MechanismModes& modes, int k) {
  const multibody::Mechanism& m = mm.mechanism;
  const multibody::Body& rod = m.body(mm.conrod);
  const Vec psi =
      modes.shapes.col(k).segment(m.coordinate(mm.conrod, multibody::kFirstMode), rod.num_modes);
  return psi.dot(rod.D * psi) / (2.0 * kTwoPi * modes.frequencies_hz(k));
}

// Issue: damping.ratio = 0.02 must be the ratio the rod's modes show in the assembled
// mechanism. Measured by the free decay of mechanism modes 1–3 (10 periods each): within 5 % of
// the request (measured 0.0200017, 0.0200000, 0.0200000). The old clamped-frame damping
// (DampingSpec::ModalRatio on the rod's own modes, 13.2 / 129.7 / 362.4 Hz: a cantilever from
// the big-end node carrying the small-end clamp) gives the mechanism's modes (50.6 / 236.9 /
// 260.7 Hz) 0.059 and 0.112 on modes 1 and 2 (the light-damping prediction
// (Ψᵀ D Ψ)_kk / 2ω_k agrees), so this test fails with it.
TEST(MechanismDamping, FreeDecayOfTheAssembledRigShowsTheRequestedRatio) {
  const Config cfg = RigAtRest();
  const MechanismModel mm = BuildMechanism(cfg, nullptr);
  const multibody::Body& rod = mm.mechanism.body(mm.conrod);
  const int n = rod.num_modes;
  ASSERT_EQ(mm.mechanism_frequencies_hz.size(), n);
  ASSERT_EQ(mm.mechanism_damping_ratios.size(), n);
  for (int i = 0; i < n; ++i) EXPECT_EQ(mm.mechanism_damping_ratios(i), kRequestedRatio);

  // The modes of the undamped mechanism are those BuildMechanism reports.
  const multibody::MechanismModes modes = UndampedModes(cfg, mm);
  ASSERT_EQ(modes.num_modes(), n);
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(modes.frequencies_hz(i), mm.mechanism_frequencies_hz(i),
                1e-12 * modes.frequencies_hz(i));
    Record("mechanism_f" + std::to_string(i + 1) + "_hz", modes.frequencies_hz(i));
    Record("clamped_frame_f" + std::to_string(i + 1) + "_hz", rod.modal_frequencies_hz(i));
  }

  const MechanismModel old = BuildMechanismWithRodDamping(
      cfg, mm.rod, true, multibody::DampingSpec::ModalRatio({kRequestedRatio}));
  for (const int k : {0, 1, 2}) {
    const Decay now = FreeDecay(mm, modes, k, 10.0);
    const std::string mode = "mode" + std::to_string(k + 1);
    Record(mode + "_measured_zeta", now.zeta);
    Record(mode + "_measured_frequency_hz", now.frequency_hz);
    ASSERT_GE(now.extrema, 18) << mode;
    EXPECT_NEAR(now.frequency_hz, modes.frequencies_hz(k), 1e-3 * modes.frequencies_hz(k)) << mode;
    EXPECT_NEAR(now.zeta, kRequestedRatio, 0.05 * kRequestedRatio) << mode;
    Record(mode + "_clamped_frame_predicted_zeta", PredictedRatio(old, modes, k));
    if (k == 1) {  // mode 1 happens to get 2.02 % on this rig's clamped-frame basis too
      const Decay before = FreeDecay(old, modes, k, 10.0);
      Record(mode + "_clamped_frame_measured_zeta", before.zeta);
      EXPECT_GT(std::abs(before.zeta - kRequestedRatio), 0.05 * kRequestedRatio) << mode;
    }
  }
}

// damping.type = band picks each mode's band by its frequency in the mechanism: mode 1
// (50.6 Hz) gets 1 %, modes 2–3 (237, 261 Hz) 10 %. The clamped-frame bands put the rod's own
// mode 2 (129.7 Hz) at 10 % and its mode 1 (13.2 Hz) at 1 %.
TEST(MechanismDamping, BandDampingPicksItsBandsFromTheMechanismFrequencies) {
  Config cfg = RigAtRest();
  cfg.SetAssignment("damping.type=band");
  const MechanismModel mm = BuildMechanism(cfg, nullptr);
  const multibody::MechanismModes modes = UndampedModes(cfg, mm);
  const multibody::DampingSpec band = multibody::DampingSpec::FrequencyBand();
  for (int i = 0; i < modes.num_modes(); ++i) {
    const double f = modes.frequencies_hz(i);
    EXPECT_EQ(mm.mechanism_damping_ratios(i), band.BandRatio(f)) << f << " Hz";
  }
  // Modes 1 and 2 lie outside the band's transitions: 1 % and 10 % exactly.
  ASSERT_LT(modes.frequencies_hz(0), band.band_low_limit_hz / std::sqrt(2.0));
  ASSERT_GT(modes.frequencies_hz(1), band.band_low_limit_hz * std::sqrt(2.0));
  const Decay mode1 = FreeDecay(mm, modes, 0, 10.0);
  const Decay mode2 = FreeDecay(mm, modes, 1, 6.0);  // 10 %: 6 periods leave 2 % of the start
  Record("band_mode1_measured_zeta", mode1.zeta);
  Record("band_mode2_measured_zeta", mode2.zeta);
  const MechanismModel old =
      BuildMechanismWithRodDamping(cfg, mm.rod, true, multibody::DampingSpec::FrequencyBand());
  Record("band_mode1_clamped_frame_predicted_zeta", PredictedRatio(old, modes, 0));
  Record("band_mode2_clamped_frame_predicted_zeta", PredictedRatio(old, modes, 1));
  EXPECT_NEAR(mode1.zeta, band.band_low_ratio, 0.05 * band.band_low_ratio);
  EXPECT_NEAR(mode2.zeta, band.band_mid_ratio, 0.05 * band.band_mid_ratio);
}

// damping.type = material gives every mode of the mechanism ζ = η / 2 of the rod's material
// (steel: η = 4e-4, Cremer, Heckl & Petersson), and rod.loss_factor overrides η. The free
// decay of mode 1 with η = 0.02 measures ζ = 0.01.
TEST(MechanismDamping, MaterialDampingGivesEveryModeHalfTheLossFactor) {
  Config cfg = RigAtRest();
  cfg.SetAssignment("damping.type=material");
  const MechanismModel steel = BuildMechanism(cfg, nullptr);
  ASSERT_GT(steel.mechanism_damping_ratios.size(), 3);
  for (int i = 0; i < steel.mechanism_damping_ratios.size(); ++i)
    EXPECT_DOUBLE_EQ(steel.mechanism_damping_ratios(i), 2e-4);
  cfg.SetAssignment("rod.loss_factor=0.02");
  const MechanismModel lossy = BuildMechanism(cfg, nullptr);
  const multibody::MechanismModes modes = UndampedModes(cfg, lossy);
  const Decay mode1 = FreeDecay(lossy, modes, 0, 10.0);
  EXPECT_NEAR(mode1.zeta, 0.01, 0.05 * 0.01);
  EXPECT_THROW(
      {
        cfg.SetAssignment("rod.loss_factor=-1");
        (void)BuildMechanism(cfg, nullptr);
      },
      InputError);
}

// The exact rod (rod.type = exact) realises the same modal damping through its co-rotated modal
// damping (multibody/corotated_damping.h): without integrating, Ψᵀ C Ψ = diag(2 ζ ω) for its
// modes up to kExactRodModalLimitHz and below critical (the Kelvin–Voigt part β K and the
// co-rotated part Bᵀ Y diag(c) Yᵀ B), β ω / 2 above; and the free decay of its modes 1–2 in the
// assembled rig measures the requested ratio (ratio 2 %; band: 1 % and 10 %) within 5 %, as the
// reduced rod's does (the Kelvin–Voigt damping fitted to mode 1 it had before gave mode 2 4.7 %
// instead of 10 %).
TEST(MechanismDamping, ExactRodFreeDecayShowsTheRequestedRatios) {
  for (const char* type : {"ratio", "band"}) {
    Config cfg = RigAtRest();
    cfg.SetAssignment("rod.type=exact");
    cfg.SetAssignment(std::string("damping.type=") + type);
    SCOPED_TRACE(type);
    const MechanismModel mm = BuildMechanism(cfg, nullptr);
    const MechanismModel undamped =
        BuildMechanismWithRodDamping(cfg, nullptr, true, multibody::DampingSpec::None());
    const multibody::MechanismModes modes = multibody::CalcMechanismModes(
        undamped.mechanism, undamped.p0, HeldForMechanismModes(undamped));
    ASSERT_EQ(mm.mechanism_damping_ratios.size(), modes.num_modes());
    const Vec asked = DampingRatiosFor(mm.damping, modes.frequencies_hz);
    for (int i = 0; i < modes.num_modes() && modes.frequencies_hz(i) <= kExactRodModalLimitHz &&
                    asked(i) < 1.0;
         ++i)
      EXPECT_EQ(mm.mechanism_damping_ratios(i), asked(i)) << modes.frequencies_hz(i) << " Hz";
    // Ψᵀ C Ψ from the damped model's residual: C ψ = ∂F2/∂v ψ at rest with the states' rates
    // eliminated (F2 holds Bᵀ Y diag(c) η̇ with η̇ = Yᵀ B v); a central difference in v removes
    // the bodies' velocity-quadratic terms.
    const multibody::Mechanism& m = mm.mechanism;
    multibody::RunData data(m);
    const int np = m.num_coordinates(), nz = m.num_element_states();
    auto F2 = [&](const Vec& v) {
      Vec y = Vec::Zero(m.size()), yp = Vec::Zero(m.size());
      y.head(np) = mm.p0;
      y.segment(np, np) = v;
      const Vec r = multibody::CalcResidual(m, &data, 0.0, y, yp);
      yp.segment(m.z_offset(), nz) = -r.segment(m.z_offset(), nz);  // η̇ = Yᵀ B v
      return Vec(multibody::CalcResidual(m, &data, 0.0, y, yp).segment(np, np));
    };
    Mat C(np, modes.num_modes());
    for (int j = 0; j < modes.num_modes(); ++j)
      C.col(j) = (F2(1e-3 * modes.shapes.col(j)) - F2(-1e-3 * modes.shapes.col(j))) / 2e-3;
    const Mat modal = modes.shapes.transpose() * C;
    const Vec want = 2.0 * mm.mechanism_damping_ratios.cwiseProduct(kTwoPi * modes.frequencies_hz);
    const double off = (modal - Mat(modal.diagonal().asDiagonal())).cwiseAbs().maxCoeff();
    EXPECT_LT(off, 1e-6 * want.maxCoeff());
    for (int i = 0; i < modes.num_modes(); ++i)
      EXPECT_NEAR(modal(i, i), want(i), 1e-6 * want(i)) << modes.frequencies_hz(i) << " Hz";
    for (const int k : {0, 1}) {
      const Decay d = FreeDecay(mm, modes, k, std::string(type) == "band" && k == 1 ? 6.0 : 10.0);
      const std::string mode = std::string(type) + "_exact_mode" + std::to_string(k + 1);
      Record(mode + "_measured_zeta", d.zeta);
      ASSERT_GE(d.extrema, 10) << mode;
      EXPECT_NEAR(d.frequency_hz, modes.frequencies_hz(k), 1e-3 * modes.frequencies_hz(k)) << mode;
      EXPECT_NEAR(d.zeta, asked(k), 0.05 * asked(k)) << mode;
    }
  }
}

// Without integrating: every rod basis, the clearance joint (its ideal twin is the reference,
// so both share one D), the DC-motor drive (no driver constraint: the held crank angle alone
// fixes the crank) and the pendulum (rod frame angle held) give the mechanism's modes exactly
// the requested ratios, Ψᵀ D Ψ = diag(2 ζ ω).
TEST(MechanismDamping, EveryRodBasisAndMechanismGetsTheRequestedModalDamping) {
  struct Case {
    const char* preset;
    std::vector<std::string> sets;
  };
  const std::vector<Case> cases = {
      {"flexible-rig", {"joint.type=ideal", "damping.type=ratio", "damping.ratio=0.03"}},
      {"flexible-rig",
       {"joint.type=ideal", "damping.type=ratio", "reduction.method=orthonormal-cb"}},
      {"flexible-rig", {"joint.type=ideal", "damping.type=ratio", "reduction.method=free-free"}},
      {"flexible-rig",
       {"joint.type=ideal", "damping.type=ratio", "reduction.method=full", "rod.elements=10"}},
      {"flexible-rig", {"joint.type=clearance", "damping.type=band"}},
      {"flexible-rig", {"joint.type=ideal", "damping.type=ratio", "drive.type=motor"}},
      {"flexible-pendulum", {"damping.type=ratio", "damping.ratio=0.05"}},
  };
  for (const Case& c : cases) {
    Config cfg;
    cfg.LoadToml(FindPreset(c.preset)->toml, c.preset);
    std::string label = c.preset;
    for (const std::string& s : c.sets) {
      cfg.SetAssignment(s);
      label += " " + s;
    }
    SCOPED_TRACE(label);
    const MechanismModel mm = BuildMechanism(cfg, nullptr);
    const multibody::MechanismModes modes = UndampedModes(cfg, mm);
    const multibody::Mechanism& m = mm.mechanism;
    const int n = m.body(mm.conrod).num_modes;
    ASSERT_EQ(modes.num_modes(), n);
    ASSERT_EQ(mm.mechanism_damping_ratios.size(), n);
    const Mat Q = modes.shapes.middleRows(m.coordinate(mm.conrod, multibody::kFirstMode), n);
    const Mat got = Q.transpose() * m.body(mm.conrod).D * Q;
    const Vec want = 2.0 * mm.mechanism_damping_ratios.cwiseProduct(kTwoPi * modes.frequencies_hz);
    Mat want_matrix = want.asDiagonal();
    EXPECT_LT((got - want_matrix).cwiseAbs().maxCoeff(), 1e-9 * want.cwiseAbs().maxCoeff());
    if (cfg.Text("joint.type") == "clearance") {
      const MechanismModel twin = BuildMechanism(cfg, mm.rod, /*ideal_joint=*/true);
      EXPECT_EQ(twin.mechanism.body(twin.conrod).D, m.body(mm.conrod).D);
    }
  }
}

}  // namespace
}  // namespace flexrod
