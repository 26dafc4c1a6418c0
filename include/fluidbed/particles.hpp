// Particles: material properties, the DMSwarm that holds them, and insertion.
//
// The swarm is a PIC DMSwarm whose cell DM is the particle grid's vertex DMDA. Every field a particle needs to
// continue after migration or restart travels with it, including its tangential contact history: for each of
// up to K contacts the partner's key (a particle id >= 0, a wall key < -1, or -1 for a free slot) and the
// contact's history, as many reals as the contact model keeps (contact_model.hpp; the linear spring-dashpot's:
// the tangential displacement xi_t (eq. 2.4), and the overlap and normal dashpot force of the previous step).
#pragma once

#include <petscdmswarm.h>

#include <string>
#include <vector>

#include "fluidbed/domain.hpp"
#include "fluidbed/grids.hpp"

namespace fluidbed {

struct ParticleProps {
  PetscReal d_min   = 1.0e-3; // m
  PetscReal d_max   = 1.0e-3; // m
  PetscReal density = 2500.0; // kg/m^3

  PetscReal Mass(PetscReal d) const { return density * (PETSC_PI / 6.0) * d * d * d; }
};

// -particle_diameter, -particle_diameter_min/max (uniform by number), -particle_density.
PetscErrorCode ParticlePropsSetFromOptions(MPI_Comm comm, const Domain &domain, ParticleProps *props);

namespace field {
constexpr const char *velocity     = "velocity";     // m/s, 3 components
constexpr const char *omega        = "omega";        // rad/s, 3 components
constexpr const char *force        = "force";        // N, 3 components: total force of the last step
constexpr const char *torque       = "torque";       // N m, 3 components
constexpr const char *diameter     = "diameter";     // m
constexpr const char *id           = "id";           // unique global id, PetscInt64
constexpr const char *contact_key  = "contact_key";  // K partner keys, PetscInt64
constexpr const char *contact_hist = "contact_hist"; // K histories of the contact model's history_size reals
constexpr const char *drag_coef    = "drag_coef";    // V_p K of the last gas step's linearised drag, N s/m (coupling)
constexpr const char *drag_ref     = "drag_ref";     // V_p K v_p at that step, N, 3 components (coupling)
constexpr const char *drag_cell    = "drag_cell";    // the coupling cell the particle was in at that step (coupling), PetscInt64

// Every field fluidbed registers, for code that must treat them all (storage reordering).
constexpr const char *all[] = {velocity, omega, force, torque, diameter, id, contact_key, contact_hist, drag_coef, drag_ref, drag_cell};
} // namespace field

constexpr PetscInt64 kFreeSlot = -1;
// Walls are keyed -2 - face so that they sort before every particle id.
inline PetscInt64 WallKey(int face)
{
  return -2 - face;
}

// Creates the PIC swarm on the particle grid's vertex DMDA with the fields above and no particles: max_contacts
// history slots per particle of history_size reals each.
PetscErrorCode ParticlesCreate(MPI_Comm comm, const Domain &domain, const ParticleGrid &pgrid, PetscInt max_contacts, PetscInt history_size,
                               DM *swarm);

// The local particles' field arrays, taken and given back together.
struct ParticleArrays {
  PetscInt    n = 0, dim = 3, K = 0, hs = 0; // K history slots per particle, hs reals per slot
  PetscReal  *x = nullptr;                   // dim components per particle (DMSwarmPIC_coor)
  PetscReal  *v = nullptr, *w = nullptr, *f = nullptr, *t = nullptr, *d = nullptr;
  PetscInt64 *id = nullptr, *ckey = nullptr;
  PetscReal  *chist = nullptr;                  // hs reals per slot
  PetscReal  *dcoef = nullptr, *dref = nullptr; // coupling: V_p K and V_p K v_p of the last gas step
  PetscInt64 *dcell = nullptr;                  // coupling: the cell of that step
};
PetscErrorCode ParticleArraysGet(DM swarm, ParticleArrays *a);
PetscErrorCode ParticleArraysRestore(DM swarm, ParticleArrays *a);

// Global particle count as a 64-bit number.
PetscErrorCode ParticlesGlobalCount(DM swarm, PetscInt64 *n);

// Options -insert_*: lattice, random, list or file; by count or settled bed height; seeded.
struct InsertionReport {
  PetscInt64  count                 = 0;
  PetscReal   solid_fraction_region = 0.0; // solid volume / region volume at insertion
  std::string file;                        // the CSV the particles were read from (-insert_type file), else empty
};
// The centres (x, y, z each) the insertion will place, where they are known before the grids exist: -insert_type
// file (read on every rank); *known false otherwise. For -pgrid_layout particles.
PetscErrorCode ParticlesInitialPositions(MPI_Comm comm, std::vector<PetscReal> *xyz, PetscBool *known);
PetscErrorCode ParticlesInsert(MPI_Comm comm, const Domain &domain, const ParticleGrid &pgrid, const ParticleProps &props, DM swarm,
                               InsertionReport *report);

} // namespace fluidbed
