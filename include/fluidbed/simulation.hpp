// A run: the scene read from PETSc options, the time loop, and its outputs.
#pragma once

#include <petscsys.h>

#include "fluidbed/coupling.hpp"
#include "fluidbed/dem.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/fluid.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/guards.hpp"
#include "fluidbed/hdf5io.hpp"
#include "fluidbed/io.hpp"
#include "fluidbed/option_report.hpp"
#include "fluidbed/outputs.hpp"
#include "fluidbed/particles.hpp"
#include "fluidbed/phases.hpp"
#include "fluidbed/scene_model.hpp"

namespace fluidbed {

struct RunControl {
  PetscReal t_final                        = 0.3;  // s (with no scene options: a 4000-particle pour that settles)
  PetscInt  max_steps                      = -1;   // < 0: no limit
  PetscReal progress_interval              = 10.0; // wall-clock s between progress lines
  PetscBool write_particles                = PETSC_TRUE;
  char      output_dir[PETSC_MAX_PATH_LEN] = "output";
  PetscBool fluid                          = PETSC_FALSE; // -fluid: the gas phase
  PetscBool particles                      = PETSC_TRUE;  // -particles: the DEM
};

// HDF5 snapshots every -output_interval (the snapshot series output), checkpoints every -checkpoint_interval (the
// checkpoints output), -restart FILE.
struct OutputSchedule {
  PetscReal interval                            = 0; // snapshots, s (0: none)
  PetscReal checkpoint_interval                 = 0; // s (0: none)
  char      checkpoint_file[PETSC_MAX_PATH_LEN] = "";
  char      restart[PETSC_MAX_PATH_LEN]         = "";
};

struct Simulation {
  MPI_Comm        comm = MPI_COMM_NULL;
  Domain          domain;
  ParticleProps   props;
  Grids           grids;
  PhaseLog        log;
  RunControl      run;
  Monitor         monitor;
  OutputSchedule  output;
  InsertionReport inserted;
  Dem            *dem      = nullptr;
  DM              swarm    = nullptr;
  Fluid          *fluid    = nullptr;
  Coupling       *coupling = nullptr;  // particles and gas both on
  OutputList      outputs;             // every output of the run (outputs.hpp): registered by SimulationAddOutputs
  const Output   *averages = nullptr;  // -average: the time averages in outputs (NULL when off), whose schedule the scene model reports
  ParticleTotals  totals;              // the particle columns of the last monitor row (summary.json, the closing line)
  Guards         *guards    = nullptr; // -guard_*: run-time checks that stop a run gone wrong
  PetscInt64      step      = 0;
  PetscReal       time      = 0.0;
  PetscInt64      steps_run = 0; // steps taken by this run (a restart continues the count in step)
  // With particles the time is time_origin + (step - step_origin) dt: (0, 0) unless a restart changed the time step
  // (a rescue with another -dem_dt_factor), which starts a new origin at the checkpoint.
  PetscInt64    step_origin = 0;
  PetscReal     time_origin = 0.0;
  int           exit_status = 0; // the process exit status (status.hpp): a guard's when one stopped the run
  double        wall_setup = 0.0, wall_run = 0.0;
  double        cpu_run = 0.0;  // this rank's processor time (user + system) over the run's steps, s
  UnusedOptions unused_options; // options without effect in the run, listed at its end
  SceneModel    model;          // what the scene models and why, and its warnings (printed at start-up, in summary.json)
};

// The DEM step that stands for time t: the first whose time step * dt reaches t - dt / 2 (the nearest step),
// counted from the origin (step0, t0). The last step of a run and the steps that write checkpoints follow this one
// rule, so that a run that stops at t and a longer run that writes a checkpoint at t do so at the same step.
inline PetscInt64 StepAtTime(PetscReal t, PetscReal dt, PetscInt64 step0 = 0, PetscReal t0 = 0.0)
{
  return step0 + (PetscInt64)PetscCeilReal((t - t0) / dt - 0.5 - 1e-9);
}
inline PetscInt64 StepAtTime(const Simulation *sim, PetscReal t)
{
  return StepAtTime(t, DemGetParams(sim->dem).dt, sim->step_origin, sim->time_origin);
}

PetscErrorCode SimulationCreate(MPI_Comm comm, Simulation **sim);
// Reads every option, creates grids and particles, and prepares the first step.
PetscErrorCode SimulationSetUp(Simulation *sim);
PetscErrorCode SimulationRun(Simulation *sim);
PetscErrorCode SimulationDestroy(Simulation **sim);

// The run as its outputs see it, now (src/app/outputs.cpp).
RunView SimulationView(const Simulation *sim);
// Creates every output of the run and registers it in sim->outputs, in the order of their monitor.csv columns,
// summary.json entries and calls (src/app/outputs.cpp, the one place outputs are registered). Call once every
// module exists, before a restart's checkpoint is read.
PetscErrorCode SimulationAddOutputs(Simulation *sim);

// The output schedule's options: snapshots, checkpoints and restart (src/app/checkpoint.cpp).
PetscErrorCode OutputScheduleSetFromOptions(Simulation *sim);
// Clears the output directory before the run writes (after the inputs are read): a fresh run removes the files of a
// previous run (RemovePreviousRun); a restart, the files its outputs wrote after the checkpoint (Output::RemoveStale:
// the snapshots).
PetscErrorCode SimulationRemoveStaleOutput(Simulation *sim);

// The application's outputs (outputs.hpp), each holding the run; SimulationAddOutputs registers them.
// The guards' verdict, summary.json's first entries ("status", GuardsAddSummary), and the diagnostic snapshot of a
// run a guard stopped (Stopped): guard_failure.h5 with the particles and gas as in a snapshot plus a "flagged" field
// (1 on the particles and gas cells the guard names), and guard_failure.xmf for ParaView (src/app/diagnostic.cpp).
PetscErrorCode GuardReportCreate(Simulation *sim, std::unique_ptr<Output> *out);
// The run's own summary entries: steps, time, ranks, the decomposition, the wall times and phases (src/app/summary.cpp).
PetscErrorCode RunEntriesCreate(Simulation *sim, std::unique_ptr<Output> *out);
// The scene's summary entries: what it models (SceneModelAddSummary) and the options without effect (src/app/summary.cpp).
PetscErrorCode SceneEntriesCreate(Simulation *sim, std::unique_ptr<Output> *out);
// summary.json at the end of every run (End): every output's AddSummary in order, "status" first (src/app/summary.cpp).
PetscErrorCode SummaryFileCreate(Simulation *sim, std::unique_ptr<Output> *out);
// The checkpoints (src/app/checkpoint.cpp): at a Step when -checkpoint_interval is due, and at the last step when
// it is set, the guards are checked and, when they pass, the checkpoint is written atomically with the run's own state
// and every output's CheckpointWrite; Restart reads -restart back (the run's state, then every output's
// CheckpointRead). Register it after every output with a Step: the checkpoint then holds what they wrote at its step.
PetscErrorCode CheckpointsCreate(Simulation *sim, std::unique_ptr<Output> *out);

} // namespace fluidbed
