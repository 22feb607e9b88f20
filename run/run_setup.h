// run/run_setup.h — what a run is made of before it is integrated: the integrator options
// from sim.*, the channels a run records (on the recorder of mechanisms/recorder.h), and the
// input checks (CheckRunInput, run/run.h). Used by run/run.cc only.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <algorithm>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "input/config.h"
#include "input/options.h"
#include "mechanisms/impact_log.h"
#include "mechanisms/mechanism_model.h"
#include "mechanisms/recorder.h"
#include "multibody/simulate.h"

namespace flexrod {

/// sim.* as the integrator's options (tolerances, step limit, linear solver, sample rate); the
/// integrator's own checks, named by the user's sim.* keys.
multibody::SimulationOptions IntegratorOptions(const SimOptions& sim);

/// The run's channels. `impacts` (clearance runs) also sees the contact at every sample;
/// `gauges_json` receives each gauge's position.
void DefineChannels(const Config& cfg, const MechanismModel& mm, Recorder* rec,
                    nlohmann::json* gauges_json, study::ImpactLogger* impacts);

}  // namespace flexrod
