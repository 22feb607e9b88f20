// SPDX-License-Identifier: GPL-3.0-or-later
// IDA's BDF against a Radau IIA formula (benchmarks/radau_iia.h) on flexrod's own DAE: the
// slider-crank of benchmarks/exudyn-match.toml, 3 s from its rigid start (issue 24, "Speed": is
// an A-stable higher-order integrator the way to the targets?). Both see the same MechanismDae
// (prescribed crank eliminated, the run's tolerance scales) and start from the same consistent
// state; neither samples.
//
// - Ideal joint: IDA at rel_tol 1e-10 / abs_tol 1e-12 is the reference, IDA at the defaults
//   (1e-6 / 1e-10) and Radau IIA at rel_tol 1e-4 to 1e-7 (abs_tol in proportion) are measured
//   against it: the slider acceleration (the slider velocity's rate) at 30 times 0.1 s apart,
//   largest difference over its largest value.
// - Clearance joint (Hunt–Crossley contact, events): the same three, compared on the times of
//   the contact onsets, pair by pair until a pair is more than 10 µs apart (a grazing touch in
//   one sequence only), at most 15 (the motion is chaotic: by the 26th onset the defaults are
//   1e-5 s off).
// Printed per run: steps, rejected steps, residual evaluations, Newton iterations, Jacobians,
// factorisations (Radau: one real and one complex), events, wall time (IDA's include its
// compiled dense LU; Radau's Eigen's, so compare counts, not walls) and the error measure.
// - Steps (`steps`): what holds IDA's steps at the defaults on both, from the DAE's linearised
//   modes along the run (MeasureStepBound): on the ideal joint a stability limit of the BDF
//   formulas (as bench_bdf_oscillator shows on one oscillator), with the clearance joint the
//   accuracy asked, a third of the steps in contact at orders 1-3 (half as many without
//   friction: the Coulomb law's ramp has corners).
// Usage: bench_radau_vs_ida [ideal|clearance|steps] [--check] (default all three; --check with
// `steps` tests its claims as ranges and exits 1 if one fails: ctest bench.step_bound_claims).
// Takes about 30 s, `steps` about 9 s.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <complex>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "benchmarks/bdf_stability.h"
#include "benchmarks/radau_iia.h"
#include "input/config.h"
#include "mechanisms/mechanism_model.h"
#include "multibody/clearance_joint.h"
#include "multibody/dae.h"
#include "multibody/prescribed.h"
#include "multibody/simulate.h"

namespace {

using namespace flexrod;

constexpr double kEnd = 3.0;  // [s]

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Config ExudynMatch(bool ideal) {
  Config cfg;
  cfg.LoadTomlFile(FLEXROD_SOURCE_DIR "/benchmarks/exudyn-match.toml");
  if (ideal) cfg.SetAssignment("joint.type=ideal");
  return cfg;
}

/// The mechanism, its consistent rigid start and the DAE IDA and Radau IIA both integrate.
struct Problem {
  MechanismModel mm;
  multibody::RunData data;
  multibody::ConsistentState start;
  multibody::PrescribedMotion prescribed;
  multibody::MechanismDae dae;
  Eigen::VectorXd y0, yp0;
  int slider_velocity{-1};  // the slider's x velocity in the DAE's (reduced) unknowns
  explicit Problem(const Config& cfg)
      : mm(BuildMechanism(cfg, nullptr)),
        data(mm.mechanism),
        start(Start()),
        prescribed(mm.mechanism, true),
        dae(mm.mechanism, &data, prescribed, std::nullopt,
            multibody::AutoVelocityTolScale(mm.mechanism)) {
    y0.resize(dae.size());
    yp0.resize(dae.size());
    prescribed.Reduce(start.y.data(), y0.data());
    prescribed.Reduce(start.yp.data(), yp0.data());
    const multibody::Mechanism& m = mm.mechanism;
    const int full = m.num_coordinates() + m.coordinate(mm.slider, multibody::kX);
    const std::vector<int>& kept = prescribed.kept_unknowns();
    for (size_t i = 0; i < kept.size(); ++i) {
      if (kept[i] == full) slider_velocity = static_cast<int>(i);
    }
  }
  /// The run's rigid start (sim.start = rigid): the recipe's pose and rigid-motion velocities.
  multibody::ConsistentState Start() {
    multibody::InitialConditionSpec ic;
    ic.coordinates = mm.p0;
    ic.velocities = mm.v0;
    return multibody::ComputeConsistentState(mm.mechanism, &data, 0.0, ic);
  }
};

void PrintRadau(double rel_tol, const bench::RadauStats& s, double wall, const char* error) {
  std::printf(
      "  Radau IIA rel_tol %.0e: %ld steps (%ld rejected, %ld Newton failures), %ld residuals, "
      "%ld Newton iterations, %ld Jacobians, %ld factorisations, %ld events, %.3f s; %s\n",
      rel_tol, s.steps, s.rejected, s.newton_failures, s.residuals, s.newton_iterations,
      s.jacobians, s.factorisations, s.events, wall, error);
}

void PrintIda(double rel_tol, double abs_tol, const multibody::IntegratorStats& s, double wall,
              const char* error) {
  std::printf(
      "  IDA rel_tol %.0e abs_tol %.0e: %ld steps (%ld error-test, %ld convergence failures), "
      "%ld residuals, %ld Jacobians, %ld factorisations, %ld events, %.3f s; %s\n",
      rel_tol, abs_tol, s.steps, s.error_test_failures, s.nonlinear_convergence_failures,
      s.residual_evaluations, s.jacobian_evaluations, s.matrix_setups, s.roots_found, wall, error);
}

/// `ida(rel_tol, abs_tol, &stats, &wall)` at 1e-10 / 1e-12, printed as the reference.
template <typename RunIda>
std::vector<double> IdaReference(RunIda&& ida) {
  multibody::IntegratorStats stats;
  double wall = 0.0;
  std::vector<double> out = ida(1e-10, 1e-12, &stats, &wall);
  PrintIda(1e-10, 1e-12, stats, wall, "the reference");
  return out;
}

/// `ida` at the run's defaults (1e-6 / 1e-10), printed with `error` of its figures.
template <typename RunIda, typename Error>
void IdaAtDefaults(RunIda&& ida, Error&& error) {
  multibody::IntegratorStats stats;
  double wall = 0.0;
  const std::vector<double> out = ida(1e-6, 1e-10, &stats, &wall);
  PrintIda(1e-6, 1e-10, stats, wall, error(out).c_str());
}

void Ideal() {
  std::printf(
      "ideal joint: slider acceleration at 30 times, largest difference to IDA at "
      "1e-10 / 1e-12 over its largest value\n");
  const Config cfg = ExudynMatch(true);
  std::vector<double> times;
  for (int k = 1; k <= 30; ++k) times.push_back(0.1 * k);
  auto ida = [&](double rel_tol, double abs_tol, multibody::IntegratorStats* stats, double* wall) {
    Problem p(cfg);
    multibody::IntegratorOptions o;
    o.rel_tol = rel_tol;
    o.abs_tol = abs_tol;
    multibody::IdaIntegrator integrator(&p.dae, o);
    integrator.Initialize(0.0, p.y0.data(), p.yp0.data());
    std::vector<double> acc;
    const auto w0 = std::chrono::steady_clock::now();
    for (double tc : times) {
      integrator.SetStopTime(tc);
      while (integrator.Step(tc).outcome != multibody::StepOutcome::kStopTime) {
      }
      acc.push_back(integrator.yp()[p.slider_velocity]);
    }
    *wall = Seconds(w0);
    *stats = integrator.stats();
    return acc;
  };
  const std::vector<double> reference = IdaReference(ida);
  auto error = [&](const std::vector<double>& acc) {
    double e = 0.0, m = 0.0;
    for (size_t k = 0; k < acc.size(); ++k) {
      e = std::max(e, std::abs(acc[k] - reference[k]));
      m = std::max(m, std::abs(reference[k]));
    }
    char text[64];
    std::snprintf(text, sizeof text, "slider acceleration off by %.2e", e / m);
    return std::string(text);
  };
  IdaAtDefaults(ida, error);
  for (double rel_tol : {1e-4, 1e-5, 1e-6, 1e-7}) {
    Problem p(cfg);
    bench::RadauDae radau(&p.dae, rel_tol, 1e-10 * rel_tol / 1e-6);
    radau.Initialize(0.0, p.y0, p.yp0);
    std::vector<double> acc;
    const auto w0 = std::chrono::steady_clock::now();
    for (double tc : times) {
      radau.Advance(tc);
      acc.push_back(radau.yp()[p.slider_velocity]);
    }
    PrintRadau(rel_tol, radau.stats, Seconds(w0), error(acc).c_str());
  }
}

void Clearance() {
  std::printf(
      "clearance joint: the first 15 contact onsets, largest difference to IDA at "
      "1e-10 / 1e-12\n");
  const Config cfg = ExudynMatch(false);
  auto ida = [&](double rel_tol, double abs_tol, multibody::IntegratorStats* stats, double* wall) {
    Problem p(cfg);
    multibody::SimulationOptions o;
    o.t_end = kEnd;
    o.sample_rate = 1e3;
    o.integrator.rel_tol = rel_tol;
    o.integrator.abs_tol = abs_tol;
    std::vector<double> onsets;
    long count = 0;
    multibody::SimulationCallbacks cb;
    cb.on_step = [&](const multibody::SampleView& s) {
      const multibody::ClearanceResponse r = multibody::CalcClearanceResponse(s, p.mm.clearance);
      if (r.onsets > count) {
        count = r.onsets;
        onsets.push_back(r.onset_time);
      }
    };
    const auto w0 = std::chrono::steady_clock::now();
    const multibody::SimulationStatus status =
        multibody::Simulate(p.mm.mechanism, &p.data, p.start, o, cb);
    *wall = Seconds(w0);
    *stats = status.stats;
    return onsets;
  };
  const std::vector<double> reference = IdaReference(ida);
  // Onsets pair up in order until one sequence has a contact the other has not (a grazing
  // touch that comes and goes with round-off): the first pair apart by more than kApart ends
  // the comparison, at most kPairs: over the first 15 onsets (0.06 s) IDA at the defaults stays
  // about 2e-7 s off the reference, and by the 26th the chaotic motion has moved them 1e-5 s.
  constexpr double kApart = 1e-5;  // [s]
  constexpr size_t kPairs = 15;
  auto error = [&](const std::vector<double>& onsets) {
    double e = 0.0;
    size_t k = 0;
    for (; k < kPairs && k < onsets.size() && k < reference.size(); ++k) {
      if (std::abs(onsets[k] - reference[k]) > kApart) break;
      e = std::max(e, std::abs(onsets[k] - reference[k]));
    }
    char text[128];
    std::snprintf(text, sizeof text,
                  "%zu onsets, the first %zu (to t = %.3f s) off by up to %.2e s", onsets.size(), k,
                  k > 0 ? reference[k - 1] : 0.0, e);
    return std::string(text);
  };
  IdaAtDefaults(ida, error);
  for (double rel_tol : {1e-5, 1e-6}) {
    Problem p(cfg);
    const multibody::Mechanism& m = p.mm.mechanism;
    bench::RadauDae radau(&p.dae, rel_tol, 1e-10 * rel_tol / 1e-6);
    std::vector<double> onsets;
    Vec y(m.size()), yp(m.size());
    // The run loop's element events (ApplyElementRoots), without its projection; the joint's
    // onsets are its first root crossing upwards with a restart.
    const int onset_root = m.element(p.mm.clearance).root_offset;
    radau.on_root = [&](double t, const Vec& yr, const Vec& ypr, const std::vector<int>& dirs) {
      p.prescribed.Expand(t, yr.data(), ypr.data(), y.data(), yp.data());
      const bool restart = multibody::ApplyElementRoots(m, &p.data, t, y.data(), dirs.data());
      if (restart && dirs[onset_root] > 0) onsets.push_back(t);
      return restart;
    };
    radau.Initialize(0.0, p.y0, p.yp0);
    const auto w0 = std::chrono::steady_clock::now();
    radau.Advance(kEnd);
    PrintRadau(rel_tol, radau.stats, Seconds(w0), error(onsets).c_str());
  }
}

/// What holds IDA's steps at the defaults (MeasureStepBound): along a run of the exudyn-match
/// slider-crank (ideal or clearance joint), every `every`-th step, the DAE's linearised modes (the
/// finite generalised eigenvalues λ of F_y v = −λ F_ẏ v at the step's solution) and, for each, how
/// far the step could grow before BDF at IDA's current order broke the root condition on it
/// (bdf_stability.h): the factor band_start / (h |λ|), 0 inside the band, none past it. The
/// smallest factor over the modes is the step's stability margin: near 1, the step sits at a
/// stability limit; well above 1, it is held by the accuracy asked. Steps within kSettle steps of
/// a (re-)initialisation (IDA's start-up at order 1) and before kWarmUp are left out. Also the
/// steps per BDF order, in contact and not. A plain IDA loop: the run loop's projection at
/// restarts is left out, so the counts differ from a run's by a few percent.
struct StepBound {
  std::vector<double> margins[2];  // [not in contact, in contact]
  long steps_by_order[2][6] = {};
  double step_sum_by_order[2][6] = {};
  long steps{0};
  /// Share of the margins at or below `factor` (c: 0 not in contact, 1 in contact).
  double ShareWithin(int c, double factor) const {
    if (margins[c].empty()) return 0.0;
    return static_cast<double>(std::count_if(margins[c].begin(), margins[c].end(),
                                             [&](double m) { return m <= factor; })) /
           static_cast<double>(margins[c].size());
  }
  double Median(int c) const {
    std::vector<double> v = margins[c];
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    return v[v.size() / 2];
  }
  /// Share of the steps at BDF orders up to `max_order`.
  double LowOrderShare(int c, int max_order) const {
    long low = 0, all = 0;
    for (int k = 1; k <= 5; ++k) {
      all += steps_by_order[c][k];
      if (k <= max_order) low += steps_by_order[c][k];
    }
    return all > 0 ? static_cast<double>(low) / static_cast<double>(all) : 0.0;
  }
};

StepBound MeasureStepBound(bool ideal, long every, const char* assignment = nullptr) {
  constexpr long kSettle = 30;     // steps after a (re-)initialisation left out
  constexpr double kWarmUp = 0.2;  // [s] the start from rest, left out
  Config cfg = ExudynMatch(ideal);
  if (assignment) cfg.SetAssignment(assignment);
  Problem p(cfg);
  const multibody::Mechanism& m = p.mm.mechanism;
  const int n = p.dae.size();
  multibody::IntegratorOptions o;  // the run's defaults
  o.rel_tol = 1e-6;
  o.abs_tol = 1e-10;
  multibody::IdaIntegrator ida(&p.dae, o);
  ida.Initialize(0.0, p.y0.data(), p.yp0.data());
  std::vector<int> roots(static_cast<size_t>(p.dae.num_roots()));
  Vec y(m.size()), yp(m.size());
  Eigen::MatrixXd fy(n, n), fyp(n, n);
  std::map<std::pair<int, long>, std::pair<double, double>> bands;  // (order, 1000 ζ) -> band
  StepBound out;
  bool contact = false;
  long since_start = 0;
  for (double t = 0.0; t < kEnd;) {
    const multibody::StepResult r = ida.Step(kEnd);
    t = r.t;
    if (r.outcome == multibody::StepOutcome::kRoot) {
      ida.RootInfo(roots.data());
      p.prescribed.Expand(t, ida.y(), ida.yp(), y.data(), yp.data());
      if (multibody::ApplyElementRoots(m, &p.data, t, y.data(), roots.data())) {
        ida.Initialize(t, ida.y(), ida.yp());
        since_start = 0;
      }
      if (!ideal) {
        contact = multibody::CalcClearanceResponse(
                      multibody::SampleView(m, &p.data, t, y.data(), yp.data()), p.mm.clearance)
                      .contact_flag;
      }
      continue;
    }
    if (r.outcome != multibody::StepOutcome::kStep) continue;
    ++out.steps;
    ++since_start;
    const multibody::IntegratorStats st = ida.stats();
    out.steps_by_order[contact][st.last_order] += 1;
    out.step_sum_by_order[contact][st.last_order] += st.last_step;
    if (out.steps % every != 0 || since_start <= kSettle || t < kWarmUp) continue;
    fy.setZero();
    fyp.setZero();
    p.dae.JacobianAndDerivativePart(t, 0.0, ida.y(), ida.yp(), fy.data(), fyp.data());
    const Eigen::GeneralizedEigenSolver<Eigen::MatrixXd> modes(fy, -fyp);
    double margin = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i) {
      const std::complex<double> alpha = modes.alphas()(i);
      const double beta = modes.betas()(i);
      if (std::abs(beta) <= 1e-12 * std::abs(alpha)) continue;  // an algebraic unknown
      const std::complex<double> lambda = alpha / beta;
      const double hw = st.last_step * std::abs(lambda);
      if (lambda.imag() < 0.0 || hw < 1e-3) continue;  // one of a pair; a slow motion
      const double zeta = std::clamp(-lambda.real() / std::abs(lambda), 0.0, 1.0);
      const auto key = std::make_pair(st.last_order, std::lround(1e3 * zeta));
      auto it = bands.find(key);
      if (it == bands.end())
        it = bands.emplace(key, bench::BdfInstabilityBand(key.first, 1e-3 * key.second)).first;
      const auto [first, last] = it->second;
      if (first == 0.0 || hw > last) continue;  // never unstable, or past the band
      margin = std::min(margin, hw < first ? first / hw : 0.0);
    }
    out.margins[contact].push_back(margin);
  }
  return out;
}

/// --check: the claims the README's "What sets the step" makes, as ranges; false if one fails.
bool StepsSection(bool check) {
  std::printf(
      "what holds IDA's steps (rel_tol 1e-6, abs_tol 1e-10): stability margin = how far the step "
      "could grow before BDF at IDA's order turned unstable on one of the DAE's linearised modes "
      "(0: it is unstable there now)\n");
  const StepBound ideal = MeasureStepBound(true, 101), clearance = MeasureStepBound(false, 499),
                  frictionless = MeasureStepBound(false, 499, "joint.friction_law=none");
  auto print = [](const char* name, const StepBound& b, int c) {
    std::printf(
        "  %-26s %6zu steps analysed: margin median %.2f, within 1.5: %4.1f %%; steps by "
        "order (mean step):",
        name, b.margins[c].size(), b.Median(c), 100.0 * b.ShareWithin(c, 1.5));
    for (int k = 1; k <= 5; ++k) {
      const long s = b.steps_by_order[c][k];
      std::printf(" %d: %ld (%.2g s)", k, s, s ? b.step_sum_by_order[c][k] / s : 0.0);
    }
    std::printf("\n");
  };
  print("ideal joint", ideal, 0);
  print("clearance, pin free", clearance, 0);
  print("clearance, in contact", clearance, 1);
  print("no friction, pin free", frictionless, 0);
  print("no friction, in contact", frictionless, 1);
  if (!check) return true;
  bool ok = true;
  auto claim = [&](bool holds, const char* what) {
    std::printf("%s: %s\n", holds ? "ok" : "FAILED", what);
    ok = ok && holds;
  };
  // README, "What sets the step": 3.6 and 6.7 times, three quarters, a third, half as many.
  claim(ideal.ShareWithin(0, 1.5) >= 0.6 && ideal.ShareWithin(0, 1.5) <= 0.9,
        "ideal joint: three quarters of the steps within 1.5 times of a stability limit (60-90 %)");
  claim(clearance.Median(0) >= 3.0 && clearance.Median(0) <= 4.5 && clearance.Median(1) >= 5.0 &&
            clearance.Median(1) <= 9.0,
        "clearance: median margin 3.6 with the pin free (3-4.5), 6.7 in contact (5-9)");
  claim(clearance.ShareWithin(0, 1.5) <= 0.2 && clearance.ShareWithin(1, 1.5) <= 0.2,
        "clearance: at most 20 % of the steps within 1.5 times of a stability limit");
  claim(clearance.LowOrderShare(1, 3) >= 0.25 && clearance.LowOrderShare(1, 3) <= 0.4,
        "clearance: a third of the steps in contact at BDF orders 1-3 (25-40 %)");
  const double half = frictionless.LowOrderShare(1, 3) / clearance.LowOrderShare(1, 3);
  claim(
      half >= 0.35 && half <= 0.65,
      "without friction, half as large a share of the steps in contact at orders 1-3 (0.35-0.65)");
  return ok;
}
}  // namespace

int main(int argc, char** argv) {
  const std::string which = argc > 1 ? argv[1] : "";
  const bool check = argc > 2 && std::string(argv[2]) == "--check";
  if (which.empty() || which == "ideal") Ideal();
  if (which.empty() || which == "clearance") Clearance();
  if (which.empty() || which == "steps") return StepsSection(check) ? 0 : 1;
  return 0;
}
