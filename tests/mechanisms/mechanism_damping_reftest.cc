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

/// Free decay of mechanism mode k of `mm`: the rod starts at rest deflected along the mode
/// (elastic coordinates ε Q_k; the position Newton puts the frame and slider on the
/// constraints), is integrated for `periods` periods, and the modal coordinate
/// η_k = (Q⁻¹ q)_k — Q the modes' elastic rows, which parametrise the motion — is sampled at
/// 64 points per period. Extrema of η_k (parabolic interpolation) give the damped period and
/// the decay rate σ (least squares on ln|η|), ζ = σ / √(ω_d² + σ²).
Decay FreeDecay(const MechanismModel& mm, const multibody::MechanismModes& modes, int k,
                double periods) {
  const multibody::Mechanism& m = mm.mechanism;
  const int n = m.body(mm.conrod).num_modes, q0 = m.coordinate(mm.conrod, multibody::kFirstMode);
  const Mat Q = modes.shapes.middleRows(q0, n);
  const Mat Qinv = Q.fullPivLu().inverse();
  // Amplitude: the largest elastic coordinate 1e-6 (CB interface dofs in m / rad): deflections
  // of micrometres, far in the linear range of the P-delta terms.
  const double eps = 1e-6 / Q.col(k).cwiseAbs().maxCoeff();
  multibody::InitialConditionSpec ic;
  ic.coordinates = mm.p0;
  ic.coordinates.segment(q0, n) += eps * Q.col(k);
  const double f = modes.frequencies_hz(k);
  multibody::SimulationOptions opt;
  opt.t_end = periods / f;
  opt.sample_rate = 64.0 * f;
  opt.integrator.rel_tol = 1e-10;
  opt.integrator.abs_tol = 1e-14;
  std::vector<double> t, eta;
  multibody::SimulationCallbacks cb;
  cb.on_sample = [&](const multibody::SampleView& s) {
    Vec q(n);
    for (int i = 0; i < n; ++i) q(i) = s.coordinate(q0 + i);
    t.push_back(s.t());
    eta.push_back((Qinv.row(k) * q)(0));
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
