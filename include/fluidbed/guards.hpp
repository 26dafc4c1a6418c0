// Run-time guards (-guard_*): a run that goes wrong says so and stops, instead of finishing with garbage.
//
// Checked every -guard_interval DEM steps (and at every gas step for the gas's guards), each against a limit of
// its own: a NaN or inf in a particle or gas field; a particle through a wall or lost in migration; a pressure
// solve that did not converge; the largest overlap; the largest distance moved in one step; the growth of the
// mechanical energy of a closed scene (pure DEM); a void fraction outside (0, 1] or at the floor in too many cells;
// the gas Courant number above its limit for too many gas steps in a row. The per-step figures are gathered where
// the step computes them anyway (the integration and contact loops, the coupling's deposit, the gas step), so a
// check costs one small reduction; the location of a failure (particle, cell, rank) is searched only when one trips.
// A trip under -guard_action stop (the default) ends the run with the guard's exit status (status.hpp), a message
// saying what, where, when and the likely remedy, a diagnostic snapshot and summary.json's "status". The decision
// rules are kernels/guard_rules.hpp; docs/reliability.md lists each guard's default limit and cost.
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

#include "fluidbed/coupling.hpp"
#include "fluidbed/dem.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/fluid.hpp"
#include "fluidbed/phases.hpp"
#include "fluidbed/kernels/guard_rules.hpp"

namespace fluidbed {

struct JsonWriter;

// In priority order: when several trip at one check, the first names the failure (status.hpp numbers them alike).
enum GuardKind {
  GUARD_NAN,
  GUARD_ESCAPE,
  GUARD_PRESSURE,
  GUARD_OVERLAP,
  GUARD_DISPLACEMENT,
  GUARD_ENERGY,
  GUARD_VOID_FRACTION,
  GUARD_COURANT,
  GUARD_COUNT
};
extern const char *const GuardNames[GUARD_COUNT]; // "nan", "escape", ... (summary.json "guard")

enum GuardAction { GUARD_ACTION_STOP, GUARD_ACTION_WARN };

struct GuardOptions {
  PetscBool   enable          = PETSC_TRUE;
  GuardAction action          = GUARD_ACTION_STOP;
  PetscInt    interval        = 1;    // DEM steps between checks
  PetscReal   overlap         = 0.5;  // largest overlap / smaller diameter
  PetscReal   displacement    = 0.25; // largest |v| dt / d
  PetscReal   energy_growth   = 0.1;  // (E - E_min) / E_min of a closed scene
  PetscInt    energy_interval = 100;  // DEM steps between energy checks (an O(N + contacts) sum)
  PetscReal   floor_share     = 0.01; // share of coupling cells at the void-fraction floor
  PetscReal   courant         = 2.0;  // gas Courant number
  PetscInt    courant_steps   = 50;   // consecutive gas steps above it
};

// One guard that tripped: what, when, where, the remedy, and what the diagnostic snapshot marks.
struct GuardTrip {
  GuardKind               kind = GUARD_COUNT;
  PetscInt64              step = 0;
  PetscReal               time = 0, value = 0, limit = 0;
  std::string             what, where, remedy;
  std::vector<PetscInt64> particles;   // ids to mark (the same list on every rank)
  std::vector<PetscInt64> fluid_cells; // this rank's fluid cells to mark (natural indices)
};

// The largest figures seen over the run (summary.json "guards"), whether or not a limit was broken.
struct GuardFigures {
  PetscReal  overlap = 0, displacement = 0, energy_growth = 0, floor_share = 0, courant = 0;
  PetscReal  eps_raw_min = 1;
  PetscInt64 courant_run = 0; // the longest run of gas steps above -guard_courant
  PetscInt64 checks = 0, energy_checks = 0, gas_checks = 0;
};

struct Guards {
  MPI_Comm      comm = MPI_COMM_NULL;
  GuardOptions  opt;
  const Domain *dom      = nullptr;
  Dem          *dem      = nullptr;
  Fluid        *fluid    = nullptr;
  Coupling     *coupling = nullptr;
  PhaseLog     *log      = nullptr;
  PetscBool     closed   = PETSC_FALSE; // no energy input: the energy guard applies

  kernels::SustainedExceedance courant_run;
  kernels::EnergyWatch         energy;
  PetscBool                    courant_warned = PETSC_FALSE;
  PetscInt64                   lost_seen = 0, ksp_failures_seen = 0;
  std::vector<GuardTrip>       trips; // every trip reported, in order
  PetscBool                    stop             = PETSC_FALSE;
  int                          interrupt_signal = 0; // the signal that ended the run early (GuardsNoteInterrupt), 0 if none
  unsigned                     warned           = 0; // guards already reported under -guard_action warn (bit per kind)
  GuardFigures                 fig;
};

// Reads -guard_*; dem, fluid and coupling may be null (what the scene does not simulate).
PetscErrorCode GuardsCreate(MPI_Comm comm, const Domain &domain, Dem *dem, Fluid *fluid, Coupling *coupling, PhaseLog *log,
                            Guards **guards);
PetscErrorCode GuardsView(const Guards *guards, PetscViewer viewer);
// After a DEM step (or the initial state at step 0): every -guard_interval steps, or always with force (before a
// checkpoint, at the last step) or when the step halted.
PetscErrorCode GuardsCheckParticles(Guards *guards, PetscInt64 step, PetscReal time, PetscBool force);
// After each gas step: pressure solve, Courant number, void fraction, and every -guard_interval gas steps the
// gas fields' finiteness.
PetscErrorCode GuardsCheckGas(Guards *guards, PetscInt64 step, PetscReal time);
// What brings the coupled gas step within its explicit limit dt_max (s): the remedy the Courant guard gives.
std::string GuardsCourantRemedy(const Guards *guards, PetscReal dt_max);
// Whether a guard stopped the run, and which (the first trip that did).
PetscBool        GuardsStopped(const Guards *guards);
const GuardTrip *GuardsStopTrip(const Guards *guards);
// A signal ended the run early (status.hpp, EXIT_INTERRUPTED): recorded for the exit status and summary.json.
void GuardsNoteInterrupt(Guards *guards, int signal);
// The process exit status: EXIT_OK, the stopping guard's, or EXIT_INTERRUPTED (status.hpp).
int GuardsExitStatus(const Guards *guards);
// summary.json: "status" ("ok", "warned", "stopped", "interrupted"), the stopping guard's figures, the limits and the
// run's maxima.
PetscErrorCode GuardsAddSummary(const Guards *guards, JsonWriter *json);
PetscErrorCode GuardsDestroy(Guards **guards);

} // namespace fluidbed
