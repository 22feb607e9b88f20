// app/main.cc — the flexrod command line: subcommands are registered from app/cmd_*.cc.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/commands.h"

int main(int argc, char** argv) { return flexrod::app::Main(argc, argv); }
