// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/plotting.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

namespace flexrod::app {
namespace {

constexpr const char* kPython = "/usr/bin/python3";

std::string ScriptPath() {
  if (const char* env = std::getenv("FLEXROD_PLOT_SCRIPT")) return env;
  return std::string(FLEXROD_SOURCE_DIR) + "/scripts/flexrod_plots.py";
}

}  // namespace

bool RunPlotScript(const std::vector<std::string>& args) {
  const std::string script = ScriptPath();
  if (!std::filesystem::exists(kPython) || !std::filesystem::exists(script)) {
    std::fprintf(stderr, "flexrod: warning: no plot (%s or %s missing)\n", kPython, script.c_str());
    return false;
  }
  std::vector<std::string> argv_s = {kPython, script};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& s : argv_s) argv.push_back(s.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    execv(kPython, argv.data());
    _exit(127);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "flexrod: warning: plotting failed (%s %s)\n", kPython, script.c_str());
    return false;
  }
  return true;
}

bool PlotRun(const std::string& dir) { return RunPlotScript({"run", dir}); }

}  // namespace flexrod::app
