// Soft-sphere DEM on the DMSwarm (seed chapter 2): contact parameters, the particles' step, and what the other
// modules read or set of it. The DEM's own state (struct Dem: neighbour lists, ghosts, bodies) is private to the
// particles and contact sources (src/particles/dem_impl.hpp); other modules see it through the functions here.
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

struct Dem;

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

// What the other modules read or set of the DEM.
const DemParams     &DemGetParams(const Dem *dem);
const ParticleProps &DemGetProps(const Dem *dem);
const Domain        &DemGetDomain(const Dem *dem);
DM                   DemGetSwarm(const Dem *dem);
// The counters and maxima of the run (monitor rows and guards reset their maxima after reading them).
DemStats       *DemGetStats(Dem *dem);
const DemStats &DemGetStats(const Dem *dem);
PetscInt        DemGhostCount(const Dem *dem); // ghost particles on this rank
// The coupling's part: the hook that adds the drag after the contact forces, and the gravity factor (1 - rho_g /
// rho_p with buoyancy, Model B).
void DemSetExternalForce(Dem *dem, DemExternalForce force, void *ctx);
void DemSetBodyForceFactor(Dem *dem, PetscReal factor);

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
