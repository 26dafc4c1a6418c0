#include "fluidbed/io.hpp"
#include "fluidbed/fluid.hpp"
#include "fluidbed/options.hpp"
#include "fluidbed/kernels/verlet.hpp"

#include <algorithm>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace fluidbed {

PetscErrorCode MakeDirectory(MPI_Comm comm, const char *dir)
{
  PetscMPIInt rank;
  int         err = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    std::string path;
    for (const char *c = dir; *c; ++c) {
      path += *c;
      if (*c == '/' || !c[1]) {
        if (mkdir(path.c_str(), 0775) && errno != EEXIST) err = errno;
      }
    }
  }
  PetscCallMPI(MPI_Bcast(&err, 1, MPI_INT, 0, comm));
  PetscCheck(!err, comm, PETSC_ERR_FILE_OPEN, "-output_dir: cannot create directory %s (%s)", dir, strerror(err));
  PetscFunctionReturn(0);
}

PetscErrorCode ComputeParticleTotals(Dem *dem, ParticleTotals *t)
{
  ParticleArrays p;
  PetscReal      loc[7] = {0, 0, 0, 0, 0, 0, 0}, glob[7], mx[2], gmx[2]; // KE, KE_rot, PE, momentum, contacts
  const Domain  &dom    = *dem->dom;
  MPI_Comm       comm   = PetscObjectComm((PetscObject)dem->swarm);

  PetscFunctionBeginUser;
  PetscCall(ParticleArraysGet(dem->swarm, &p));
  PetscReal vmax2 = 0;
  for (PetscInt i = 0; i < p.n; ++i) {
    const PetscReal  m = dem->props->Mass(p.d[i]), I = kernels::sphere_inertia(m, p.d[i]);
    const PetscReal *v = &p.v[3 * i], *w = &p.w[3 * i];
    const PetscReal  v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    loc[0] += 0.5 * m * v2;
    loc[1] += 0.5 * I * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    PetscReal gx = 0;
    for (PetscInt a = 0; a < p.dim; ++a) gx += dom.gravity[a] * (p.x[p.dim * i + a] - dom.lo[a]);
    loc[2] -= m * gx;
    for (int a = 0; a < 3; ++a) loc[3 + a] += m * v[a];
    vmax2 = PetscMax(vmax2, v2);
  }
  loc[6] = (PetscReal)dem->stats.contacts;
  PetscCall(ParticleArraysRestore(dem->swarm, &p));
  PetscCallMPI(MPI_Allreduce(loc, glob, 7, MPIU_REAL, MPI_SUM, comm));
  mx[0] = PetscSqrtReal(vmax2);
  mx[1] = dem->stats.max_overlap_rel;
  PetscCallMPI(MPI_Allreduce(mx, gmx, 2, MPIU_REAL, MPI_MAX, comm));
  PetscCall(ParticlesGlobalCount(dem->swarm, &t->count));
  t->ke_trans = glob[0];
  t->ke_rot   = glob[1];
  t->pe_grav  = glob[2];
  for (int a = 0; a < 3; ++a) t->momentum[a] = glob[3 + a];
  t->contacts_per_particle   = t->count ? glob[6] / (PetscReal)t->count : 0.0;
  t->max_speed               = gmx[0];
  t->max_overlap_rel         = gmx[1];
  dem->stats.max_overlap_rel = 0.0; // the next row reports the maximum over its own interval
  PetscFunctionReturn(0);
}

PetscErrorCode MonitorCreate(MPI_Comm comm, const char *dir, PetscReal t_final, PetscBool append, Monitor *m)
{
  PetscMPIInt rank;
  PetscInt    ids[256], nids = 256;
  PetscBool   set = PETSC_FALSE;

  PetscFunctionBeginUser;
  m->interval = t_final / 200.0;
  PetscOptionsBegin(comm, "monitor_", "Monitor: global quantities and tracked particles", "Output");
  PetscCall(OptionsReal(PetscOptionsObject, "-dt", "Simulated time between rows of monitor.csv (default t_final / 200; 0: every step)", "s",
                        NonNegative(), &m->interval, NULL));
  PetscCall(OptionsIntArray(PetscOptionsObject, "-track_ids", "Particle ids whose state goes to track.csv", PETSC_MIN_INT, PETSC_MAX_INT,
                            ids, &nids, &set));
  PetscCall(OptionsInt(PetscOptionsObject, "-track_every", "Steps between rows of track.csv", 1, PETSC_MAX_INT, &m->track_every, NULL));
  PetscOptionsEnd();
  if (set) m->track_ids.assign(ids, ids + nids);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    const std::string path  = std::string(dir) + "/monitor.csv";
    const bool        fresh = !append || access(path.c_str(), F_OK) != 0;
    m->csv                  = fopen(path.c_str(), fresh ? "w" : "a");
    PetscCheck(m->csv, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s", path.c_str());
    if (fresh) {
      fprintf(m->csv, "step,time");
      if (m->particles)
        fprintf(m->csv,
                ",particles,contacts_per_particle,ke_trans,ke_rot,pe_grav,momentum_x,momentum_y,momentum_z,max_speed,max_overlap_rel,"
                "outlet_removed,rebuilds");
      if (m->fluid) fprintf(m->csv, ",fluid_dt,gas_max_speed,gas_courant,ksp_its,ksp_rnorm,ksp_time,max_div,div_scale,inflow,outflow");
      for (const std::string &name : m->extra_columns) fprintf(m->csv, ",%s", name.c_str());
      fprintf(m->csv, "\n");
    }
    if (!m->track_ids.empty()) {
      const std::string tpath  = std::string(dir) + "/track.csv";
      const bool        tfresh = !append || access(tpath.c_str(), F_OK) != 0;
      m->track                 = fopen(tpath.c_str(), tfresh ? "w" : "a");
      PetscCheck(m->track, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "cannot write %s", tpath.c_str());
      if (tfresh) fprintf(m->track, "step,time,id,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz\n");
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MonitorWrite(MPI_Comm comm, Monitor *m, Dem *dem, PetscInt64 step, PetscReal time, const ParticleTotals &t,
                            const FluidStats *fluid, const std::vector<PetscReal> *extra)
{
  PetscFunctionBeginUser;
  (void)comm;
  if (m->csv) {
    fprintf(m->csv, "%lld,%.10e", (long long)step, (double)time);
    if (m->particles)
      fprintf(m->csv, ",%lld,%.6g,%.10e,%.10e,%.10e,%.10e,%.10e,%.10e,%.6e,%.6e,%lld,%lld", (long long)t.count,
              (double)t.contacts_per_particle, (double)t.ke_trans, (double)t.ke_rot, (double)t.pe_grav, (double)t.momentum[0],
              (double)t.momentum[1], (double)t.momentum[2], (double)t.max_speed, (double)t.max_overlap_rel,
              (long long)dem->stats.outlet_removed, (long long)dem->stats.rebuilds);
    if (m->fluid && fluid)
      fprintf(m->csv, ",%.6e,%.6e,%.4f,%d,%.6e,%.6e,%.6e,%.6e,%.15e,%.15e", (double)fluid->dt, (double)fluid->max_speed,
              (double)fluid->courant, (int)fluid->ksp_its, (double)fluid->ksp_rnorm, (double)fluid->ksp_time, (double)fluid->max_div,
              (double)fluid->rhs_scale, (double)fluid->inflow, (double)fluid->outflow);
    if (extra)
      for (PetscReal v : *extra) fprintf(m->csv, ",%.12e", (double)v);
    fprintf(m->csv, "\n");
    fflush(m->csv);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MonitorTrack(MPI_Comm comm, Monitor *m, Dem *dem, PetscInt64 step, PetscReal time)
{
  const std::size_t      nt = m->track_ids.size();
  std::vector<PetscReal> loc(nt * 13, 0.0), glob(nt * 13);
  ParticleArrays         p;

  PetscFunctionBeginUser;
  if (!nt || step % m->track_every) PetscFunctionReturn(0);
  PetscCall(ParticleArraysGet(dem->swarm, &p));
  for (PetscInt i = 0; i < p.n; ++i) {
    const auto it = std::find(m->track_ids.begin(), m->track_ids.end(), p.id[i]);
    if (it == m->track_ids.end()) continue;
    PetscReal *row = &loc[13 * (std::size_t)(it - m->track_ids.begin())];
    row[0]         = 1.0; // found
    for (PetscInt a = 0; a < p.dim; ++a) row[1 + a] = p.x[p.dim * i + a];
    for (int a = 0; a < 3; ++a) {
      row[4 + a]  = p.v[3 * i + a];
      row[7 + a]  = p.w[3 * i + a];
      row[10 + a] = p.f[3 * i + a];
    }
  }
  PetscCall(ParticleArraysRestore(dem->swarm, &p));
  PetscCallMPI(MPI_Reduce(loc.data(), glob.data(), (int)loc.size(), MPIU_REAL, MPI_SUM, 0, comm));
  if (m->track) {
    for (std::size_t k = 0; k < nt; ++k) {
      const PetscReal *r = &glob[13 * k];
      if (r[0] == 0.0) continue; // not (or no longer) in the system
      fprintf(m->track, "%lld,%.12e,%lld,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e,%.15e\n", (long long)step,
              (double)time, (long long)m->track_ids[k], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8], r[9], r[10], r[11], r[12]);
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MonitorDestroy(Monitor *m)
{
  PetscFunctionBeginUser;
  if (m->csv) fclose(m->csv);
  if (m->track) fclose(m->track);
  m->csv = m->track = nullptr;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
