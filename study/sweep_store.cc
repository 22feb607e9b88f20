// SPDX-License-Identifier: GPL-3.0-or-later
// StoredRun: analysis of a run for the store, HDF5 layout, part files and the store file.
#include "study/sweep_store.h"

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
#include "study/signals.h"

namespace flexrod::study {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kFormat = "flexrod-sweep-store 1";
constexpr const char* kAcc = "slider_acceleration";
constexpr const char* kCrank = "crank_angle";

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

StoredPoints ToStored(const std::vector<TurningPoint>& points) {
  StoredPoints p;
  for (const TurningPoint& t : points) {
    p.time.push_back(t.time);
    p.crank_angle.push_back(t.crank_angle);
    p.value.push_back(t.value);
  }
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

StoredRun Base(const Config& cfg, const StoreOptions& store) {
  StoredRun out;
  out.fingerprint = RunFingerprint(cfg, store);
  out.input_toml = InputToml(cfg);
  return out;
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

// ---- analysis -------------------------------------------------------------------------------

StoredRun FailedRun(const Config& cfg, const StoreOptions& store, const std::string& status,
                    const std::string& message) {
  StoredRun out = Base(cfg, store);
  out.status = status;
  out.message = message;
  out.summary_json = "{}";
  return out;
}

StoredRun AnalyseRun(const Config& cfg, const RunResult& run, const StoreOptions& store) {
  StoredRun out = Base(cfg, store);
  out.status = run.ok() ? "completed" : multibody::ToString(run.status.outcome);
  if (!run.ok()) {
    out.message = "t = " + FormatValue(run.status.t_reached) + " s: " + run.status.message;
    if (!run.status.hint.empty()) out.message += " (hint: " + run.status.hint + ")";
  }
  out.summary_json = run.summary.dump();
  if (run.summary.contains("wall_time [s]") && run.summary["wall_time [s]"].is_number()) {
    out.wall_time = run.summary["wall_time [s]"].get<double>();
  }
  const TimeSeries& ts = run.channels;
  const double rate = ts.sample_rate();
  const double index_angle = cfg.Quantity("sim.index_angle");
  const bool has_acc = ts.num_samples() >= 3 && ts.HasChannel(kAcc) && ts.HasChannel(kCrank);
  auto add = [&out](const std::string& name, double v, const std::string& unit) {
    out.summary.push_back({name, v, unit});
  };
  add("num_samples", static_cast<double>(ts.num_samples()), "1");

  if (has_acc) {
    // Peaks and per-revolution statistics; a record too short for a revolution gives NaNs.
    try {
      const SignalSummary s = CalcSignalSummary(ts, kAcc, kCrank, index_angle, ts.all());
      add("peak_positive", s.peak_positive, "m/s^2");
      add("peak_negative", s.peak_negative, "m/s^2");
      add("rms", s.rms, "m/s^2");
      add("revolutions", static_cast<double>(s.positive.num_revolutions), "1");
      add("positive_median", s.positive.median, "m/s^2");
      add("positive_p95", s.positive.p95, "m/s^2");
      add("positive_max", s.positive.max, "m/s^2");
      add("negative_median", s.negative.median, "m/s^2");
      add("negative_p95", s.negative.p95, "m/s^2");
      add("negative_max", s.negative.max, "m/s^2");
      LoadAmplification amp{kNaN, kNaN, kNaN, kNaN};
      double ideal_pos = kNaN, ideal_neg = kNaN;
      if (run.ideal && run.ideal->num_samples() == ts.num_samples() &&
          run.ideal->HasChannel(kAcc)) {
        const SignalSummary i =
            CalcSignalSummary(*run.ideal, kAcc, kCrank, index_angle, run.ideal->all());
        amp = CalcLoadAmplification(s, i);
        ideal_pos = i.peak_positive;
        ideal_neg = i.peak_negative;
      }
      add("ideal_peak_positive", ideal_pos, "m/s^2");
      add("ideal_peak_negative", ideal_neg, "m/s^2");
      add("amplification_positive", amp.positive, "1");
      add("amplification_negative", amp.negative, "1");
      add("amplification_positive_p95", amp.positive_p95, "1");
      add("amplification_negative_p95", amp.negative_p95, "1");
      const auto& la = run.summary.contains("load_amplification")
                           ? run.summary["load_amplification"]
                           : nlohmann::json();
      auto ratio = [&la](const char* key) {
        return la.is_object() && la.contains(key) && la[key].is_number() ? la[key].get<double>()
                                                                         : kNaN;
      };
      add("amplification_bearing_force", ratio("bearing_force"), "1");
      add("amplification_bearing_force_p95", ratio("bearing_force_p95"), "1");
    } catch (const InputError&) {
    }
    try {
      const InflectionPoints p =
          FindInflectionPoints(ts, kAcc, kCrank, ts.all(), store.inflection_floor);
      out.positive = ToStored(p.positive);
      out.negative = ToStored(p.negative);
    } catch (const InputError&) {
    }
    add("num_inflection_positive", static_cast<double>(out.positive.time.size()), "1");
    add("num_inflection_negative", static_cast<double>(out.negative.time.size()), "1");
    add("inflection_floor", store.inflection_floor, "m/s^2");
    try {
      std::vector<std::string> names;
      for (const std::string& c : store.poincare_channels) {
        if (ts.HasChannel(c)) names.push_back(c);
      }
      const PoincareMap map = CalcPoincareMap(ts, kCrank, index_angle, names, ts.all());
      out.poincare.push_back({"time", "s", map.time});
      for (std::size_t c = 0; c < names.size(); ++c) {
        const Vec col = map.points.col(static_cast<Eigen::Index>(c));
        out.poincare.push_back({names[c], map.units[c], ToStd(col)});
        PoincareJitter j{kNaN, kNaN, 0};
        if (map.num_points() >= 4)
          j = CalcPoincareJitter(std::span<const double>(col.data(), col.size()));
        out.poincare_jitter.push_back({"jitter_" + names[c], j.total, map.units[c]});
        out.poincare_jitter.push_back(
            {"jitter_normalised_" + names[c], j.normalised, map.units[c]});
      }
    } catch (const InputError&) {
      out.poincare.clear();
      out.poincare_jitter.clear();
    }
    try {
      const Spectrum sp = CalcAmplitudeSpectrum(ts, kAcc, ts.all(), store.spectrum_window);
      out.spectrum_channel = kAcc;
      out.spectrum_window = ToString(sp.window);
      out.spectrum_resolution = sp.resolution;
      out.spectrum_num_samples = static_cast<double>(sp.num_samples);
      out.amplitude_unit = ts.channel(kAcc).unit;
      for (std::size_t k = 0; k < sp.num_bins() && sp.frequency[k] <= store.spectrum_max; ++k) {
        out.frequency.push_back(sp.frequency[k]);
        out.amplitude.push_back(sp.amplitude[k]);
      }
    } catch (const InputError&) {
    } catch (const NumericalError&) {
    }
  }
  // Stored channels, decimated (plain subsampling: the analysis above used every sample).
  if (ts.num_samples() > 0) {
    const std::size_t decimation =
        store.rate < rate ? static_cast<std::size_t>(std::lround(rate / store.rate)) : 1;
    out.decimation = static_cast<double>(decimation);
    out.channel_rate = rate / static_cast<double>(decimation);
    out.channel_start = ts.start_time();
    for (const std::string& name : store.channels) {
      if (!ts.HasChannel(name)) continue;
      const Channel& c = ts.channel(name);
      StoredSeries s{c.name, c.unit, {}};
      s.values.reserve(c.values.size() / decimation + 1);
      for (std::size_t i = 0; i < c.values.size(); i += decimation) s.values.push_back(c.values[i]);
      out.channels.push_back(std::move(s));
    }
  }
  return out;
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
  if (!file.HasAttr("format") || file.GetString("format") != kFormat) {
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
    return file.HasAttr("format") && file.GetString("format") == kFormat;
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
