// input/config.h — the one input layer of flexrod. Every input (a preset, a TOML file,
// `--set key=value`, command-line flags) becomes a dotted key ("rod.height") with a text
// value; a schema of known keys gives each its dimension, default, allowed choices and doc.
// Values are converted to SI once, here. Unknown keys, wrong types and values outside the
// allowed set throw InputError naming key, value and rule — before any work starts.
// The resolved input (every key, defaults filled in, SI value and unit) is written with every
// result. What does not live here: what the keys mean (the builders that read them).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <limits>
#include <map>
#include <string>
#include <vector>

#include "common/units.h"

namespace flexrod {

enum class ParamKind { kQuantity, kInteger, kChoice, kText, kBool };

/// The admissible SI values of a quantity or integer key: checked whenever the key is set
/// (file, --set, a sweep's [set] or axis), whether or not the run will read it. Unbounded by
/// default; rules that involve other keys are checked by the builders that read them.
struct ValueRange {
  double low{-std::numeric_limits<double>::infinity()};
  bool low_open{false};  ///< low itself excluded
  double high{std::numeric_limits<double>::infinity()};
  bool high_open{false};  ///< high itself excluded
  bool Contains(double v) const;
  /// "must be > 0", "must be >= 1", "must lie in (0, 1]".
  std::string Rule() const;
};

struct ParamDef {
  ParamDef(std::string k, ParamKind kd, Dimension d, std::string def, std::string dc,
           std::vector<std::string> ch = {})
      : key(std::move(k)),
        kind(kd),
        dim(d),
        default_text(std::move(def)),
        doc(std::move(dc)),
        choices(std::move(ch)) {}
  std::string key;
  ParamKind kind{ParamKind::kQuantity};
  Dimension dim{Dimension::kDimensionless};
  std::string default_text;          ///< as a user would type it ("19.05 mm")
  std::string doc;                   ///< one line, with the rule
  std::vector<std::string> choices;  ///< for kChoice
  ValueRange range;                  ///< for kQuantity and kInteger
};

/// The schema: every key flexrod accepts, in documentation order.
const std::vector<ParamDef>& Schema();
const ParamDef* FindParam(const std::string& key);

/// Items of a comma-separated list (list-valued text keys, store attributes), each trimmed of
/// blanks; empty items are dropped.
std::vector<std::string> SplitList(const std::string& text);
/// SplitList of the user's value of `key`: an empty item ("a,,b", "a,") or an item listed twice
/// is an InputError naming the key, the value and the rule.
std::vector<std::string> SplitUserList(const std::string& key, const std::string& text);

class Config {
 public:
  /// Sets a key from text. Throws InputError for unknown keys or values that do not parse.
  void Set(const std::string& key, const std::string& text);
  /// "key=value" as given to --set.
  void SetAssignment(const std::string& assignment);
  /// Loads a TOML document (tables flatten to dotted keys). `origin` names it in errors.
  void LoadToml(const std::string& toml_text, const std::string& origin);
  void LoadTomlFile(const std::string& path);

  bool IsSet(const std::string& key) const { return values_.count(key) > 0; }
  /// SI value of a quantity key (default if unset).
  double Quantity(const std::string& key) const;
  int Integer(const std::string& key) const;
  bool Bool(const std::string& key) const;
  std::string Text(const std::string& key) const;  ///< choice or text keys

  /// Every schema key with its resolved value: (key, text as SI or choice, unit).
  struct Resolved {
    std::string key, value, unit;
    bool is_default;
  };
  std::vector<Resolved> Resolve() const;
  /// What a run derived from the input (a clearance joint's contact parameters), for the
  /// resolved input: `beside` maps a schema key to a note on its line (the value the run used
  /// where the key says 0 = derive); `listed` maps a section to comment lines at its end.
  struct DerivedNotes {
    std::map<std::string, std::string> beside;
    std::map<std::string, std::vector<std::string>> listed;
  };
  /// The resolved input as TOML text (SI numbers, units in comments). The notes are comments
  /// only: the file loads as an input and gives the same run.
  std::string ResolvedToml(const DerivedNotes& notes = {}) const;

 private:
  std::string Raw(const std::string& key) const;
  std::map<std::string, std::string> values_;
};

}  // namespace flexrod
