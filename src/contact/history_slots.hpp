// The local particles' contact history slots in the swarm (particles.hpp), for the contact models and the
// neighbour lists: a slot is taken, zeroed, when a contact begins and freed, zeroed, when it ends. A history is the
// contact model's p.hs reals; the code here does not read them.
#pragma once

#include "fluidbed/particles.hpp"

namespace fluidbed {

inline PetscReal *SlotHistory(const ParticleArrays &p, PetscInt i, PetscInt s)
{
  return &p.chist[p.hs * (p.K * i + s)];
}
inline void HistoryCopy(PetscInt hs, const PetscReal *from, PetscReal *to)
{
  for (PetscInt c = 0; c < hs; ++c) to[c] = from[c];
}
inline void HistoryClear(PetscInt hs, PetscReal *h)
{
  for (PetscInt c = 0; c < hs; ++c) h[c] = 0.0;
}

// The error of a particle i with no free slot for a new contact with key: it names -dem_max_contacts.
PetscErrorCode HistorySlotsFull(const ParticleArrays &p, PetscInt i, PetscInt64 key);

// A free slot of particle i for a new contact with key (a partner's id or a wall key), its history zeroed. Inline, so
// that the force loops that call it keep their sums in registers.
inline PetscErrorCode HistorySlotTake(const ParticleArrays &p, PetscInt i, PetscInt64 key, PetscInt *slot)
{
  for (PetscInt s = 0; s < p.K; ++s)
    if (p.ckey[p.K * i + s] == kFreeSlot) {
      p.ckey[p.K * i + s] = key;
      HistoryClear(p.hs, SlotHistory(p, i, s));
      *slot = s;
      return 0;
    }
  return HistorySlotsFull(p, i, key);
}
inline void HistorySlotFree(const ParticleArrays &p, PetscInt i, PetscInt s)
{
  p.ckey[p.K * i + s] = kFreeSlot;
  HistoryClear(p.hs, SlotHistory(p, i, s));
}

} // namespace fluidbed
