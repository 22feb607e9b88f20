// SPDX-License-Identifier: GPL-3.0-or-later
#include <gsl/gsl_errno.h>

#include <CLI/CLI.hpp>
#include <iostream>

#include "app/commands.h"
#include "common/error.h"

namespace flexrod::app {
namespace {

/// A flag given with an empty value (`--out ""`) is an input error, not the flag left out: the
/// commands take an empty string as "not given", so it would silently write elsewhere.
void RefuseEmptyValues(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands()) {
    for (const CLI::Option* o : sub->get_options()) {
      if (o->get_lnames().empty() || o->count() == 0 || o->get_type_size() == 0) continue;
      for (const std::string& value : o->results()) {
        if (value.empty())
          throw InputError("--" + o->get_lnames().front(), "", "must not be empty");
      }
    }
    RefuseEmptyValues(*sub);
  }
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
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    RefuseEmptyValues(app);
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
}

}  // namespace flexrod::app
