// multibody/simulate_internal.h — Internal to multibody/: what multibody/simulate.cc (initial
// conditions, the DAE adapter) shares with the run loop in multibody/simulation_loop.cc.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "common/eigen.h"
#include "multibody/mechanism.h"
#include "multibody/run_data.h"

namespace flexrod::multibody {

/// Index of the entry of largest magnitude (a non-finite entry counts as infinite); −1 if empty.
int WorstIndex(const Vec& r);

/// The mechanism's total energy at the full state y, with no reference energy subtracted [J].
double InitialEnergy(const Mechanism& model, RunData* data, const Vec& y);

/// Projects a full state (y, with ẏ recomputed into yp) at time t onto the position
/// constraints g = 0 and the velocity constraints G v + g_t = 0, moving only the coordinates
/// `movable`: every re-initialisation of the integration starts from it, since the integrator's
/// state meets the constraints only to its tolerance. NumericalError if that fails.
void ProjectOntoConstraints(const Mechanism& model, RunData* data, double t,
                            const std::vector<int>& movable, Vec* y, Vec* yp);

}  // namespace flexrod::multibody
