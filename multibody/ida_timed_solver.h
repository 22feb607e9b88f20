// multibody/ida_timed_solver.h — a SUNDIALS linear solver that times its wrapped solver's setup
// (factorisation) and solve. Internal to multibody/ (used by ida_integrator.cc).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

namespace flexrod::multibody {

/// Wraps `inner` (owned, freed with the wrapper); adds the wall time of each setup and solve
/// to *seconds. NumericalError (and `inner` freed) if SUNDIALS cannot allocate the wrapper.
SUNLinearSolver MakeTimedSolver(SUNLinearSolver inner, double* seconds, SUNContext ctx);

}  // namespace flexrod::multibody
