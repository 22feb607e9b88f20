// SPDX-License-Identifier: GPL-3.0-or-later
// Matrix files: parsing (toml++), validation against the key schema, expansion into runs.
#include "sweep/sweep_matrix.h"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "common/error.h"
#include "common/files.h"
#include "input/options.h"
#include "input/presets.h"
#include "input/toml_value.h"

namespace flexrod::study {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxRuns = 1000000;  // a guard against a runaway range, not a physics limit

/// One axis: its keys (several for a zipped axis) and its points (one value per key each).
struct Axis {
  std::vector<std::string> keys;
  std::vector<std::vector<std::string>> points;
  std::size_t line{0}, column{0};  ///< position in the file: axes run in document order
};

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

std::string JoinNames(const std::vector<std::string>& v, const char* sep = ", ") {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + v[i];
  return s;
}

const ParamDef& KnownKey(const std::string& key, const std::string& value,
                         const std::string& where) {
  const ParamDef* p = FindParam(key);
  if (!p)
    throw InputError(key, value, "unknown input key in " + where + " (`flexrod keys` lists them)");
  return *p;
}

/// Validates one value for its key (the key's own rule, via Config::Set).
void CheckValue(const std::string& key, const std::string& value, const std::string& where) {
  KnownKey(key, value, where);
  Config scratch;
  scratch.Set(key, value);
}

/// Splits "100 rpm" into its number and unit text; false if it does not start with a number.
bool SplitNumber(const std::string& text, double* number, std::string* unit) {
  const std::string t = Trim(text);
  char* end = nullptr;
  *number = std::strtod(t.c_str(), &end);
  if (end == t.c_str()) return false;
  *unit = Trim(std::string(end));
  return true;
}

std::string FormatRangeValue(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

/// {from, to, step} → the values from, from + step, ... ≤ to (+ a relative 1e-9 of slack).
Axis RangeAxis(const std::string& key, const toml::table& t) {
  const ParamDef& p = KnownKey(key, "{from, to, step}", "a range");
  if (p.kind != ParamKind::kQuantity && p.kind != ParamKind::kInteger) {
    throw InputError(key, "{from, to, step}",
                     "a range needs a numeric key; list the values instead");
  }
  std::string text[3];
  const char* names[3] = {"from", "to", "step"};
  for (int i = 0; i < 3; ++i) text[i] = ScalarText(*t.get(names[i]), key + "." + names[i]);
  const Dimension dim = p.kind == ParamKind::kInteger ? Dimension::kDimensionless : p.dim;
  const double from = ParseQuantity(key + ".from", text[0], dim);
  const double to = ParseQuantity(key + ".to", text[1], dim);
  const double step = ParseQuantity(key + ".step", text[2], dim);
  if (!(step > 0.0)) throw InputError(key + ".step", text[2], "must be > 0");
  if (!(to >= from)) throw InputError(key + ".to", text[1], "must be >= from = " + text[0]);
  const double count_real = std::floor((to - from) / step + 1e-9) + 1.0;
  if (count_real > static_cast<double>(kMaxRuns)) {
    throw InputError(key + ".step", text[2], "gives more than 10^6 values");
  }
  const auto count = static_cast<std::size_t>(count_real);
  // Keep the user's unit in the values when from, to and step share it ("110 rpm").
  double n[3];
  std::string u[3];
  bool same_unit = true;
  for (int i = 0; i < 3; ++i) same_unit = SplitNumber(text[i], &n[i], &u[i]) && same_unit;
  same_unit = same_unit && u[0] == u[1] && u[1] == u[2];
  Axis axis;
  axis.keys = {key};
  for (std::size_t k = 0; k < count; ++k) {
    const double kd = static_cast<double>(k);
    const std::string v =
        same_unit ? FormatRangeValue(n[0] + kd * n[2]) + (u[0].empty() ? "" : " " + u[0])
                  : FormatRangeValue(from + kd * step);
    axis.points.push_back({v});
  }
  return axis;
}

bool IsRange(const toml::table& t) {
  if (t.size() != 3) return false;
  for (const char* k : {"from", "to", "step"}) {
    if (!t.contains(k)) return false;
  }
  return true;
}

/// Axes of one table ([axes] or one [[combinations]] entry), in document order. In a
/// combination a scalar is an axis of one value; in [axes] too (a fixed value).
void CollectAxes(const toml::table& table, const std::string& prefix, const std::string& where,
                 std::vector<Axis>* axes) {
  for (const auto& [k, node] : table) {
    const std::string name = std::string(k.str());
    const std::string key = prefix.empty() ? name : prefix + "." + name;
    Axis axis;
    if (const toml::table* sub = node.as_table()) {
      if (!IsRange(*sub)) {
        if (FindParam(key) &&
            (sub->contains("from") || sub->contains("to") || sub->contains("step"))) {
          for (const auto& [field, value] : *sub) {  // a field beyond the three, by name
            const std::string f(field.str());
            if (f != "from" && f != "to" && f != "step") {
              throw InputError(key + "." + f, TomlText(value),
                               "unknown field of a range; a range takes from, to and step");
            }
          }
          throw InputError(key, TomlText(*sub),
                           "a range needs all of from, to and step (a missing step is not "
                           "guessed); or list the values");
        }
        CollectAxes(*sub, key, where, axes);
        continue;
      }
      axis = RangeAxis(key, *sub);
    } else if (name.find(',') != std::string::npos) {  // zipped axis: "k1,k2" = [[v1, v2], ...]
      std::vector<std::string> keys;
      for (const std::string& part : SplitList(name))
        keys.push_back(prefix.empty() ? part : prefix + "." + part);
      if (keys.size() < 2)
        throw InputError(where + "." + key, "(keys)", "a zipped axis names two or more keys");
      const toml::array* rows = node.as_array();
      if (!rows)
        throw InputError(key, "(value)", "a zipped axis takes a list of rows, one value per key");
      axis.keys = keys;
      for (std::size_t r = 0; r < rows->size(); ++r) {
        const toml::array* row = rows->get(r)->as_array();
        if (!row || row->size() != keys.size()) {
          throw InputError(
              key, "row " + std::to_string(r + 1),
              "must be a list of " + std::to_string(keys.size()) + " values, one per key");
        }
        std::vector<std::string> point;
        for (std::size_t i = 0; i < keys.size(); ++i)
          point.push_back(ScalarText(*row->get(i), keys[i]));
        axis.points.push_back(point);
      }
    } else if (const toml::array* list = node.as_array()) {
      axis.keys = {key};
      for (std::size_t i = 0; i < list->size(); ++i) {
        const toml::node& item = *list->get(i);
        if (const toml::table* r = item.as_table(); r && IsRange(*r)) {
          for (auto& p : RangeAxis(key, *r).points) axis.points.push_back(p);
        } else {
          axis.points.push_back({ScalarText(item, key)});
        }
      }
    } else {
      axis.keys = {key};
      axis.points.push_back({ScalarText(node, key)});
    }
    if (axis.points.empty())
      throw InputError(key, "[]", "an axis needs at least one value (" + where + ")");
    for (std::size_t i = 0; i < axis.keys.size(); ++i) {
      for (const auto& point : axis.points) CheckValue(axis.keys[i], point[i], where);
    }
    axis.line = node.source().begin.line;
    axis.column = node.source().begin.column;
    axes->push_back(std::move(axis));
  }
}

std::vector<Axis> AxesOf(const toml::table& table, const std::string& where) {
  std::vector<Axis> axes;
  CollectAxes(table, "", where, &axes);
  std::stable_sort(axes.begin(), axes.end(), [](const Axis& a, const Axis& b) {
    return a.line != b.line ? a.line < b.line : a.column < b.column;
  });
  std::set<std::string> seen;
  for (const Axis& a : axes) {
    for (const std::string& k : a.keys) {
      if (!seen.insert(k).second) throw InputError(k, "(twice)", "is given twice in " + where);
    }
  }
  return axes;
}

void FlattenSet(const toml::table& t, const std::string& prefix,
                std::vector<std::pair<std::size_t, Assignment>>* out) {
  for (const auto& [k, node] : t) {
    const std::string key =
        prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const toml::table* sub = node.as_table()) {
      FlattenSet(*sub, key, out);
    } else {
      const std::string v = ValueText(node, key);
      CheckValue(key, v, "[set]");
      out->push_back({node.source().begin.line, {key, v}});
    }
  }
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Assignment ParseAssignment(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set", text, "must have the form key=value");
  std::string value = Trim(text.substr(eq + 1));
  if (value.size() >= 2 && value.front() == '"' && value.back() == '"')
    value = value.substr(1, value.size() - 2);
  return {Trim(text.substr(0, eq)), value};
}

void ValidateStoreRates(const SweepMatrix& m) {
  for (const SweepRun& run : m.runs) {
    const Config cfg = m.ConfigFor(run.id);
    const double rate = cfg.Quantity("sim.sample_rate");
    RequirePositive("sim.sample_rate", rate);
    if (m.store.rate < rate) {
      const double ratio = rate / m.store.rate;
      if (std::abs(ratio - std::round(ratio)) > 1e-9 * ratio) {
        throw InputError("store.rate", FormatValue(m.store.rate) + " Hz",
                         "must divide sim.sample_rate = " + FormatValue(rate) + " Hz (run " +
                             std::to_string(run.id) + ": " + run.Label() + ")");
      }
    }
  }
}

}  // namespace

// ---- store options ---------------------------------------------------------------------------

std::string StoreOptions::Describe() const {
  std::ostringstream os;
  os.precision(17);
  os << "channels=" << JoinNames(channels, ",") << ";rate=" << rate
     << ";window=" << ToString(spectrum_window) << ";spectrum_max=" << spectrum_max
     << ";inflection_floor=" << inflection_floor
     << ";poincare=" << JoinNames(poincare_channels, ",");
  return os.str();
}

void SetStoreOption(StoreOptions* o, const std::string& key, const std::string& value) {
  const std::string k = "store." + key;
  if (key == "channels" || key == "poincare_channels") {
    std::vector<std::string> names = SplitList(value);
    if (names.empty()) throw InputError(k, value, "must name at least one channel");
    for (const std::string& n : names) {
      if (n.find_first_of("[]\"/ ") != std::string::npos)
        throw InputError(k, n, "is not a channel name");
    }
    (key == "channels" ? o->channels : o->poincare_channels) = names;
  } else if (key == "rate") {
    o->rate = ParseQuantity(k, value, Dimension::kFrequency);
    RequirePositive(k, o->rate);
  } else if (key == "spectrum_window") {
    o->spectrum_window = WindowFromString(k, value);
  } else if (key == "spectrum_max") {
    o->spectrum_max = ParseQuantity(k, value, Dimension::kFrequency);
    RequirePositive(k, o->spectrum_max);
  } else if (key == "inflection_floor") {
    o->inflection_floor = ParseQuantity(k, value, Dimension::kAcceleration);
    RequireNonNegative(k, o->inflection_floor);
  } else {
    throw InputError(k, value,
                     "unknown store option; known: channels, rate, spectrum_window, spectrum_max, "
                     "inflection_floor, poincare_channels");
  }
}

// ---- runs --------------------------------------------------------------------------------------

std::string SweepRun::Label() const {
  std::string s;
  for (std::size_t i = 0; i < values.size(); ++i)
    s += (i ? ", " : "") + values[i].key + "=" + values[i].value;
  return s;
}

Config SweepMatrix::ConfigFor(int id) const {
  FLEXROD_ASSERT(id >= 0 && static_cast<std::size_t>(id) < runs.size());
  Config cfg;
  cfg.LoadToml(base_toml, "base " + base);
  for (const Assignment& a : overrides) cfg.Set(a.key, a.value);
  for (const Assignment& a : runs[id].values) cfg.Set(a.key, a.value);
  return cfg;
}

namespace {

/// Every top-level key is one of the matrix's sections, of the right kind.
void CheckSections(const toml::table& doc) {
  for (const auto& [k, node] : doc) {
    const std::string section(k.str());
    const bool known = section == "sweep" || section == "set" || section == "axes" ||
                       section == "combinations" || section == "store";
    if (!known) {
      throw InputError(
          section, "(section)",
          "unknown matrix section; expected [sweep], [set], [axes], [[combinations]], [store]");
    }
    const bool is_array = section == "combinations";
    if (is_array ? !node.is_array_of_tables() : !node.is_table()) {
      throw InputError(section, "(value)",
                       is_array ? "must be an array of tables: [[combinations]]"
                                : "must be a table: [" + section + "]");
    }
  }
}

/// [sweep]: name (a plain file name), base, description.
void ReadSweepSection(const toml::table& doc, SweepMatrix* m) {
  if (const toml::table* sweep = doc["sweep"].as_table()) {
    for (const auto& [k, node] : *sweep) {
      const std::string key(k.str());
      const std::string v = ScalarText(node, "sweep." + key);
      if (key == "name") {
        // The name becomes a file name (out/<name>.h5): one plain component, nothing that
        // could leave the output folder.
        const bool plain =
            !v.empty() && v.size() <= 200 && v != "." && v != ".." &&
            v.find_first_of("/\\") == std::string::npos &&
            std::all_of(v.begin(), v.end(), [](unsigned char c) { return c >= 0x20; });
        if (!plain) {
          throw InputError("sweep.name", "\"" + v + "\"",
                           "must be a plain file name: 1 to 200 characters, no '/', '\\', control "
                           "characters, '.' or '..'");
        }
        m->name = v;
      } else if (key == "base") {
        m->base = v;
      } else if (key == "description") {
        m->description = v;
      } else {
        throw InputError("sweep." + key, v, "unknown key; [sweep] takes name, base, description");
      }
    }
  }
}

/// The base run input (a run preset, or a TOML file relative to `base_dir`), checked.
void LoadBase(const std::string& base_dir, SweepMatrix* m) {
  // The base input: a run's input, not a matrix.
  if (FindPreset(m->base) && !FindRunPreset(m->base)) {
    throw InputError("sweep.base", m->base,
                     "is a sweep matrix; the base is a run input: a preset (" + RunPresetNames() +
                         ") or a TOML file");
  }
  if (const Preset* p = FindRunPreset(m->base)) {
    m->base_toml = p->toml;
  } else {
    fs::path path(m->base);
    if (path.is_relative()) path = fs::path(base_dir) / path;
    CheckPathLength("sweep.base", path.string());
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
      throw InputError("sweep.base", m->base,
                       "is neither a preset (" + RunPresetNames() + ") nor a readable TOML file");
    }
    m->base_toml = ReadText(path.string());
  }
  try {
    Config check;
    check.LoadToml(m->base_toml, m->base);
  } catch (const InputError& e) {
    throw InputError("sweep.base", m->base, "is not a valid run input: " + std::string(e.what()));
  }
}

/// The overrides: [set] in document order, then the command line's --set (store.* keys set
/// the store options); [store].
void ReadOverrides(const toml::table& doc, const std::vector<std::string>& extra_sets,
                   SweepMatrix* m) {
  if (const toml::table* set = doc["set"].as_table()) {
    std::vector<std::pair<std::size_t, Assignment>> flat;
    FlattenSet(*set, "", &flat);
    std::stable_sort(flat.begin(), flat.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& f : flat) m->overrides.push_back(f.second);
  }
  if (const toml::table* store = doc["store"].as_table()) {
    for (const auto& [k, node] : *store) {
      SetStoreOption(&m->store, std::string(k.str()),
                     ValueText(node, "store." + std::string(k.str())));
    }
  }
  for (const std::string& s : extra_sets) {
    const Assignment a = ParseAssignment(s);
    if (a.key.rfind("store.", 0) == 0) {
      SetStoreOption(&m->store, a.key.substr(6), a.value);
      continue;
    }
    CheckValue(a.key, a.value, "--set");
    m->overrides.push_back(a);
  }
}

/// [axes] and each [[combinations]] entry (a key in both is refused); the axis keys in order.
void ReadAxes(const toml::table& doc, std::vector<Axis>* global,
              std::vector<std::vector<Axis>>* blocks, SweepMatrix* m) {
  if (const toml::table* axes = doc["axes"].as_table()) *global = AxesOf(*axes, "[axes]");
  if (const toml::array* combos = doc["combinations"].as_array()) {
    for (std::size_t i = 0; i < combos->size(); ++i) {
      const std::string where = "[[combinations]] #" + std::to_string(i + 1);
      std::vector<Axis> block = AxesOf(*combos->get(i)->as_table(), where);
      if (block.empty()) throw InputError(where, "{}", "a combination needs at least one key");
      for (const Axis& a : block) {
        for (const std::string& k : a.keys) {
          for (const Axis& g : *global) {
            if (std::find(g.keys.begin(), g.keys.end(), k) != g.keys.end()) {
              throw InputError(k, "(twice)", "is set by both [axes] and " + where);
            }
          }
        }
      }
      blocks->push_back(std::move(block));
    }
  }
  if (blocks->empty()) blocks->emplace_back();
  auto note_keys = [m](const std::vector<Axis>& axes) {
    for (const Axis& a : axes) {
      for (const std::string& k : a.keys) {
        if (std::find(m->axis_keys.begin(), m->axis_keys.end(), k) == m->axis_keys.end())
          m->axis_keys.push_back(k);
      }
    }
  };
  note_keys(*global);
  for (const auto& block : *blocks) note_keys(block);
}

/// Expansion: combinations in file order (outermost), then [axes], then the combination's own
/// keys, each in document order; the last axis varies fastest.
void Expand(const std::vector<Axis>& global, const std::vector<std::vector<Axis>>& blocks,
            SweepMatrix* m) {
  for (const auto& block : blocks) {
    std::vector<const Axis*> axes;
    for (const Axis& a : global) axes.push_back(&a);
    for (const Axis& a : block) axes.push_back(&a);
    double total = 1.0;
    for (const Axis* a : axes) total *= static_cast<double>(a->points.size());
    if (total + static_cast<double>(m->runs.size()) > static_cast<double>(kMaxRuns)) {
      throw InputError(m->origin, FormatValue(total) + " runs",
                       "more than 10^6 runs in one matrix");
    }
    std::vector<std::size_t> index(axes.size(), 0);
    for (;;) {
      SweepRun run;
      run.id = static_cast<int>(m->runs.size());
      for (std::size_t a = 0; a < axes.size(); ++a) {
        for (std::size_t i = 0; i < axes[a]->keys.size(); ++i) {
          run.values.push_back({axes[a]->keys[i], axes[a]->points[index[a]][i]});
        }
      }
      m->runs.push_back(std::move(run));
      bool carry = true;  // odometer: the last axis turns fastest
      for (std::size_t a = axes.size(); carry && a > 0; --a) {
        if (++index[a - 1] < axes[a - 1]->points.size()) {
          carry = false;
        } else {
          index[a - 1] = 0;
        }
      }
      if (carry) break;
    }
  }
}

/// A case whose ensemble.members is N > 1 becomes N runs, adjacent, member k with its start
/// (EnsembleMemberSettings); the keys members set may not be axes.
void ExpandEnsembles(SweepMatrix* m) {
  std::vector<SweepRun> runs;
  for (const SweepRun& c : m->runs) {
    const Config cfg = m->ConfigFor(c.id);
    const EnsembleOptions options = ReadEnsembleOptions(cfg);
    const int members = EnsembleMembers(options, false);
    const int case_id = static_cast<int>(runs.size());
    for (int k = 0; k < members; ++k) {
      SweepRun run = c;
      run.id = static_cast<int>(runs.size());
      run.member = k;
      run.case_id = case_id;
      for (auto& [key, value] : EnsembleMemberSettings(cfg, options, members, k)) {
        if (std::find(m->axis_keys.begin(), m->axis_keys.end(), key) != m->axis_keys.end()) {
          throw InputError(key, "(an axis)",
                           "ensemble.members = " + std::to_string(members) +
                               " sets it for each member; leave it out of the axes");
        }
        run.values.push_back({key, value});
      }
      runs.push_back(std::move(run));
      if (runs.size() > kMaxRuns) {
        throw InputError(m->origin, std::to_string(runs.size()) + " runs",
                         "more than 10^6 runs in one matrix (ensemble members included)");
      }
    }
  }
  m->runs = std::move(runs);
}

/// Every run must resolve, and no two runs may be the same run.
void CheckDistinctRuns(const SweepMatrix& m) {
  std::map<std::string, int> seen;
  for (const SweepRun& run : m.runs) {
    const std::string fp = RunFingerprint(m.ConfigFor(run.id), m.store);
    const auto [it, fresh] = seen.emplace(fp, run.id);
    if (!fresh) {
      throw InputError("matrix",
                       "runs " + std::to_string(it->second) + " and " + std::to_string(run.id),
                       "have the same resolved input (" + m.runs[it->second].Label() + " / " +
                           run.Label() + ")");
    }
  }
}

}  // namespace

SweepMatrix ParseSweepMatrix(const std::string& toml_text, const std::string& origin,
                             const std::string& base_dir,
                             const std::vector<std::string>& extra_sets) {
  const toml::table doc = ParseToml(toml_text, origin, "(matrix file)");
  SweepMatrix m;
  m.origin = origin;
  m.source = toml_text;
  m.name = fs::path(origin).stem().string();
  m.base = "flexible-rig";
  CheckSections(doc);
  ReadSweepSection(doc, &m);
  LoadBase(base_dir, &m);
  ReadOverrides(doc, extra_sets, &m);
  std::vector<Axis> global;
  std::vector<std::vector<Axis>> blocks;
  ReadAxes(doc, &global, &blocks, &m);
  Expand(global, blocks, &m);
  ExpandEnsembles(&m);
  CheckDistinctRuns(m);
  ValidateStoreRates(m);
  return m;
}

SweepMatrix LoadSweepMatrix(const std::string& name_or_path,
                            const std::vector<std::string>& extra_sets) {
  if (name_or_path.rfind("sweep-", 0) == 0) {
    if (const Preset* p = FindPreset(name_or_path))
      return ParseSweepMatrix(p->toml, name_or_path, ".", extra_sets);
  }
  CheckPathLength("sweep matrix", name_or_path);
  std::error_code ec;
  if (!fs::is_regular_file(name_or_path, ec)) {
    std::vector<std::string> builtin;
    for (const Preset& p : Presets()) {
      if (p.name.rfind("sweep-", 0) == 0) builtin.push_back(p.name);
    }
    throw InputError(
        "matrix", name_or_path,
        "is neither a built-in matrix (" + JoinNames(builtin) + ") nor a readable file");
  }
  const std::string dir = fs::path(name_or_path).parent_path().string();
  return ParseSweepMatrix(ReadText(name_or_path), name_or_path, dir.empty() ? "." : dir,
                          extra_sets);
}

}  // namespace flexrod::study
