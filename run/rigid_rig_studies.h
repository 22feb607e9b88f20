// run/rigid_rig_studies.h — the definitions of the thesis's rigid-rig studies (`flexrod study
// rigid-rig-laws`: every normal law at 101 and 177 rpm, 1 mm clearance, thesis §3.3;
// `flexrod study rigid-rig-friction`: clearance 0.5 and 1.0 mm × joint friction 0.2, 0.4, 0.6,
// thesis §3.4 / Fig. 39): their cases, the tolerances they run at, and the figures of a case's
// row. What does not live here: running the cases and writing their files and tables
// (app/cmd_study.cc).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flexrod {

struct StudyCase {
  std::string tag;                ///< the case's output directory under --out
  std::vector<std::string> row;   ///< the case's own columns (law and speed, or clearance ...)
  std::vector<std::string> sets;  ///< "key=value" assignments on top of the rigid-rig preset
};

struct RigidRigStudy {
  std::string title;
  std::vector<std::string> header;  ///< the cases' own columns, then RigidRigStudyColumns()
  std::vector<StudyCase> cases;
};

/// The names of the rigid-rig studies, for the command line.
const std::vector<std::string>& RigidRigStudyNames();

/// The study called `name` (one of RigidRigStudyNames()); std::logic_error for another name.
RigidRigStudy FindRigidRigStudy(const std::string& name);

/// The integrator tolerances every case runs at before the user's --set: the impact peaks on
/// this rig need them (tests/run/clearance_trends_slowtest.cc checks the trends at these).
const std::vector<std::string>& RigidRigStudyTolerances();

/// The figure columns of every case's row, with their units.
const std::vector<std::string>& RigidRigStudyColumns();

/// A case's figures, in the order of RigidRigStudyColumns(), as printed ("n/a" where the run
/// has none): from the run's outcome, summary and wall time [s].
std::vector<std::string> RigidRigStudyFigures(const std::string& outcome,
                                              const nlohmann::json& summary, double wall);

/// A figure as the study tables print it: 4 significant digits, "n/a" for null or NaN.
std::string StudyNumber(const nlohmann::json& j);

}  // namespace flexrod
