// SPDX-License-Identifier: GPL-3.0-or-later
#include "input/config.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "common/files.h"
#include "input/toml_value.h"

namespace flexrod {

const ParamDef* FindParam(const std::string& key) {
  for (const ParamDef& p : Schema()) {
    if (p.key == key) return &p;
  }
  return nullptr;
}

namespace {

std::string Join(const std::vector<std::string>& v) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + v[i];
  return s;
}

/// `value` is the text the user gave, for the message (none when the code asks for a key).
const ParamDef& Lookup(const std::string& key, const std::string& value = "(any)") {
  const ParamDef* p = FindParam(key);
  if (!p) {
    // Suggest keys sharing the section for the message.
    const std::string section = key.substr(0, key.find('.'));
    std::vector<std::string> near;
    for (const ParamDef& q : Schema()) {
      if (q.key.rfind(section + ".", 0) == 0) near.push_back(q.key);
    }
    throw InputError(
        key, value,
        near.empty() ? "unknown key" : "unknown key; known in this section: " + Join(near));
  }
  return *p;
}

void CheckRange(const ParamDef& p, double v) {
  if (!p.range.Contains(v)) throw InputError(p.key, FormatValue(v), p.range.Rule());
}

/// Checks a text value against its definition; returns normalised text.
void CheckValue(const ParamDef& p, const std::string& text) {
  switch (p.kind) {
    case ParamKind::kQuantity:
      CheckRange(p, ParseQuantity(p.key, text, p.dim));
      return;
    case ParamKind::kInteger: {
      const double v = ParseQuantity(p.key, text, Dimension::kDimensionless);
      if (v != std::floor(v)) throw InputError(p.key, text, "must be an integer");
      // Every integer key counts something (elements, modes, revolutions): 10⁹ is far beyond
      // any of their own limits, and keeps the conversion to int defined.
      if (std::abs(v) > 1e9)
        throw InputError(p.key, text, "must be an integer of at most 1e9 in magnitude");
      CheckRange(p, v);
      return;
    }
    case ParamKind::kBool:
      if (text != "true" && text != "false") throw InputError(p.key, text, "must be true or false");
      return;
    case ParamKind::kChoice:
      if (std::find(p.choices.begin(), p.choices.end(), text) == p.choices.end()) {
        throw InputError(p.key, text, "must be one of " + Join(p.choices));
      }
      return;
    case ParamKind::kText:
      return;
  }
}

void Flatten(const toml::table& t, const std::string& prefix, Config* cfg) {
  for (const auto& [k, v] : t) {
    const std::string key =
        prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const toml::table* sub = v.as_table()) {
      Flatten(*sub, key, cfg);
    } else if (const toml::array* a = v.as_array(); a != nullptr && a->is_array_of_tables()) {
      throw InputError(key, "[[" + key + "]]",
                       "an array of tables is not allowed here: write [" + key +
                           "] once, with its keys beneath it");
    } else {
      cfg->Set(key, ValueText(v, key));
    }
  }
}

}  // namespace

bool ValueRange::Contains(double v) const {
  const bool above = low_open ? v > low : v >= low;
  const bool below = high_open ? v < high : v <= high;
  return above && below;  // false for NaN
}

std::string ValueRange::Rule() const {
  const std::string lo = FormatValue(low), hi = FormatValue(high);
  if (std::isinf(high)) return "must be " + std::string(low_open ? "> " : ">= ") + lo;
  if (std::isinf(low)) return "must be " + std::string(high_open ? "< " : "<= ") + hi;
  return "must lie in " + std::string(low_open ? "(" : "[") + lo + ", " + hi +
         (high_open ? ")" : "]");
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto b = item.find_first_not_of(" \t");
    if (b == std::string::npos) continue;
    out.push_back(item.substr(b, item.find_last_not_of(" \t") - b + 1));
  }
  return out;
}

std::vector<std::string> SplitUserList(const std::string& key, const std::string& text) {
  std::vector<std::string> out = SplitList(text);
  const auto commas = static_cast<std::size_t>(std::count(text.begin(), text.end(), ','));
  if (!out.empty() && out.size() != commas + 1) {
    throw InputError(key, "\"" + text + "\"",
                     "has an empty item: a comma list names each item once");
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (std::find(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(i), out[i]) !=
        out.begin() + static_cast<std::ptrdiff_t>(i)) {
      throw InputError(key, "\"" + text + "\"",
                       "lists \"" + out[i] + "\" twice: a comma list names each item once");
    }
  }
  return out;
}

void Config::Set(const std::string& key, const std::string& text) {
  const ParamDef& p = Lookup(key, text);
  CheckValue(p, text);
  values_[key] = text;
}

void Config::SetAssignment(const std::string& assignment) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || assignment.find_first_not_of(" \t") >= eq) {
    throw InputError(
        "--set", "\"" + assignment + "\"",
        "must have the form key=value; the key \"" + assignment.substr(0, eq) + "\" is blank");
  }
  std::string value = assignment.substr(eq + 1);
  if (value.size() >= 2 && value.front() == '"' && value.back() == '"')
    value = value.substr(1, value.size() - 2);
  Set(assignment.substr(0, eq), value);
}

void Config::LoadToml(const std::string& toml_text, const std::string& origin) {
  const toml::table t = ParseToml(toml_text, origin, "(file)");
  if (t.contains("sweep") || t.contains("axes")) {
    throw InputError("input file", origin,
                     "is a sweep matrix ([sweep], [axes]), not a run input: run it with "
                     "`flexrod sweep " +
                         origin + "`");
  }
  Flatten(t, "", this);
}

void Config::LoadTomlFile(const std::string& path) {
  CheckPathLength("input file", path);
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    // A directory or /dev/null read as an empty input ran the defaults; a pipe could hang.
    throw InputError("input file", path,
                     "must be a regular TOML file, not a directory, device or pipe");
  }
  std::ifstream in(path);
  if (!in) throw InputError("input file", path, "cannot be read (does it exist?)");
  std::stringstream ss;
  ss << in.rdbuf();
  LoadToml(ss.str(), path);
}

std::string Config::Raw(const std::string& key) const {
  const ParamDef& p = Lookup(key);
  auto it = values_.find(key);
  return it != values_.end() ? it->second : p.default_text;
}

double Config::Quantity(const std::string& key) const {
  const ParamDef& p = Lookup(key);
  FLEXROD_ASSERT(p.kind == ParamKind::kQuantity);
  const double v = ParseQuantity(key, Raw(key), p.dim);
  // The angle keys are crank angles, reduced to [0, 2π): a crank at 1e12 deg stands where its
  // remainder puts it, and an unreduced angle would make the integrator's relative tolerance
  // on θ meaningless (and the revolution count exceed a double's integers).
  return p.dim == Dimension::kAngle ? WrapToTwoPi(v) : v;
}

int Config::Integer(const std::string& key) const {
  return static_cast<int>(ParseQuantity(key, Raw(key), Dimension::kDimensionless));
}

bool Config::Bool(const std::string& key) const { return Raw(key) == "true"; }

std::string Config::Text(const std::string& key) const { return Raw(key); }

std::vector<Config::Resolved> Config::Resolve() const {
  std::vector<Resolved> out;
  for (const ParamDef& p : Schema()) {
    Resolved r;
    r.key = p.key;
    r.is_default = !IsSet(p.key);
    const std::string raw = Raw(p.key);
    if (p.kind == ParamKind::kQuantity) {
      std::ostringstream os;
      os.precision(12);
      os << Quantity(p.key);
      r.value = os.str();
      r.unit = SiUnit(p.dim);
    } else if (p.kind == ParamKind::kInteger) {
      r.value = std::to_string(Integer(p.key));
      r.unit = "1";
    } else {
      r.value = raw;
    }
    out.push_back(r);
  }
  return out;
}

std::string Config::ResolvedToml(const DerivedNotes& notes) const {
  std::ostringstream os;
  os << "# flexrod resolved input: every key, SI values; '# default' marks values not set by the "
        "user\n";
  // Group keys by section (a TOML table may appear only once), sections in schema order.
  std::vector<Resolved> all = Resolve();
  std::vector<std::string> order;
  for (const Resolved& r : all) {
    const std::string sec = r.key.substr(0, r.key.rfind('.'));
    if (std::find(order.begin(), order.end(), sec) == order.end()) order.push_back(sec);
  }
  std::stable_sort(all.begin(), all.end(), [&](const Resolved& a, const Resolved& b) {
    auto rank = [&](const Resolved& r) {
      return std::find(order.begin(), order.end(), r.key.substr(0, r.key.rfind('.'))) -
             order.begin();
    };
    return rank(a) < rank(b);
  });
  std::string section;
  auto list_notes = [&] {
    const auto it = notes.listed.find(section);
    if (it == notes.listed.end()) return;
    for (const std::string& line : it->second) os << "# " << line << "\n";
  };
  for (const Resolved& r : all) {
    const size_t dot = r.key.rfind('.');
    const std::string sec = r.key.substr(0, dot);
    if (sec != section) {
      list_notes();
      os << "\n[" << sec << "]\n";
      section = sec;
    }
    const ParamDef* p = FindParam(r.key);
    const bool quoted = p->kind == ParamKind::kChoice || p->kind == ParamKind::kText;
    os << r.key.substr(dot + 1) << " = " << (quoted ? "\"" + r.value + "\"" : r.value);
    os << "  # " << (r.unit.empty() ? "" : "[" + r.unit + "] ")
       << (r.is_default ? "default" : "set");
    const auto note = notes.beside.find(r.key);
    if (note != notes.beside.end()) os << "; " << note->second;
    os << "\n";
  }
  list_notes();
  return os.str();
}

}  // namespace flexrod
