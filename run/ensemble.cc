// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/ensemble.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <thread>

#include "common/error.h"
#include "mechanisms/mechanism_model.h"
#include "mechanisms/mechanism_recipe.h"
#include "signals/regimes.h"

namespace flexrod {
namespace {

/// One headline figure pooled over the members: the 95th percentile of a per-revolution series
/// of every member, divided by `scale` (the ideal twin's value for an amplification, 1 for a
/// load).
struct PooledFigure {
  const char* name;
  const char* unit;
  const char* series;  // PerRevolutionSeries name
  double scale;
};

const std::vector<double>* FindSeries(
    const std::vector<std::pair<std::string, std::vector<double>>>& all, const char* name) {
  for (const auto& [n, x] : all) {
    if (n == name) return &x;
  }
  return nullptr;
}

double Median(std::vector<double> v) { return study::Percentile(v, 50.0); }

}  // namespace

std::vector<Config> EnsembleMemberInputs(const Config& cfg, const EnsembleOptions& options,
                                         int members) {
  std::vector<Config> inputs;
  for (int k = 0; k < members; ++k) {
    inputs.push_back(cfg);
    for (const auto& [key, value] : EnsembleMemberSettings(cfg, options, members, k))
      inputs.back().Set(key, value);
  }
  return inputs;
}

nlohmann::json SummariseEnsemble(const std::vector<Config>& inputs,
                                 const std::vector<const RunResult*>& runs, const RunResult& twin,
                                 const EnsembleOptions& options) {
  FLEXROD_ASSERT(inputs.size() == runs.size() && !runs.empty());
  nlohmann::json e;
  e["members"] = runs.size();
  e["confidence"] = options.confidence;
  study::BootstrapOptions boot;
  boot.confidence = options.confidence;
  e["bootstrap"] = {{"resamples", boot.resamples},
                    {"block_length", "ceil(n^(1/3)) revolutions (moving blocks within a member)"},
                    {"levels", "members with replacement, then revolutions within each member"},
                    {"seed", boot.seed}};
  if (!twin.slider_acceleration || !twin.bearing_force) return e;
  std::vector<PooledFigure> figures = {
      {"slider_acceleration_positive_p95", "1", "slider_acceleration_positive [m/s^2]",
       twin.slider_acceleration->positive.p95},
      {"slider_acceleration_negative_p95", "1", "slider_acceleration_negative [m/s^2]",
       twin.slider_acceleration->negative.p95},
      {"bearing_force_p95", "1", "bearing_force [N]", twin.bearing_force->positive.p95},
      {"gauge_stress_p95 [Pa]", "Pa", "gauge_stress [Pa]", 1.0},
  };
  std::vector<std::vector<std::pair<std::string, std::vector<double>>>> series;
  for (const RunResult* r : runs) series.push_back(PerRevolutionSeries(*r));
  std::vector<nlohmann::json> member_json(runs.size());
  for (size_t m = 0; m < runs.size(); ++m) {
    const nlohmann::json& s = runs[m]->summary;
    member_json[m] = {{"drive.initial_angle [rad]", inputs[m].Quantity("drive.initial_angle")},
                      {"sim.settle [s]", inputs[m].Quantity("sim.settle")},
                      {"outcome", multibody::ToString(runs[m]->status.outcome)},
                      {"capture_start [s]",
                       runs[m]->channels.num_samples() ? runs[m]->channels.start_time() : 0.0},
                      {"stationary", s.contains("steady_window") ? s["steady_window"]["stationary"]
                                                                 : nlohmann::json()},
                      {"regime", s.contains("regime") ? s["regime"]["window"] : nlohmann::json()},
                      {"revolutions", series[m].empty() ? 0 : series[m].front().second.size()}};
    if (s.contains("load_amplification")) {
      for (const char* key :
           {"slider_acceleration_positive", "slider_acceleration_negative", "bearing_force"})
        member_json[m]["figures"][key] = s["load_amplification"][key];
    }
  }
  nlohmann::json out_figures = nlohmann::json::object();
  // Steady states: the members grouped by their pooled amplifications together.
  std::vector<std::vector<study::Interval>> state_figures;
  std::vector<size_t> state_members;  // the members grouped: those with every amplification
  // Each pooled figure's members (index into runs) and their scaled series, for the states.
  std::vector<std::pair<std::vector<size_t>, std::vector<std::vector<double>>>> pooled_inputs;
  for (const PooledFigure& f : figures) {
    std::vector<std::vector<double>> members;
    std::vector<study::Interval> own;
    std::vector<size_t> which;  // members with revolutions in this series
    for (size_t m = 0; m < runs.size(); ++m) {
      const std::vector<double>* x = FindSeries(series[m], f.series);
      if (!runs[m]->ok() || x == nullptr || x->empty() || !(f.scale > 0.0)) continue;
      std::vector<double> scaled(*x);
      for (double& v : scaled) v /= f.scale;
      const study::Interval i =
          study::BootstrapInterval({scaled}, study::PooledPercentile(95.0), boot);
      member_json[m]["figures"][f.name] = {{"value", i.centre}, {"interval", {i.low, i.high}}};
      own.push_back(i);
      which.push_back(m);
      members.push_back(std::move(scaled));
    }
    pooled_inputs.emplace_back(which, members);
    if (members.empty()) continue;
    const study::Interval pooled =
        study::BootstrapInterval(members, study::PooledPercentile(95.0), boot);
    std::vector<double> centres;
    for (const study::Interval& i : own) centres.push_back(i.centre);
    const auto [lo, hi] = std::minmax_element(centres.begin(), centres.end());
    out_figures[f.name] = {{"unit", f.unit},
                           {"statistic", "95th percentile of the per-revolution peaks, pooled"},
                           {"centre", pooled.centre},
                           {"interval", {pooled.low, pooled.high}},
                           {"members_range", {*lo, *hi}}};
    if (std::string(f.unit) == "1" && (state_figures.empty() || which == state_members)) {
      state_figures.push_back(own);
      state_members = which;
    }
  }
  study::SteadyStates states = study::GroupSteadyStates(state_figures);
  std::vector<int> member_state(runs.size(), -1);  // -1: failed, not grouped
  for (size_t k = 0; k < state_members.size(); ++k)
    member_state[state_members[k]] = states.state[k];
  states.state = member_state;
  // Whole-window peaks: one extreme revolution each, so no interval of their own; the median
  // and range over the members.
  for (const char* key :
       {"slider_acceleration_positive", "slider_acceleration_negative", "bearing_force"}) {
    std::vector<double> v;
    for (const RunResult* r : runs) {
      const nlohmann::json& s = r->summary;
      if (r->ok() && s.contains("load_amplification") && s["load_amplification"][key].is_number())
        v.push_back(s["load_amplification"][key].get<double>());
    }
    if (v.empty()) continue;
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    out_figures[key] = {{"unit", "1"},
                        {"statistic", "largest peak of the window; median and range over members"},
                        {"centre", Median(v)},
                        {"members_range", {*lo, *hi}}};
  }
  e["figures"] = out_figures;
  std::map<std::string, int> windows;
  for (size_t m = 0; m < runs.size(); ++m) {
    member_json[m]["steady_state"] = states.state[m];
    if (member_json[m]["regime"].is_string())
      ++windows[member_json[m]["regime"].get<std::string>()];
  }
  e["member_runs"] = member_json;
  if (states.count > 1) {
    // Coexisting steady states are named, not averaged away: each state's pooled figures.
    nlohmann::json list = nlohmann::json::array();
    for (int st = 0; st < states.count; ++st) {
      nlohmann::json one = {{"members", nlohmann::json::array()}};
      for (size_t m = 0; m < runs.size(); ++m) {
        if (states.state[m] == st) one["members"].push_back(m);
      }
      for (size_t k = 0; k < figures.size(); ++k) {
        std::vector<std::vector<double>> in_state;
        const auto& [which, members] = pooled_inputs[k];
        for (size_t j = 0; j < which.size(); ++j) {
          if (states.state[which[j]] == st) in_state.push_back(members[j]);
        }
        if (in_state.empty()) continue;
        const study::Interval i =
            study::BootstrapInterval(in_state, study::PooledPercentile(95.0), boot);
        one["figures"][figures[k].name] = {{"centre", i.centre}, {"interval", {i.low, i.high}}};
      }
      list.push_back(one);
    }
    e["states"] = list;
  }
  std::string label = states.count > 1 ? std::to_string(states.count) + " steady states"
                                       : std::string("one steady state");
  std::string kinds;
  for (const auto& [k, n] : windows)
    kinds += (kinds.empty() ? "" : ", ") + std::to_string(n) + " " + k;
  e["regime"] = {{"steady_states", states.count},
                 {"grouped_by",
                  "slider_acceleration_positive_p95, slider_acceleration_negative_p95, "
                  "bearing_force_p95: alike if every interval overlaps or is within 20 %"},
                 {"windows", windows},
                 {"label", label + (kinds.empty() ? "" : "; windows: " + kinds)}};
  return e;
}

RunResult RunEnsemble(const Config& cfg, const RunOutputOptions& outputs, int jobs) {
  const EnsembleOptions options = ReadEnsembleOptions(cfg);
  // One rod for all: the members differ only in their start.
  MechanismModel built = BuildMechanism(cfg, nullptr, false);
  const bool clearance = built.clearance.index >= 0 && built.recipe->turns_a_crank();
  (void)CheckRunInput(cfg, built);  // a bad input starts nothing
  const int members = EnsembleMembers(options, clearance);
  if (!clearance) {
    // No twin, no amplification, and from any start the same periodic motion: one member is
    // the run.
    Require(members == 1, "ensemble.members", members,
            "an ensemble needs a clearance joint on a crank (its amplification over the ideal "
            "joint); use 1 (or 0) for an ideal joint or a mechanism without a crank");
    return RunSimulation(cfg, built.rod, false, outputs);
  }
  const std::vector<Config> inputs = EnsembleMemberInputs(cfg, options, members);
  TwinCache twins(1);
  std::shared_ptr<const RunResult> twin;
  std::vector<RunResult> runs(static_cast<size_t>(members));
  const int tasks = members + 1;  // the twin, then the members
  const int workers = std::min(
      tasks, jobs > 0 ? jobs : std::max(1, static_cast<int>(std::thread::hardware_concurrency())));
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto work = [&] {
    for (int t = next++; t < tasks; t = next++) {
      try {
        if (t == 0) {
          RunOutputOptions o;
          o.stop = outputs.stop;
          o.keep_channel = outputs.keep_channel;
          twin = twins.Get(cfg, [&] {
            return std::make_shared<const RunResult>(RunSimulation(cfg, built.rod, true, o));
          });
          continue;
        }
        const size_t m = static_cast<size_t>(t - 1);
        RunOutputOptions o = outputs;
        o.twins = &twins;
        o.twin_input = &cfg;
        if (m > 0) {
          o.record_vtk = false;
          o.profile = false;
          o.keep_channel = [](const std::string&) { return false; };
        }
        runs[m] = RunSimulation(inputs[m], built.rod, false, o);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < workers; ++w) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  std::vector<const RunResult*> ptrs;
  for (const RunResult& r : runs) ptrs.push_back(&r);
  runs[0].summary["ensemble"] = SummariseEnsemble(inputs, ptrs, *twin, options);
  return std::move(runs[0]);
}

}  // namespace flexrod
