// SPDX-License-Identifier: GPL-3.0-or-later
#include "input/toml_value.h"

#include <algorithm>
#include <charconv>
#include <sstream>

#include "common/error.h"
#include "input/config.h"

namespace flexrod {
namespace {

/// "malformed TOML: <description> at line L, column C". toml++ garbles a quoted key in "cannot
/// redefine existing ... '<key>'" (its first characters doubled); the key is taken from the
/// source line instead.
std::string MalformedTomlRule(const std::string& description, const std::string& toml_text,
                              std::size_t line, std::size_t column) {
  std::string what = description;
  const std::size_t open = what.find('\''), close = what.rfind('\'');
  if (what.find("cannot redefine existing") != std::string::npos && open < close) {
    std::istringstream in(toml_text);
    std::string source;
    for (std::size_t i = 0; i < line && std::getline(in, source);) ++i;
    std::string key = source.substr(0, source.find('='));
    key.erase(std::remove(key.begin(), key.end(), '['), key.end());
    key.erase(std::remove(key.begin(), key.end(), ']'), key.end());
    const std::size_t b = key.find_first_not_of(" \t");
    if (b != std::string::npos)
      what = what.substr(0, open + 1) + key.substr(b, key.find_last_not_of(" \t") - b + 1) +
             what.substr(close);
  }
  return "malformed TOML: " + what + " at line " + std::to_string(line) + ", column " +
         std::to_string(column);
}

}  // namespace

toml::table ParseToml(const std::string& text, const std::string& origin, const std::string& what) {
  try {
    return toml::parse(text, origin);
  } catch (const toml::parse_error& e) {
    throw InputError(origin, what,
                     MalformedTomlRule(std::string(e.description()), text, e.source().begin.line,
                                       e.source().begin.column));
  }
}

std::string TomlText(const toml::node& node) {
  std::ostringstream os;
  node.visit([&os](const auto& n) { os << n; });
  return os.str();
}

std::string ScalarText(const toml::node& node, const std::string& key) {
  if (auto s = node.as_string()) return s->get();
  if (auto i = node.as_integer()) return std::to_string(i->get());
  if (auto d = node.as_floating_point()) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, d->get());
    return std::string(buf, r.ptr);
  }
  if (auto b = node.as_boolean()) return b->get() ? "true" : "false";
  throw InputError(key, TomlText(node), "must be a number, string or boolean here");
}

std::string ValueText(const toml::node& node, const std::string& key) {
  const toml::array* a = node.as_array();
  if (!a) return ScalarText(node, key);
  const ParamDef* p = FindParam(key);
  if (p && p->kind != ParamKind::kText)
    throw InputError(key, TomlText(node), "must be a single value, not an array");
  std::string s;
  for (std::size_t i = 0; i < a->size(); ++i) {
    if (i) s += ',';
    s += ScalarText(*a->get(i), key);
  }
  return s;
}

}  // namespace flexrod
