// Spatial ordering of the local particles. After migration new arrivals sit at the end of the swarm and the
// rest in whatever order earlier migrations left; sorting the storage by neighbour bin at each rebuild keeps a
// particle's neighbours close in memory, which the contact loop (dominated by loads of the partners' state)
// needs once the bodies no longer fit in cache. Results do not depend on the order (dem.hpp).
#include "fluidbed/particle_system.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace fluidbed {

PetscErrorCode ParticlesPermute(DM sw, const std::vector<PetscInt> &order, std::vector<char> *scratch)
{
  std::vector<const char *> names = {DMSwarmPICField_coor, DMSwarmField_pid, DMSwarmField_rank, DMSwarmPICField_cellid};
  names.insert(names.end(), std::begin(field::all), std::end(field::all));
  std::vector<char>  own;
  std::vector<char> &tmp = scratch ? *scratch : own;
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetLocalSize(sw, &n));
  PetscCheck((PetscInt)order.size() == n, PETSC_COMM_SELF, PETSC_ERR_PLIB, "permutation of %d entries for %d particles", (int)order.size(),
             (int)n);
  for (const char *name : names) {
    PetscInt      bs;
    PetscDataType type;
    size_t        tsize;
    char         *data;
    PetscCall(DMSwarmGetField(sw, name, &bs, &type, (void **)&data));
    PetscCall(PetscDataTypeGetSize(type, &tsize));
    const size_t esize = (size_t)bs * tsize;
    tmp.resize(esize * (size_t)n);
    for (PetscInt k = 0; k < n; ++k) std::memcpy(&tmp[esize * (size_t)k], &data[esize * (size_t)order[(std::size_t)k]], esize);
    std::memcpy(data, tmp.data(), esize * (size_t)n);
    PetscCall(DMSwarmRestoreField(sw, name, &bs, &type, (void **)&data));
  }
  PetscFunctionReturn(0);
}

namespace {
// Interleaves the bits of three bin coordinates (Morton order): bins close in any direction get close keys.
std::uint64_t MortonKey(std::uint64_t x, std::uint64_t y, std::uint64_t z)
{
  std::uint64_t key = 0;
  for (int b = 0; b < 21; ++b) key |= ((x >> b) & 1u) << (3 * b) | ((y >> b) & 1u) << (3 * b + 1) | ((z >> b) & 1u) << (3 * b + 2);
  return key;
}
} // namespace

PetscErrorCode ParticlesSortLocal(ParticleSystem *ps)
{
  const ParticleGrid                             &pg  = *ps->pgrid;
  const PetscReal                                 bin = ps->props->d_max + ps->skin;
  ParticleArrays                                  p;
  PetscInt                                        nb[3];
  std::vector<std::pair<std::uint64_t, PetscInt>> key;
  std::vector<PetscInt>                           order;

  PetscFunctionBeginUser;
  for (int a = 0; a < 3; ++a) nb[a] = a < ps->dom->dim ? PetscMax(1, (PetscInt)((pg.sub_hi[a] - pg.sub_lo[a]) / bin)) : 1;
  PetscCall(ParticleArraysGet(ps->swarm, &p));
  key.resize((std::size_t)p.n);
  for (PetscInt i = 0; i < p.n; ++i) {
    PetscInt c[3] = {0, 0, 0};
    for (PetscInt a = 0; a < p.dim; ++a) {
      const PetscReal w = (pg.sub_hi[a] - pg.sub_lo[a]) / nb[a];
      c[a]              = PetscMin(PetscMax((PetscInt)((p.x[p.dim * i + a] - pg.sub_lo[a]) / w), 0), nb[a] - 1);
    }
    key[(std::size_t)i] = {MortonKey((std::uint64_t)c[0], (std::uint64_t)c[1], (std::uint64_t)c[2]), i};
  }
  PetscCall(ParticleArraysRestore(ps->swarm, &p));
  std::sort(key.begin(), key.end()); // ties broken by the old index: deterministic
  order.resize(key.size());
  for (std::size_t k = 0; k < key.size(); ++k) order[k] = key[k].second;
  PetscCall(ParticlesPermute(ps->swarm, order, &ps->permute_scratch));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
