// SPDX-License-Identifier: GPL-3.0-or-later
#include <gsl/gsl_errno.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "app/commands.h"
#include "common/error.h"
#include "common/hdf5.h"

namespace flexrod::app {
namespace {

/// A flag given with an empty value (`--out ""`) is an input error, not the flag left out: the
/// commands take an empty string as "not given", so it would silently write elsewhere. A value
/// that is itself a flag (`--out --no-plot`) is the value forgotten: taken as given, it named a
/// directory `--no-plot`.
void CheckOptionValues(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands()) {
    for (const CLI::Option* o : sub->get_options()) {
      if (o->get_lnames().empty() || o->count() == 0 || o->get_type_size() == 0) continue;
      const std::string flag = "--" + o->get_lnames().front();
      for (const std::string& value : o->results()) {
        if (value.empty()) throw InputError(flag, "", "must not be empty");
        if (value.rfind("--", 0) == 0)
          throw InputError(flag, value, "is a flag, not a value: give " + flag + " its value");
      }
    }
    CheckOptionValues(*sub);
  }
}

/// CLI11 answers `flexrod runn` and `flexrod --frobnicate` with only "A subcommand is required";
/// the first argument is checked here so that the message names it.
void CheckCommand(const CLI::App& app, int argc, char** argv) {
  if (argc < 2) return;
  const std::string first = argv[1];
  if (first == "-h" || first == "--help") return;
  std::string names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (sub->get_name() == first) return;
    names += (names.empty() ? "" : ", ") + sub->get_name();
  }
  throw InputError(
      "command", first,
      (first.rfind('-', 0) == 0 ? "is a flag, but the command comes first" : "unknown command") +
          std::string("; flexrod COMMAND [options], COMMAND one of ") + names);
}

}  // namespace

int Main(int argc, char** argv) {
  CLI::App app{
      "flexrod — flexible connecting rods in slider-crank mechanisms with a clearance joint"};
  app.require_subcommand(1);
  gsl_set_error_handler_off();  // every GSL status is checked where it is returned
  Handler handler;
  RegisterModes(app, &handler);
  RegisterRun(app, &handler);
  RegisterStudy(app, &handler);
  RegisterContact(app, &handler);
  RegisterSweep(app, &handler);
  RegisterCompare(app, &handler);
  try {
    CheckCommand(app, argc, argv);
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const InputError& e) {
    std::cerr << "flexrod: error: " << e.what() << "\n";
    return 2;
  }
  const int code = [&] {
    try {
      CheckOptionValues(app);
      return handler ? handler() : 2;
    } catch (const InputError& e) {
      std::cerr << "flexrod: error: " << e.what() << "\n";
      return 2;
    } catch (const NumericalError& e) {
      std::cerr << "flexrod: numerical failure: " << e.what() << "\n";
      return 1;
    } catch (const IoError& e) {
      std::cerr << "flexrod: I/O error: " << e.what() << "\n";
      return 3;
    } catch (const std::bad_alloc&) {
      std::cerr << "flexrod: internal error: out of memory\n";
      return 4;
    } catch (const std::exception& e) {
      std::cerr << "flexrod: internal error (please report it): " << e.what() << "\n";
      return 4;
    }
  }();
  if (h5::CloseFailed()) {  // HDF5's clean-up at exit would crash on the file it still holds
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    std::_Exit(code);
  }
  return code;
}

}  // namespace flexrod::app
