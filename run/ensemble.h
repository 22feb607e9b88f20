// run/ensemble.h — a run's answer as a distribution (DESIGN.md, "A run's answer is a
// distribution, not a number"): the same case run from several starts (crank start angles
// spread over the revolution, settle lengths), in parallel, sharing member 0's ideal-joint twin,
// and each headline figure reported as a centre with a bootstrap interval over revolutions and
// members, the members' own figures, their windows' regimes and the steady states they fall
// into. What does not live here: the statistics (signals/regimes.h), one run (run/run.h).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "input/config.h"
#include "input/options.h"
#include "run/run.h"

namespace flexrod {

/// The inputs of the members: member 0 is `cfg` itself; member k (1 ≤ k < members) starts its
/// crank at drive.initial_angle + k · angle_step (2π / members for 0) and settles sim.settle + k ·
/// settle_spread / members.
std::vector<Config> EnsembleMemberInputs(const Config& cfg, const EnsembleOptions& options,
                                         int members);

/// What `flexrod run` runs: the ensemble of `cfg` (ensemble.*; EnsembleMembers with the
/// automatic choice for a clearance joint on a crank). Member 0 runs with `outputs` (its
/// channels, files and VTK are the run's), the others keep only what their summaries read, all
/// share member 0's ideal-joint twin (computed once, as the first task), on `jobs` threads (0:
/// the machine's cores). Returns member 0's run with summary["ensemble"] (SummariseEnsemble;
/// failed members are listed and left out of the figures). Without a clearance joint on a
/// crank, one member only (InputError for more): RunSimulation(cfg, outputs).
RunResult RunEnsemble(const Config& cfg, const RunOutputOptions& outputs, int jobs = 0);

/// The ensemble summary of finished members (their inputs `inputs`, their runs `runs`, all
/// against the twin `twin`):
/// - "figures": per headline figure (the 95th percentile of the per-revolution peaks: slider
///   acceleration amplification + and −, bearing-force amplification, gauge stress) its unit,
///   centre (the statistic of all members' revolutions pooled), interval (two-level bootstrap,
///   study::BootstrapInterval, at `options.confidence`) and the members' range; for the
///   whole-window peaks (amplification + and −, bearing force) the median and range over the
///   members;
/// - "members": each member's start, capture start, stationarity, window regime, steady state
///   and figures with their own (revolutions-only) interval;
/// - "regime": the number of steady states (study::GroupSteadyStates of the members' p95
///   figures), the windows' regimes counted, and one label for the run;
/// - "states" (with more than one steady state): each state's members and pooled p95 figures.
nlohmann::json SummariseEnsemble(const std::vector<Config>& inputs,
                                 const std::vector<const RunResult*>& runs, const RunResult& twin,
                                 const EnsembleOptions& options);

}  // namespace flexrod
