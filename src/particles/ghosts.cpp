// Ghost particles for contacts across rank boundaries and periodic faces.
//
// At each neighbour-list rebuild, every local particle within the halo width of a subdomain face, edge or corner
// is copied once per neighbouring subdomain (26 in 3D, 8 in 2D; periodic images carry their offset). The copies
// travel in a BASIC ghost swarm through DMSwarmMigrate, which sends each point to the rank in its DMSwarm_rank
// field. The received ghosts know their owner's rank and index, which defines a PetscSF that refreshes their
// state from the owners every step.
#include "fluidbed/particle_system.hpp"

#include <vector>

namespace fluidbed {

namespace {

constexpr const char *kGhostBody  = "ghost_body";  // 11 reals: ParticleBody
constexpr const char *kGhostId    = "ghost_id";    // PetscInt64
constexpr const char *kGhostOwner = "ghost_owner"; // 2 PetscInt: owner rank, owner local index
constexpr const char *kGhostShift = "ghost_shift"; // 3 reals: periodic image offset

PetscErrorCode GhostSwarmCreate(MPI_Comm comm, DM *gsw)
{
  PetscFunctionBeginUser;
  PetscCall(DMCreate(comm, gsw));
  PetscCall(PetscObjectSetName((PetscObject)*gsw, "ghost_particles"));
  PetscCall(DMSetType(*gsw, DMSWARM));
  PetscCall(DMSwarmSetType(*gsw, DMSWARM_BASIC));
  PetscCall(DMSwarmRegisterPetscDatatypeField(*gsw, kGhostBody, (PetscInt)(sizeof(ParticleBody) / sizeof(PetscReal)), PETSC_REAL));
  PetscCall(DMSwarmRegisterPetscDatatypeField(*gsw, kGhostId, 1, PETSC_INT64));
  PetscCall(DMSwarmRegisterPetscDatatypeField(*gsw, kGhostOwner, 2, PETSC_INT));
  PetscCall(DMSwarmRegisterPetscDatatypeField(*gsw, kGhostShift, 3, PETSC_REAL));
  PetscCall(DMSwarmFinalizeFieldRegister(*gsw));
  PetscCall(DMSwarmSetLocalSizes(*gsw, 0, 256));
  PetscFunctionReturn(0);
}

struct GhostCopy {
  PetscMPIInt rank;
  PetscInt    index;
  PetscReal   shift[3];
};

} // namespace

PetscErrorCode ParticlesGhostsBuild(ParticleSystem *ps)
{
  static_assert(sizeof(ParticleBody) == 11 * sizeof(PetscReal), "ParticleBody must be 11 packed reals for the ghost PetscSF");
  GhostExchange         &gx   = ps->ghosts;
  const Domain          &dom  = *ps->dom;
  const ParticleGrid    &pg   = *ps->pgrid;
  MPI_Comm               comm = PetscObjectComm((PetscObject)ps->swarm);
  const int              dim  = (int)dom.dim;
  const PetscReal        h    = ps->halo;
  PetscMPIInt            rank;
  PetscInt               nlocal;
  std::vector<GhostCopy> copies;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(DMSwarmGetLocalSize(ps->swarm, &nlocal));
  if (!gx.swarm) PetscCall(GhostSwarmCreate(comm, &gx.swarm));
  PetscCall(PetscSFDestroy(&gx.sf));

  // Which neighbouring subdomains need each particle.
  for (PetscInt i = 0; i < nlocal; ++i) {
    const ParticleBody &b    = ps->bodies[(std::size_t)i];
    const PetscReal     x[3] = {b.x.x, b.x.y, b.x.z};
    bool                near_lo[3], near_hi[3];
    for (int a = 0; a < 3; ++a) {
      near_lo[a] = a < dim && x[a] - pg.sub_lo[a] < h;
      near_hi[a] = a < dim && pg.sub_hi[a] - x[a] < h;
    }
    if (!(near_lo[0] || near_hi[0] || near_lo[1] || near_hi[1] || near_lo[2] || near_hi[2])) continue;
    const int zr = dim == 3 ? 1 : 0;
    for (int oz = -zr; oz <= zr; ++oz)
      for (int oy = -1; oy <= 1; ++oy)
        for (int ox = -1; ox <= 1; ++ox) {
          const int off[3] = {ox, oy, oz};
          if (!ox && !oy && !oz) continue;
          GhostCopy c{0, i, {0, 0, 0}};
          PetscInt  q[3];
          bool      ok = true;
          for (int a = 0; a < 3 && ok; ++a) {
            q[a] = pg.proc[a] + off[a];
            if (!off[a]) continue;
            if ((off[a] < 0 && !near_lo[a]) || (off[a] > 0 && !near_hi[a])) ok = false;
            else if (q[a] < 0 || q[a] >= pg.procs[a]) {
              if (!dom.periodic[a]) ok = false;
              else {
                // wrap to the other end of the domain; the image sits on the far side of that subdomain
                q[a]       = q[a] < 0 ? pg.procs[a] - 1 : 0;
                c.shift[a] = off[a] < 0 ? dom.len[a] : -dom.len[a];
              }
            }
          }
          if (!ok) continue;
          c.rank = pg.RankAt(q);
          copies.push_back(c);
        }
  }

  // Send the copies through the ghost swarm.
  {
    PetscInt      *dest, *owner;
    PetscReal     *body, *shift;
    PetscInt64    *gid;
    ParticleArrays p;
    PetscCall(DMSwarmSetLocalSizes(gx.swarm, (PetscInt)copies.size(), 256));
    PetscCall(ParticleArraysGet(ps->swarm, &p));
    PetscCall(DMSwarmGetField(gx.swarm, DMSwarmField_rank, NULL, NULL, (void **)&dest));
    PetscCall(DMSwarmGetField(gx.swarm, kGhostBody, NULL, NULL, (void **)&body));
    PetscCall(DMSwarmGetField(gx.swarm, kGhostId, NULL, NULL, (void **)&gid));
    PetscCall(DMSwarmGetField(gx.swarm, kGhostOwner, NULL, NULL, (void **)&owner));
    PetscCall(DMSwarmGetField(gx.swarm, kGhostShift, NULL, NULL, (void **)&shift));
    for (std::size_t k = 0; k < copies.size(); ++k) {
      const GhostCopy &c = copies[k];
      dest[k]            = c.rank;
      gid[k]             = p.id[c.index];
      owner[2 * k]       = rank;
      owner[2 * k + 1]   = c.index;
      for (int a = 0; a < 3; ++a) shift[3 * k + a] = c.shift[a];
      const PetscReal *src = reinterpret_cast<const PetscReal *>(&ps->bodies[(std::size_t)c.index]);
      for (int s = 0; s < 11; ++s) body[11 * k + s] = src[s];
    }
    PetscCall(DMSwarmRestoreField(gx.swarm, kGhostShift, NULL, NULL, (void **)&shift));
    PetscCall(DMSwarmRestoreField(gx.swarm, kGhostOwner, NULL, NULL, (void **)&owner));
    PetscCall(DMSwarmRestoreField(gx.swarm, kGhostId, NULL, NULL, (void **)&gid));
    PetscCall(DMSwarmRestoreField(gx.swarm, kGhostBody, NULL, NULL, (void **)&body));
    PetscCall(DMSwarmRestoreField(gx.swarm, DMSwarmField_rank, NULL, NULL, (void **)&dest));
    PetscCall(ParticleArraysRestore(ps->swarm, &p));
  }
  PetscCall(DMSwarmMigrate(gx.swarm, PETSC_TRUE));

  // Received ghosts: append their bodies, keep ids and offsets, and point the SF at their owners.
  {
    PetscInt    *owner;
    PetscReal   *body, *shift;
    PetscInt64  *gid;
    PetscSFNode *remote;
    PetscCall(DMSwarmGetLocalSize(gx.swarm, &gx.n));
    ps->bodies.resize((std::size_t)(nlocal + gx.n));
    gx.id.resize((std::size_t)gx.n);
    gx.shift.resize(3 * (std::size_t)gx.n);
    PetscCall(PetscMalloc1(gx.n, &remote));
    PetscCall(DMSwarmGetField(gx.swarm, kGhostBody, NULL, NULL, (void **)&body));
    PetscCall(DMSwarmGetField(gx.swarm, kGhostId, NULL, NULL, (void **)&gid));
    PetscCall(DMSwarmGetField(gx.swarm, kGhostOwner, NULL, NULL, (void **)&owner));
    PetscCall(DMSwarmGetField(gx.swarm, kGhostShift, NULL, NULL, (void **)&shift));
    for (PetscInt g = 0; g < gx.n; ++g) {
      PetscReal *dst = reinterpret_cast<PetscReal *>(&ps->bodies[(std::size_t)(nlocal + g)]);
      for (int s = 0; s < 11; ++s) dst[s] = body[11 * g + s];
      gx.id[(std::size_t)g] = gid[g];
      for (int a = 0; a < 3; ++a) gx.shift[3 * (std::size_t)g + a] = shift[3 * g + a];
      remote[g].rank  = owner[2 * g];
      remote[g].index = owner[2 * g + 1];
    }
    PetscCall(DMSwarmRestoreField(gx.swarm, kGhostShift, NULL, NULL, (void **)&shift));
    PetscCall(DMSwarmRestoreField(gx.swarm, kGhostOwner, NULL, NULL, (void **)&owner));
    PetscCall(DMSwarmRestoreField(gx.swarm, kGhostId, NULL, NULL, (void **)&gid));
    PetscCall(DMSwarmRestoreField(gx.swarm, kGhostBody, NULL, NULL, (void **)&body));
    PetscCall(PetscSFCreate(comm, &gx.sf));
    PetscCall(PetscSFSetGraph(gx.sf, nlocal, gx.n, NULL, PETSC_OWN_POINTER, remote, PETSC_OWN_POINTER));
    PetscCall(PetscSFSetUp(gx.sf));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesGhostsUpdate(ParticleSystem *ps)
{
  GhostExchange &gx     = ps->ghosts;
  const PetscInt nlocal = (PetscInt)ps->bodies.size() - gx.n;

  PetscFunctionBeginUser;
  if (!gx.sf) PetscFunctionReturn(0);
  ParticleBody *all = ps->bodies.data();
  PetscCall(PetscSFBcastBegin(gx.sf, gx.body_type, all, all + nlocal, MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(gx.sf, gx.body_type, all, all + nlocal, MPI_REPLACE));
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesGhostsDestroy(GhostExchange *gx)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSFDestroy(&gx->sf));
  PetscCall(DMDestroy(&gx->swarm));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
