// Moves particles to the ranks that own their particle cells with DMSwarmMigrate, after removing (and counting)
// those that left through the outlet or through a wall. In PETSc 3.18 DMSwarmMigrate deletes without a word
// particles that left the domain or jumped past a neighbouring rank, so the global count is checked across every
// migration; what is lost is counted in DemStats::lost, and the escape guard stops the run on it.
#include "fluidbed/particle_system.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace fluidbed {

namespace {
constexpr PetscInt64 kNoParticle = INT64_MAX;
} // namespace

PetscErrorCode ParticlesMigrate(ParticleSystem *ps)
{
  const Domain         &dom  = *ps->dom;
  MPI_Comm              comm = PetscObjectComm((PetscObject)ps->swarm);
  ParticleArrays        p;
  std::vector<PetscInt> outlet, escaped;
  PetscInt64            escaped_id   = kNoParticle, n_local[2], n[2];
  PetscReal             escaped_x[3] = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCall(ParticleArraysGet(ps->swarm, &p));
  for (PetscInt i = 0; i < p.n; ++i) {
    for (PetscInt a = 0; a < p.dim; ++a) {
      if (dom.periodic[a]) continue; // wrapped in the drift
      const PetscReal x = p.x[p.dim * i + a];
      if (a == 1 && dom.top_outlet && x >= dom.hi[1]) {
        outlet.push_back(i);
        break;
      }
      if (x < dom.lo[a] || x >= dom.hi[a]) {
        // through a wall: the contact was not resolved. Removed here (DMSwarmMigrate would drop it without a
        // word), counted, and the first one named by the escape guard, which stops the run.
        escaped.push_back(i);
        if (p.id[i] < escaped_id) {
          escaped_id = p.id[i];
          for (PetscInt b = 0; b < p.dim; ++b) escaped_x[b] = p.x[p.dim * i + b];
        }
        break;
      }
    }
  }
  PetscCall(ParticleArraysRestore(ps->swarm, &p));

  // Remove from the highest index down, so that the particle swapped into a hole is never one to remove.
  std::vector<PetscInt> remove(outlet);
  remove.insert(remove.end(), escaped.begin(), escaped.end());
  std::sort(remove.rbegin(), remove.rend());
  for (PetscInt i : remove) PetscCall(DMSwarmRemovePointAtIndex(ps->swarm, i));
  n_local[0] = (PetscInt64)outlet.size();
  n_local[1] = (PetscInt64)escaped.size();
  PetscCallMPI(MPI_Allreduce(n_local, n, 2, MPIU_INT64, MPI_SUM, comm));
  ps->stats.outlet_removed += n[0];
  if (n[1]) {
    PetscInt64 first;
    PetscCallMPI(MPI_Allreduce(&escaped_id, &first, 1, MPIU_INT64, MPI_MIN, comm));
    if (ps->stats.lost.first_id < 0) {
      PetscReal x[3], xl[3] = {0, 0, 0};
      if (escaped_id == first)
        for (int b = 0; b < 3; ++b) xl[b] = escaped_x[b];
      PetscCallMPI(MPI_Allreduce(xl, x, 3, MPIU_REAL, MPI_SUM, comm));
      ps->stats.lost.first_id = first;
      for (int b = 0; b < 3; ++b) ps->stats.lost.first_x[b] = x[b];
    }
    ps->stats.lost.count += n[1];
  }

  PetscInt64 before, after;
  PetscCall(ParticlesGlobalCount(ps->swarm, &before));
  PetscCall(DMSwarmMigrate(ps->swarm, PETSC_TRUE));
  PetscCall(ParticlesGlobalCount(ps->swarm, &after));
  if (before != after) { // a particle moved further than a neighbouring rank between rebuilds: counted, and guarded
    ps->stats.lost.count += before - after;
    ps->stats.lost.migration = PETSC_TRUE;
  }
  PetscFunctionReturn(0);
}

} // namespace fluidbed
