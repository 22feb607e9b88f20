// SPDX-License-Identifier: GPL-3.0-or-later
// StoredRun: HDF5 layout, part files and the store file (the analysis of a run for the store:
// sweep/sweep_analysis.cc).
#include "sweep/sweep_store.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <sstream>

#include "common/error.h"
#include "common/files.h"
#include "signals/signals.h"

namespace flexrod::study {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kFormat = "flexrod-sweep-store 1";

/// Every HDF5 call of the sweep goes through this lock: parts are written from worker threads.
std::recursive_mutex& Hdf5Mutex() {
  static std::recursive_mutex mutex;
  return mutex;
}

Vec ToVec(const std::vector<double>& v) {
  return Eigen::Map<const Vec>(v.data(), static_cast<Eigen::Index>(v.size()));
}
std::vector<double> ToStd(const Vec& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

std::string Join(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + v[i];
  return s;
}

/// Datasets of one group in a given order, with an index attribute "names" (and "units") so
/// the order and units read back without HDF5 attribute iteration.
void WriteSeries(const h5::Node& group, const std::vector<StoredSeries>& series, bool compress) {
  std::vector<std::string> names, units;
  std::vector<h5::Node::VectorView> compressed;
  for (const StoredSeries& s : series) {
    names.push_back(s.name);
    units.push_back(s.unit.empty() ? "1" : s.unit);
    if (compress && !s.values.empty()) {
      compressed.push_back({s.name, units.back(), s.values.data(), s.values.size()});
    } else {
      group.WriteVector(s.name, ToVec(s.values), units.back());
    }
  }
  group.WriteCompressedVectors(compressed);
  group.SetAttr("names", Join(names));
  group.SetAttr("units", Join(units));
}
std::vector<StoredSeries> ReadSeries(const h5::Node& group) {
  const std::vector<std::string> names = SplitList(group.GetString("names"));
  const std::vector<std::string> units = SplitList(group.GetString("units"));
  if (units.size() != names.size())
    throw IoError("store: names and units of a group differ in count");
  std::vector<StoredSeries> out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out.push_back({names[i], units[i], ToStd(group.ReadVector(names[i]))});
  return out;
}

// An HDF5 attribute lives in its object header, which holds at most 64 KiB: a longer text is
// split into "<name>", "<name>.1", "<name>.2", ... of kTextPiece bytes each.
constexpr std::size_t kTextPiece = 60000;

void SetText(const h5::Node& node, const std::string& name, const std::string& text) {
  node.SetAttr(name, text.substr(0, kTextPiece));
  for (std::size_t k = 1; k * kTextPiece < text.size(); ++k) {
    node.SetAttr(name + "." + std::to_string(k), text.substr(k * kTextPiece, kTextPiece));
  }
}
std::string GetText(const h5::Node& node, const std::string& name) {
  std::string text = node.GetString(name);
  for (std::size_t k = 1; node.HasAttr(name + "." + std::to_string(k)); ++k) {
    text += node.GetString(name + "." + std::to_string(k));
  }
  return text;
}

void WriteScalars(const h5::Node& group, const std::vector<StoredScalar>& scalars) {
  std::vector<std::string> names;
  for (const StoredScalar& s : scalars) {
    group.SetAttr(s.name, s.value, s.unit.empty() ? "1" : s.unit);
    names.push_back(s.name);
  }
  group.SetAttr("names", Join(names));
}
std::vector<StoredScalar> ReadScalars(const h5::Node& group) {
  std::vector<StoredScalar> out;
  for (const std::string& n : SplitList(group.GetString("names"))) {
    out.push_back({n, group.GetDouble(n), group.GetString(n + ".unit")});
  }
  return out;
}

void WritePoints(const h5::Node& parent, const std::string& name, const StoredPoints& p) {
  const h5::Node g = parent.CreateGroup(name);
  WriteSeries(
      g,
      {{"time", "s", p.time}, {"crank_angle", "rad", p.crank_angle}, {"value", "m/s^2", p.value}},
      true);
}
StoredPoints ReadPoints(const h5::Node& parent, const std::string& name) {
  const h5::Node g = parent.OpenGroup(name);
  StoredPoints p;
  p.time = ToStd(g.ReadVector("time"));
  p.crank_angle = ToStd(g.ReadVector("crank_angle"));
  p.value = ToStd(g.ReadVector("value"));
  return p;
}

bool SameBits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}
bool SameVector(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!SameBits(a[i], b[i])) return false;
  }
  return true;
}

/// A TOML basic string.
std::string Quote(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    if (c == '\n') {
      q += "\\n";
      continue;
    }
    q += c;
  }
  return q + "\"";
}

}  // namespace

std::string InputToml(const Config& cfg) {
  // Only the keys the input set: a key's default can mean "derive it" (rod.E = 0: the
  // material's), so setting it explicitly would be another input.
  std::string text =
      "# flexrod run input: every key set for this run, as given; the others are defaults\n";
  for (const Config::Resolved& r : cfg.Resolve()) {
    if (!r.is_default) text += Quote(r.key) + " = " + Quote(cfg.Text(r.key)) + "\n";
  }
  return text;
}

double StoredRun::Summary(const std::string& name) const {
  for (const StoredScalar& s : summary) {
    if (s.name == name) return s.value;
  }
  return kNaN;
}

Config StoredRun::Input() const {
  Config cfg;
  cfg.LoadToml(input_toml, "stored input of run " + std::to_string(id));
  return cfg;
}

// ---- HDF5 layout ----------------------------------------------------------------------------

std::string RunGroupName(int id) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "run_%05d", id);
  return buf;
}

void WriteStoredRun(const h5::Node& g, const StoredRun& run, bool with_channels) {
  g.SetAttr("run_id", static_cast<double>(run.id), "1");
  g.SetAttr("fingerprint", run.fingerprint);
  g.SetAttr("status", run.status);
  SetText(g, "message", run.message);
  SetText(g, "label", run.label);
  SetText(g, "input_toml", run.input_toml);
  SetText(g, "summary_json", run.summary_json);
  g.SetAttr("wall_time", run.wall_time, "s");
  // The resolved input as attributes: key = SI value with "<key>.unit", or text.
  const Config input = run.Input();
  for (const Config::Resolved& r : input.Resolve()) {
    const ParamDef* p = FindParam(r.key);
    if (p && p->kind == ParamKind::kQuantity) {
      g.SetAttr(r.key, input.Quantity(r.key), r.unit.empty() ? "1" : r.unit);
    } else if (p && p->kind == ParamKind::kInteger) {
      g.SetAttr(r.key, static_cast<double>(input.Integer(r.key)), "1");
    } else {
      g.SetAttr(r.key, r.value);
    }
  }
  WriteScalars(g.CreateGroup("summary"), run.summary);
  {
    const h5::Node ip = g.CreateGroup("inflection_points");
    WritePoints(ip, "positive", run.positive);
    WritePoints(ip, "negative", run.negative);
  }
  {
    const h5::Node pc = g.CreateGroup("poincare");
    WriteSeries(pc, run.poincare, false);
    std::vector<std::string> names;
    for (const StoredScalar& s : run.poincare_jitter) {
      pc.SetAttr(s.name, s.value, s.unit.empty() ? "1" : s.unit);
      names.push_back(s.name);
    }
    pc.SetAttr("jitter_names", Join(names));
  }
  {
    const h5::Node sp = g.CreateGroup("spectrum");
    sp.SetAttr("channel", run.spectrum_channel);
    sp.SetAttr("window", run.spectrum_window);
    sp.SetAttr("resolution", run.spectrum_resolution, "Hz");
    sp.SetAttr("num_samples", run.spectrum_num_samples, "1");
    WriteSeries(
        sp, {{"frequency", "Hz", run.frequency}, {"amplitude", run.amplitude_unit, run.amplitude}},
        true);
  }
  if (with_channels) {
    WriteChannels(g.CreateGroup("channels"), run.channel_rate, run.channel_start, run.decimation,
                  run.channels);
  }
}

void WriteChannels(const h5::Node& group, double rate, double start, double decimation,
                   const std::vector<StoredSeries>& channels) {
  group.SetAttr("sample_rate", rate, "Hz");
  group.SetAttr("start_time", start, "s");
  group.SetAttr("decimation", decimation, "1");
  WriteSeries(group, channels, true);
}

StoredRun ReadStoredRun(const h5::Node& g, bool with_channels) {
  StoredRun run;
  run.id = static_cast<int>(g.GetDouble("run_id"));
  run.fingerprint = g.GetString("fingerprint");
  run.status = g.GetString("status");
  run.message = GetText(g, "message");
  run.label = GetText(g, "label");
  run.input_toml = GetText(g, "input_toml");
  run.summary_json = GetText(g, "summary_json");
  run.wall_time = g.GetDouble("wall_time");
  run.summary = ReadScalars(g.OpenGroup("summary"));
  {
    const h5::Node ip = g.OpenGroup("inflection_points");
    run.positive = ReadPoints(ip, "positive");
    run.negative = ReadPoints(ip, "negative");
  }
  {
    const h5::Node pc = g.OpenGroup("poincare");
    run.poincare = ReadSeries(pc);
    for (const std::string& n : SplitList(pc.GetString("jitter_names"))) {
      run.poincare_jitter.push_back({n, pc.GetDouble(n), pc.GetString(n + ".unit")});
    }
  }
  {
    const h5::Node sp = g.OpenGroup("spectrum");
    run.spectrum_channel = sp.GetString("channel");
    run.spectrum_window = sp.GetString("window");
    run.spectrum_resolution = sp.GetDouble("resolution");
    run.spectrum_num_samples = sp.GetDouble("num_samples");
    const std::vector<StoredSeries> s = ReadSeries(sp);
    run.frequency = s.at(0).values;
    run.amplitude = s.at(1).values;
    run.amplitude_unit = s.at(1).unit;
  }
  {
    const h5::Node ch = g.OpenGroup("channels");
    run.channel_rate = ch.GetDouble("sample_rate");
    run.channel_start = ch.GetDouble("start_time");
    run.decimation = ch.GetDouble("decimation");
    if (with_channels) run.channels = ReadSeries(ch);
  }
  return run;
}

// ---- files ----------------------------------------------------------------------------------

std::string ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot read " + path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Writes `tmp` with `write`, closes it (which flushes and checks every buffered write),
/// re-opens it for `check` (if given; it throws IoError when the file is not what was written)
/// and commits it under `path`; on any failure removes `tmp` and throws IoError naming `path`.
void WriteH5File(const std::string& tmp, const std::string& path,
                 const std::function<void(const h5::Node&)>& write,
                 const std::function<void(const h5::Node&)>& check = nullptr) {
  try {
    std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
    h5::Node file = h5::CreateFile(tmp);
    write(file);
    file.Close(tmp);
    if (check) check(h5::OpenFile(tmp));  // what a reader will see, before it gets the name
  } catch (const IoError& e) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw IoError(std::string(e.what()) + " (writing " + path + ")");
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  CommitFile(tmp, path);
}

void WritePartFile(const std::string& path, const StoredRun& run) {
  WriteH5File(path + ".tmp", path, [&](const h5::Node& file) {
    file.SetAttr("format", std::string(kFormat) + " part");
    WriteStoredRun(file, run);
  });
}

StoredRun ReadPartFile(const std::string& path, bool with_channels) {
  std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
  const h5::Node file = h5::OpenFile(path);
  if (!file.HasAttr("format") || file.GetString("format") != std::string(kFormat) + " part") {
    throw IoError(path + " is not a flexrod sweep part file");
  }
  return ReadStoredRun(file, with_channels);
}

void WriteStore(const std::string& path, const StoreHeader& header,
                const std::function<bool(StoredRun*)>& next) {
  const std::string tmp = path + ".tmp";
  WriteH5File(
      tmp, path,
      [&](const h5::Node& file) {
        file.SetAttr("format", kFormat);
        file.SetAttr("name", header.name);
        file.SetAttr("origin", header.origin);
        file.SetAttr("base", header.base);
        SetText(file, "matrix", header.matrix_source);
        SetText(file, "axes", Join(header.axis_keys));
        file.SetAttr("num_runs", static_cast<double>(header.num_runs), "1");
        const h5::Node runs = file.CreateGroup("runs");
        int failed = 0, written = 0;
        StoredRun run;
        while (next(&run)) {
          WriteStoredRun(runs.CreateGroup(RunGroupName(run.id)), run);
          failed += run.ok() ? 0 : 1;
          ++written;
        }
        if (written != header.num_runs) {
          throw std::logic_error("store " + path + ": " + std::to_string(written) + " of " +
                                 std::to_string(header.num_runs) + " runs delivered");
        }
        file.SetAttr("num_failed", static_cast<double>(failed), "1");
      },
      [&](const h5::Node& file) {
        const bool complete =
            file.HasAttr("format") && file.GetString("format") == kFormat &&
            file.HasAttr("num_failed") &&
            file.OpenGroup("runs").Children().size() == static_cast<std::size_t>(header.num_runs);
        if (!complete) throw IoError("the written store does not read back complete: " + path);
      });
}

namespace {

SweepStore ReadStoreContent(const h5::Node& file, bool with_channels) {
  SweepStore store;
  store.header.name = file.GetString("name");
  store.header.origin = file.GetString("origin");
  store.header.base = file.GetString("base");
  store.header.matrix_source = GetText(file, "matrix");
  store.header.axis_keys = SplitList(GetText(file, "axes"));
  store.header.num_runs = static_cast<int>(file.GetDouble("num_runs"));
  store.num_failed = static_cast<int>(file.GetDouble("num_failed"));
  const h5::Node runs = file.OpenGroup("runs");
  for (const std::string& name : runs.Children())
    store.runs.push_back(ReadStoredRun(runs.OpenGroup(name), with_channels));
  return store;
}

}  // namespace

SweepStore ReadStore(const std::string& path, bool with_channels) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw InputError("store", path, "does not exist");
  if (fs::is_directory(status)) throw InputError("store", path, "is a directory, not a store file");
  if (!fs::is_regular_file(status))
    throw InputError("store", path, "must be a regular file, not a device or pipe");
  std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
  h5::Node file;
  try {
    file = h5::OpenFile(path);
  } catch (const IoError&) {
    throw InputError("store", path, "is not an HDF5 file");
  }
  std::string format;
  try {
    if (file.HasAttr("format")) format = file.GetString("format");
  } catch (const IoError&) {  // not a string: not flexrod's
  }
  if (format != kFormat) {
    throw InputError(
        "store", path,
        "is not a flexrod sweep store (attribute format != '" + std::string(kFormat) + "')");
  }
  try {
    return ReadStoreContent(file, with_channels);
  } catch (const IoError& e) {
    throw InputError("store", path, std::string("is damaged: ") + e.what());
  }
}

StoreIndex::StoreIndex(const std::string& path) : path_(path) {
  if (!fs::is_regular_file(path)) return;
  try {
    std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
    const h5::Node file = h5::OpenFile(path);
    if (!file.HasAttr("format") || file.GetString("format") != kFormat) return;
    const h5::Node runs = file.OpenGroup("runs");
    for (const std::string& name : runs.Children()) {
      const h5::Node g = runs.OpenGroup(name);
      groups_[g.GetString("fingerprint")] = name;
    }
  } catch (const IoError&) {
    groups_.clear();  // not a readable store: nothing to reuse
  }
}

bool StoreIndex::IsStore(const std::string& path) {
  if (!fs::is_regular_file(path)) return false;
  try {
    std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
    const h5::Node file = h5::OpenFile(path);
    return file.HasAttr("format") && file.GetString("format") == kFormat;  // IoError: not a string
  } catch (const IoError&) {
    return false;
  }
}

StoredRun StoreIndex::Read(const std::string& fingerprint) const {
  std::lock_guard<std::recursive_mutex> lock(Hdf5Mutex());
  const h5::Node file = h5::OpenFile(path_);
  return ReadStoredRun(file.OpenGroup("runs").OpenGroup(groups_.at(fingerprint)), true);
}

// ---- comparison -----------------------------------------------------------------------------

bool SameResults(const StoredRun& a, const StoredRun& b, std::string* why) {
  auto differ = [why](const std::string& what) {
    if (why) *why = what;
    return false;
  };
  if (a.fingerprint != b.fingerprint) return differ("fingerprint");
  if (a.input_toml != b.input_toml) return differ("input");
  if (a.status != b.status) return differ("status " + a.status + " vs " + b.status);
  if (a.message != b.message) return differ("message");
  if (a.summary.size() != b.summary.size()) return differ("number of summary values");
  for (std::size_t i = 0; i < a.summary.size(); ++i) {
    const StoredScalar &x = a.summary[i], &y = b.summary[i];
    if (x.name != y.name || x.unit != y.unit || !SameBits(x.value, y.value)) {
      return differ("summary " + x.name + ": " + FormatValue(x.value) + " vs " +
                    FormatValue(y.value));
    }
  }
  const std::pair<const StoredPoints*, const StoredPoints*> pts[2] = {{&a.positive, &b.positive},
                                                                      {&a.negative, &b.negative}};
  for (const auto& [p, q] : pts) {
    if (!SameVector(p->time, q->time) || !SameVector(p->crank_angle, q->crank_angle) ||
        !SameVector(p->value, q->value)) {
      return differ("inflection points");
    }
  }
  auto same_series = [](const std::vector<StoredSeries>& x, const std::vector<StoredSeries>& y) {
    if (x.size() != y.size()) return false;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (x[i].name != y[i].name || x[i].unit != y[i].unit || !SameVector(x[i].values, y[i].values))
        return false;
    }
    return true;
  };
  if (!same_series(a.poincare, b.poincare)) return differ("Poincaré points");
  if (a.poincare_jitter.size() != b.poincare_jitter.size()) return differ("Poincaré jitter");
  for (std::size_t i = 0; i < a.poincare_jitter.size(); ++i) {
    if (a.poincare_jitter[i].name != b.poincare_jitter[i].name ||
        !SameBits(a.poincare_jitter[i].value, b.poincare_jitter[i].value)) {
      return differ("Poincaré jitter " + a.poincare_jitter[i].name);
    }
  }
  if (a.spectrum_window != b.spectrum_window ||
      !SameBits(a.spectrum_resolution, b.spectrum_resolution) ||
      !SameVector(a.frequency, b.frequency) || !SameVector(a.amplitude, b.amplitude)) {
    return differ("spectrum");
  }
  if (!SameBits(a.channel_rate, b.channel_rate) || !SameBits(a.channel_start, b.channel_start) ||
      !SameBits(a.decimation, b.decimation) || !same_series(a.channels, b.channels)) {
    return differ("channels");
  }
  return true;
}

}  // namespace flexrod::study
