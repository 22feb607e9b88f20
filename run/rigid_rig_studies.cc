// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/rigid_rig_studies.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "contact/normal_law.h"

namespace flexrod {

const std::vector<std::string>& RigidRigStudyNames() {
  static const std::vector<std::string> kNames = {"rigid-rig-laws", "rigid-rig-friction"};
  return kNames;
}

RigidRigStudy FindRigidRigStudy(const std::string& name) {
  RigidRigStudy s;
  if (name == "rigid-rig-laws") {
    s.title = "Rigid rig, 1 mm clearance: every normal law (thesis section 3.3)";
    s.header = {"law", "speed [rpm]"};
    for (const std::string& law : contact::NormalLawNames()) {
      for (const char* rpm : {"101", "177"}) {
        s.cases.push_back({law + "-" + rpm + "rpm",
                           {law, rpm},
                           {"joint.type=clearance", "joint.clearance=1 mm", "joint.law=" + law,
                            "drive.speed=" + std::string(rpm) + " rpm"}});
      }
    }
  } else if (name == "rigid-rig-friction") {
    s.title = "Rigid rig: clearance x joint friction (thesis section 3.4, Fig. 39)";
    s.header = {"clearance [mm]", "friction [-]"};
    for (const char* c : {"0.5", "1.0"}) {
      for (const char* mu : {"0.2", "0.4", "0.6"}) {
        s.cases.push_back({std::string("c") + c + "mm-mu" + mu,
                           {c, mu},
                           {"joint.type=clearance", std::string("joint.clearance=") + c + " mm",
                            std::string("joint.friction=") + mu}});
      }
    }
  } else {
    throw std::logic_error("FindRigidRigStudy: no study \"" + name + "\"");
  }
  const auto& cols = RigidRigStudyColumns();
  s.header.insert(s.header.end(), cols.begin(), cols.end());
  return s;
}

const std::vector<std::string>& RigidRigStudyTolerances() {
  static const std::vector<std::string> kSets = {"sim.rel_tol=1e-8", "sim.abs_tol=1e-10"};
  return kSets;
}

const std::vector<std::string>& RigidRigStudyColumns() {
  static const std::vector<std::string> kColumns = {"outcome",
                                                    "peak abs slider acc. [m/s^2]",
                                                    "median per-rev. peak abs slider acc. [m/s^2]",
                                                    "amplification +",
                                                    "amplification -",
                                                    "impacts per rev.",
                                                    "peak bearing force [N]",
                                                    "wall [s]"};
  return kColumns;
}

std::string StudyNumber(const nlohmann::json& j) {
  if (j.is_null() || std::isnan(j.get<double>())) return "n/a";
  std::ostringstream os;
  os.precision(4);
  os << j.get<double>();
  return os.str();
}

std::vector<std::string> RigidRigStudyFigures(const std::string& outcome, const nlohmann::json& s,
                                              double wall) {
  auto get = [&](const char* a, const char* b) {
    return s.contains(a) && s[a].contains(b) ? StudyNumber(s[a][b]) : std::string("n/a");
  };
  std::string peak = "n/a", median = "n/a";
  if (s.contains("slider_acceleration")) {
    const nlohmann::json& a = s["slider_acceleration"];
    peak =
        StudyNumber(std::max(a["peak_positive"].get<double>(), a["peak_negative"].get<double>()));
    median = StudyNumber(a["per_revolution_abs"]["median"]);
  }
  return {outcome,
          peak,
          median,
          get("load_amplification", "slider_acceleration_positive"),
          get("load_amplification", "slider_acceleration_negative"),
          get("impacts", "per_revolution"),
          get("load_amplification", "bearing_force_peak_real [N]"),
          StudyNumber(wall)};
}

}  // namespace flexrod
