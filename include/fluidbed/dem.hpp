// Soft-sphere DEM on the DMSwarm (seed chapter 2): the contact stage on top of the particles' motion. Contact
// parameters, the DEM step (velocity Verlet of src/particles around the contact forces of src/contact), and what the
// modules above read of it. The DEM's own state (struct Dem: the particles' motion, the neighbour lists, the
// contact model) is private to the contact sources (src/contact/dem_impl.hpp); other modules see it through the
// functions here and, for the particles' part (what the coupling sets), fluidbed/particle_motion.hpp.
//
// Decomposition independence: each particle sums its contact forces itself (a full neighbour list; a pair of local
// particles is evaluated once, from the smaller id, and the partner takes the negated force, which is what its own
// evaluation would give since the kernel is exactly antisymmetric; a pair with a ghost is evaluated on each side),
// walls first and then partners in increasing id, so forces, and hence trajectories, are the same bit for bit on
// any number of ranks and do not depend on when neighbour lists are rebuilt. Periodic directions use the
// minimum-image separation.
#pragma once

#include <petscdmswarm.h>

#include "fluidbed/contact_model.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/particle_motion.hpp"
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
  PetscReal dt_factor     = 0.1;                                           // dt = dt_factor * t_cr
  PetscReal skin          = 0.1;                                           // Verlet skin in largest diameters (the largest)
  PetscBool skin_adaptive = PETSC_FALSE; // a particle's share of the skin from its speed and the last rebuild interval
  PetscReal skin_min      = 0.1;         // adaptive skin: the skin of two slow particles, largest diameters
  PetscInt  sort_interval = 0;           // rebuilds between storage sorts; 0: automatic
  PetscInt  max_contacts  = 16;          // history slots per particle
  PetscBool pseudo2d      = PETSC_FALSE; // 3D: motion confined to the x-y plane

  kernels::LsdModel pp, pw;                  // particle-particle and particle-wall contact models
  PetscReal         t_cr = 0, t_cr_wall = 0; // contact durations of the lightest pair / particle on a wall, s
  PetscReal         dt = 0;                  // time step, s
};

PetscErrorCode DemParamsSetFromOptions(MPI_Comm comm, const Domain &domain, const ParticleProps &props, DemParams *par);
PetscErrorCode DemParamsView(const DemParams &par, PetscViewer viewer);

struct Dem;

PetscErrorCode DemCreate(MPI_Comm comm, const Domain &domain, const ParticleGrid &pgrid, const ParticleProps &props, PhaseLog *log,
                         Dem **dem);
// Creates the swarm (ParticlesCreate) with -dem_max_contacts history slots of the contact model's size.
PetscErrorCode DemCreateSwarm(Dem *dem, DM *swarm);
// Initial migration, ghosts, neighbour lists and forces; call after insertion. After a restart the forces of the
// checkpoint are kept (recomputing them would advance the contact histories), so the run continues bit for bit.
PetscErrorCode DemSetUp(Dem *dem, DM swarm, PetscBool restart);
// One velocity-Verlet step of length DemParams::dt.
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
// The particles' motion under the contact stage (what the coupling sets of it: particle_motion.hpp).
ParticleSystem *DemGetParticles(Dem *dem);

// Diagnostics for the run-time guards (src/contact/dem_diagnostics.cpp; those of the motion alone, such as the
// fastest particle, are in particle_motion.hpp), collective, every rank gets the result.
// The contact with the largest overlap / smaller diameter of the pair (this step's positions).
PetscErrorCode DemLocateMaxOverlap(Dem *dem, ParticleSite *site);
// Kinetic (with rotation) + gravitational (above the box's lowest point) + elastic contact energy, J.
PetscErrorCode DemMechanicalEnergy(Dem *dem, PetscReal *energy);

} // namespace fluidbed
