// SPDX-License-Identifier: GPL-3.0-or-later
// A sweep matrix as JSON and back (how MPI ranks receive the matrix they run).
#include <string>
#include <vector>

#include "common/error.h"
#include "sweep/sweep_matrix.h"

namespace flexrod::study {

nlohmann::json SweepMatrixToJson(const SweepMatrix& m) {
  nlohmann::json j;
  j["name"] = m.name;
  j["description"] = m.description;
  j["origin"] = m.origin;
  j["source"] = m.source;
  j["base"] = m.base;
  j["base_toml"] = m.base_toml;
  for (const Assignment& a : m.overrides) j["overrides"].push_back({a.key, a.value});
  j["axis_keys"] = m.axis_keys;
  j["runs"] = nlohmann::json::array();
  for (const SweepRun& r : m.runs) {
    nlohmann::json values = nlohmann::json::array();
    for (const Assignment& a : r.values) values.push_back({a.key, a.value});
    j["runs"].push_back({{"values", values}, {"member", r.member}, {"case_id", r.case_id}});
  }
  const StoreOptions& s = m.store;
  j["store"] = {{"channels", s.channels},
                {"rate", s.rate},
                {"spectrum_window", ToString(s.spectrum_window)},
                {"spectrum_max", s.spectrum_max},
                {"inflection_floor", s.inflection_floor},
                {"poincare_channels", s.poincare_channels}};
  return j;
}

SweepMatrix SweepMatrixFromJson(const nlohmann::json& j) {
  SweepMatrix m;
  m.name = j.at("name");
  m.description = j.at("description");
  m.origin = j.at("origin");
  m.source = j.at("source");
  m.base = j.at("base");
  m.base_toml = j.at("base_toml");
  if (j.contains("overrides")) {
    for (const auto& a : j["overrides"]) m.overrides.push_back({a[0], a[1]});
  }
  m.axis_keys = j.at("axis_keys").get<std::vector<std::string>>();
  for (const auto& r : j.at("runs")) {
    SweepRun run;
    run.id = static_cast<int>(m.runs.size());
    for (const auto& a : r.at("values")) run.values.push_back({a[0], a[1]});
    run.member = r.at("member");
    run.case_id = r.at("case_id");
    m.runs.push_back(std::move(run));
  }
  const auto& s = j.at("store");
  m.store.channels = s.at("channels").get<std::vector<std::string>>();
  m.store.rate = s.at("rate");
  m.store.spectrum_window = WindowFromString("store.spectrum_window", s.at("spectrum_window"));
  m.store.spectrum_max = s.at("spectrum_max");
  m.store.inflection_floor = s.at("inflection_floor");
  m.store.poincare_channels = s.at("poincare_channels").get<std::vector<std::string>>();
  return m;
}

}  // namespace flexrod::study
