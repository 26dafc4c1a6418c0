// The DEM's own state, private to the contact stage (src/contact) and the component tests of its pieces: the
// particles' motion (fluidbed/particle_system.hpp) extended with the contact model, the neighbour lists with the
// contacts' histories between rebuilds, and the pieces of the contact step.
#pragma once

#include "fluidbed/dem.hpp"
#include "fluidbed/particle_system.hpp"

#include <vector>

namespace fluidbed {

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

// A wall the particle may touch before the next rebuild (within r + 2 s of it at the rebuild, s its share of the
// skin, or holding a history slot for it); its history is kept in the list as a pair's (NeighbourList::wall_hist).
struct WallContact {
  PetscInt face;
  PetscInt slot; // the particle's history slot for the wall, -1 when not in contact
};

// Verlet neighbour list. Full: for each local particle, the bodies within r_i + r_j + s_i + s_j (s: the shares of
// the skin, neighbour.cpp) sorted by id, each entry naming where its pair's contribution is left (2 out: the pair is
// evaluated by this particle, 2 out + 1: by the partner, and the contribution is mirrored). Half: the pairs each
// local particle evaluates, in the order of its entries. Walls: the walls each local particle may touch, in face
// order. The force loop evaluates the particles' pairs in storage order and sums each particle as soon as all its
// pairs are evaluated: after the pairs of particle i, the particles finish[finish_start[i]] ..
// finish[finish_start[i + 1] - 1]. Most contributions are read soon after they are written, so they share a ring of
// kContributionRing places, which stays in cache; the pairs whose contributions are read later than that have places
// of their own after it.
// The force loop gathers the pairs in contact and evaluates them in SIMD lanes; it sums the particles whose pairs
// are all evaluated each time, at the latest once it has visited kLanePairsVisited pairs since the last time (and the
// pairs of the particle it is at): the ring allows for that delay.
constexpr PetscInt kContributionRing = 8192; // a power of 2
constexpr PetscInt kLanePairsVisited = 512;
struct NeighbourList {
  std::vector<PetscInt>    start;      // nlocal + 1 offsets into entries
  std::vector<PetscInt>    entries;    // 2 out + (1 if the partner evaluates the pair)
  std::vector<PetscInt>    pair_start; // nlocal + 1 offsets into pairs
  std::vector<ContactPair> pairs;
  std::vector<PetscInt>    wall_start; // nlocal + 1 offsets into walls
  std::vector<WallContact> walls;
  std::vector<PetscInt>    finish_start; // nlocal + 1 offsets into finish
  std::vector<PetscInt>    finish;
  PetscInt                 ncontrib  = 0; // places for contributions: the ring, then those of their own
  PetscInt                 max_pairs = 0; // the most pairs one particle holds in the half list
  // The histories of the listed contacts, the contact model's history_size reals per pair and per wall contact
  // (meaningful while its slot >= 0), in the order of pairs and walls.
  PetscInt               hs = 0;
  std::vector<PetscReal> pair_hist, wall_hist;
  PetscReal             *PairHistory(PetscInt q) { return &pair_hist[(std::size_t)(hs * q)]; }
  PetscReal             *WallHistory(PetscInt k) { return &wall_hist[(std::size_t)(hs * k)]; }
  const PetscReal       *PairHistory(PetscInt q) const { return &pair_hist[(std::size_t)(hs * q)]; }
  const PetscReal       *WallHistory(PetscInt k) const { return &wall_hist[(std::size_t)(hs * k)]; }
};

// The working arrays of a neighbour-list build (neighbour.cpp), kept between rebuilds: a rebuild then writes into
// memory it has used before instead of allocating, growing and faulting in some 50 MB for 100,000 particles.
struct NeighbourScratch {
  struct BinnedBody {
    PetscReal x, y, z, reach; // a body's binning position and its reach r + share
  };
  struct Candidate {
    PetscInt64 id;   // the partner's id
    PetscInt   near; // its place in the particle's unsorted partners
  };
  std::vector<kernels::Vec3>                 pos;   // binning positions (ghosts at their image)
  std::vector<PetscReal>                     share; // each body's share of its pairs' skin
  std::vector<PetscReal>                     mass;  // the bodies' masses, compact for the pairs' loop
  std::vector<PetscInt>                      bin_start, bin_body, body_bin;
  std::vector<BinnedBody>                    binned;                   // bodies in bin order
  std::vector<std::pair<PetscInt, PetscInt>> found_pairs;              // each pair within its cutoff once
  std::vector<PetscInt>                      near_start, near, mirror; // partners per local particle (CSR), the pair's other place
  std::vector<PetscInt>                      entry_of_near;            // the list entry of each place in near
  std::vector<PetscInt>                      partner;                  // per list entry: the partner's body index
  std::vector<PetscInt64>                    entry_id;                 // per list entry: the partner's id
  std::vector<Candidate>                     found;                    // one particle's partners, sorted by id
  std::vector<PetscInt>                      fill, ready;
  std::vector<PetscInt>                      pair_out; // per pair: its ContactPair::out, compact for the entries' remap
};

// The DEM: the particles' motion and, on top of it, the contact stage.
struct Dem : ParticleSystem {
  DemParams                        par;
  ContactModel                     contact; // the model -dem_contact_model names
  NeighbourList                    nl;
  NeighbourScratch                 nl_scratch;    // the build's working arrays (neighbour.cpp)
  std::vector<ContactContribution> contributions; // this step's, per pair (ContactPair::out); zero (or skipped) when the pair is apart
  std::vector<unsigned char>       touching;      // per place of contributions, when the sums skip pairs apart: 1 when written
  PetscReal                        contact_share       = 1; // share of the listed pairs in contact at the last force evaluation
  PetscInt                         rebuilds_since_sort = 0; // list rebuilds since the storage was last sorted
  PetscInt                         steps_since_rebuild = 0; // DEM steps since the lists were last built
  PetscInt                         rebuild_interval    = 0; // steps between the last two rebuilds the motion asked for; 0: none yet
};

// Pieces of the contact step (src/contact), exposed for tests and the coupled solver.
PetscErrorCode DemNeighbourBuild(Dem *dem);
// The contact model's forces (ContactModel::forces), then the external forces (drag).
PetscErrorCode DemContactForces(Dem *dem);
// Between rebuilds a pair's history is kept in the neighbour list (nl.pair_hist) from the evaluating side; this stores
// it in that particle's swarm slot and (negated) in a local partner's. Called before particles migrate and before
// a checkpoint.
PetscErrorCode DemSyncPairHistory(Dem *dem);

} // namespace fluidbed
