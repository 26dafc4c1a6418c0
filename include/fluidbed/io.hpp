// Run outputs: the monitor CSV of global quantities, and the outputs of the list (fluidbed/outputs.hpp) for the
// tracked particles and the final tables (the checked writes and the JSON writer they go through:
// fluidbed/files.hpp). Rank 0 writes the text files; the data are reduced or gathered first.
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

#include "fluidbed/dem.hpp"
#include "fluidbed/files.hpp"
#include "fluidbed/outputs.hpp"

namespace fluidbed {

// Global sums over the particles (monitor.csv columns).
struct ParticleTotals {
  PetscInt64 count    = 0;
  PetscReal  ke_trans = 0, ke_rot = 0, pe_grav = 0; // J
  PetscReal  momentum[3]{0, 0, 0};                  // kg m/s
  PetscReal  max_speed             = 0;             // m/s
  PetscReal  contacts_per_particle = 0;
  PetscReal  max_overlap_rel       = 0; // largest overlap / diameter since the previous row
};
PetscErrorCode ComputeParticleTotals(Dem *dem, ParticleTotals *t);

// monitor.csv: a row of step, time and every output's columns (OutputListValues) every -monitor_dt.
struct Monitor {
  OutputFile                 csv;
  PetscReal                  interval = 0, next = 0;
  std::vector<MonitorColumn> columns;            // after step and time: the outputs' (OutputListColumns), set before MonitorCreate
  PetscInt64                 last_row_step = -1; // the step of the last row written
};

// append: continue the file of a restarted run instead of starting it anew, dropping first the rows after last_step
// (the checkpoint's step: rows written after it by the run that is continued).
PetscErrorCode MonitorCreate(MPI_Comm comm, const char *dir, PetscReal t_final, PetscBool append, PetscInt64 last_step, Monitor *m);
// One row: step, time and the values of m->columns (OutputListValues).
PetscErrorCode MonitorWrite(MPI_Comm comm, Monitor *m, PetscInt64 step, PetscReal time, const std::vector<PetscReal> &values);
// Closes monitor.csv at the end of a run, checked (collective).
PetscErrorCode MonitorClose(MPI_Comm comm, Monitor *m);
PetscErrorCode MonitorDestroy(Monitor *m);

// The tracked particles as an output: a row of track.csv per particle of -monitor_track_ids every
// -monitor_track_every steps (Step), continued after the checkpoint's step on a restart (Start); none without the
// option.
PetscErrorCode ParticleTrackCreate(const RunView &run, std::unique_ptr<Output> *out);

// particles.csv sorted by id: id,d,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz (readable by -insert_type file).
PetscErrorCode WriteParticlesCSV(DM swarm, const char *path);
// The final tables as an output: at the end of a run that no guard stopped (Finalize), particles.csv (with particles
// and `particles`, -output_particles) and fluid_cells.csv (with the gas and -fluid_output_cells); none when neither.
PetscErrorCode FinalTablesCreate(const RunView &run, PetscBool particles, std::unique_ptr<Output> *out);

} // namespace fluidbed
