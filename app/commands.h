// app/commands.h — registration of the flexrod subcommands. Each subcommand lives in its own
// app/cmd_<name>.cc, parses its flags with CLI11, converts units once (common/units.h) and
// calls into the libraries. Exit codes: 0 success, 2 bad input (InputError), 1 failure.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <functional>

namespace CLI {
class App;
}

namespace flexrod::app {

/// A registered subcommand: the handler runs after parsing and returns the exit code.
using Handler = std::function<int()>;

void RegisterModes(CLI::App& app, Handler* handler);
void RegisterRun(CLI::App& app, Handler* handler);
void RegisterStudy(CLI::App& app, Handler* handler);
void RegisterContact(CLI::App& app, Handler* handler);
void RegisterSweep(CLI::App& app, Handler* handler);
void RegisterCompare(CLI::App& app, Handler* handler);

int Main(int argc, char** argv);

}  // namespace flexrod::app
