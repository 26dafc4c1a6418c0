// What the run-time guards (src/guards) ask of the particles' motion when a limit is broken: which particle, where,
// on which rank. Collective; run only at guard checks, never in the step.
#include "fluidbed/particle_system.hpp"

#include <cmath>

namespace fluidbed {

namespace {

bool Finite3(const PetscReal *a)
{
  return std::isfinite(a[0] + a[1] + a[2]);
}

} // namespace

// MPI_MAXLOC, then a broadcast of the site's fields.
PetscErrorCode ParticleSiteReduce(MPI_Comm comm, ParticleSite *s)
{
  PetscMPIInt rank;
  struct {
    double v;
    int    r;
  } loc, glob; // MPI_DOUBLE_INT

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  loc.v = s->value;
  loc.r = rank;
  PetscCallMPI(MPI_Allreduce(&loc, &glob, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm));
  double buf[6] = {s->value, (double)s->id, (double)s->partner, s->x[0], s->x[1], s->x[2]};
  PetscCallMPI(MPI_Bcast(buf, 6, MPI_DOUBLE, glob.r, comm));
  s->value   = buf[0];
  s->id      = (PetscInt64)buf[1];
  s->partner = (PetscInt64)buf[2];
  for (int a = 0; a < 3; ++a) s->x[a] = buf[3 + a];
  s->rank = glob.r;
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesLocateFastest(ParticleSystem *ps, ParticleSite *site)
{
  ParticleArrays p;

  PetscFunctionBeginUser;
  *site       = ParticleSite{};
  site->value = -1.0;
  PetscCall(ParticleArraysGet(ps->swarm, &p));
  for (PetscInt i = 0; i < p.n; ++i) {
    const PetscReal *v = &p.v[3 * i], rel = PetscSqrtReal(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * ps->dt / p.d[i];
    if (rel > site->value) {
      site->value = rel;
      site->id    = p.id[i];
      for (PetscInt a = 0; a < p.dim; ++a) site->x[a] = p.x[p.dim * i + a];
    }
  }
  PetscCall(ParticleArraysRestore(ps->swarm, &p));
  PetscCall(ParticleSiteReduce(PetscObjectComm((PetscObject)ps->swarm), site));
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesLocateNonFinite(ParticleSystem *ps, ParticleSite *site, std::vector<PetscInt64> *ids)
{
  ParticleArrays p;
  PetscInt64     n_local, n;

  PetscFunctionBeginUser;
  *site       = ParticleSite{};
  site->value = -PETSC_MAX_REAL; // the smallest id wins: value = -id
  ids->clear();
  PetscCall(ParticleArraysGet(ps->swarm, &p));
  for (PetscInt i = 0; i < p.n; ++i) {
    bool ok = Finite3(&p.v[3 * i]) && Finite3(&p.w[3 * i]) && Finite3(&p.f[3 * i]) && Finite3(&p.t[3 * i]);
    for (PetscInt a = 0; a < p.dim; ++a) ok = ok && std::isfinite(p.x[p.dim * i + a]);
    if (ok) continue;
    ids->push_back(p.id[i]);
    if (-(PetscReal)p.id[i] > site->value) {
      site->value = -(PetscReal)p.id[i];
      site->id    = p.id[i];
      for (PetscInt a = 0; a < p.dim; ++a) site->x[a] = p.x[p.dim * i + a];
    }
  }
  PetscCall(ParticleArraysRestore(ps->swarm, &p));
  n_local = (PetscInt64)ids->size();
  PetscCallMPI(MPI_Allreduce(&n_local, &n, 1, MPIU_INT64, MPI_SUM, PetscObjectComm((PetscObject)ps->swarm)));
  PetscCall(ParticleSiteReduce(PetscObjectComm((PetscObject)ps->swarm), site));
  site->count = n;
  if (!n) site->id = -1;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
