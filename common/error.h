// common/error.h — the error tiers of flexrod (STYLE.md §12) and the CLI's exit codes
// (app/cli.cc; the same for every command):
//
// * Bad user input: InputError, thrown before any work starts; its message names the key,
//   the value and the rule, e.g. "rod.height = -3 mm: must be > 0". Exit 2.
// * Numerical outcome (integrator failure, no convergence): NumericalError, carrying time,
//   state and a hint; callers keep what was computed so far. Exit 1.
// * Storage: IoError, a file that cannot be written (or a file flexrod wrote that cannot be
//   read back), naming the file and the system's reason ("No space left on device: out/run/
//   run.h5"); nothing is left under the file's final name. Exit 3.
// * The caller stopped the work: Interrupted (the Python module's Ctrl-C).
// * Programmer bug: FLEXROD_ASSERT (debug assertion); any other exception (a logic error,
//   out of memory) is internal. Exit 4.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cassert>
#include <sstream>
#include <stdexcept>
#include <string>

#define FLEXROD_ASSERT(cond) assert(cond)

namespace flexrod {

/// Bad user input. what() reads "<key> = <value>: <rule>".
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& key, const std::string& value, const std::string& rule)
      : std::runtime_error(Printable(key) + " = " +
                           (value.empty() ? std::string("\"\"") : Printable(value)) + ": " +
                           rule),  // an empty value reads "": seen as one
        key_(key),
        value_(value),
        rule_(rule) {}
  const std::string& key() const { return key_; }
  const std::string& value() const { return value_; }
  /// `text` with control characters as \xNN (a terminal would act on them, a log hide them).
  static std::string Printable(const std::string& text) {
    std::string out;
    for (const char ch : text) {
      const unsigned char u = static_cast<unsigned char>(ch);
      if (u < 0x20 || u == 0x7f) {
        static const char kHex[] = "0123456789abcdef";
        out += "\\x";
        out += kHex[u >> 4];
        out += kHex[u & 15];
      } else {
        out += ch;
      }
    }
    return out;
  }
  const std::string& rule() const { return rule_; }

 private:
  std::string key_, value_, rule_;
};

/// A numerical outcome the caller must handle (solver gave up, no convergence, library error).
class NumericalError : public std::runtime_error {
 public:
  explicit NumericalError(const std::string& what) : std::runtime_error(what) {}
};

/// A file that cannot be written or read back. what() reads "<reason>: <file>".
class IoError : public std::runtime_error {
 public:
  explicit IoError(const std::string& what) : std::runtime_error(what) {}
};

/// The caller stopped the work (Ctrl-C in the Python module): not an error of the input nor
/// of the numerics. Sweeps let it through instead of recording a failed run.
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(const std::string& what) : std::runtime_error(what) {}
};

/// Formats a double for error messages with enough digits to be unambiguous.
inline std::string FormatValue(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

/// Throws InputError(key, value, rule) unless cond holds.
inline void Require(bool cond, const std::string& key, double value, const std::string& rule) {
  if (!cond) throw InputError(key, FormatValue(value), rule);
}
inline void RequirePositive(const std::string& key, double value) {
  Require(value > 0.0 && value == value, key, value, "must be > 0");
}
inline void RequireNonNegative(const std::string& key, double value) {
  Require(value >= 0.0, key, value, "must be >= 0");
}

}  // namespace flexrod
