// mechanisms/rod_config.h — builds the rod (fem::RodSpec) and its reduction (fem::ReductionSpec)
// from the input keys rod.* and reduction.* (input/config.h). Attachments are added by the
// mechanism builders, not here.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include "fem/reduced_rod.h"
#include "input/config.h"

namespace flexrod {

/// Material, section, length and discretisation from rod.*; validated.
fem::RodSpec RodFromConfig(const Config& cfg);

/// Reduction for the mechanism: big-end node fixed in the frame, interface the small end
/// (free–free: no fixed dofs), method and mode count from reduction.*.
fem::ReductionSpec MechanismReductionFromConfig(const Config& cfg, const fem::RodSpec& rod);

/// Interface node list from "small-end", "ends" or "0,20,40" (key names the source).
std::vector<int> InterfaceNodes(const std::string& key, const std::string& text,
                                const fem::RodSpec& rod);

}  // namespace flexrod
