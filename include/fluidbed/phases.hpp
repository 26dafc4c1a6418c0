// Per-phase timing: a PETSc log stage for -log_view and a wall-clock total for summary.json.
#pragma once

#include <petscsys.h>

namespace fluidbed {

enum Phase {
  PHASE_NEIGHBOUR,
  PHASE_CONTACT,
  PHASE_INTEGRATE,
  PHASE_MIGRATE,
  PHASE_GHOSTS,
  PHASE_FLUID,
  PHASE_PRESSURE,
  PHASE_COUPLING,
  PHASE_OUTPUT,
  PHASE_GUARDS,
  PHASE_COUNT
};

extern const char *const PhaseNames[PHASE_COUNT]; // -log_view stage names
extern const char *const PhaseKeys[PHASE_COUNT];  // summary.json keys

struct PhaseLog {
  PetscLogStage stage[PHASE_COUNT]{};
  double        seconds[PHASE_COUNT]{};
  double        started[PHASE_COUNT]{};
};

PetscErrorCode PhaseLogRegister(PhaseLog *log);
PetscErrorCode PhaseBegin(PhaseLog *log, Phase p);
PetscErrorCode PhaseEnd(PhaseLog *log, Phase p);

} // namespace fluidbed
