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
  PetscFunctionReturn(0);
}

PetscErrorCode PhaseBegin(PhaseLog *log, Phase p)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePush(log->stage[p]));
  log->started[p] = MPI_Wtime();
  PetscFunctionReturn(0);
}

PetscErrorCode PhaseEnd(PhaseLog *log, Phase p)
{
  PetscFunctionBeginUser;
  log->seconds[p] += MPI_Wtime() - log->started[p];
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

} // namespace fluidbed
