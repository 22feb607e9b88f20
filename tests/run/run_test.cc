// SPDX-License-Identifier: GPL-3.0-or-later
// The run layer end to end: builder geometry, channels and their signs, energy, bad input.
#include "run/run.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "common/error.h"
#include "input/presets.h"

namespace flexrod {
namespace {

/// Exact slider-crank kinematics: journal position x(θ) = r cos θ + sqrt(ℓ² − (e − r sin θ)²)
/// (crank axis at the origin, guide at y = e); derivatives by a 5-point stencil in θ
/// (truncation ~h⁴ = 1e-12 relative for h = 1e-3).
struct ExactCrank {
  double r, l, e;
  double x(double th) const {
    return r * std::cos(th) + std::sqrt(l * l - std::pow(e - r * std::sin(th), 2));
  }
  double dx(double th, double h = 1e-3) const {
    return (-x(th + 2 * h) + 8 * x(th + h) - 8 * x(th - h) + x(th - 2 * h)) / (12 * h);
  }
  double ddx(double th, double h = 1e-3) const {
    return (-x(th + 2 * h) + 16 * x(th + h) - 30 * x(th) + 16 * x(th - h) - x(th - 2 * h)) /
           (12 * h * h);
  }
};

double MaxRelativeError(const study::TimeSeries& ts, const ExactCrank& k, double w,
                        const char* what) {
  const auto th = ts.values("crank_angle");
  const auto ch = ts.values(what);
  double err = 0.0, scale = 0.0;
  for (size_t i = 0; i < th.size(); i += 7) {
    double exact = 0.0;
    if (std::string(what) == "slider_position") exact = k.x(th[i]);
    if (std::string(what) == "slider_velocity") exact = w * k.dx(th[i]);
    if (std::string(what) == "slider_acceleration") exact = w * w * k.ddx(th[i]);
    err = std::max(err, std::abs(ch[i] - exact));
    scale = std::max(scale, std::abs(exact));
  }
  return err / scale;
}

TEST(RigidRig, IdealJointWithSliderOffsetMatchesExactKinematics) {
  const Config cfg = LoadRunInput(
      "rigid-rig", {"joint.type=ideal", "slider.offset=12 mm", "slider.damping=0",
                    "slider.friction=0", "sim.settle=0 s", "sim.capture=0.35 s",
                    "sim.sample_rate=20 kHz", "sim.rel_tol=1e-10", "sim.abs_tol=1e-12"});
  const RunResult r = RunSimulation(cfg);
  ASSERT_TRUE(r.ok()) << r.status.Summary();
  const ExactCrank k{0.05, 0.30, 0.012};
  const double w = 177.0 * 2 * M_PI / 60;
  EXPECT_LT(MaxRelativeError(r.channels, k, w, "slider_position"), 1e-8);
  EXPECT_LT(MaxRelativeError(r.channels, k, w, "slider_velocity"), 1e-7);
  EXPECT_LT(MaxRelativeError(r.channels, k, w, "slider_acceleration"), 1e-6);
}

// sim.eliminate_prescribed: the ideal rig integrates 25 unknowns instead of 40 (the crank's x,
// y, θ and the slider's y, θ dropped with their velocities and GGL multipliers μ;
// multibody/prescribed.h) and the two runs agree. References: the full-DAE run at the same
// tolerance (rel_tol 1e-10: slider acceleration, crank torque and bearing force to 1e-6 of their
// peaks), and the slider's equation of motion along the guide, −F_bearing,x = m a + c v, which
// both must satisfy (measured: 7e-9 and 1.1e-8 of the peak force). Guide Coulomb friction is off:
// its 1 mm/s regularisation makes the reaction a steep ramp at each velocity reversal, where the
// two runs differ by 3e-5 of the peak.
TEST(RigidRig, EliminatingThePrescribedCoordinatesKeepsTheRun) {
  auto run = [](const char* eliminate) {
    return RunSimulation(LoadRunInput(
        "rigid-rig",
        {"joint.type=ideal", "slider.friction=0 N", "sim.settle=0 s", "sim.capture=0.2 s",
         "sim.sample_rate=10 kHz", "sim.rel_tol=1e-10", "sim.abs_tol=1e-12", eliminate}));
  };
  const RunResult reduced = run("sim.eliminate_prescribed=true"),
                  full = run("sim.eliminate_prescribed=false");
  ASSERT_TRUE(reduced.ok() && full.ok());
  EXPECT_EQ(full.summary["integrator"]["unknowns"].get<int>(),
            40);  // 9 p, 9 v, 9 λ, 9 μ, 4 energies
  EXPECT_EQ(reduced.summary["integrator"]["unknowns"].get<int>(), 25);
  const Config preset = LoadRunInput("rigid-rig", {});
  const double mass = preset.Quantity("slider.mass"), damping = preset.Quantity("slider.damping");
  for (const RunResult* r : {&reduced, &full}) {
    const auto& a = r->channels.values("slider_acceleration");
    const auto& v = r->channels.values("slider_velocity");
    const auto& fx = r->channels.values("bearing_force_x");  // on the rod's bush
    double worst = 0.0, peak = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
      worst = std::max(worst, std::abs(-fx[i] - (mass * a[i] + damping * v[i])));
      peak = std::max(peak, std::abs(fx[i]));
    }
    EXPECT_LT(worst, 1e-7 * peak);
  }
  for (const char* ch : {"slider_acceleration", "crank_torque", "bearing_force"}) {
    const auto& a = reduced.channels.values(ch);
    const auto& b = full.channels.values(ch);
    ASSERT_EQ(a.size(), b.size());
    double diff = 0.0, peak = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
      diff = std::max(diff, std::abs(a[i] - b[i]));
      peak = std::max(peak, std::abs(b[i]));
    }
    EXPECT_LT(diff, 1e-6 * peak) << ch;
  }
}

// The stiff-rod limit (10⁴ × E reproduces the rigid kinematics) is tested at the engine level
// in tests/multibody/flexible_rod_test.cc on a coarse rod; on the rig's 40-element rod its MHz
// modes make the run too slow for the unit suite.

TEST(FlexibleRig, EnergyBalanceClosesAndConstraintsHold) {
  const RunResult r =
      RunSimulation(LoadRunInput("flexible-rig", {"joint.type=ideal", "sim.settle=0.2 s",
                                                  "sim.capture=0.4 s", "sim.sample_rate=10 kHz"}));
  ASSERT_TRUE(r.ok());
  // The driver-work quadrature is outside IDA's error test (its rate −λθ̇ carries the index-2
  // multiplier noise, multibody/simulate.h), so the balance closes to ~1e-5 at default tolerances.
  EXPECT_LT(r.summary["energy"]["relative_balance_error"].get<double>(), 1e-4);
  // Default tolerances (abs 1e-8): position constraints hold to ~1e-9 m (1e-9 at 1e-10, engine
  // test).
  EXPECT_LT(r.summary["max_constraint_violation [m]"].get<double>(), 1e-8);
  EXPECT_GT(r.summary["rod"]["safety_factor"].get<double>(), 1.0);
  // Positive acceleration points away from the crank: at θ = 0 (index) the slider is at its
  // outer dead centre and accelerates towards the crank.
  EXPECT_LT(r.channels.values("slider_acceleration")[0], 0.0);
}

// sim.start = steady finds the periodic state: the capture starts at the crank index (here a
// quarter turn after the initial angle), its rod deflection over the first revolution equals
// that of a run settled for 20 revolutions from rest at the same crank angles, to the steady
// search's tolerance (1000 · rel_tol of the peak; the settled run's own transient is far below).
TEST(FlexibleRig, SteadyStartReachesThePeriodicStateOfALongSettling) {
  // rel_tol 3e-8: the band damping now refers to the rig's modes in the mechanism (mode 1 at
  // 50.6 Hz gets 1 %, it had about 3.8 % on the clamped-frame basis), so the transient decays
  // 0.39× per revolution and the search's revolution-to-revolution change must not be limited by
  // the integration error (at 1e-7 the difference to the long settling was 8.8e-4 of the peak).
  const std::vector<std::string> common = {"joint.type=ideal",  "drive.initial_angle=90 deg",
                                           "sim.capture=0.3 s", "sim.sample_rate=10 kHz",
                                           "sim.rel_tol=3e-8",  "sim.abs_tol=1e-11"};
  std::vector<std::string> steady_sets = common, settled_sets = common;
  steady_sets.push_back("sim.start=steady");
  settled_sets.push_back("sim.settle=6 s");
  const RunResult steady = RunSimulation(LoadRunInput("flexible-rig", steady_sets));
  const RunResult settled = RunSimulation(LoadRunInput("flexible-rig", settled_sets));
  ASSERT_TRUE(steady.ok() && settled.ok());
  const nlohmann::json& info = steady.summary["steady_start"];
  EXPECT_TRUE(info["converged"].get<bool>()) << info.dump();
  EXPECT_NEAR(info["tolerance"].get<double>(), 3e-5, 1e-16);  // 1e3 × sim.rel_tol
  const auto a = steady.channels.values("crank_angle"), b = settled.channels.values("crank_angle");
  EXPECT_NEAR(std::remainder(a.front(), 2 * std::numbers::pi), 0.0, 1e-9);  // sim.index_angle = 0
  EXPECT_NEAR(std::remainder(b.front(), 2 * std::numbers::pi), 0.0, 1e-9);
  const auto da = steady.channels.values("rod_deflection"),
             db = settled.channels.values("rod_deflection");
  const size_t per_rev = 3000;  // 0.3 s at 200 rpm, 10 kHz
  ASSERT_GE(std::min(da.size(), db.size()), per_rev);
  double diff = 0.0, peak = 0.0;
  for (size_t i = 0; i < per_rev; ++i) {
    diff = std::max(diff, std::abs(da[i] - db[i]));
    peak = std::max(peak, std::abs(db[i]));
  }
  EXPECT_LT(diff, 3e-4 * peak) << "peak " << peak;
}

// A steady search cut short (sim.steady_revolutions = 2: one comparison, from rest, far from the
// periodic state) says so: converged false, its revolutions and last change, a warning, and the
// capture from where it stopped.
TEST(FlexibleRig, SteadyStartThatDoesNotRepeatWarnsAndCapturesFromWhereItStopped) {
  const RunResult r = RunSimulation(LoadRunInput(
      "flexible-rig", {"joint.type=ideal", "sim.capture=0.1 s", "sim.sample_rate=10 kHz",
                       "sim.rel_tol=1e-7", "sim.start=steady", "sim.steady_revolutions=2"}));
  ASSERT_TRUE(r.ok()) << r.status.Summary();
  const nlohmann::json& info = r.summary["steady_start"];
  EXPECT_FALSE(info["converged"].get<bool>()) << info.dump();
  EXPECT_EQ(info["revolutions"].get<int>(), 2);
  EXPECT_GT(info["relative_change"].get<double>(), info["tolerance"].get<double>());
  ASSERT_TRUE(r.summary.contains("warnings"));
  bool warned = false;
  for (const auto& w : r.summary["warnings"])
    warned |= w.get<std::string>().find("did not repeat") != std::string::npos;
  EXPECT_TRUE(warned) << r.summary["warnings"].dump();
  // The capture starts at the crank index two revolutions after the first one (t = 0.6 s at 200
  // rpm).
  EXPECT_EQ(r.channels.num_samples(), 1000u);
  EXPECT_NEAR(std::remainder(r.channels.values("crank_angle").front(), 2 * std::numbers::pi), 0.0,
              1e-9);
  EXPECT_NEAR(r.channels.start_time(), 0.6, 1e-9);
}

TEST(FlexiblePendulum, UndampedConservesEnergy) {
  const RunResult r = RunSimulation(
      LoadRunInput("flexible-pendulum", {"sim.capture=0.4 s", "sim.sample_rate=5 kHz"}));
  ASSERT_TRUE(r.ok()) << r.status.Summary();
  EXPECT_LT(r.summary["energy"]["relative_balance_error"].get<double>(), 1e-6);
  // It actually swung: the rod turned through more than 60 degrees.
  double min_angle = 0.0;
  for (double a : r.channels.values("rod_angle")) min_angle = std::min(min_angle, a);
  EXPECT_LT(min_angle, -M_PI / 3);
}

// DC motor on armature-voltage control: drive.speed is the no-load crank speed, the slope is
// the rated line's. Every sample lies on T = c (ω_set − ω) with c = ratio² T_s / ω₀ =
// 9 · 20 N m / 1900 rpm; the mean speed droops below the set speed by mean load / c, and
// the motor's work closes the energy balance.
TEST(RigidRig, MotorDriveRunsAtTheSetSpeedOnTheRatedTorqueLine) {
  const Config cfg = LoadRunInput(
      "rigid-rig", {"drive.type=motor", "drive.speed=177 rpm", "joint.type=ideal",
                    "sim.settle=0.5 s", "sim.capture=0.7 s", "sim.sample_rate=20 kHz"});
  const RunResult r = RunSimulation(cfg);
  ASSERT_TRUE(r.ok()) << r.status.Summary();
  constexpr double kRpm = 2.0 * std::numbers::pi / 60.0;
  const double w_set = 177 * kRpm, c = 9.0 * 20.0 / (1900 * kRpm);
  const auto w = r.channels.values("crank_speed"), torque = r.channels.values("crank_torque");
  double worst = 0.0, mean_torque = 0.0;
  for (size_t i = 0; i < w.size(); ++i) {
    worst = std::max(worst, std::abs(torque[i] - c * (w_set - w[i])));
    mean_torque += torque[i] / static_cast<double>(w.size());
  }
  EXPECT_LT(worst, 1e-9 * c * w_set);
  const double mean = r.summary["crank_speed"]["mean [rad/s]"].get<double>();
  EXPECT_GT(mean, 0.95 * w_set);  // the ideal rig's load (guide damping and friction) is light
  EXPECT_LT(mean, w_set);
  EXPECT_GT(mean_torque, 0.0);  // the motor drives against the guide's losses
  EXPECT_NEAR(r.summary["crank_speed"]["set [rad/s]"].get<double>(), w_set, 1e-12 * w_set);
  EXPECT_LT(r.summary["energy"]["relative_balance_error"].get<double>(), 1e-4);
}

// The crank torque is the driver constraint's multiplier. With a driven crank and an ideal
// joint the rigid rig has no degree of freedom, so nothing but the Newton test checks the
// multipliers; at each guide-friction reversal (1 N Coulomb over 1 mm/s) they jump. Power
// balance at every instant, independent of the multiplier: τ ω = dT/dt + dD/dt (kinetic
// energy T and dissipated energy D from their own channels, central differences at
// 20 kHz, truncation ~1e-5 of the peak). At the default rel_tol 1e-6 the torque was 20×
// too large after each reversal (peak 25.9 N m against 1.2724 N m, independent Newton–Euler
// inverse dynamics at rtol 1e-10) and the energy balance 9 % of the peak kinetic energy.
// Now 1.1e-3 of the peak power, a few ms after a reversal: the multipliers' Newton weights
// are scaled by the step (3.6 ms here, IntegratorOptions), which leaves them ~1e-3 of play.
TEST(RigidRig, IdealJointCrankTorqueCarriesThePowerAtTheDefaultTolerance) {
  const RunResult r =
      RunSimulation(LoadRunInput("rigid-rig", {"joint.type=ideal", "sim.settle=0.5 s",
                                               "sim.capture=1 s", "sim.sample_rate=20 kHz"}));
  ASSERT_TRUE(r.ok()) << r.status.Summary();
  const auto w = r.channels.values("crank_speed");
  const auto torque = r.channels.values("crank_torque"), ke = r.channels.values("energy_kinetic");
  const auto dis = r.channels.values("energy_dissipated");
  double worst = 0.0, peak = 0.0;
  for (size_t i = 1; i + 1 < w.size(); ++i) {
    const double dt = r.channels.time(i + 1) - r.channels.time(i - 1);
    const double power = (ke[i + 1] - ke[i - 1] + dis[i + 1] - dis[i - 1]) / dt;
    worst = std::max(worst, std::abs(torque[i] * w[i] - power));
    peak = std::max(peak, std::abs(torque[i] * w[i]));
  }
  EXPECT_NEAR(peak, 1.2724 * 177 * 2 * std::numbers::pi / 60, 1e-3 * peak);
  EXPECT_LT(worst, 3e-3 * peak);
  EXPECT_LT(r.summary["energy"]["relative_balance_error"].get<double>(), 1e-3);
}

TEST(RunInput, BadInputNamesKeyValueAndRule) {
  auto expect_error = [](const std::vector<std::string>& sets, const std::string& key) {
    try {
      RunSimulation(LoadRunInput("flexible-rig", sets));
      ADD_FAILURE() << "no InputError for " << key;
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), key) << e.what();
    }
  };
  expect_error({"rod.height=-3 mm"}, "rod.height");
  expect_error({"crank.length=400 mm"}, "rod.length");  // rod shorter than the crank throw
  expect_error({"slider.mass=0"}, "slider.mass");
  expect_error({"drive.speed=-5 rpm"}, "drive.speed");
  expect_error({"rod.type=rigid", "sim.start=steady"}, "sim.start");  // no elastic state to settle
  expect_error({"drive.type=motor", "sim.start=steady"}, "sim.start");  // no fixed period
  expect_error({"sim.steady_revolutions=1"}, "sim.steady_revolutions");
  // Keys the multibody layer checks again under its own names: the error names the input key.
  expect_error({"slider.damping=-1"}, "slider.damping");
  expect_error({"slider.friction=-1 N"}, "slider.friction");
  expect_error({"slider.friction_velocity=0"}, "slider.friction_velocity");
  expect_error({"drive.type=motor", "motor.belt_ratio=0"}, "motor.belt_ratio");
  // 700 rpm at the crank needs 2100 rpm at the motor, beyond its 1900 rpm at rated voltage.
  expect_error({"drive.type=motor", "drive.speed=700 rpm"}, "drive.speed");
  expect_error({"drive.type=profile", "drive.profile=0:0,0.5:100,0.4:200"}, "drive.profile");
  // Positions on the 0.28 m rod (0.3 m used to read past the rod's nodes), both rod models.
  for (const char* type : {"rod.type=flexible", "rod.type=exact"}) {
    expect_error({type, "output.midspan=0.3 m"}, "output.midspan");
    expect_error({type, "output.midspan=-1 mm"}, "output.midspan");
    expect_error({type, "output.gauges=0.1 m, 0.29 m"}, "output.gauges");
  }
  expect_error({"sim.capture=15 us"}, "sim.capture");  // 1.5 samples at 100 kHz
  EXPECT_THROW(LoadRunInput("flexible-rig", {"rod.elements=1e12"}), InputError);  // not a valid int
  EXPECT_THROW(LoadRunInput("flexible-rig", {"rod.colour=red"}), InputError);
  EXPECT_THROW(LoadRunInput("flexible-rig", {"rod.height=tall"}), InputError);
  EXPECT_THROW(LoadRunInput("flexible-rig", {"drive.speed=3 kg"}), InputError);
  EXPECT_THROW(LoadRunInput("flexible-rig", {"rod.material=unobtainium"}), InputError);
}

// A crank angle is reduced to [0, 2π): 90° + 10¹² turns is 90°, for the start and the index
// (unreduced, the run never ended: the relative tolerance on θ ≈ 6e12 rad allowed anything).
TEST(RunInput, CrankAnglesAreReducedModuloOneTurn) {
  const std::vector<std::string> base = {"rod.type=rigid", "joint.type=ideal", "sim.settle=0 s",
                                         "sim.capture=0.05 s"};
  auto run = [&](const std::string& initial, const std::string& index) {
    std::vector<std::string> sets = base;
    sets.push_back("drive.initial_angle=" + initial);
    sets.push_back("sim.index_angle=" + index);
    const RunResult r = RunSimulation(LoadRunInput("flexible-rig", sets));
    EXPECT_TRUE(r.ok()) << r.status.message;
    return r;
  };
  const RunResult plain = run("90 deg", "10 deg");
  const RunResult turned = run("360000000000090 deg", "-3600000000350 deg");
  ASSERT_EQ(plain.channels.num_samples(), turned.channels.num_samples());
  EXPECT_NEAR(plain.channels.start_time(), turned.channels.start_time(), 1e-4);
  const auto a = plain.channels.values("slider_acceleration");
  const auto b = turned.channels.values("slider_acceleration");
  double worst = 0.0, peak = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, std::abs(a[i] - b[i]));
    peak = std::max(peak, std::abs(a[i]));
  }
  // 3.6e14 deg is 6.3e12 rad, whose double carries the angle to its ulp, 1e-3 rad: the two
  // runs differ by that much start angle (5e-5 s of motion at 200 rpm), no more.
  EXPECT_LT(worst, 1e-2 * peak);
}

// --check's comparison: each headline figure present in both summaries with its relative
// difference to the reference, figures either lacks left out, the largest |difference| named.
TEST(AccuracyCheck, ComparesEveryHeadlineFigureBothSummariesHave) {
  const nlohmann::json run = {
      {"slider_acceleration",
       {{"peak_positive", 101.0},
        {"peak_negative", 99.0},
        {"per_revolution_abs", {{"p95", 100.0}}}}},
      {"load_amplification", {{"slider_acceleration_positive", 7.7}, {"bearing_force", 4.0}}},
      {"rod", {{"peak_gauge_stress [Pa]", 3.0e7}}}};
  const nlohmann::json ref = {{"slider_acceleration",
                               {{"peak_positive", 100.0},
                                {"peak_negative", 100.0},
                                {"per_revolution_abs", {{"p95", 100.0}}}}},
                              {"load_amplification", {{"slider_acceleration_positive", 7.0}}},
                              {"rod", {{"peak_gauge_stress [Pa]", 3.0e7}}}};
  const nlohmann::json c = CompareHeadlineFigures(run, ref);
  const auto& f = c["figures"];
  EXPECT_EQ(f.size(), 5u);  // bearing_force: the reference lacks it
  EXPECT_NEAR(f["slider_acceleration.peak_positive"]["difference [%]"].get<double>(), 1.0, 1e-12);
  EXPECT_NEAR(f["slider_acceleration.peak_negative"]["difference [%]"].get<double>(), -1.0, 1e-12);
  EXPECT_NEAR(f["slider_acceleration.per_revolution_abs.p95"]["difference [%]"].get<double>(), 0.0,
              1e-12);
  EXPECT_NEAR(f["load_amplification.slider_acceleration_positive"]["difference [%]"].get<double>(),
              10.0, 1e-12);
  EXPECT_EQ(f["rod.peak_gauge_stress [Pa]"]["unit"], "Pa");
  EXPECT_FALSE(f.contains("load_amplification.bearing_force"));
  EXPECT_NEAR(c["max_difference [%]"].get<double>(), 10.0, 1e-12);
  EXPECT_EQ(c["max_difference_figure"], "load_amplification.slider_acceleration_positive");
  // The check's tolerances are the run's, 100 times tighter, and must stay above the floor.
  const Config tight =
      TightenedForCheck(LoadRunInput("rigid-rig", {"sim.rel_tol=1e-7", "sim.abs_tol=1e-9"}));
  EXPECT_NEAR(tight.Quantity("sim.rel_tol"), 1e-9, 1e-24);
  EXPECT_NEAR(tight.Quantity("sim.abs_tol"), 1e-11, 1e-26);
  try {
    (void)TightenedForCheck(LoadRunInput("rigid-rig", {"sim.rel_tol=1e-13"}));
    ADD_FAILURE() << "a check below the rel_tol floor was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "--check");
  }
}

/// 95th percentile (type 7) of the per-revolution peaks of f, revolutions binned by the crank
/// angle: revolution k holds the samples with floor((θ − index) / 2π) = k. The last bin and a
/// first bin that starts after its index crossing are partial and left out. Independent of
/// study::SplitRevolutions' crossing search.
double PerRevolutionPeakP95(const std::vector<double>& f, std::span<const double> angle,
                            double index) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  auto bin = [&](double th) { return static_cast<long>(std::floor((th - index) / kTwoPi)); };
  long first = bin(angle.front());
  if (angle.front() - index - kTwoPi * static_cast<double>(first) > 1e-9) ++first;
  const long last = bin(angle.back());
  std::vector<double> peak(static_cast<size_t>(std::max(0L, last - first)), 0.0);
  for (size_t i = 0; i < f.size(); ++i) {
    const long k = bin(angle[i]);
    if (k >= first && k < last)
      peak[static_cast<size_t>(k - first)] = std::max(peak[static_cast<size_t>(k - first)], f[i]);
  }
  std::sort(peak.begin(), peak.end());
  const double h = 0.95 * static_cast<double>(peak.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(h));
  return lo + 1 < peak.size() ? peak[lo] + (h - static_cast<double>(lo)) * (peak[lo + 1] - peak[lo])
                              : peak[lo];
}

TEST(LoadAmplification, BearingForceOverRevolutionsMatchesItsDefinition) {
  // Rigid rig, 1 mm, 101 rpm, 5 complete revolutions: bearing_force_p95 is the ratio of the
  // 95th percentiles of the per-revolution peaks of |F| (real joint: √(Fn² + Ft²) of the
  // contact; ideal joint: the reaction), and bearing_force the ratio of the whole-window peaks.
  // Here the per-revolution peaks differ (measured ratios over the 5 revolutions: p95 164.729,
  // max 164.906, median 149.3), so the check tells the statistics apart.
  const Config cfg =
      LoadRunInput("rigid-rig", {"joint.clearance=1 mm", "drive.speed=101 rpm", "sim.settle=0.2 s",
                                 "sim.capture=3 s", "sim.sample_rate=20 kHz"});
  const RunResult r = RunSimulation(cfg);
  ASSERT_TRUE(r.ok() && r.ideal) << r.status.Summary();
  const auto fn = r.channels.values("contact_normal_force"),
             ft = r.channels.values("contact_friction_force");
  std::vector<double> real(fn.size()),
      ideal(r.ideal->values("bearing_force").begin(), r.ideal->values("bearing_force").end());
  for (size_t i = 0; i < fn.size(); ++i) real[i] = std::hypot(fn[i], ft[i]);
  const double index = cfg.Quantity("sim.index_angle");
  const double expected_p95 = PerRevolutionPeakP95(real, r.channels.values("crank_angle"), index) /
                              PerRevolutionPeakP95(ideal, r.ideal->values("crank_angle"), index);
  const double expected_peak =
      *std::max_element(real.begin(), real.end()) / *std::max_element(ideal.begin(), ideal.end());
  const auto& amp = r.summary["load_amplification"];
  EXPECT_NEAR(amp["bearing_force_p95"].get<double>(), expected_p95, 1e-9 * expected_p95);
  EXPECT_NEAR(amp["bearing_force"].get<double>(), expected_peak, 1e-12 * expected_peak);
  EXPECT_GT(expected_p95, 1.0);  // the clearance raises the bearing load in every revolution's peak
}

TEST(RunSummary, ItsStatisticsAreThoseOfTheRecord) {
  // The summary's channel statistics are gathered while the samples are recorded, and its
  // slider-acceleration statistics share one split into revolutions; both must equal what the
  // record itself gives. Rigid rig, 1 mm clearance, 177 rpm, 3 revolutions at 20 kHz.
  const Config cfg = LoadRunInput("rigid-rig", {"drive.speed=177 rpm", "sim.settle=0.1 s",
                                                "sim.capture=1.02 s", "sim.sample_rate=20 kHz"});
  const RunResult r = RunSimulation(cfg);
  ASSERT_TRUE(r.ok()) << r.status.Summary();
  const study::TimeSeries& ts = r.channels;
  const nlohmann::json& s = r.summary;
  auto max_of = [](std::span<const double> v, auto f) {
    double m = -INFINITY;
    for (double x : v) m = std::max(m, f(x));
    return m;
  };
  const auto abs = [](double x) { return std::abs(x); };
  const auto same = [](double x) { return x; };
  for (const study::Channel& c : ts.channels()) {
    double sq = 0.0;
    for (double v : c.values) sq += v * v;
    EXPECT_EQ(s["channels"][c.name]["peak_abs"].get<double>(), max_of(c.values, abs)) << c.name;
    EXPECT_NEAR(s["channels"][c.name]["rms"].get<double>(), std::sqrt(sq / c.values.size()),
                1e-13 * std::sqrt(sq / c.values.size()) + 1e-300)
        << c.name;
  }
  EXPECT_EQ(s["crank_speed"]["max [rad/s]"].get<double>(), max_of(ts.values("crank_speed"), same));
  EXPECT_EQ(s["crank_speed"]["min [rad/s]"].get<double>(),
            -max_of(ts.values("crank_speed"), std::negate<>()));
  EXPECT_EQ(s["energy"]["max_balance_error [J]"].get<double>(),
            max_of(ts.values("energy_balance_error"), abs));
  EXPECT_EQ(s["max_constraint_violation [m]"].get<double>(),
            max_of(ts.values("constraint_violation"), same));
  const study::SignalSummary a = study::CalcSignalSummary(
      ts, "slider_acceleration", "crank_angle", cfg.Quantity("sim.index_angle"), ts.all());
  EXPECT_EQ(a.positive.num_revolutions, 3u);
  EXPECT_EQ(s["slider_acceleration"]["peak_negative"].get<double>(), a.peak_negative);
  EXPECT_EQ(s["slider_acceleration"]["per_revolution_positive"]["p95"].get<double>(),
            a.positive.p95);
  EXPECT_EQ(s["slider_acceleration"]["per_revolution_abs"]["median"].get<double>(),
            a.magnitude.median);
  // The clearance joint's bearing force is |F| of the contact: √(Fn² + Ft²).
  const auto fn = ts.values("contact_normal_force"), ft = ts.values("contact_friction_force");
  const auto f = ts.values("bearing_force");
  for (size_t i = 0; i < f.size(); ++i) ASSERT_EQ(f[i], std::hypot(fn[i], ft[i])) << i;
}

/// `j` without the wall-clock figures (which differ between any two runs), recursively.
nlohmann::json WithoutWallTimes(nlohmann::json j) {
  if (!j.is_object()) return j;
  for (const char* key : {"wall_time [s]", "output_time [s]"}) j.erase(key);
  for (auto& [key, value] : j.items()) value = WithoutWallTimes(value);
  return j;
}

TEST(RunSummary, ARunKeepingFewChannelsSummarisesAndRecordsThemAsOneKeepingAll) {
  // RunOutputOptions::keep_channel: the samples of the other channels are not kept, but every
  // channel still enters the summary's statistics, and the run itself is the same. Rigid rig,
  // 1 mm clearance (so an ideal-joint twin runs too), 177 rpm, 0.3 s at 20 kHz.
  const Config cfg = LoadRunInput("rigid-rig", {"drive.speed=177 rpm", "sim.settle=0 s",
                                                "sim.capture=0.3 s", "sim.sample_rate=20 kHz"});
  const RunResult all = RunSimulation(cfg);
  RunOutputOptions keep_one;
  keep_one.keep_channel = [](const std::string& name) { return name == "slider_position"; };
  const RunResult few = RunSimulation(cfg, nullptr, false, keep_one);
  ASSERT_TRUE(all.ok() && few.ok()) << few.status.Summary();
  EXPECT_EQ(WithoutWallTimes(few.summary).dump(), WithoutWallTimes(all.summary).dump());
  EXPECT_GT(all.summary["channels"].size(), 20u);
  ASSERT_TRUE(all.ideal && few.ideal);
  for (const auto& [kept, full] :
       {std::pair{&few.channels, &all.channels}, std::pair{few.ideal.get(), all.ideal.get()}}) {
    // The kept one and those the summary reads sample by sample; each sample as in a full run.
    std::vector<std::string> names;
    for (const study::Channel& c : kept->channels()) names.push_back(c.name);
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"bearing_force", "crank_angle",
                                               "slider_acceleration", "slider_position"}));
    EXPECT_EQ(kept->num_samples(), full->num_samples());
    for (const std::string& n : names) {
      const auto a = kept->values(n), b = full->values(n);
      EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << n;
    }
  }
}

TEST(RunSummary, ARunKeepingNoChannelStillCountsItsSamplesAndSummarisesThemAll) {
  // The pendulum has none of the channels a run always keeps (crank angle, slider acceleration,
  // bearing force): a record keeping nothing else keeps one channel, so the sample count and
  // the summary stay (flexrod run --check's reference run keeps nothing).
  const Config cfg = LoadRunInput("flexible-pendulum", {"sim.capture=0.02 s"});
  const RunResult all = RunSimulation(cfg);
  RunOutputOptions keep_none;
  keep_none.keep_channel = [](const std::string&) { return false; };
  const RunResult none = RunSimulation(cfg, nullptr, false, keep_none);
  ASSERT_TRUE(all.ok() && none.ok()) << none.status.Summary();
  EXPECT_EQ(none.channels.num_channels(), 1u);
  EXPECT_EQ(none.channels.num_samples(), all.channels.num_samples());
  EXPECT_GT(all.summary["channels"].size(), 10u);
  EXPECT_EQ(WithoutWallTimes(none.summary).dump(), WithoutWallTimes(all.summary).dump());
}

// Integrator robustness on contact events (regressions; each failed before its fix).

TEST(RunRobustness, LooseToleranceRunsPastContactSeparations) {
  // Rigid rig, hybrid law, 1 mm, 177 rpm at rel_tol 1e-5 (and 1e-4): the first separation
  // (t = 0.0102 s) opens the joint, its force-derivative entries in the iteration matrix
  // become exactly zero, and KLU's re-factorisation with the old pivot sequence met a zero
  // pivot at every step size (IDA_CONV_FAIL at h = 2e-12). A fresh factorisation after such a
  // failure fixes it (multibody/ida_integrator.cc, TimedSetup). The dense LU, which the rig
  // selects by default, pivots afresh at every factorisation; both must run through.
  for (const auto& [solver, kind] :
       {std::pair{"sim.linear_solver=klu", multibody::LinearSolverKind::kKlu},
        std::pair{"sim.linear_solver=auto", multibody::LinearSolverKind::kDense}}) {
    for (const char* tol : {"sim.rel_tol=1e-5", "sim.rel_tol=1e-4"}) {
      const RunResult r = RunSimulation(LoadRunInput(
          "rigid-rig", {"joint.clearance=1 mm", "drive.speed=177 rpm", "sim.settle=0 s",
                        "sim.capture=0.3 s", "sim.sample_rate=10 kHz", tol, solver}));
      EXPECT_TRUE(r.ok()) << tol << " " << solver << ": " << r.status.Summary();
      EXPECT_EQ(r.status.linear_solver, kind) << solver;
      EXPECT_GT(r.status.stats.roots_found, 4) << tol << " " << solver;  // onsets, separations
    }
  }
}

TEST(RunRobustness, ARestartAfterAContactEventStartsOnTheConstraints) {
  // Issue 24's reproduction: rigid rig, Hertz law, no friction, rel_tol 1e-9, abs_tol 1e-12,
  // crank started at 5°. Restarted after the contact event at t = 2.79352 s from IDA's state
  // as it was (joints closed only to the tolerance), the first step failed for every step
  // size (IDA_ERR_FAIL at h = 6.9e-19). Every restart now projects p onto g = 0 and v onto
  // G v + g_t = 0 first (multibody/simulate.cc). The trajectory is chaotic: another build's
  // round-off may move or remove this particular failure, which the assertion below cannot see.
  const RunResult r = RunSimulation(
      LoadRunInput("rigid-rig", {"joint.law=hertz", "joint.friction_law=none", "sim.rel_tol=1e-9",
                                 "sim.abs_tol=1e-12", "sim.settle=0 s", "drive.initial_angle=5 deg",
                                 "sim.capture=2.6 s", "sim.sample_rate=10 kHz"}));
  ASSERT_TRUE(r.ok()) << r.status.Summary();
  EXPECT_GT(r.status.t_reached, 2.8);
  EXPECT_GT(r.status.stats.roots_found, 20);
  // The joints stay closed to the tolerance everywhere (the samples between restarts).
  EXPECT_LT(r.summary["max_constraint_violation [m]"].get<double>(), 1e-9);
}

TEST(RunRobustness, LuGreFrictionKeepsThePinOutsideTheBushWall) {
  // Flexible rig, 0.5 mm, LuGre joint friction. The joint restarts the integrator at every
  // separation (the bristle state switches law), and the contact root δ sat at ±1e-16 m after
  // each restart, so IDA reported onset, separation, onset, ... at one instant thousands of
  // times. With Hertz the alternation ended with the flag off at t = 0.117 s and the pin went
  // through the bush (centimetres of penetration, zero force); with Kelvin–Voigt IDA gave up at
  // t = 0.0124 s. The event band of ClearanceJoint (a hysteresis on the root) fixed both.
  for (const char* law : {"joint.law=hertz", "joint.law=kelvin-voigt"}) {
    const RunResult r = RunSimulation(LoadRunInput(
        "flexible-rig", {law, "joint.friction_law=lugre", "sim.settle=0 s", "sim.capture=0.15 s"}));
    ASSERT_TRUE(r.ok()) << law << ": " << r.status.Summary();
    const auto pen = r.channels.values("penetration");
    const auto rate = r.channels.values("penetration_rate");
    const auto fn = r.channels.values("contact_normal_force");
    double deepest = 0.0;
    long unloaded_inside = 0;  // going in, inside the wall, and no force (Kelvin–Voigt's force
    for (size_t i = 0; i < pen.size(); ++i) {  // may clip to zero inside while coming out)
      deepest = std::max(deepest, pen[i]);
      if (pen[i] > 1e-9 && rate[i] >= 0.0 && fn[i] == 0.0) ++unloaded_inside;
    }
    EXPECT_LT(deepest, 2e-5) << law;  // micrometres, as with Coulomb friction
    EXPECT_EQ(unloaded_inside, 0) << law;
    EXPECT_GE(r.summary["impacts"]["count"].get<int>(), 2) << law;
    EXPECT_FALSE(r.summary.contains("warnings")) << law << ": " << r.summary["warnings"].dump();
    EXPECT_LT(r.status.stats.roots_found, 200) << law;  // no chatter
  }
}

TEST(RunRobustness, AnEnergyBalanceErrorAboveOnePercentIsWarnedAbout) {
  // Rigid rig: 2.3 % of the peak kinetic energy at rel_tol 3e-2 (warned), 2e-5 at 1e-6 (not).
  for (const char* tol : {"sim.rel_tol=3e-2", "sim.rel_tol=1e-6"}) {
    const RunResult r = RunSimulation(LoadRunInput(
        "rigid-rig", {tol, "sim.settle=0 s", "sim.capture=0.3 s", "sim.sample_rate=10 kHz"}));
    ASSERT_TRUE(r.ok()) << r.status.Summary();
    const bool loose = std::string(tol) == "sim.rel_tol=3e-2";
    EXPECT_EQ(r.summary["energy"]["relative_balance_error"].get<double>() > 1e-2, loose) << tol;
    ASSERT_EQ(r.summary.contains("warnings"), loose) << tol;
    if (loose) {
      EXPECT_NE(r.summary["warnings"][0].get<std::string>().find("tighten sim.rel_tol"),
                std::string::npos);
    }
  }
}

// Loosened tolerances must not catch IDA's step control. The exudyn-match ideal joint
// (benchmarks/exudyn-match.toml, 1 s) at rel_tol 1e-5 / abs_tol 1e-9 caught it at a stiff
// elastic frequency of the rod: without the step-growth guard (multibody/ida_integrator.cc,
// kGrowthWindow) it failed the error test on 24 578 of 26 860 steps with 49 162 Jacobians,
// against 10 016 steps at the defaults. Measured with the guard and the Jacobian reuse: 11 575
// steps against 10 037, 595 error-test failures, 2 844 matrix set-ups. The step ratio moves with
// round-off (0.99 to 1.20 over rel_tol 1e-5 × (1 ± 1e-6) and a rounding change, session 38), so
// the bound, 1.5, sits between that and the trap's 2.7. Not checked, because it does not hold:
// that the loose run is faster. It takes about twice the defaults' solver wall (0.064 to
// 0.066 s against 0.033 to 0.037 s, 3 runs each): 1 750 Newton convergence failures against
// 34, most diverging at the first iteration on the damping-dissipation quadrature and the
// rod's first modal velocity.
TEST(RunRobustness, LoosenedTolerancesDoNotCatchTheStepControl) {
  auto run = [](std::vector<std::string> sets) {
    for (const char* s : {"joint.type=ideal", "sim.sample_rate=10 kHz", "sim.capture=1 s"})
      sets.emplace_back(s);
    const RunResult r = RunSimulation(
        LoadRunInput(std::string(FLEXROD_SOURCE_DIR) + "/benchmarks/exudyn-match.toml", sets));
    EXPECT_TRUE(r.ok()) << r.status.Summary();
    return r.status.stats;
  };
  const multibody::IntegratorStats loose = run({"sim.rel_tol=1e-5", "sim.abs_tol=1e-9"});
  const multibody::IntegratorStats tight = run({});
  EXPECT_LT(loose.steps, 1.5 * tight.steps);
  EXPECT_LT(loose.error_test_failures, loose.steps / 10);
  EXPECT_LT(loose.matrix_setups, loose.steps / 2);
}

// The same slider-crank at rel_tol 1e-5 (abs_tol 1e-10), 1 s: IDA takes about half of its
// 21 824 steps at order 1 (at the defaults 17 of 9 964), which the summary warns about with the
// keys to change (multibody::CaughtStepControlNote); the defaults get no warning.
TEST(RunRobustness, AStepControlHeldAtOrderOneIsWarnedAbout) {
  long steps[2] = {0, 0};  // [defaults, loose]
  for (const bool loose : {true, false}) {
    std::vector<std::string> sets = {"joint.type=ideal", "sim.sample_rate=10 kHz",
                                     "sim.capture=1 s"};
    if (loose) sets.emplace_back("sim.rel_tol=1e-5");
    const RunResult r = RunSimulation(
        LoadRunInput(std::string(FLEXROD_SOURCE_DIR) + "/benchmarks/exudyn-match.toml", sets));
    ASSERT_TRUE(r.ok()) << r.status.Summary();
    const multibody::IntegratorStats& st = r.status.stats;
    steps[loose] = st.steps;
    const long order_one = st.steps_by_order[1];
    long counted = 0;
    for (int k = 1; k <= 5; ++k) {
      const long n = r.summary["integrator"]["steps_by_order"][std::to_string(k)].get<long>();
      EXPECT_EQ(n, st.steps_by_order[static_cast<size_t>(k)]) << k;
      counted += n;
    }
    EXPECT_EQ(counted, st.steps);  // every step at one order
    ASSERT_EQ(r.summary.contains("warnings"), loose) << r.summary.dump(1);
    if (loose) {
      EXPECT_GT(order_one, 0.4 * st.steps);
      const std::string w = r.summary["warnings"][0].get<std::string>();
      EXPECT_NE(w.find("at BDF order 1"), std::string::npos) << w;
      EXPECT_NE(w.find("sim.rel_tol"), std::string::npos) << w;
    } else {
      EXPECT_LT(order_one, 0.01 * st.steps);
    }
  }
  EXPECT_GT(steps[1], 1.8 * steps[0]);
}

TEST(RunRobustness, APenetrationOfATenthOfTheClearanceIsWarnedAbout) {
  // A linear spring of 1e3 N/m cannot carry the joint load within the clearance.
  const RunResult r = RunSimulation(
      LoadRunInput("rigid-rig", {"joint.law=linear-spring", "joint.stiffness=1e3", "sim.settle=0 s",
                                 "sim.capture=0.1 s", "sim.sample_rate=10 kHz"}));
  ASSERT_TRUE(r.ok()) << r.status.Summary();
  ASSERT_TRUE(r.summary.contains("warnings"));
  EXPECT_NE(r.summary["warnings"][0].get<std::string>().find("% of joint.clearance"),
            std::string::npos);
}

TEST(ImpactLog, ARigidRigRunLogsEveryLocatedContactAndAgreesWithItsChannels) {
  // Rigid rig, hybrid law with friction, 1 mm, 177 rpm, one revolution. The log is built from
  // the located onsets and separations and the solution points between them (samples included),
  // so (1) its impacts account for every contact root IDA returned, (2) each impact's peak force
  // is at least every sample's force inside it, (3) its dissipated energy is the time integral
  // of the contact_dissipation channel (sampled at 100 kHz; the log's points are finer).
  const RunResult r = RunSimulation(
      LoadRunInput("rigid-rig", {"joint.clearance=1 mm", "joint.friction=0.18",
                                 "drive.speed=177 rpm", "sim.settle=0 s", "sim.capture=0.339 s"}));
  ASSERT_TRUE(r.ok()) << r.status.Summary();
  const std::vector<study::Impact>& log = r.impacts;
  ASSERT_GE(log.size(), 3u);
  long located = 0;  // onsets and separations inside the window
  for (const study::Impact& im : log) located += (im.complete ? 2 : 1);
  const long index_roots = static_cast<long>(r.status.index_crossings.size());
  EXPECT_LE(located, r.status.stats.roots_found - index_roots);
  EXPECT_GE(located, r.status.stats.roots_found - index_roots -
                         2);  // at most one event outside on each side

  const study::TimeSeries& ts = r.channels;
  const auto f = ts.values("contact_normal_force");
  const auto p = ts.values("contact_dissipation");
  double channel_energy = 0.0;
  for (size_t i = 1; i < p.size(); ++i)
    channel_energy += 0.5 * (p[i - 1] + p[i]) * ts.sample_period();
  double log_energy = 0.0;
  for (const study::Impact& im : log) {
    log_energy += im.dissipated_energy;
    EXPECT_GE(im.duration, 0.0);
    const size_t a = static_cast<size_t>(std::ceil((im.time - ts.start_time()) * ts.sample_rate()));
    const size_t b = std::min(
        f.size(),
        static_cast<size_t>((im.time + im.duration - ts.start_time()) * ts.sample_rate()) + 1);
    for (size_t i = a; i < b; ++i)
      EXPECT_LE(f[i], im.peak_force) << "impact at " << im.time << " s, sample " << i;
  }
  EXPECT_NEAR(log_energy, channel_energy, 2e-3 * channel_energy);  // observed 2.5e-4
  std::printf("impacts %zu, contact roots %ld, energy log %.6g J, channel %.6g J\n", log.size(),
              r.status.stats.roots_found - index_roots, log_energy, channel_energy);
}

}  // namespace
}  // namespace flexrod
