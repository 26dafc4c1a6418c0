// The DEM step: kick-drift, (rebuild: migrate, ghosts, lists), ghost refresh, contact forces, kick.
#include "dem_impl.hpp"

namespace fluidbed {

namespace {

PetscErrorCode Rebuild(Dem *dem)
{
  PetscFunctionBeginUser;
  PetscCall(PhaseBegin(dem->log, PHASE_MIGRATE));
  PetscCall(DemSyncPairHistory(dem));
  PetscCall(DemMigrate(dem));
  PetscCall(DemSortLocal(dem));
  PetscCall(PhaseEnd(dem->log, PHASE_MIGRATE));
  PetscCall(PhaseBegin(dem->log, PHASE_GHOSTS));
  PetscCall(DemPackBodies(dem));
  PetscCall(DemGhostsBuild(dem));
  PetscCall(PhaseEnd(dem->log, PHASE_GHOSTS));
  PetscCall(PhaseBegin(dem->log, PHASE_NEIGHBOUR));
  PetscCall(DemNeighbourBuild(dem));
  PetscCall(PhaseEnd(dem->log, PHASE_NEIGHBOUR));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode DemRebuild(Dem *dem)
{
  PetscFunctionBeginUser;
  PetscCall(Rebuild(dem));
  PetscFunctionReturn(0);
}

PetscErrorCode DemCreate(MPI_Comm comm, const Domain &dom, const ParticleGrid &pgrid, const ParticleProps &props, PhaseLog *log, Dem **dem)
{
  Dem *d = new Dem;

  PetscFunctionBeginUser;
  d->dom   = &dom;
  d->pgrid = &pgrid;
  d->props = &props;
  d->log   = log;
  PetscCall(DemParamsSetFromOptions(comm, dom, props, &d->par));
  PetscCall(ContactModelGet(d->par.contact_model, &d->contact));
  d->skin = d->par.skin * props.d_max;
  d->halo = props.d_max + d->skin;
  for (int a = 0; a < dom.dim; ++a)
    PetscCheck(!dom.periodic[a] || dom.len[a] >= 2.0 * d->halo, comm, PETSC_ERR_USER_INPUT,
               "periodic length %.6g m along axis %d is shorter than two contact cutoffs (%.6g m): enlarge the domain", (double)dom.len[a],
               a, (double)(2.0 * d->halo));
  // Ghosts go to the neighbouring subdomains only (ghosts.cpp): a subdomain narrower than the ghost layer would let
  // a pair within the neighbour-list cutoff straddle it unseen, and its contact be missed.
  for (int a = 0; a < dom.dim; ++a)
    for (PetscInt r = 0; r < pgrid.procs[a] && pgrid.procs[a] > 1; ++r) {
      const PetscInt  cells = pgrid.start[a][(std::size_t)r + 1] - pgrid.start[a][(std::size_t)r];
      const PetscReal width = cells * pgrid.h[a];
      PetscCheck(
        width >= d->halo, comm, PETSC_ERR_USER_INPUT,
        "the subdomain of process %d of %d along %c is %.6g m wide (%d particle cells), narrower than the ghost layer d_max + skin "
        "= %.6g m: ghosts reach the neighbouring subdomains only, and contacts across it would be missed; use fewer ranks along %c "
        "(-pgrid_processors), larger particle cells (-pgrid_cell_diameters, -pgrid_ratio) or a smaller -dem_skin",
        (int)r, (int)pgrid.procs[a], "xyz"[a], (double)width, (int)cells, (double)d -> halo, "xyz"[a]);
    }
  PetscCallMPI(MPI_Type_contiguous((int)(sizeof(ContactBody) / sizeof(PetscReal)), MPIU_REAL, &d->ghosts.body_type));
  PetscCallMPI(MPI_Type_commit(&d->ghosts.body_type));
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
  PetscCall(Rebuild(dem));
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
  PetscCall(DemKickDrift(dem, &local[0]));
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
  if (any[0]) PetscCall(Rebuild(dem));
  else {
    PetscCall(PhaseBegin(dem->log, PHASE_GHOSTS));
    PetscCall(DemPackBodies(dem));
    PetscCall(DemGhostsUpdate(dem));
    PetscCall(PhaseEnd(dem->log, PHASE_GHOSTS));
  }

  PetscCall(PhaseBegin(dem->log, PHASE_CONTACT));
  PetscCall(DemContactForces(dem));
  PetscCall(PhaseEnd(dem->log, PHASE_CONTACT));

  PetscCall(PhaseBegin(dem->log, PHASE_INTEGRATE));
  PetscCall(DemKick(dem));
  PetscCall(PhaseEnd(dem->log, PHASE_INTEGRATE));
  PetscFunctionReturn(0);
}

PetscErrorCode DemDestroy(Dem **dem)
{
  PetscFunctionBeginUser;
  if (!*dem) PetscFunctionReturn(0);
  PetscCall(DemGhostsDestroy(&(*dem)->ghosts));
  PetscCallMPI(MPI_Type_free(&(*dem)->ghosts.body_type));
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
void DemSetExternalForce(Dem *dem, DemExternalForce force, void *ctx)
{
  dem->external     = force;
  dem->external_ctx = ctx;
}
void DemSetBodyForceFactor(Dem *dem, PetscReal factor)
{
  dem->body_force_factor = factor;
}

} // namespace fluidbed
