// Moves particles to the ranks that own their particle cells with DMSwarmMigrate, after removing (and counting)
// those that left through the outlet. In PETSc 3.18 DMSwarmMigrate deletes without a word particles that left
// the domain or jumped past a neighbouring rank, so the global count is checked across every migration.
#include "fluidbed/dem.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace fluidbed {

namespace {
constexpr PetscInt64 kNoParticle = INT64_MAX;
} // namespace

PetscErrorCode DemMigrate(Dem *dem)
{
  const Domain         &dom  = *dem->dom;
  MPI_Comm              comm = PetscObjectComm((PetscObject)dem->swarm);
  ParticleArrays        p;
  std::vector<PetscInt> outlet;
  PetscInt64            escaped_id   = kNoParticle, nout_local, nout;
  PetscReal             escaped_x[3] = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCall(ParticleArraysGet(dem->swarm, &p));
  for (PetscInt i = 0; i < p.n; ++i) {
    for (PetscInt a = 0; a < p.dim; ++a) {
      if (dom.periodic[a]) continue; // wrapped in the drift
      const PetscReal x = p.x[p.dim * i + a];
      if (a == 1 && dom.top_outlet && x >= dom.hi[1]) {
        outlet.push_back(i);
        break;
      }
      if ((x < dom.lo[a] || x >= dom.hi[a]) && p.id[i] < escaped_id) {
        escaped_id = p.id[i];
        for (PetscInt b = 0; b < p.dim; ++b) escaped_x[b] = p.x[p.dim * i + b];
      }
    }
  }
  PetscCall(ParticleArraysRestore(dem->swarm, &p));

  // A particle through a wall means the contact was not resolved: stop, naming the first such particle.
  PetscInt64 first;
  PetscCallMPI(MPI_Allreduce(&escaped_id, &first, 1, MPIU_INT64, MPI_MIN, comm));
  if (first != kNoParticle) {
    PetscReal x[3], xl[3] = {0, 0, 0};
    if (escaped_id == first)
      for (int b = 0; b < 3; ++b) xl[b] = escaped_x[b];
    PetscCallMPI(MPI_Allreduce(xl, x, 3, MPIU_REAL, MPI_SUM, comm));
    SETERRQ(comm, PETSC_ERR_NOT_CONVERGED,
            "particle %lld left the domain through a wall at (%.6g, %.6g, %.6g) m: the contact was not resolved; reduce -dem_dt_factor "
            "(now %.6g) or raise -wall_kn",
            (long long)first, (double)x[0], (double)x[1], (double)x[2], (double)dem->par.dt_factor);
  }

  // Outlet: remove from the highest index down, so that the particle swapped into a hole is never one to remove.
  std::sort(outlet.rbegin(), outlet.rend());
  for (PetscInt i : outlet) PetscCall(DMSwarmRemovePointAtIndex(dem->swarm, i));
  nout_local = (PetscInt64)outlet.size();
  PetscCallMPI(MPI_Allreduce(&nout_local, &nout, 1, MPIU_INT64, MPI_SUM, comm));
  dem->stats.outlet_removed += nout;

  PetscInt64 before, after;
  PetscCall(ParticlesGlobalCount(dem->swarm, &before));
  PetscCall(DMSwarmMigrate(dem->swarm, PETSC_TRUE));
  PetscCall(ParticlesGlobalCount(dem->swarm, &after));
  PetscCheck(
    before == after, comm, PETSC_ERR_PLIB,
    "DMSwarmMigrate lost %lld of %lld particles (a particle moved further than a neighbouring rank between neighbour-list rebuilds)",
    (long long)(before - after), (long long)before);
  PetscFunctionReturn(0);
}

} // namespace fluidbed
