// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/plotting.h"

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>
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

RunPlotter::RunPlotter(const std::string& dir) : dir_(dir) {
  const std::string script = ScriptPath();
  if (!std::filesystem::exists(kPython) || !std::filesystem::exists(script)) return;
  int fds[2];
  if (pipe(fds) != 0) return;
  std::signal(SIGPIPE, SIG_IGN);  // a plotter that died is a warning, not the end of flexrod
  std::vector<std::string> argv_s = {kPython, script, "run", dir, "--wait"};
  std::vector<char*> argv;
  for (std::string& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(nullptr);
  pid_ = fork();
  if (pid_ == 0) {
    dup2(fds[0], STDIN_FILENO);
    close(fds[0]);
    close(fds[1]);
    execv(kPython, argv.data());
    _exit(127);
  }
  close(fds[0]);
  if (pid_ < 0) {
    close(fds[1]);
    return;
  }
  to_child_ = fds[1];
}

RunPlotter::~RunPlotter() { Stop(false); }

bool RunPlotter::Finish() {
  if (pid_ < 0) return PlotRun(dir_);  // not started: plot the usual way (or warn why not)
  return Stop(true);
}

bool RunPlotter::Stop(bool plot) {
  if (pid_ < 0) return false;
  // Without plots there is nothing to wait for, not even the imports.
  if (!plot) kill(pid_, SIGKILL);
  const bool sent = plot && write(to_child_, "go\n", 3) == 3;
  close(to_child_);
  int status = 0;
  const bool ok =
      waitpid(pid_, &status, 0) == pid_ && WIFEXITED(status) && WEXITSTATUS(status) == 0 && sent;
  pid_ = -1;
  if (!ok && plot)
    std::fprintf(stderr, "flexrod: warning: plotting failed (%s %s)\n", kPython,
                 ScriptPath().c_str());
  return ok;
}

}  // namespace flexrod::app
