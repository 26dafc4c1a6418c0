// Run outputs: the monitor CSV of global quantities, tracked particles and the final particle table (the checked
// writes and the JSON writer they go through: fluidbed/files.hpp). Rank 0 writes the text files; the data are
// reduced or gathered first.
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

struct Monitor {
  OutputFile                 csv, track; // track: open only with -monitor_track_ids
  std::vector<PetscInt64>    track_ids;
  PetscInt                   track_every = 1;
  PetscReal                  interval = 0, next = 0;
  std::vector<MonitorColumn> columns;            // after step and time: the outputs' (OutputListColumns), set before MonitorCreate
  PetscInt64                 last_row_step = -1; // the step of the last row written
};

// append: continue the files of a restarted run instead of starting them anew, dropping first the rows after
// last_step (the checkpoint's step: rows written after it by the run that is continued).
PetscErrorCode MonitorCreate(MPI_Comm comm, const char *dir, PetscReal t_final, PetscBool append, PetscInt64 last_step, Monitor *m);
// One row: step, time and the values of m->columns (OutputListValues).
PetscErrorCode MonitorWrite(MPI_Comm comm, Monitor *m, PetscInt64 step, PetscReal time, const std::vector<PetscReal> &values);
PetscErrorCode MonitorTrack(MPI_Comm comm, Monitor *m, Dem *dem, PetscInt64 step, PetscReal time);
// Closes monitor.csv and track.csv at the end of a run, checked (collective).
PetscErrorCode MonitorClose(MPI_Comm comm, Monitor *m);
PetscErrorCode MonitorDestroy(Monitor *m);

// particles.csv sorted by id: id,d,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz (readable by -insert_type file).
PetscErrorCode WriteParticlesCSV(DM swarm, const char *path);

} // namespace fluidbed
