// The DEM step: the particles' motion (src/particles: kick-drift, rebuild: migrate, ghosts; ghost refresh; kick) around
// the contact stage (neighbour lists, contact forces).
#include <cmath>

#include "dem_impl.hpp"

namespace fluidbed {

namespace {

// Rebuilds between sorts of the storage: -dem_sort_interval, or with 0 the rebuilds after which a particle may have
// moved one neighbour bin (d_max + skin) since the last sort. Between rebuilds no particle moves more than half the
// skin, so that is 2 (d_max + skin) / skin rebuilds (22 at the default skin of 0.1 d).
PetscInt SortEvery(const DemParams &par)
{
  return par.sort_interval > 0 ? par.sort_interval : (PetscInt)std::ceil(2.0 * (1.0 + par.skin) / par.skin - 1e-9);
}

// A rebuild sorts the storage (for the contact loop's locality) at set-up, for a checkpoint (so that the run and its
// restart hold the same storage order) and every SortEvery rebuilds: between rebuilds a particle moves less than
// half the skin, so the order of one sort serves many rebuilds, and a sort moves every field of every particle
// (about 1 kB each with the contact histories). Nothing else depends on the storage order.
PetscErrorCode Rebuild(Dem *dem, PetscBool force_sort)
{
  PetscFunctionBeginUser;
  PetscCall(PhaseBegin(dem->log, PHASE_MIGRATE));
  PetscCall(DemSyncPairHistory(dem));
  PetscCall(ParticlesMigrate(dem));
  if (force_sort || ++dem->rebuilds_since_sort >= SortEvery(dem->par)) {
    PetscCall(ParticlesSortLocal(dem));
    dem->rebuilds_since_sort = 0;
    dem->stats.storage_sorts++;
  }
  PetscCall(PhaseEnd(dem->log, PHASE_MIGRATE));
  PetscCall(PhaseBegin(dem->log, PHASE_GHOSTS));
  PetscCall(ParticlesPackBodies(dem));
  PetscCall(ParticlesGhostsBuild(dem));
  PetscCall(PhaseEnd(dem->log, PHASE_GHOSTS));
  PetscCall(PhaseBegin(dem->log, PHASE_NEIGHBOUR));
  PetscCall(DemNeighbourBuild(dem));
  PetscCall(PhaseEnd(dem->log, PHASE_NEIGHBOUR));
  dem->steps_since_rebuild = 0;
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode DemRebuild(Dem *dem)
{
  PetscFunctionBeginUser;
  PetscCall(Rebuild(dem, PETSC_TRUE));
  PetscFunctionReturn(0);
}

PetscErrorCode DemCreate(MPI_Comm comm, const Domain &dom, const ParticleGrid &pgrid, const ParticleProps &props, PhaseLog *log, Dem **dem)
{
  Dem *d = new Dem;

  PetscFunctionBeginUser;
  PetscCall(DemParamsSetFromOptions(comm, dom, props, &d->par));
  PetscCall(ContactModelGet(d->par.contact_model, &d->contact));
  PetscCall(ParticleSystemSetUp(comm, dom, pgrid, props, log, d->par.dt, d->par.pseudo2d, d->par.skin * props.d_max, d));
  *dem = d;
  PetscFunctionReturn(0);
}

PetscErrorCode DemCreateSwarm(Dem *dem, DM *swarm)
{
  PetscFunctionBeginUser;
  PetscCall(ParticlesCreate(PetscObjectComm((PetscObject)dem->pgrid->da_vertex), *dem->dom, *dem->pgrid, dem->par.max_contacts,
                            dem->contact.history_size, swarm));
  PetscFunctionReturn(0);
}

PetscErrorCode DemSetUp(Dem *dem, DM swarm, PetscBool restart)
{
  PetscFunctionBeginUser;
  dem->swarm = swarm;
  PetscCall(Rebuild(dem, PETSC_TRUE));
  if (restart) PetscFunctionReturn(0);
  PetscCall(PhaseBegin(dem->log, PHASE_CONTACT));
  PetscCall(DemContactForces(dem));
  PetscCall(PhaseEnd(dem->log, PHASE_CONTACT));
  PetscFunctionReturn(0);
}

PetscErrorCode DemStep(Dem *dem)
{
  PetscBool local[2], any[2]; // a rebuild is needed; a velocity or spin is not a number

  PetscFunctionBeginUser;
  PetscCall(PhaseBegin(dem->log, PHASE_INTEGRATE));
  PetscCall(ParticlesKickDrift(dem, &local[0]));
  PetscCall(PhaseEnd(dem->log, PHASE_INTEGRATE));

  PetscCall(PhaseBegin(dem->log, PHASE_NEIGHBOUR));
  local[1] = dem->stats.nonfinite;
  PetscCallMPI(MPI_Allreduce(local, any, 2, MPIU_BOOL, MPI_LOR, PetscObjectComm((PetscObject)dem->swarm)));
  PetscCall(PhaseEnd(dem->log, PHASE_NEIGHBOUR));
  if (any[1]) {
    // Nothing after a NaN is meaningful, and migration cannot place a particle at NaN: stop the step here and let
    // the guards report the state as it is.
    dem->stats.halted = PETSC_TRUE;
    PetscFunctionReturn(0);
  }
  dem->steps_since_rebuild++;
  if (any[0]) {
    dem->rebuild_interval = dem->steps_since_rebuild; // the adaptive skin's time scale (neighbour.cpp)
    PetscCall(Rebuild(dem, PETSC_FALSE));
  } else {
    PetscCall(PhaseBegin(dem->log, PHASE_GHOSTS));
    PetscCall(ParticlesPackBodies(dem));
    PetscCall(ParticlesGhostsUpdate(dem));
    PetscCall(PhaseEnd(dem->log, PHASE_GHOSTS));
  }

  PetscCall(PhaseBegin(dem->log, PHASE_CONTACT));
  PetscCall(DemContactForces(dem));
  PetscCall(PhaseEnd(dem->log, PHASE_CONTACT));

  PetscCall(PhaseBegin(dem->log, PHASE_INTEGRATE));
  PetscCall(ParticlesKick(dem));
  PetscCall(PhaseEnd(dem->log, PHASE_INTEGRATE));
  PetscFunctionReturn(0);
}

PetscErrorCode DemDestroy(Dem **dem)
{
  PetscFunctionBeginUser;
  if (!*dem) PetscFunctionReturn(0);
  PetscCall(ParticleSystemFinalize(*dem));
  delete *dem;
  *dem = nullptr;
  PetscFunctionReturn(0);
}

const DemParams &DemGetParams(const Dem *dem)
{
  return dem->par;
}
const ParticleProps &DemGetProps(const Dem *dem)
{
  return *dem->props;
}
const Domain &DemGetDomain(const Dem *dem)
{
  return *dem->dom;
}
DM DemGetSwarm(const Dem *dem)
{
  return dem->swarm;
}
DemStats *DemGetStats(Dem *dem)
{
  return &dem->stats;
}
const DemStats &DemGetStats(const Dem *dem)
{
  return dem->stats;
}
PetscInt DemGhostCount(const Dem *dem)
{
  return dem->ghosts.n;
}
ParticleSystem *DemGetParticles(Dem *dem)
{
  return dem;
}

} // namespace fluidbed
