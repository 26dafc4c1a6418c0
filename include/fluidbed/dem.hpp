// Soft-sphere DEM on the DMSwarm (seed chapter 2): contact parameters, neighbour lists, ghost particles,
// migration and the velocity-Verlet step.
//
// Decomposition independence: each particle sums its contact forces itself (a full neighbour list, every pair
// evaluated from both sides by a kernel that is exactly antisymmetric), walls first and then partners in
// increasing id, so forces, and hence trajectories, are the same bit for bit on any number of ranks and do not
// depend on when neighbour lists are rebuilt. Periodic directions use the minimum-image separation.
#pragma once

#include <petscdmswarm.h>
#include <petscsf.h>

#include <vector>

#include "fluidbed/domain.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/particles.hpp"
#include "fluidbed/phases.hpp"
#include "fluidbed/kernels/contact_lsd.hpp"

namespace fluidbed {

// Contact parameters (-dem_*, -wall_*) and the time step they imply.
struct DemParams {
  PetscReal kn = 800.0, kt = -1.0, e = 0.9, mu = 0.3;                      // particle-particle; kt < 0: kt = kn
  PetscReal wall_kn = -1.0, wall_kt = -1.0, wall_e = -1.0, wall_mu = -1.0; // < 0: same as the particles
  PetscReal dt_factor    = 0.1;                                            // dt = dt_factor * t_cr
  PetscReal skin         = 0.1;                                            // Verlet skin in largest diameters
  PetscInt  max_contacts = 16;                                             // history slots per particle
  PetscBool pseudo2d     = PETSC_FALSE;                                    // 3D: motion confined to the x-y plane

  kernels::LsdModel pp, pw;                  // particle-particle and particle-wall contact models
  PetscReal         t_cr = 0, t_cr_wall = 0; // contact durations of the lightest pair / particle on a wall, s
  PetscReal         dt = 0;                  // time step, s
};

PetscErrorCode DemParamsSetFromOptions(MPI_Comm comm, const Domain &domain, const ParticleProps &props, DemParams *par);
PetscErrorCode DemParamsView(const DemParams &par, PetscViewer viewer);

// Per-step particle state as the contact kernels see it: locals first, then ghosts. Eleven reals, sent to
// ghosts each step through a PetscSF. v and w are the predicted end-of-step velocities (kernels/verlet.hpp).
struct ContactBody {
  kernels::Vec3 x, v, w;
  double        r, m;
};

// Verlet neighbour list: for each local particle, the bodies within r_i + r_j + skin, sorted by id.
struct NeighbourEntry {
  PetscInt  partner;   // body index
  PetscInt  slot;      // history slot of the contact, -1 when not in contact
  PetscReal sqrt_meff; // sqrt of the pair's effective mass, constant for the pair
  PetscInt  mirror;    // the partner's entry for this pair when the partner is local, else -1
};
// What one listed pair adds to its particle this step: the contact force, n x f_t (the torque is r n x f_t) and
// the dashpot impulse correction; zero when the pair is apart.
struct ContactContribution {
  kernels::Vec3 force, n_cross_ft, impulse;
};

struct NeighbourList {
  std::vector<PetscInt>       start; // nlocal + 1 offsets
  std::vector<NeighbourEntry> entries;
};

// Ghost particles of the 26 (3D) or 8 (2D) neighbouring subdomains, periodic images included. Built at each
// rebuild by sending copies through a BASIC ghost swarm with DMSwarmMigrate; refreshed every step through a
// PetscSF from the owners' bodies.
struct GhostExchange {
  DM                      swarm = nullptr;
  PetscSF                 sf    = nullptr;
  MPI_Datatype            body_type{};
  PetscInt                n = 0;
  std::vector<PetscInt64> id;    // ghost ids
  std::vector<PetscReal>  shift; // 3 per ghost: periodic image offset applied for binning
};

struct DemStats {
  PetscInt64 rebuilds        = 0;
  PetscInt64 outlet_removed  = 0; // particles that left through the outlet (global, cumulative)
  PetscInt64 contacts        = 0; // contacts counted from both sides during the last force evaluation (local)
  PetscReal  max_overlap_rel = 0; // largest overlap / diameter since the last reset (local)
};

// Hook for forces other than contacts and gravity (drag, for the coupled solver): adds to the swarm's force
// field, given the bodies with predicted velocities (locals first).
typedef PetscErrorCode (*DemExternalForce)(void *ctx, DM swarm, const ContactBody *bodies);

struct Dem {
  DemParams            par;
  const Domain        *dom   = nullptr;
  const ParticleGrid  *pgrid = nullptr;
  const ParticleProps *props = nullptr;
  PhaseLog            *log   = nullptr;
  DM                   swarm = nullptr;

  PetscReal                        halo              = 0;   // ghost layer width, 2 r_max + skin (m)
  PetscReal                        skin              = 0;   // m
  PetscReal                        body_force_factor = 1.0; // gravity scale: 1 - rho_g / rho_p with buoyancy (Model B)
  std::vector<ContactBody>         bodies;
  std::vector<PetscInt64>          body_id;
  std::vector<PetscReal>           x_ref;     // positions at the last rebuild, 3 per local particle
  std::vector<PetscReal>           impulse;   // dashpot impulse corrections of this step, 3 per local particle (N s)
  std::vector<unsigned char>       wall_mask; // bit f set: the particle holds a history slot for wall f
  NeighbourList                    nl;
  std::vector<ContactContribution> contributions;       // per neighbour entry, this step
  std::vector<unsigned char>       contribution_active; // the entry's contribution is set (the pair touched)
  GhostExchange                    ghosts;
  DemStats                         stats;
  DemExternalForce                 external     = nullptr;
  void                            *external_ctx = nullptr;
};

PetscErrorCode DemCreate(MPI_Comm comm, const Domain &domain, const ParticleGrid &pgrid, const ParticleProps &props, PhaseLog *log,
                         Dem **dem);
// Creates the swarm (ParticlesCreate) with the contact history sized by -dem_max_contacts.
PetscErrorCode DemCreateSwarm(Dem *dem, DM *swarm);
// Initial migration, ghosts, neighbour lists and forces; call after insertion. After a restart the forces of the
// checkpoint are kept (recomputing them would advance the contact histories), so the run continues bit for bit.
PetscErrorCode DemSetUp(Dem *dem, DM swarm, PetscBool restart);
// One velocity-Verlet step of length par.dt.
PetscErrorCode DemStep(Dem *dem);
// Migration, contact-history sync, ghosts and neighbour lists now (as at a restart); the forces are unchanged.
PetscErrorCode DemRebuild(Dem *dem);
PetscErrorCode DemDestroy(Dem **dem);

// Pieces of the step (src/particles, src/contact), exposed for tests and the coupled solver.
PetscErrorCode DemMigrate(Dem *dem);
PetscErrorCode DemSortLocal(Dem *dem);                                         // orders the local particles' storage by neighbour bin
PetscErrorCode ParticlesPermute(DM swarm, const std::vector<PetscInt> &order); // new[k] = old[order[k]], every field
PetscErrorCode DemPackBodies(Dem *dem);
PetscErrorCode DemGhostsBuild(Dem *dem);
PetscErrorCode DemGhostsUpdate(Dem *dem);
PetscErrorCode DemGhostsDestroy(GhostExchange *gx);
PetscErrorCode DemNeighbourBuild(Dem *dem);
PetscErrorCode DemContactForces(Dem *dem);
// Between rebuilds only the smaller-id side of a local pair keeps its history current; this copies it
// (negated) to the partner. Called before particles migrate and before a checkpoint.
PetscErrorCode DemSyncPairHistory(Dem *dem);
PetscErrorCode DemKickDrift(Dem *dem, PetscBool *need_rebuild);
PetscErrorCode DemKick(Dem *dem);

} // namespace fluidbed
