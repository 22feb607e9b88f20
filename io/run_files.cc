// SPDX-License-Identifier: GPL-3.0-or-later
#include "io/run_files.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "common/error.h"
#include "common/files.h"
#include "common/hdf5.h"
#include "common/units.h"
#include "mechanisms/impact_log.h"
#include "sweep/sweep_store.h"

namespace flexrod {
namespace {

namespace fs = std::filesystem;

constexpr const char* kRunFormat = "flexrod-run 1";

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

/// The selected view of a record: `ts` itself when everything is selected (no copy).
const study::TimeSeries& Selected(const study::TimeSeries& ts, const OutputSelection& sel,
                                  study::TimeSeries* storage) {
  if (!sel.standard && sel.channels.empty() && sel.stride == 1) return ts;
  *storage = SelectChannels(ts, sel);
  return *storage;
}

void WriteChannelGroup(const h5::Node& group, const study::TimeSeries& ts,
                       const OutputSelection& sel) {
  study::TimeSeries storage(1.0, 0.0);
  const study::TimeSeries& out = Selected(ts, sel, &storage);
  study::WriteChannels(group, out.sample_rate(), out.start_time(), static_cast<double>(sel.stride),
                       out.channels());
}

/// run.h5: written to run.h5.tmp, closed (which flushes and checks every buffered write), then
/// renamed into place.
void WriteRunH5(const std::string& dir, const Config& cfg, const RunResult& run,
                const OutputSelection& sel, const std::string& shared_twin_dir) {
  const std::string path = dir + "/run.h5", tmp = path + ".tmp";
  study::StoreOptions store;
  store.channels.clear();  // written below, without the copy a StoredRun would hold
  const double rate = run.channels.sample_rate();
  store.rate = rate / static_cast<double>(sel.stride);
  const study::StoredRun stored = study::AnalyseRun(cfg, run, store);
  try {
    h5::Node file = h5::CreateFile(tmp);
    file.SetAttr("format", kRunFormat);
    study::WriteStoredRun(file, stored, false);
    WriteChannelGroup(file.CreateGroup("channels"), run.channels, sel);
    if (run.ideal && !shared_twin_dir.empty()) {
      const std::string target =
          fs::relative(fs::absolute(shared_twin_dir + "/run.h5"), fs::absolute(dir)).string();
      file.LinkExternal("ideal", target, "/ideal");
    } else if (run.ideal) {
      WriteChannelGroup(file.CreateGroup("ideal").CreateGroup("channels"), *run.ideal, sel);
    }
    const h5::Node impacts = file.CreateGroup("impacts");
    std::string names, units;
    for (const study::Channel& c : study::ImpactColumns(run.impacts)) {
      impacts.WriteVector(
          c.name,
          Eigen::Map<const Vec>(c.values.data(), static_cast<Eigen::Index>(c.values.size())),
          c.unit);
      names += (names.empty() ? "" : ",") + c.name;
      units += (units.empty() ? "" : ",") + c.unit;
    }
    impacts.SetAttr("names", names);  // the column order, as in the other groups
    impacts.SetAttr("units", units);
    file.Close(tmp);
  } catch (const IoError& e) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError(std::string(e.what()) + " (writing " + path + ")");
  } catch (...) {  // a bug or out of memory stays what it is; the half file goes
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  CommitFile(tmp, path);
}

void WriteRunCsv(const std::string& dir, const RunResult& run, const OutputSelection& sel,
                 const std::string& shared_twin_dir) {
  study::TimeSeries storage(1.0, 0.0);
  study::WriteCsv(Selected(run.channels, sel, &storage), dir + "/channels.csv");
  if (!run.impacts.empty()) study::WriteImpactCsv(run.impacts, dir + "/impacts.csv");
  if (!run.ideal) return;
  EnsureDirectory("--out", dir + "/ideal");
  const std::string path = dir + "/ideal/channels.csv";
  if (shared_twin_dir.empty()) {
    study::WriteCsv(Selected(*run.ideal, sel, &storage), path);
    return;
  }
  std::error_code ec;
  fs::remove(path, ec);
  const fs::path target = fs::relative(fs::absolute(shared_twin_dir + "/ideal/channels.csv"),
                                       fs::absolute(dir + "/ideal"));
  fs::create_symlink(target, path, ec);
  if (ec) throw IoError("cannot link " + path + " to " + target.string() + ": " + ec.message());
}

}  // namespace

study::TimeSeries SelectChannels(const study::TimeSeries& ts, const OutputSelection& sel) {
  study::TimeSeries out(ts.sample_rate() / static_cast<double>(sel.stride), ts.start_time());
  for (const study::Channel& c : ts.channels()) {
    const bool keep =
        sel.standard ? IsStandardChannel(c.name)
                     : sel.channels.empty() || std::find(sel.channels.begin(), sel.channels.end(),
                                                         c.name) != sel.channels.end();
    if (!keep) continue;
    std::vector<double> v;
    v.reserve(c.values.size() / sel.stride + 1);
    for (std::size_t i = 0; i < c.values.size(); i += sel.stride) v.push_back(c.values[i]);
    out.AddChannel(c.name, c.unit, std::move(v));
  }
  return out;
}

double WriteRunFiles(const std::string& dir, const Config& cfg, const RunResult& run,
                     const std::string& shared_twin_dir) {
  EnsureDirectory("--out", dir);
  const OutputSelection sel = ReadOutputSelection(cfg, cfg.Quantity("sim.sample_rate"), nullptr);
  const Config::DerivedNotes notes = run.summary.contains("joint_parameters")
                                         ? JointNotes(cfg, run.summary["joint_parameters"])
                                         : Config::DerivedNotes{};
  // A previous run's channel files that this run does not replace would be read as its own.
  std::error_code ec;
  for (const char* stale : {"run.h5", "channels.csv", "impacts.csv", "ideal/channels.csv"}) {
    fs::remove(dir + "/" + stale, ec);
  }
  fs::remove(dir + "/ideal", ec);  // only if empty
  WriteFileAtomic(dir + "/resolved.toml", cfg.ResolvedToml(notes));
  // The summary first: the figures survive a disk that fills up with the channels.
  WriteFileAtomic(dir + "/summary.json", run.summary.dump(2) + "\n");
  if (sel.hdf5) WriteRunH5(dir, cfg, run, sel, shared_twin_dir);
  if (sel.csv) WriteRunCsv(dir, run, sel, shared_twin_dir);
  double bytes = 0.0;
  for (const char* f : {"resolved.toml", "summary.json", "run.h5", "channels.csv", "impacts.csv",
                        "ideal/channels.csv"}) {
    const fs::path p = fs::path(dir) / f;
    if (fs::is_regular_file(fs::symlink_status(p, ec)))
      bytes += static_cast<double>(fs::file_size(p, ec));
  }
  return bytes;
}

}  // namespace flexrod
