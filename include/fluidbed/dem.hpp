// Soft-sphere DEM on the DMSwarm (seed chapter 2): contact parameters, neighbour lists, ghost particles,
// migration and the velocity-Verlet step.
//
// Decomposition independence: each particle sums its contact forces itself (a full neighbour list; a pair of local
// particles is evaluated once, from the smaller id, and the partner takes the negated force, which is what its own
// evaluation would give since the kernel is exactly antisymmetric; a pair with a ghost is evaluated on each side),
// walls first and then partners in increasing id, so forces, and hence trajectories, are the same bit for bit on
// any number of ranks and do not depend on when neighbour lists are rebuilt. Periodic directions use the
// minimum-image separation.
#pragma once

#include <petscdmswarm.h>
#include <petscsf.h>

#include <vector>

#include "fluidbed/contact_model.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/particles.hpp"
#include "fluidbed/phases.hpp"
#include "fluidbed/kernels/contact_lsd.hpp"

namespace fluidbed {

// Contact parameters (-dem_*, -wall_*) and the time step they imply. k_n, k_t, e and mu are the parameters of the
// linear spring-dashpot (-dem_contact_model lsd).
struct DemParams {
  char      contact_model[64] = "lsd";                                     // -dem_contact_model
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

// A listed pair as the particle that evaluates it sees it: the smaller id of two local particles, or the local
// one of a pair with a ghost. Between syncs (DemSyncPairHistory) the pair's history in the list
// (NeighbourList::pair_hist) is the authoritative copy of that particle's history slot; the swarm's slots are
// brought up to date before particles migrate or are written.
struct ContactPair {
  PetscInt  partner;      // body index
  PetscInt  slot;         // the evaluating particle's history slot, -1 when not in contact
  PetscInt  partner_slot; // a local partner's slot for the pair (its copy from the last sync), else -1
  PetscInt  out;          // where the force loop leaves the pair's contribution (Dem::contributions)
  PetscReal sqrt_meff;    // sqrt of the pair's effective mass, constant for the pair
};
// What one listed pair adds to its particle this step: the contact force, n x f_t (the torque is r n x f_t) and
// the dashpot impulse correction, as seen from the evaluating particle; zero when the pair is apart.
struct ContactContribution {
  kernels::Vec3 force, n_cross_ft, impulse;
};

// A wall the particle may touch before the next rebuild (within r + skin of it at the rebuild, or holding a
// history slot for it); its history is kept in the list as a pair's (NeighbourList::wall_hist).
struct WallContact {
  PetscInt face;
  PetscInt slot; // the particle's history slot for the wall, -1 when not in contact
};

// Verlet neighbour list. Full: for each local particle, the bodies within r_i + r_j + skin sorted by id, each
// entry naming where its pair's contribution is left (2 out: the pair is evaluated by this particle, 2 out + 1: by
// the partner, and the contribution is mirrored). Half: the pairs each local particle evaluates, in the order of
// its entries. Walls: the walls each local particle may touch, in face order. The force loop evaluates the
// particles' pairs in storage order and sums each particle as soon as all its pairs are evaluated: after the
// pairs of particle i, the particles finish[finish_start[i]] .. finish[finish_start[i + 1] - 1]. Most
// contributions are read soon after they are written, so they share a ring of kContributionRing places, which
// stays in cache; the pairs whose contributions are read later than that have places of their own after it.
constexpr PetscInt kContributionRing = 8192; // a power of 2
struct NeighbourList {
  std::vector<PetscInt>    start;      // nlocal + 1 offsets into entries
  std::vector<PetscInt>    entries;    // 2 out + (1 if the partner evaluates the pair)
  std::vector<PetscInt>    pair_start; // nlocal + 1 offsets into pairs
  std::vector<ContactPair> pairs;
  std::vector<PetscInt>    wall_start; // nlocal + 1 offsets into walls
  std::vector<WallContact> walls;
  std::vector<PetscInt>    finish_start; // nlocal + 1 offsets into finish
  std::vector<PetscInt>    finish;
  PetscInt                 ncontrib = 0; // places for contributions: the ring, then those of their own
  // The histories of the listed contacts, the contact model's history_size reals per pair and per wall contact
  // (meaningful while its slot >= 0), in the order of pairs and walls.
  PetscInt               hs = 0;
  std::vector<PetscReal> pair_hist, wall_hist;
  PetscReal             *PairHistory(PetscInt q) { return &pair_hist[(std::size_t)(hs * q)]; }
  PetscReal             *WallHistory(PetscInt k) { return &wall_hist[(std::size_t)(hs * k)]; }
  const PetscReal       *PairHistory(PetscInt q) const { return &pair_hist[(std::size_t)(hs * q)]; }
  const PetscReal       *WallHistory(PetscInt k) const { return &wall_hist[(std::size_t)(hs * k)]; }
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

// What escaped a wall or was lost in migration: the run-time guards (src/guards) stop the run on it, so that no
// particle is ever lost without a word.
struct ParticleLoss {
  PetscInt64 count    = 0;            // particles removed because they crossed a wall or a migration dropped them (global)
  PetscInt64 first_id = -1;           // the first (smallest id) of those that crossed a wall, -1 if none
  PetscReal  first_x[3]{0, 0, 0};     // its position, m
  PetscBool  migration = PETSC_FALSE; // DMSwarmMigrate dropped particles (moved past a neighbouring rank)
};

struct DemStats {
  PetscInt64   rebuilds        = 0;
  PetscInt64   outlet_removed  = 0; // particles that left through the outlet (global, cumulative)
  PetscInt64   contacts        = 0; // contacts counted from both sides during the last force evaluation (local)
  PetscReal    max_overlap_rel = 0; // largest overlap / diameter since the last monitor row (local)
  ParticleLoss lost;
  // For the run-time guards: maxima since the last guard check (local), reset by the guards.
  PetscReal guard_overlap_rel = 0;           // largest overlap / smaller diameter of the pair
  PetscReal guard_step_rel    = 0;           // largest |v| dt / d, the distance moved in one step in diameters
  PetscBool nonfinite         = PETSC_FALSE; // a particle velocity or spin is NaN or inf (local until the step's reduction)
  PetscBool halted            = PETSC_FALSE; // the step stopped early (a non-finite state on some rank): guards must stop the run
};

// Hook for forces other than contacts and gravity (drag, for the coupled solver): adds to the swarm's force
// field, given the bodies with predicted velocities (locals first).
typedef PetscErrorCode (*DemExternalForce)(void *ctx, DM swarm, const ContactBody *bodies);

struct Dem {
  DemParams            par;
  ContactModel         contact; // the model -dem_contact_model names
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
  std::vector<PetscReal>           x_ref;   // positions at the last rebuild, 3 per local particle
  std::vector<PetscReal>           impulse; // dashpot impulse corrections of this step, 3 per local particle (N s)
  NeighbourList                    nl;
  std::vector<ContactContribution> contributions; // this step's, per pair (ContactPair::out); zero when the pair is apart
  GhostExchange                    ghosts;
  DemStats                         stats;
  DemExternalForce                 external     = nullptr;
  void                            *external_ctx = nullptr;
};

PetscErrorCode DemCreate(MPI_Comm comm, const Domain &domain, const ParticleGrid &pgrid, const ParticleProps &props, PhaseLog *log,
                         Dem **dem);
// Creates the swarm (ParticlesCreate) with -dem_max_contacts history slots of the contact model's size.
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
// The contact model's forces (ContactModel::forces), then the external forces (drag).
PetscErrorCode DemContactForces(Dem *dem);
// Between rebuilds a pair's history is kept in the neighbour list (nl.pair_hist) from the evaluating side; this stores
// it in that particle's swarm slot and (negated) in a local partner's. Called before particles migrate and before
// a checkpoint.
PetscErrorCode DemSyncPairHistory(Dem *dem);
PetscErrorCode DemKickDrift(Dem *dem, PetscBool *need_rebuild);
PetscErrorCode DemKick(Dem *dem);

// Diagnostics for the run-time guards (src/particles/dem_diagnostics.cpp), collective, every rank gets the result:
// a particle (its id, a partner's id or wall key, its position, the rank that owns it) where a figure is extreme.
struct ParticleSite {
  PetscReal   value = 0;
  PetscInt64  id = -1, partner = -1; // partner: a particle id, a wall key (WallKey) or -1
  PetscReal   x[3]  = {0, 0, 0};     // m
  PetscMPIInt rank  = -1;
  PetscInt64  count = 0; // how many particles share the fault (non-finite state)
};
// The contact with the largest overlap / smaller diameter of the pair (this step's positions).
PetscErrorCode DemLocateMaxOverlap(Dem *dem, ParticleSite *site);
// The particle that moves the most diameters in one step, |v| dt / d.
PetscErrorCode DemLocateFastest(Dem *dem, ParticleSite *site);
// The particles whose position, velocity, spin, force or torque is not a finite number: the smallest id in site,
// their number in site->count, this rank's ids in ids.
PetscErrorCode DemLocateNonFinite(Dem *dem, ParticleSite *site, std::vector<PetscInt64> *ids);
// Kinetic (with rotation) + gravitational (above the box's lowest point) + elastic contact energy, J.
PetscErrorCode DemMechanicalEnergy(Dem *dem, PetscReal *energy);

} // namespace fluidbed
