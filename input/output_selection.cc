// SPDX-License-Identifier: GPL-3.0-or-later
#include "input/output_selection.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "common/units.h"

namespace flexrod {

bool IsStandardChannel(const std::string& name) {
  static const std::vector<std::string> kNames = {"crank_angle",
                                                  "crank_speed",
                                                  "crank_torque",
                                                  "slider_position",
                                                  "slider_velocity",
                                                  "slider_acceleration",
                                                  "rod_angle",
                                                  "rod_angular_velocity",
                                                  "bearing_force",
                                                  "journal_eccentricity_x",
                                                  "journal_eccentricity_y",
                                                  "contact_normal_force",
                                                  "contact_friction_force",
                                                  "rod_deflection"};
  return std::find(kNames.begin(), kNames.end(), name) != kNames.end() ||
         name.rfind("strain_", 0) == 0;
}

bool Selects(const OutputSelection& sel, const std::string& name) {
  if (sel.standard) return IsStandardChannel(name);
  return sel.channels.empty() ||
         std::find(sel.channels.begin(), sel.channels.end(), name) != sel.channels.end();
}

OutputSelection ReadOutputSelection(const Config& cfg, double sample_rate,
                                    const std::vector<std::string>* available) {
  OutputSelection sel;
  const std::string list = cfg.Text("output.channels");
  sel.standard = list == "standard";
  if (!sel.standard && list != "all") {
    for (const std::string& item : SplitUserList("output.channels", list)) {
      if (available && std::find(available->begin(), available->end(), item) == available->end()) {
        std::string names;
        for (const std::string& n : *available) names += (names.empty() ? "" : ", ") + n;
        throw InputError("output.channels", item,
                         "is not a channel of this run; channels: " + names);
      }
      sel.channels.push_back(item);
    }
    if (sel.channels.empty())
      throw InputError("output.channels", "\"" + list + "\"",
                       "names no channel; use all or a list");
  }
  const double rate = cfg.Quantity("output.rate");
  RequireNonNegative("output.rate", rate);
  if (rate > 0.0) {
    const double ratio = sample_rate / rate;
    sel.stride = static_cast<std::size_t>(std::lround(ratio));
    if (ratio < 1.0 - 1e-9 || std::abs(ratio - static_cast<double>(sel.stride)) > 1e-9 * ratio) {
      throw InputError("output.rate", FormatValue(rate) + " Hz",
                       "must divide sim.sample_rate = " + FormatValue(sample_rate) + " Hz");
    }
  }
  const std::string formats = cfg.Text("output.format");
  sel.hdf5 = sel.csv = false;
  for (const std::string& f : SplitUserList("output.format", formats)) {
    if (f == "hdf5") {
      sel.hdf5 = true;
    } else if (f == "csv") {
      sel.csv = true;
    } else {
      throw InputError("output.format", "\"" + formats + "\"",
                       "must be hdf5, csv or hdf5,csv (\"" + f + "\" is neither)");
    }
  }
  if (!sel.hdf5 && !sel.csv)
    throw InputError("output.format", "\"" + formats + "\"", "must be hdf5, csv or hdf5,csv");
  return sel;
}

}  // namespace flexrod
