// Component test of the DEM's neighbour lists and ghosts on any number of ranks: after a few steps of the scene
// given by the options (and a rebuild), every rank's lists are compared with a brute-force search over all
// particles of all ranks (minimum image along periodic axes):
//   - each pair closer than r_i + r_j + s_i + s_j is listed, and no other (s: a particle's share of the skin, half
//     of -dem_skin, or with -dem_skin_adaptive its own between the halves of -dem_skin_min and -dem_skin, which must
//     differ between particles once they move): once when both particles are local to one
//     rank, and from each side when it is seen through a ghost (its own rank's ghost, or a periodic image), so
//     every ghost the lists need was there;
//   - each particle's full list holds exactly its brute-force partners;
//   - each wall within r + 2 s is in the particle's wall list, and a listed wall is either that near or still
//     holds a contact history.
// Prints one line per check and exits nonzero on the first failure (the test driver runs it on 1, 2 and 4 ranks).
#include "../../src/contact/dem_impl.hpp"
#include "component_common.hpp"
#include "dem_scene.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/kernels/periodic.hpp"
#include "fluidbed/particles.hpp"
#include "fluidbed/phases.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <vector>

using namespace fluidbed;
using component::AllGather;
using component::Check;

static const char help[] = "Neighbour lists and ghosts against a brute-force search (-steps N: DEM steps before the check)\n";

namespace {

struct Body {
  PetscInt64 id;
  PetscReal  x[3], r, share; // share: the particle's part of its pairs' skin (half of -dem_skin, or adaptive)
};

// Every rank's local bodies, on every rank.
PetscErrorCode GatherBodies(MPI_Comm comm, const Dem &dem, PetscInt nlocal, std::vector<Body> *all)
{
  std::vector<PetscReal> mine, flat;
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < nlocal; ++i) {
    const ParticleBody &b = dem.bodies[(std::size_t)i];
    mine.insert(mine.end(), {(PetscReal)dem.body_id[(std::size_t)i], b.x.x, b.x.y, b.x.z, b.r, dem.x_move[(std::size_t)i]});
  }
  PetscCall(AllGather(comm, MPIU_REAL, mine, &flat));
  all->clear();
  for (std::size_t k = 0; k < flat.size(); k += 6)
    all->push_back({(PetscInt64)flat[k], {flat[k + 1], flat[k + 2], flat[k + 3]}, flat[k + 4], flat[k + 5]});
  PetscFunctionReturn(0);
}

// Every rank's half lists, on every rank, as (a, b, kind) triples: kind 0 a local-local pair, 1 seen from a through
// a ghost.
PetscErrorCode GatherListedPairs(MPI_Comm comm, const Dem &dem, PetscInt nlocal, std::vector<PetscInt64> *triples)
{
  const NeighbourList    &nl = dem.nl;
  std::vector<PetscInt64> mine;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < nlocal; ++i)
    for (PetscInt q = nl.pair_start[(std::size_t)i]; q < nl.pair_start[(std::size_t)i + 1]; ++q) {
      const PetscInt j = nl.pairs[(std::size_t)q].partner;
      mine.insert(mine.end(), {dem.body_id[(std::size_t)i], dem.body_id[(std::size_t)j], j < nlocal ? 0 : 1});
    }
  PetscCall(AllGather(comm, MPIU_INT64, mine, triples));
  PetscFunctionReturn(0);
}

// The pairs (smaller id, larger id) of all bodies closer than cut(a, b), minimum image along periodic axes.
template <class Cut>
std::set<std::pair<PetscInt64, PetscInt64>> PairsWithin(const Domain &dom, const std::vector<Body> &all, Cut cut)
{
  std::set<std::pair<PetscInt64, PetscInt64>> pairs;
  for (std::size_t a = 0; a < all.size(); ++a)
    for (std::size_t b = a + 1; b < all.size(); ++b) {
      PetscReal d2 = 0;
      for (int k = 0; k < 3; ++k) {
        PetscReal d = all[b].x[k] - all[a].x[k];
        if (dom.periodic[k]) d = kernels::min_image(d, dom.len[k]);
        d2 += d * d;
      }
      const PetscReal c = cut(all[a], all[b]);
      if (d2 < c * c) pairs.insert({std::min(all[a].id, all[b].id), std::max(all[a].id, all[b].id)});
    }
  return pairs;
}

// Between rebuilds, after each step: no particle has moved more than its share of the skin since the lists were
// built (else it could touch a partner its lists do not hold), every touching pair of particles (closer than
// r_i + r_j) is in the lists, and every wall a particle touches is in its wall list.
PetscErrorCode CheckContactsListed(MPI_Comm comm, const Domain &dom, Dem &dem, long long *missing)
{
  const PetscInt          nlocal = (PetscInt)dem.bodies.size() - dem.ghosts.n;
  const NeighbourList    &nl     = dem.nl;
  std::vector<Body>       all;
  std::vector<PetscInt64> triples;

  PetscFunctionBeginUser;
  PetscCall(GatherBodies(comm, dem, nlocal, &all));
  PetscCall(GatherListedPairs(comm, dem, nlocal, &triples));
  std::set<std::pair<PetscInt64, PetscInt64>> listed;
  for (std::size_t k = 0; k < triples.size(); k += 3)
    listed.insert({std::min(triples[k], triples[k + 1]), std::max(triples[k], triples[k + 1])});
  long long local[2] = {0, 0}, global[2]; // walls touched but not listed; particles beyond their share
  for (PetscInt i = 0; i < nlocal; ++i) {
    const ParticleBody &b = dem.bodies[(std::size_t)i];
    for (PetscInt f = 0; f < 2 * dom.dim; ++f) {
      const int a = (int)f / 2;
      if (dom.periodic[a]) continue;
      const PetscReal xa  = (&b.x.x)[a];
      const PetscReal gap = (f % 2) ? dom.hi[a] - xa : xa - dom.lo[a];
      bool            in  = false;
      for (PetscInt k = nl.wall_start[(std::size_t)i]; k < nl.wall_start[(std::size_t)i + 1]; ++k)
        in = in || nl.walls[(std::size_t)k].face == f;
      if (gap < b.r && !in) ++local[0];
    }
  }
  // The invariant that keeps them listed: no particle has moved more than its share since the lists were built.
  for (PetscInt i = 0; i < nlocal; ++i) {
    const PetscReal *xb = &dem.bodies[(std::size_t)i].x.x;
    PetscReal        d2 = 0;
    for (int a = 0; a < 3; ++a) {
      const PetscReal d = kernels::min_image(xb[a] - dem.x_ref[3 * (std::size_t)i + a], dom.periodic[a] ? dom.len[a] : 0.0);
      d2 += d * d;
    }
    if (d2 > dem.x_move[(std::size_t)i] * dem.x_move[(std::size_t)i]) ++local[1];
  }
  long long pairs_missing = 0;
  for (const auto &e : PairsWithin(dom, all, [](const Body &a, const Body &b) { return a.r + b.r; }))
    if (!listed.count(e)) ++pairs_missing;
  PetscCallMPI(MPI_Allreduce(local, global, 2, MPI_LONG_LONG, MPI_SUM, comm));
  *missing = pairs_missing + global[0] + global[1];
  PetscFunctionReturn(0);
}

PetscErrorCode CheckLists(MPI_Comm comm, const Domain &dom, Dem &dem, bool moving)
{
  const PetscInt       nlocal = (PetscInt)dem.bodies.size() - dem.ghosts.n;
  const NeighbourList &nl     = dem.nl;
  std::vector<Body>    all;
  ParticleArrays       p;

  PetscFunctionBeginUser;
  PetscCall(GatherBodies(comm, dem, nlocal, &all));
  std::sort(all.begin(), all.end(), [](const Body &a, const Body &b) { return a.id < b.id; });

  std::set<std::pair<PetscInt64, PetscInt64>> expected;
  std::map<PetscInt64, PetscInt>              partners_of;
  for (const auto &e : PairsWithin(dom, all, [](const Body &a, const Body &b) { return a.r + b.r + (a.share + b.share); })) {
    expected.insert(e);
    partners_of[e.first]++;
    partners_of[e.second]++;
  }

  // the full lists' sizes
  bool       full_ok  = true;
  PetscInt64 full_bad = -1;
  for (PetscInt i = 0; i < nlocal; ++i) {
    const PetscInt64 id     = dem.body_id[(std::size_t)i];
    const PetscInt   listed = nl.start[(std::size_t)i + 1] - nl.start[(std::size_t)i];
    const auto       it     = partners_of.find(id);
    if (listed != (it == partners_of.end() ? 0 : it->second) && full_ok) {
      full_ok  = false;
      full_bad = id;
    }
  }
  std::vector<PetscInt64> triples;
  PetscCall(GatherListedPairs(comm, dem, nlocal, &triples));
  std::map<std::pair<PetscInt64, PetscInt64>, std::vector<PetscInt64>> seen; // pair (min, max) -> (from, kind)...
  for (std::size_t k = 0; k < triples.size(); k += 3) {
    const PetscInt64 a = triples[k], b = triples[k + 1];
    seen[{std::min(a, b), std::max(a, b)}].insert(seen[{std::min(a, b), std::max(a, b)}].end(), {a, triples[k + 2]});
  }
  long long missing = 0, extra = 0, wrong = 0;
  for (const auto &e : expected)
    if (!seen.count(e)) ++missing;
  for (const auto &s : seen) {
    if (!expected.count(s.first)) {
      ++extra;
      continue;
    }
    const std::vector<PetscInt64> &v          = s.second; // from, kind, from, kind...
    const bool                     local_once = v.size() == 2 && v[1] == 0;
    const bool                     both_sides = v.size() == 4 && v[1] == 1 && v[3] == 1 && v[0] != v[2];
    if (!local_once && !both_sides) ++wrong;
  }
  PetscReal share_lo = PETSC_MAX_REAL, share_hi = 0;
  for (const Body &b : all) {
    share_lo = PetscMin(share_lo, b.share);
    share_hi = PetscMax(share_hi, b.share);
  }
  PetscCall(PetscPrintf(comm, "%zu particles, %zu pairs within r_i + r_j + s_i + s_j (skin %.3g m, shares %.3g to %.3g m), %zu listed\n",
                        all.size(), expected.size(), (double)dem.skin, (double)share_lo, (double)share_hi, seen.size()));
  PetscCall(Check(comm, share_lo > 0 && share_hi <= 0.5 * dem.skin, "every share is positive and at most half the skin (largest, nm)",
                  (long long)(1e9 * share_hi)));
  if (moving && dem.par.skin_adaptive)
    PetscCall(Check(comm, share_lo < share_hi, "the adaptive shares differ between particles (smallest, nm)", (long long)(1e9 * share_lo)));
  PetscCall(Check(comm, missing == 0, "every pair within the cutoff is listed (missing)", missing));
  PetscCall(Check(comm, extra == 0, "no pair beyond the cutoff is listed (extra)", extra));
  PetscCall(Check(comm, wrong == 0, "each pair once when local, from both sides through ghosts (wrong)", wrong));
  PetscCall(Check(comm, full_ok, "each full list holds exactly its particle's partners (first wrong id)", (long long)full_bad));

  // walls
  long long wall_missing = 0, wall_extra = 0;
  PetscCall(ParticleArraysGet(dem.swarm, &p));
  for (PetscInt i = 0; i < nlocal; ++i) {
    const ParticleBody &b = dem.bodies[(std::size_t)i];
    std::set<PetscInt>  listed;
    for (PetscInt k = nl.wall_start[(std::size_t)i]; k < nl.wall_start[(std::size_t)i + 1]; ++k) {
      const WallContact &wc = nl.walls[(std::size_t)k];
      listed.insert(wc.face);
    }
    for (PetscInt f = 0; f < 2 * dom.dim; ++f) {
      const int a = (int)f / 2;
      if (dom.periodic[a]) {
        if (listed.count(f)) ++wall_extra;
        continue;
      }
      const PetscReal xa   = (&b.x.x)[a];
      const PetscReal gap  = (f % 2) ? dom.hi[a] - xa : xa - dom.lo[a];
      const bool      near = gap < b.r + 2.0 * dem.x_move[(std::size_t)i];
      bool            held = false;
      for (PetscInt s = 0; s < p.K; ++s) held = held || p.ckey[p.K * i + s] == WallKey((int)f);
      if (near && !listed.count(f)) ++wall_missing;
      if (!near && listed.count(f) && !held) ++wall_extra;
    }
  }
  PetscCall(ParticleArraysRestore(dem.swarm, &p));
  PetscCall(Check(comm, wall_missing == 0, "every wall within r + 2 s is listed (missing)", wall_missing));
  PetscCall(Check(comm, wall_extra == 0, "no other wall is listed, unless it holds a contact history (extra)", wall_extra));
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv)
{
  component::DemScene sc;
  InsertionReport     inserted;
  PetscInt            steps = 50;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-steps", &steps, NULL));
  PetscCall(component::DemSceneCreate(PETSC_COMM_WORLD, &sc));
  const MPI_Comm comm = sc.comm;
  Dem           *dem  = sc.dem;
  PetscCall(ParticlesInsert(comm, sc.dom, sc.grids.particle, sc.props, sc.swarm, &inserted));
  PetscCall(DemSetUp(dem, sc.swarm, PETSC_FALSE));
  PetscCall(CheckLists(comm, sc.dom, *dem, false)); // the lists of the insertion
  long long unlisted = 0;                           // touching pairs and walls missing from the lists, summed over the steps
  for (PetscInt s = 0; s < steps; ++s) {
    long long missing = 0;
    PetscCall(DemStep(dem));
    PetscCall(CheckContactsListed(comm, sc.dom, *dem, &missing));
    unlisted += missing;
  }
  PetscCall(Check(comm, unlisted == 0,
                  "after every step, each particle within its share of its position at the rebuild, and every touching pair and wall "
                  "listed (failures, over the steps)",
                  unlisted));
  PetscCall(DemRebuild(dem));
  PetscCall(PetscPrintf(comm, "after %d steps and a rebuild (%lld rebuilds in all):\n", (int)steps, (long long)dem->stats.rebuilds));
  PetscCall(CheckLists(comm, sc.dom, *dem, true));
  PetscCall(component::DemSceneDestroy(&sc));
  PetscCall(PetscFinalize());
  return 0;
}
