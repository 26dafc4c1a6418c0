// The particles' motion: its set-up (the ghost layer against the decomposition) and what the coupling sets and reads.
#include "fluidbed/particle_system.hpp"

namespace fluidbed {

PetscErrorCode ParticleSystemSetUp(MPI_Comm comm, const Domain &dom, const ParticleGrid &pgrid, const ParticleProps &props, PhaseLog *log,
                                   PetscReal dt, PetscBool pseudo2d, PetscReal skin, ParticleSystem *ps)
{
  PetscFunctionBeginUser;
  ps->dom      = &dom;
  ps->pgrid    = &pgrid;
  ps->props    = &props;
  ps->log      = log;
  ps->dt       = dt;
  ps->pseudo2d = pseudo2d;
  ps->skin     = skin;
  ps->halo     = props.d_max + skin;
  for (int a = 0; a < dom.dim; ++a)
    PetscCheck(!dom.periodic[a] || dom.len[a] >= 2.0 * ps->halo, comm, PETSC_ERR_USER_INPUT,
               "periodic length %.6g m along axis %d is shorter than two contact cutoffs (%.6g m): enlarge the domain", (double)dom.len[a],
               a, (double)(2.0 * ps->halo));
  // Ghosts go to the neighbouring subdomains only (ghosts.cpp): a subdomain narrower than the ghost layer would let
  // a pair within the neighbour-list cutoff straddle it unseen, and its contact be missed.
  for (int a = 0; a < dom.dim; ++a)
    for (PetscInt r = 0; r < pgrid.procs[a] && pgrid.procs[a] > 1; ++r) {
      const PetscInt  cells = pgrid.start[a][(std::size_t)r + 1] - pgrid.start[a][(std::size_t)r];
      const PetscReal width = cells * pgrid.h[a];
      PetscCheck(
        width >= ps->halo, comm, PETSC_ERR_USER_INPUT,
        "the subdomain of process %d of %d along %c is %.6g m wide (%d particle cells), narrower than the ghost layer d_max + skin "
        "= %.6g m: ghosts reach the neighbouring subdomains only, and contacts across it would be missed; use fewer ranks along %c "
        "(-pgrid_processors), larger particle cells (-pgrid_cell_diameters, -pgrid_ratio) or a smaller -dem_skin",
        (int)r, (int)pgrid.procs[a], "xyz"[a], (double)width, (int)cells, (double)ps -> halo, "xyz"[a]);
    }
  PetscCallMPI(MPI_Type_contiguous((int)(sizeof(ParticleBody) / sizeof(PetscReal)), MPIU_REAL, &ps->ghosts.body_type));
  PetscCallMPI(MPI_Type_commit(&ps->ghosts.body_type));
  PetscFunctionReturn(0);
}

PetscErrorCode ParticleSystemFinalize(ParticleSystem *ps)
{
  PetscFunctionBeginUser;
  PetscCall(ParticlesGhostsDestroy(&ps->ghosts));
  PetscCallMPI(MPI_Type_free(&ps->ghosts.body_type));
  PetscFunctionReturn(0);
}

void ParticlesSetExternalForce(ParticleSystem *ps, ParticleExternalForce force, void *ctx)
{
  ps->external     = force;
  ps->external_ctx = ctx;
}
void ParticlesSetBodyForceFactor(ParticleSystem *ps, PetscReal factor)
{
  ps->body_force_factor = factor;
}
PetscReal ParticlesTimeStep(const ParticleSystem *ps)
{
  return ps->dt;
}
const ParticleProps &ParticlesGetProps(const ParticleSystem *ps)
{
  return *ps->props;
}

} // namespace fluidbed
