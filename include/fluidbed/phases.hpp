// Per-phase timing: a PETSc log stage for -log_view and a wall-clock total for summary.json, each phase's own time
// (a phase begun inside another is not counted in the outer one).
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

// seconds[p]: the wall time spent in phase p and in no phase begun inside it (the phases nest: the innermost is
// active[depth - 1])
struct PhaseLog {
  static constexpr int kMaxDepth = 2 * PHASE_COUNT;
  PetscLogStage        stage[PHASE_COUNT]{};
  double               seconds[PHASE_COUNT]{};
  double               started[PHASE_COUNT]{};
  int                  active[kMaxDepth]{};
  int                  depth = 0;
};

PetscErrorCode PhaseLogRegister(PhaseLog *log);
PetscErrorCode PhaseBegin(PhaseLog *log, Phase p);
PetscErrorCode PhaseEnd(PhaseLog *log, Phase p);

} // namespace fluidbed
