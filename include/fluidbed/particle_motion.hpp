// The particles' motion as the modules above them see it: the state of a particle the force laws read (its body),
// the hook through which other forces (drag) act, the counters of the run and the particles the run-time guards
// point at. The motion itself (velocity Verlet, migration, ghosts; struct ParticleSystem) is the particles
// module's (fluidbed/particle_system.hpp, for the DEM's own modules); the contact forces that drive it sit a layer
// above (fluidbed/dem.hpp).
#pragma once

#include <petscdmswarm.h>

#include <vector>

#include "fluidbed/kernels/vec3.hpp"
#include "fluidbed/particles.hpp"

namespace fluidbed {

// Per-step particle state as the force laws see it: locals first, then ghosts. Eleven reals, sent to ghosts each
// step through a PetscSF. v and w are the predicted end-of-step velocities (kernels/verlet.hpp).
struct ParticleBody {
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

// The DEM's counters: the particles' motion keeps the rebuilds, the outlet and the losses; the contact stage the
// contacts and overlaps.
struct DemStats {
  PetscInt64   rebuilds        = 0;
  PetscInt64   storage_sorts   = 0; // rebuilds that also sorted the local particles' storage (ParticlesSortLocal)
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
typedef PetscErrorCode (*ParticleExternalForce)(void *ctx, DM swarm, const ParticleBody *bodies);

struct ParticleSystem;

// What the coupling sets and reads: the hook that adds the drag after the contact forces, the gravity factor (1 -
// rho_g / rho_p with buoyancy, Model B), the time step (s) and the particles' properties.
void                 ParticlesSetExternalForce(ParticleSystem *ps, ParticleExternalForce force, void *ctx);
void                 ParticlesSetBodyForceFactor(ParticleSystem *ps, PetscReal factor);
PetscReal            ParticlesTimeStep(const ParticleSystem *ps);
const ParticleProps &ParticlesGetProps(const ParticleSystem *ps);

// Diagnostics for the run-time guards, collective, every rank gets the result: a particle (its id, a partner's id
// or wall key, its position, the rank that owns it) where a figure is extreme.
struct ParticleSite {
  PetscReal   value = 0;
  PetscInt64  id = -1, partner = -1; // partner: a particle id, a wall key (WallKey) or -1
  PetscReal   x[3]  = {0, 0, 0};     // m
  PetscMPIInt rank  = -1;
  PetscInt64  count = 0; // how many particles share the fault (non-finite state)
};
// The site with the largest value over the ranks, given to every rank.
PetscErrorCode ParticleSiteReduce(MPI_Comm comm, ParticleSite *site);
// The particle that moves the most diameters in one step, |v| dt / d.
PetscErrorCode ParticlesLocateFastest(ParticleSystem *ps, ParticleSite *site);
// The particles whose position, velocity, spin, force or torque is not a finite number: the smallest id in site,
// their number in site->count, this rank's ids in ids.
PetscErrorCode ParticlesLocateNonFinite(ParticleSystem *ps, ParticleSite *site, std::vector<PetscInt64> *ids);

} // namespace fluidbed
