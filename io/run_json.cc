// SPDX-License-Identifier: GPL-3.0-or-later
// The "json" run writer (io/run_writer.h): resolved.toml and summary.json.
#include <algorithm>

#include "common/files.h"
#include "common/units.h"
#include "io/run_writer.h"

namespace flexrod {
namespace {

/// The clearance joint's resolved contact parameters (summary "joint_parameters") as notes for
/// the resolved input: beside a joint.* key, the value the run used where the key's value
/// differs (0 = derive); the others (pin radius, moduli, a law's internal quantities, the
/// friction law's) listed at the end of [joint].
Config::DerivedNotes JointNotes(const Config& cfg, const nlohmann::json& params) {
  Config::DerivedNotes notes;
  for (const auto& [name, p] : params.items()) {
    const double value = p.at("value").get<double>();
    const std::string unit = p.at("unit").get<std::string>();
    const std::string text = FormatValue(value) + (unit.empty() || unit == "1" ? "" : " " + unit) +
                             " (" + p.at("source").get<std::string>() + ")";
    std::string key = name;
    const std::string law = "joint.law.";
    if (key.rfind(law, 0) == 0) {
      key = "joint." + key.substr(law.size());
      std::replace(key.begin(), key.end(), '-', '_');
    }
    const ParamDef* def = FindParam(key);
    if (def && def->kind == ParamKind::kQuantity) {
      if (cfg.Quantity(key) != value) notes.beside[key] = "used: " + text;
    } else {
      notes.listed["joint"].push_back("resolved " + name + " = " + text);
    }
  }
  return notes;
}

class JsonWriter final : public RunWriter {
 public:
  const char* format() const override { return "json"; }
  bool Selected(const RunFileRequest& r, const OutputSelection& /*sel*/) const override {
    return !r.dir.empty();
  }
  void RemoveStale(const RunFileRequest& /*r*/) const override {}  // always replaced
  double Write(const RunFileRequest& r, const RunFileContext& c) const override {
    const Config::DerivedNotes notes = c.run.summary.contains("joint_parameters")
                                           ? JointNotes(c.cfg, c.run.summary["joint_parameters"])
                                           : Config::DerivedNotes{};
    WriteFileAtomic(r.dir + "/resolved.toml", c.cfg.ResolvedToml(notes));
    WriteFileAtomic(r.dir + "/summary.json", c.run.summary.dump(2) + "\n");
    return RegularFileBytes(r.dir + "/resolved.toml") + RegularFileBytes(r.dir + "/summary.json");
  }
};

}  // namespace

std::unique_ptr<RunWriter> MakeJsonWriter() { return std::make_unique<JsonWriter>(); }

}  // namespace flexrod
