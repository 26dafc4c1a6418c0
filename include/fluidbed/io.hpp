// Run outputs: the monitor CSV of global quantities, tracked particles, the final particle table and
// summary.json. Rank 0 writes; the data are reduced or gathered first.
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

#include "fluidbed/dem.hpp"

namespace fluidbed {

struct FluidStats;

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
  FILE                    *csv = nullptr, *track = nullptr;
  std::vector<PetscInt64>  track_ids;
  PetscInt                 track_every = 1;
  PetscReal                interval = 0, next = 0;
  bool                     particles = true, fluid = false; // column groups, set before MonitorCreate
  std::vector<std::string> extra_columns;                   // further columns (coupling, probes), set before MonitorCreate
};

// append: continue the files of a restarted run instead of starting them anew.
PetscErrorCode MonitorCreate(MPI_Comm comm, const char *dir, PetscReal t_final, PetscBool append, Monitor *m);
// One row: the particle columns when m->particles, the gas columns (fluid, the last gas step) when m->fluid.
// extra: the values of m->extra_columns.
PetscErrorCode MonitorWrite(MPI_Comm comm, Monitor *m, Dem *dem, PetscInt64 step, PetscReal time, const ParticleTotals &t,
                            const FluidStats *fluid = nullptr, const std::vector<PetscReal> *extra = nullptr);
PetscErrorCode MonitorTrack(MPI_Comm comm, Monitor *m, Dem *dem, PetscInt64 step, PetscReal time);
PetscErrorCode MonitorDestroy(Monitor *m);

// particles.csv sorted by id: id,d,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz (readable by -insert_type file).
PetscErrorCode WriteParticlesCSV(DM swarm, const char *path);

// Creates a directory (and its parents) on rank 0.
PetscErrorCode MakeDirectory(MPI_Comm comm, const char *dir);

// A flat JSON object written by rank 0; values are added in order.
struct JsonWriter {
  std::string body;
  void        Number(const char *key, double v);
  void        Integer(const char *key, long long v);
  void        String(const char *key, const std::string &v);
  void        Object(const char *key, const JsonWriter &inner);
  void        StringArray(const char *key, const std::vector<std::string> &v);
  std::string Text() const;
};
PetscErrorCode JsonWrite(MPI_Comm comm, const char *path, const JsonWriter &json);

} // namespace fluidbed
