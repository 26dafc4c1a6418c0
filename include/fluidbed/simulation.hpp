// A run: the scene read from PETSc options, the time loop, and its outputs.
#pragma once

#include <petscsys.h>

#include "fluidbed/averaging.hpp"
#include "fluidbed/coupling.hpp"
#include "fluidbed/dem.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/fluid.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/hdf5io.hpp"
#include "fluidbed/io.hpp"
#include "fluidbed/option_report.hpp"
#include "fluidbed/particles.hpp"
#include "fluidbed/phases.hpp"
#include "fluidbed/probes.hpp"

namespace fluidbed {

struct RunControl {
  PetscReal t_final                        = 0.3;  // s (with no scene options: a 4000-particle pour that settles)
  PetscInt  max_steps                      = -1;   // < 0: no limit
  PetscReal progress_interval              = 10.0; // wall-clock s between progress lines
  PetscBool write_particles                = PETSC_TRUE;
  char      output_dir[PETSC_MAX_PATH_LEN] = "output";
  PetscBool fluid                          = PETSC_FALSE; // -fluid: the gas phase
  PetscBool particles                      = PETSC_TRUE;  // -particles: the DEM
  PetscInt  couple_substeps                = 1;           // -couple_substeps: gas step = DEM step x this, with both on
};

// HDF5 snapshots every -output_interval, checkpoints every -checkpoint_interval, -restart FILE.
struct OutputSchedule {
  PetscReal                   interval = 0, next = 0; // snapshots, s (0: none)
  PetscReal                   checkpoint_interval = 0, next_checkpoint = 0;
  char                        checkpoint_file[PETSC_MAX_PATH_LEN] = "";
  char                        restart[PETSC_MAX_PATH_LEN]         = "";
  std::vector<SnapshotRecord> series;
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
  Coupling       *coupling = nullptr; // particles and gas both on
  GasProbes       probes;
  BedAverages    *averages   = nullptr; // -average: time averages and the bed measures (analysis.h5)
  PetscInt64      step       = 0;
  PetscReal       time       = 0.0;
  PetscInt64      steps_run  = 0; // steps taken by this run (a restart continues the count in step)
  double          wall_setup = 0.0, wall_run = 0.0;
  UnusedOptions   unused_options; // options without effect in the run, listed at its end
};

// The DEM step that stands for time t: the first whose time step * dt reaches t - dt / 2 (the nearest step). The
// last step of a run and the steps that write checkpoints follow this one rule, so that a run that stops at t
// and a longer run that writes a checkpoint at t do so at the same step.
inline PetscInt64 StepAtTime(PetscReal t, PetscReal dt)
{
  return (PetscInt64)PetscCeilReal(t / dt - 0.5 - 1e-9);
}

PetscErrorCode SimulationCreate(MPI_Comm comm, Simulation **sim);
// Reads every option, creates grids and particles, and prepares the first step.
PetscErrorCode SimulationSetUp(Simulation *sim);
PetscErrorCode SimulationRun(Simulation *sim);
PetscErrorCode SimulationDestroy(Simulation **sim);

// Snapshots, checkpoints and restart (src/io/checkpoint.cpp).
PetscErrorCode OutputScheduleSetFromOptions(Simulation *sim);
PetscErrorCode SimulationWriteSnapshot(Simulation *sim);
PetscErrorCode SimulationWriteCheckpoint(Simulation *sim);
PetscErrorCode SimulationReadCheckpoint(Simulation *sim);
// Writes what is due at the current time (snapshot, checkpoint); `last` forces a final checkpoint.
PetscErrorCode SimulationOutputStep(Simulation *sim, PetscBool last);

} // namespace fluidbed
