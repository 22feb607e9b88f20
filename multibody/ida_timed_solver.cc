// multibody/ida_timed_solver.cc — a SUNDIALS linear solver that times its wrapped solver's
// setup (factorisation) and solve (IntegratorOptions::time_calls).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/ida_timed_solver.h"

#include <sundials/sundials_linearsolver.h>
#include <sunlinsol/sunlinsol_klu.h>

#include "common/error.h"
#include "common/scope_timer.h"

namespace flexrod::multibody {
namespace {

struct TimedContent {
  SUNLinearSolver inner{nullptr};
  double* seconds{nullptr};
  bool klu{false};
};

TimedContent* Content(SUNLinearSolver S) { return static_cast<TimedContent*>(S->content); }

SUNLinearSolver_Type TimedGetType(SUNLinearSolver S) { return SUNLinSolGetType(Content(S)->inner); }
SUNLinearSolver_ID TimedGetId(SUNLinearSolver S) { return SUNLinSolGetID(Content(S)->inner); }
int TimedInitialize(SUNLinearSolver S) { return SUNLinSolInitialize(Content(S)->inner); }
int TimedSetup(SUNLinearSolver S, SUNMatrix A) {
  const ScopeTimer timer(Content(S)->seconds);
  int rc = SUNLinSolSetup(Content(S)->inner, A);
  if (rc == SUNLS_PACKAGE_FAIL_REC && Content(S)->klu) {
    // SUNDIALS' KLU set-up re-factors with the pivot sequence of the last full factorisation
    // and gives up when that sequence meets a zero pivot. The iteration matrix changes
    // structure in value when a contact opens or closes (its force derivatives vanish or
    // appear), so an old pivot can be exactly zero on a regular matrix; IDA would then cut
    // the step to hmin with the same failure every time (seen: rigid rig, 1 mm clearance,
    // rel_tol 1e-5, right after the first separation). Factor afresh instead.
    if (SUNLinSol_KLUReInit(Content(S)->inner, A, SUNSparseMatrix_NNZ(A), SUNKLU_REINIT_PARTIAL) ==
        SUNLS_SUCCESS) {
      rc = SUNLinSolSetup(Content(S)->inner, A);
    }
  }
  return rc;
}
int TimedSolve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, realtype tol) {
  const ScopeTimer timer(Content(S)->seconds);
  return SUNLinSolSolve(Content(S)->inner, A, x, b, tol);
}
sunindextype TimedLastFlag(SUNLinearSolver S) { return SUNLinSolLastFlag(Content(S)->inner); }
int TimedSpace(SUNLinearSolver S, long* lrw, long* liw) {
  return SUNLinSolSpace(Content(S)->inner, lrw, liw);
}
int TimedFree(SUNLinearSolver S) {
  if (S == nullptr) return 0;
  TimedContent* c = Content(S);
  if (c != nullptr) {
    SUNLinSolFree(c->inner);
    delete c;
    S->content = nullptr;
  }
  SUNLinSolFreeEmpty(S);
  return 0;
}

}  // namespace

SUNLinearSolver MakeTimedSolver(SUNLinearSolver inner, double* seconds, SUNContext ctx) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (S == nullptr) {
    SUNLinSolFree(inner);
    throw NumericalError("SUNLinSolNewEmpty returned NULL");
  }
  S->content = new TimedContent{inner, seconds, SUNLinSolGetID(inner) == SUNLINEARSOLVER_KLU};
  S->ops->gettype = TimedGetType;
  S->ops->getid = TimedGetId;
  S->ops->initialize = TimedInitialize;
  S->ops->setup = TimedSetup;
  S->ops->solve = TimedSolve;
  S->ops->lastflag = TimedLastFlag;
  S->ops->space = TimedSpace;
  S->ops->free = TimedFree;
  return S;
}

}  // namespace flexrod::multibody
