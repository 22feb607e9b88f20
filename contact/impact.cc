// contact/impact.cc — single mass–wall impact through a normal law (see impact.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "contact/impact.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "common/error.h"
#include "contact/golden_section.h"

namespace flexrod::contact {
namespace {

constexpr int kMaxDim = 3;
using StateVec = std::array<double, kMaxDim>;

/// Equations of the mass on the wall: y = [δ, δ̇, x_d (differential-state laws only)],
/// δ̈ = −F/m. History states (elasto-plastic) are held outside y and frozen within a step.
struct ImpactSystem {
  const NormalLaw* law;
  double mass;
  double approach_speed;
  bool differential;
  LawState history;

  LawState StateOf(const double* y) const {
    LawState s = history;
    if (differential) s[0] = y[2];
    return s;
  }
  double Force(const double* y) const {
    return CalcNormalForce(*law, y[0], y[1], approach_speed, StateOf(y)).force;
  }
};

int Rhs(double /*t*/, const double y[], double dydt[], void* params) {
  const auto* sys = static_cast<const ImpactSystem*>(params);
  const LawState s = sys->StateOf(y);
  dydt[0] = y[1];
  dydt[1] = -CalcNormalForce(*sys->law, y[0], y[1], sys->approach_speed, s).force / sys->mass;
  if (sys->differential) dydt[2] = CalcLawStateRate(*sys->law, y[0], s).rate;
  return GSL_SUCCESS;
}

/// A point of the trajectory from which integration can be restarted.
struct Snapshot {
  double t;
  StateVec y;
  LawState history;
};

/// Thin RAII wrapper over gsl_odeiv2 step/control/evolve; every call checked.
class Integrator {
 public:
  Integrator(ImpactSystem* sys, int dim, double rel_tol, const StateVec& scale, double max_step)
      : sys_(sys),
        max_step_(max_step),
        step_(gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, dim), &gsl_odeiv2_step_free),
        control_(gsl_odeiv2_control_scaled_new(rel_tol, rel_tol, 1.0, 0.0, scale.data(), dim),
                 &gsl_odeiv2_control_free),
        evolve_(gsl_odeiv2_evolve_alloc(dim), &gsl_odeiv2_evolve_free),
        system_{Rhs, nullptr, static_cast<size_t>(dim), sys} {
    if (!step_ || !control_ || !evolve_) throw NumericalError("impact: GSL allocation failed");
  }

  /// One accepted adaptive step from s towards s.t + max_step; h is the step-size memory.
  void Step(Snapshot* s, double* h) {
    sys_->history = s->history;
    const double t1 = s->t + max_step_;
    *h = std::min(*h, max_step_);
    const int status = gsl_odeiv2_evolve_apply(evolve_.get(), control_.get(), step_.get(), &system_,
                                               &s->t, t1, h, s->y.data());
    if (status != GSL_SUCCESS) {
      throw NumericalError("impact: RK8(9) step failed at t = " + FormatValue(s->t) +
                           " s (delta = " + FormatValue(s->y[0]) + " m): " + gsl_strerror(status));
    }
    UpdateLawHistory(*sys_->law, s->y[0], &s->history);
  }

  /// Integrates a copy of `from` exactly to time t1 ≥ from.t.
  Snapshot AdvanceTo(const Snapshot& from, double t1) {
    Snapshot s = from;
    gsl_odeiv2_evolve_reset(evolve_.get());
    double h = std::max(std::min(max_step_, t1 - s.t), 1e-300);
    while (s.t < t1) {
      sys_->history = s.history;
      const int status = gsl_odeiv2_evolve_apply(evolve_.get(), control_.get(), step_.get(),
                                                 &system_, &s.t, t1, &h, s.y.data());
      if (status != GSL_SUCCESS) {
        throw NumericalError("impact: RK8(9) step failed at t = " + FormatValue(s.t) +
                             " s: " + gsl_strerror(status));
      }
      UpdateLawHistory(*sys_->law, s.y[0], &s.history);
      h = std::min(h, max_step_);
    }
    gsl_odeiv2_evolve_reset(evolve_.get());
    return s;
  }

  double Force(const Snapshot& s) const {
    sys_->history = s.history;
    return sys_->Force(s.y.data());
  }

 private:
  ImpactSystem* sys_;
  double max_step_;
  std::unique_ptr<gsl_odeiv2_step, decltype(&gsl_odeiv2_step_free)> step_;
  std::unique_ptr<gsl_odeiv2_control, decltype(&gsl_odeiv2_control_free)> control_;
  std::unique_ptr<gsl_odeiv2_evolve, decltype(&gsl_odeiv2_evolve_free)> evolve_;
  gsl_odeiv2_system system_;
};

/// Bisection in time: `holds` is true at `from` and false at `from` advanced to t1. Returns the
/// first snapshot where it is false, to a relative time resolution of a few ulps.
template <typename Predicate>
Snapshot Bisect(Integrator* integ, const Snapshot& from, double t1, Predicate&& holds) {
  double lo = from.t, hi = t1;
  Snapshot at_hi = integ->AdvanceTo(from, hi);
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (!(mid > lo && mid < hi)) break;
    Snapshot at_mid = integ->AdvanceTo(from, mid);
    if (holds(at_mid)) {
      lo = mid;
    } else {
      hi = mid;
      at_hi = at_mid;
    }
  }
  return at_hi;
}

/// Penetration δ* at which the elastic part of the law (δ̇ = 0, initial state) has stored the
/// incoming kinetic energy: a scale for tolerances and the step size.
double EnergyPenetrationScale(const NormalLaw& law, double mass, double v0) {
  const double energy = 0.5 * mass * v0 * v0;
  const LawState s0 = InitialLawState(law);
  auto work = [&](double d) {  // Simpson, 64 intervals
    const int n = 64;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      sum += w * CalcNormalForce(law, d * i / n, 0.0, v0, s0).force;
    }
    return sum * d / (3.0 * n);
  };
  double hi = 1e-12;
  for (int i = 0; i < 400 && work(hi) < energy; ++i) hi *= 2.0;
  double lo = 0.5 * hi;
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (lo + hi);
    (work(mid) < energy ? lo : hi) = mid;
  }
  return hi;
}

/// Integrates the impact from onset (δ = 0, δ̇ = v₀) until the mass leaves the wall, locating
/// the maximum penetration, the end of the force and the exit by bisection. Appends every
/// accepted point to *snaps and result->loop, sets the peak penetration, its time and the
/// contact duration, and returns the exit point. Throws NumericalError if the mass has not
/// left after options.max_steps steps or max_duration_factor·time_scale.
Snapshot IntegrateContact(Integrator* integ, const NormalLaw& law, double approach_speed,
                          double time_scale, const ImpactOptions& options, ImpactResult* result,
                          std::vector<Snapshot>* snaps) {
  auto push = [&](const Snapshot& s) {
    snaps->push_back(s);
    result->loop.push_back({s.t, s.y[0], s.y[1], integ->Force(s)});
  };
  Snapshot cur{0.0, {0.0, approach_speed, 0.0}, InitialLawState(law)};
  push(cur);
  double h = time_scale * 1e-6;
  bool exited = false;
  const double max_time = options.max_duration_factor * time_scale;
  for (int step = 0; !exited; ++step) {
    if (step >= options.max_steps || cur.t > max_time) {
      throw NumericalError(
          "impact: the mass has not left the wall after " + FormatValue(cur.t) + " s (" +
          std::to_string(step) + " steps; delta = " + FormatValue(cur.y[0]) +
          " m, rate = " + FormatValue(cur.y[1]) + " m/s); the law holds it (over-damped?)");
    }
    const Snapshot prev = cur;
    const double force_prev = integ->Force(prev);
    integ->Step(&cur, &h);
    if (prev.y[1] > 0.0 && cur.y[1] <= 0.0) {
      // Maximum penetration: restart from it, so a history law records δ_max exactly.
      cur = Bisect(integ, prev, cur.t, [](const Snapshot& s) { return s.y[1] > 0.0; });
      UpdateLawHistory(law, cur.y[0], &cur.history);
      result->peak_penetration = cur.y[0];
      result->time_of_peak_penetration = cur.t;
    } else if (force_prev > 0.0 && integ->Force(cur) <= 0.0 && cur.y[1] < 0.0) {
      // The force drops to zero while receding (δ → 0, or clipped damping, or permanent set).
      cur = Bisect(integ, prev, cur.t, [&](const Snapshot& s) { return integ->Force(s) > 0.0; });
      result->contact_duration = cur.t;
    }
    if (prev.y[0] > 0.0 && cur.y[0] <= 0.0) {
      cur = Bisect(integ, prev, cur.t, [](const Snapshot& s) { return s.y[0] > 0.0; });
      exited = true;
    }
    push(cur);
  }
  return cur;
}

/// Peak force [N]: the largest sample of `loop`, refined by golden section between its
/// neighbours (`snaps` are the points of `loop`, to restart from).
double PeakForce(Integrator* integ, const std::vector<LoopSample>& loop,
                 const std::vector<Snapshot>& snaps) {
  size_t imax = 0;
  for (size_t i = 0; i < loop.size(); ++i) {
    if (loop[i].force > loop[imax].force) imax = i;
  }
  double peak_force = loop[imax].force;
  if (imax > 0 && imax + 1 < snaps.size()) {
    const Snapshot& base = snaps[imax - 1];
    // The maximum of the force: the minimum of its negative (negation is exact).
    auto minus_force = [&](double t) { return -integ->Force(integ->AdvanceTo(base, t)); };
    const GoldenBracket peak =
        GoldenSectionMinimum(minus_force, base.t, snaps[imax + 1].t, 60, 1e-15);
    peak_force = std::max({peak_force, -peak.f1, -peak.f2});
  }
  return peak_force;
}

}  // namespace

void ImpactOptions::Validate() const {
  Require(std::isfinite(rel_tol) && rel_tol >= 1e-14 && rel_tol <= 1e-3, "impact.rel_tol", rel_tol,
          "must lie in [1e-14, 1e-3]");
  Require(num_samples >= 4, "impact.num_samples", num_samples, "must be >= 4");
  Require(max_steps >= 100, "impact.max_steps", max_steps, "must be >= 100");
  Require(max_duration_factor > 1.0, "impact.max_duration_factor", max_duration_factor,
          "must be > 1");
}

ImpactResult SimulateImpact(const NormalLaw& law, double mass, double approach_speed,
                            const ImpactOptions& options) {
  Require(std::isfinite(mass) && mass > 0.0, "mass", mass, "must be finite and > 0 [kg]");
  Require(std::isfinite(approach_speed) && approach_speed > 0.0, "velocity", approach_speed,
          "approach speed must be finite and > 0 [m/s]");
  options.Validate();

  const bool differential = StateKind(law) == LawStateKind::kDifferential;
  const int dim = differential ? 3 : 2;
  ImpactSystem sys{&law, mass, approach_speed, differential, InitialLawState(law)};

  const double delta_scale = EnergyPenetrationScale(law, mass, approach_speed);
  const double time_scale = 3.0 * delta_scale / approach_speed;  // Hertz: 2.94 δ_max/v₀
  const StateVec scale{delta_scale, approach_speed, delta_scale};
  Integrator integ(&sys, dim, options.rel_tol, scale, time_scale / options.num_samples);

  ImpactResult result;
  result.incoming_speed = approach_speed;
  std::vector<Snapshot> snaps;
  const Snapshot exit_point =
      IntegrateContact(&integ, law, approach_speed, time_scale, options, &result, &snaps);
  result.exit_time = exit_point.t;
  result.outgoing_speed = -exit_point.y[1];
  result.achieved_restitution = result.outgoing_speed / approach_speed;
  result.dissipated_energy =
      0.5 * mass *
      (approach_speed * approach_speed - result.outgoing_speed * result.outgoing_speed);
  result.peak_force = PeakForce(&integ, result.loop, snaps);
  return result;
}

}  // namespace flexrod::contact
