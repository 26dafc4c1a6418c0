#include "fluidbed/phases.hpp"

namespace fluidbed {

const char *const PhaseNames[PHASE_COUNT] = {"Neighbour search", "Contact",  "Integrate", "Migrate", "Ghosts", "Fluid",
                                             "Pressure",         "Coupling", "Output",    "Guards"};
const char *const PhaseKeys[PHASE_COUNT]  = {"neighbour", "contact",  "integrate", "migrate", "ghosts",
                                             "fluid",     "pressure", "coupling",  "output",  "guards"};

PetscErrorCode PhaseLogRegister(PhaseLog *log)
{
  PetscFunctionBeginUser;
  for (int p = 0; p < PHASE_COUNT; ++p) {
    PetscCall(PetscLogStageGetId(PhaseNames[p], &log->stage[p]));
    if (log->stage[p] < 0) PetscCall(PetscLogStageRegister(PhaseNames[p], &log->stage[p]));
    log->seconds[p] = 0.0;
  }
  log->depth = 0;
  PetscFunctionReturn(0);
}

// A phase begun inside another (the drag added to the particles inside the contact phase, for one) stops the outer
// phase's clock until it ends: each phase's seconds are its own, as PETSc's log stages count them, and the phases'
// seconds add up to no more than the step's.
PetscErrorCode PhaseBegin(PhaseLog *log, Phase p)
{
  PetscFunctionBeginUser;
  PetscCheck(log->depth < PhaseLog::kMaxDepth, PETSC_COMM_SELF, PETSC_ERR_PLIB, "phase '%s' begun %d deep", PhaseNames[p], log->depth);
  const double now = MPI_Wtime();
  if (log->depth > 0) {
    const int outer = log->active[log->depth - 1];
    log->seconds[outer] += now - log->started[outer];
  }
  log->active[log->depth++] = p;
  log->started[p]           = now;
  PetscCall(PetscLogStagePush(log->stage[p]));
  PetscFunctionReturn(0);
}

PetscErrorCode PhaseEnd(PhaseLog *log, Phase p)
{
  PetscFunctionBeginUser;
  PetscCheck(log->depth > 0 && log->active[log->depth - 1] == p, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "phase '%s' ended, not the innermost begun", PhaseNames[p]);
  const double now = MPI_Wtime();
  log->seconds[p] += now - log->started[p];
  if (--log->depth > 0) log->started[log->active[log->depth - 1]] = now;
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

} // namespace fluidbed
