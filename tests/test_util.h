// SPDX-License-Identifier: GPL-3.0-or-later
// tests/test_util.h — what tests of every module share: π, scratch paths unique to the test
// process, and running a shell command or the built flexrod binary with its output captured.
// One definition each, so that unity-built test sources (CMakeLists.txt, FLEXROD_UNITY_TESTS)
// never meet two file-local helpers of the same name.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>

namespace flexrod::test {

inline constexpr double kPi = std::numbers::pi;

/// <system temp>/flexrod_<pid>_<name>, removed if it exists: a path no other test process
/// uses (a file keeps the extension of `name`); the test or the code under test creates it.
inline std::filesystem::path ScratchPath(const std::string& name) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() /
                                  ("flexrod_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(p);
  return p;
}

/// ScratchPath(name), created as an empty directory.
inline std::filesystem::path ScratchDir(const std::string& name) {
  const std::filesystem::path p = ScratchPath(name);
  std::filesystem::create_directories(p);
  return p;
}

struct CommandResult {
  int exit_code;       ///< the command's exit status; −1 if it did not exit (a signal)
  std::string output;  ///< its stdout and stderr, interleaved
};

/// Runs `command` in /bin/sh with stderr joined to stdout, and waits for it.
inline CommandResult Shell(const std::string& command) {
  CommandResult r{-1, {}};
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return r;
  char buffer[4096];
  for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) r.output.append(buffer, n);
  const int status = ::pclose(pipe);
  if (status != -1 && WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  return r;
}

/// Runs the built flexrod with `args` (shell words, quoted as the shell needs).
inline CommandResult Flexrod(const std::string& args) {
  std::string command = FLEXROD_BINARY;  // (appended, not `+`: GCC 12 -Warray-bounds, PR 105329)
  command += ' ';
  command += args;
  return Shell(command);
}

}  // namespace flexrod::test
