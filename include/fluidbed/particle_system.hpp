// The particles' motion, for the DEM's own modules (src/particles, src/contact) and their component tests only
// (tests/layout/test_layers.py keeps it so): the bodies of locals and ghosts, the ghost exchange, migration,
// storage order and the velocity-Verlet halves. The contact stage (src/contact/dem_impl.hpp) extends this state
// with its neighbour lists and puts the step together; the modules above see the particles through
// fluidbed/particle_motion.hpp and fluidbed/dem.hpp.
#pragma once

#include <petscsf.h>

#include <vector>

#include "fluidbed/domain.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/particle_motion.hpp"
#include "fluidbed/phases.hpp"

namespace fluidbed {

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

struct ParticleSystem {
  const Domain        *dom   = nullptr;
  const ParticleGrid  *pgrid = nullptr;
  const ParticleProps *props = nullptr;
  PhaseLog            *log   = nullptr;
  DM                   swarm = nullptr;

  PetscReal                 dt                = 0;           // time step, s
  PetscBool                 pseudo2d          = PETSC_FALSE; // 3D: motion confined to the x-y plane
  PetscReal                 halo              = 0;           // ghost layer width, 2 r_max + skin (m)
  PetscReal                 skin              = 0;           // Verlet skin, m
  PetscReal                 body_force_factor = 1.0;         // gravity scale: 1 - rho_g / rho_p with buoyancy (Model B)
  std::vector<ParticleBody> bodies;
  std::vector<PetscInt64>   body_id;
  std::vector<PetscReal>    x_ref;           // positions at the last rebuild, 3 per local particle
  std::vector<PetscReal>    x_move;          // how far each local particle may move before its lists are rebuilt (its skin share), m
  std::vector<PetscReal>    impulse;         // dashpot impulse corrections of this step, 3 per local particle (N s)
  std::vector<char>         permute_scratch; // ParticlesSortLocal's buffer, kept between sorts
  GhostExchange             ghosts;
  DemStats                  stats;
  ParticleExternalForce     external     = nullptr;
  void                     *external_ctx = nullptr;
};

// Fills in what the motion needs (time step dt, s; Verlet skin, m) and checks that the ghost layer fits the
// decomposition: periodic lengths of at least two ghost layers, and subdomains no narrower than one.
PetscErrorCode ParticleSystemSetUp(MPI_Comm comm, const Domain &domain, const ParticleGrid &pgrid, const ParticleProps &props,
                                   PhaseLog *log, PetscReal dt, PetscBool pseudo2d, PetscReal skin, ParticleSystem *ps);
// Releases the ghost exchange.
PetscErrorCode ParticleSystemFinalize(ParticleSystem *ps);

// Pieces of the step, exposed for the contact stage that orders them (src/contact/dem_step.cpp) and for tests.
PetscErrorCode ParticlesMigrate(ParticleSystem *ps);
PetscErrorCode ParticlesSortLocal(ParticleSystem *ps); // orders the local particles' storage by neighbour bin
// new[k] = old[order[k]], every field; scratch (may be null) holds one field's copy, and a buffer kept between calls
// spares the page faults of some 60 MB per sort for 100,000 particles with their contact histories.
PetscErrorCode ParticlesPermute(DM swarm, const std::vector<PetscInt> &order, std::vector<char> *scratch = nullptr);
PetscErrorCode ParticlesPackBodies(ParticleSystem *ps);
PetscErrorCode ParticlesGhostsBuild(ParticleSystem *ps);
PetscErrorCode ParticlesGhostsUpdate(ParticleSystem *ps);
PetscErrorCode ParticlesGhostsDestroy(GhostExchange *gx);
// The first half kick and the drift; *need_rebuild when a particle moved its share of the skin (x_move) since the last rebuild.
PetscErrorCode ParticlesKickDrift(ParticleSystem *ps, PetscBool *need_rebuild);
// The second half kick, with the forces, torques and dashpot impulse corrections of this step.
PetscErrorCode ParticlesKick(ParticleSystem *ps);

} // namespace fluidbed
