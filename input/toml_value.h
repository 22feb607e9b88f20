// input/toml_value.h — TOML (toml++) for the readers of run inputs (input/config.cc) and sweep
// matrices (sweep/sweep_matrix.cc): one parse with flexrod's error, one rule for turning a TOML
// value into the value text of a key, one way to show a TOML value in a message.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <toml++/toml.h>

#include <string>

namespace flexrod {

/// Parses TOML text. A malformed document is an InputError naming `origin`, `what` as its value
/// ("(file)", "(matrix file)") and the parser's reason with its line and column.
toml::table ParseToml(const std::string& text, const std::string& origin, const std::string& what);

/// A scalar as the text a user would type: a string as it is, a number in its shortest exact
/// form, true or false. A table, array or date is an InputError naming `key` and the value.
std::string ScalarText(const toml::node& node, const std::string& key);

/// The value text of `key`, as Config::Set takes it: ScalarText, except that an array is joined
/// into a comma list for the keys that take one (text keys of the schema, and keys outside it
/// such as store.*). A one-element array for any other key is refused, not read as its scalar.
std::string ValueText(const toml::node& node, const std::string& key);

/// The value as TOML writes it, for messages.
std::string TomlText(const toml::node& node);

}  // namespace flexrod
