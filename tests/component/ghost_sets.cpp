// Component test of the DEM's ghost particles (src/particles/ghosts.cpp) on any number of ranks. The test places
// the particles itself (portable pseudo-random positions, the same on every rank, half of them within 1.5 halo
// widths of a subdomain face of the process grid, domain and periodic faces included; every rank keeps those of its
// particle cells, as the insertion does) and builds the ghosts. Then, on every rank, the ghosts it received are
// compared with a brute-force search over all particles of all ranks:
//   - the ghost layer of a rank is its subdomain [sub_lo, sub_hi) widened by the halo h = d_max + skin on every side
//     (Dem::halo; the test of each axis is strict, |x - face| < h, as in ParticlesGhostsBuild); a particle of another rank,
//     or a periodic image of any particle (shifted by -len, 0 or +len along each periodic axis), whose centre lies in
//     that layer is a ghost, once, and nothing else is;
//   - each ghost's periodic offset is that image's shift, exactly, and its body (position, predicted velocity and
//     spin, radius, mass) is its owner's, bit for bit (ghosts keep the unshifted position; the shift is applied
//     when binning);
//   - after the owners' bodies change, ParticlesGhostsUpdate (the PetscSF refresh of every step) brings each ghost its
//     owner's new body, bit for bit.
// Positions within 1e-9 of the domain size of a face or a face +- h are redrawn, so that the brute force and the
// code never disagree by a rounding. Prints one line per check and exits nonzero on the first failure.
#include "component_common.hpp"
#include "dem_scene.hpp"

#include "../../src/contact/dem_impl.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/particles.hpp"
#include "fluidbed/phases.hpp"

#include <cmath>
#include <cstring>
#include <map>
#include <tuple>
#include <vector>

using namespace fluidbed;
using component::AllGather;
using component::Check;

static const char help[] = "Ghost sets against a brute-force search (-count N particles, -seed S)\n";

namespace {

constexpr int kBodyReals = (int)(sizeof(ParticleBody) / sizeof(PetscReal));

struct Owned {
  PetscInt64   id;
  PetscMPIInt  rank;
  ParticleBody body;
};

// The global faces of the process grid along each axis (domain faces included).
std::vector<PetscReal> Faces(const Domain &dom, const ParticleGrid &pg, int a)
{
  std::vector<PetscReal> f;
  for (PetscInt i = 0; i <= pg.procs[a]; ++i) f.push_back(dom.lo[a] + pg.start[a][(std::size_t)i] * pg.h[a]);
  return f;
}

// Places count particles; each rank keeps those of its own particle cells (the rule of ParticlesInsert).
PetscErrorCode PlaceParticles(const Domain &dom, const ParticleGrid &pg, const ParticleProps &props, PetscReal h, PetscInt count,
                              PetscInt seed, DM swarm)
{
  const int              dim = (int)dom.dim;
  component::Random      rng((std::uint64_t)seed);
  std::vector<PetscReal> faces[3];
  struct P {
    PetscReal x[3], v[3], w[3], d;
  };
  std::vector<P> all;

  PetscFunctionBeginUser;
  for (int a = 0; a < dim; ++a) faces[a] = Faces(dom, pg, a);
  auto ambiguous = [&](const PetscReal x[3]) {
    for (int a = 0; a < dim; ++a)
      for (PetscReal f : faces[a])
        for (PetscReal o : {-h, 0.0, h})
          if (std::fabs(x[a] - (f + o)) < 1e-9 * dom.len[a]) return true;
    return false;
  };
  while ((PetscInt)all.size() < count) {
    P p;
    p.d = props.d_min + (props.d_max - props.d_min) * rng.Uniform();
    for (int a = 0; a < 3; ++a) {
      p.x[a] = a < dim ? rng.Uniform(dom.lo[a], dom.hi[a]) : 0.5 * (dom.lo[a] + dom.hi[a]);
      p.v[a] = a < dim ? rng.Uniform(-0.5, 0.5) : 0.0;
      p.w[a] = rng.Uniform(-50.0, 50.0);
    }
    // half of them near a face of the process grid along one axis, a quarter of those along a second axis too
    if (rng.Uniform() < 0.5) {
      const int naxes = rng.Uniform() < 0.25 && dim > 1 ? 2 : 1;
      int       first = -1;
      for (int m = 0; m < naxes; ++m) {
        int a = (int)(rng.Uniform() * dim);
        if (a == first) a = (a + 1) % dim;
        first                = a;
        const std::size_t fi = (std::size_t)(rng.Uniform() * (double)faces[a].size());
        p.x[a]               = faces[a][fi] + rng.Uniform(-1.5 * h, 1.5 * h);
      }
    }
    bool inside = true;
    for (int a = 0; a < dim; ++a) {
      if (dom.periodic[a]) {
        if (p.x[a] < dom.lo[a]) p.x[a] += dom.len[a];
        if (p.x[a] >= dom.hi[a]) p.x[a] -= dom.len[a];
      }
      inside = inside && p.x[a] >= dom.lo[a] && p.x[a] < dom.hi[a];
    }
    if (!inside || ambiguous(p.x)) continue;
    all.push_back(p);
  }

  std::vector<PetscInt> mine;
  for (PetscInt i = 0; i < count; ++i) {
    bool own = true;
    for (int a = 0; a < dim; ++a) {
      PetscInt cell = (PetscInt)std::floor((all[(std::size_t)i].x[a] - dom.lo[a]) / pg.h[a]);
      cell          = PetscMin(PetscMax(cell, 0), pg.n[a] - 1);
      own           = own && cell >= pg.cell_lo[a] && cell < pg.cell_hi[a];
    }
    if (own) mine.push_back(i);
  }
  ParticleArrays q;
  PetscCall(DMSwarmSetLocalSizes(swarm, (PetscInt)mine.size(), 1024));
  PetscCall(ParticleArraysGet(swarm, &q));
  for (PetscInt k = 0; k < q.n; ++k) {
    const P &p = all[(std::size_t)mine[(std::size_t)k]];
    for (int a = 0; a < dim; ++a) q.x[dim * k + a] = p.x[a];
    for (int a = 0; a < 3; ++a) {
      q.v[3 * k + a] = p.v[a];
      q.w[3 * k + a] = p.w[a];
      q.f[3 * k + a] = q.t[3 * k + a] = q.dref[3 * k + a] = 0.0;
    }
    q.d[k]     = p.d;
    q.id[k]    = mine[(std::size_t)k];
    q.dcoef[k] = 0.0;
    q.dcell[k] = 0;
    for (PetscInt s = 0; s < q.K; ++s) {
      q.ckey[q.K * k + s] = kFreeSlot;
      for (PetscInt c = 0; c < q.hs; ++c) q.chist[q.hs * (q.K * k + s) + c] = 0.0;
    }
  }
  PetscCall(ParticleArraysRestore(swarm, &q));
  PetscFunctionReturn(0);
}

// Every rank's local bodies with their ids and owners, on every rank, sorted by id.
PetscErrorCode GatherOwned(MPI_Comm comm, const Dem &dem, PetscInt nlocal, std::map<PetscInt64, Owned> *all)
{
  PetscMPIInt            rank;
  std::vector<PetscReal> mine, flat;
  const int              stride = 2 + kBodyReals;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  for (PetscInt i = 0; i < nlocal; ++i) {
    const PetscReal *b = reinterpret_cast<const PetscReal *>(&dem.bodies[(std::size_t)i]);
    mine.push_back(0); // the id, below
    mine.push_back((PetscReal)rank);
    mine.insert(mine.end(), b, b + kBodyReals);
  }
  // the ids come from the swarm (body_id is filled by the neighbour build, which this test does not call)
  {
    PetscInt64 *ids;
    PetscCall(DMSwarmGetField(dem.swarm, field::id, NULL, NULL, (void **)&ids));
    for (PetscInt i = 0; i < nlocal; ++i) mine[(std::size_t)(stride * i)] = (PetscReal)ids[i];
    PetscCall(DMSwarmRestoreField(dem.swarm, field::id, NULL, NULL, (void **)&ids));
  }
  PetscCall(AllGather(comm, MPIU_REAL, mine, &flat));
  all->clear();
  for (std::size_t k = 0; k < flat.size(); k += stride) {
    Owned o;
    o.id           = (PetscInt64)flat[k];
    o.rank         = (PetscMPIInt)flat[k + 1];
    PetscReal *dst = reinterpret_cast<PetscReal *>(&o.body);
    for (int r = 0; r < kBodyReals; ++r) dst[r] = flat[k + 2 + (std::size_t)r];
    (*all)[o.id] = o;
  }
  PetscFunctionReturn(0);
}

using ImageKey = std::tuple<PetscInt64, int, int, int>; // id, shift sign along x, y, z

PetscErrorCode CheckGhosts(MPI_Comm comm, const Domain &dom, const ParticleGrid &pg, Dem &dem)
{
  const int                   dim    = (int)dom.dim;
  const PetscReal             h      = dem.halo;
  const GhostExchange        &gx     = dem.ghosts;
  const PetscInt              nlocal = (PetscInt)dem.bodies.size() - gx.n;
  PetscMPIInt                 rank;
  std::map<PetscInt64, Owned> all;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(GatherOwned(comm, dem, nlocal, &all));

  // brute force: every image of every particle in this rank's ghost layer, except its own particles unshifted
  std::map<ImageKey, const Owned *> expected;
  long long                         corner = 0, images = 0; // in the layer outside the subdomain along >= 2 axes; shifted
  for (const auto &e : all) {
    const Owned &o = e.second;
    int          s[3];
    for (s[2] = -1; s[2] <= 1; ++s[2])
      for (s[1] = -1; s[1] <= 1; ++s[1])
        for (s[0] = -1; s[0] <= 1; ++s[0]) {
          bool      ok      = true;
          int       outside = 0;
          PetscReal x[3]    = {o.body.x.x, o.body.x.y, o.body.x.z};
          for (int a = 0; a < 3 && ok; ++a) {
            if (s[a] && (a >= dim || !dom.periodic[a])) ok = false;
            if (!ok) break;
            const PetscReal y = x[a] + s[a] * dom.len[a];
            if (a < dim) {
              ok = pg.sub_lo[a] - y < h && y - pg.sub_hi[a] < h;
              outside += (y < pg.sub_lo[a] || y >= pg.sub_hi[a]) ? 1 : 0;
            }
          }
          if (!ok || (o.rank == rank && !s[0] && !s[1] && !s[2])) continue;
          expected[ImageKey{o.id, s[0], s[1], s[2]}] = &o;
          if (outside >= 2) ++corner;
          if (s[0] || s[1] || s[2]) ++images;
        }
  }

  // what this rank received
  long long                    bad_shift = 0, duplicate = 0, extra = 0, wrong_body = 0, missing = 0;
  std::map<ImageKey, PetscInt> received;
  for (PetscInt g = 0; g < gx.n; ++g) {
    int  s[3];
    bool ok = true;
    for (int a = 0; a < 3; ++a) {
      const PetscReal sh = gx.shift[3 * (std::size_t)g + a];
      s[a]               = sh == 0 ? 0 : (sh == dom.len[a] ? 1 : (sh == -dom.len[a] ? -1 : 2));
      ok                 = ok && s[a] != 2;
    }
    if (!ok) {
      ++bad_shift;
      continue;
    }
    const ImageKey key{gx.id[(std::size_t)g], s[0], s[1], s[2]};
    if (received.count(key)) {
      ++duplicate;
      continue;
    }
    received[key] = g;
    const auto it = expected.find(key);
    if (it == expected.end()) {
      ++extra;
      continue;
    }
    if (std::memcmp(&dem.bodies[(std::size_t)(nlocal + g)], &it->second->body, sizeof(ParticleBody))) ++wrong_body;
  }
  for (const auto &e : expected)
    if (!received.count(e.first)) ++missing;

  long long   local[3] = {(long long)gx.n, images, corner}, total[3];
  PetscReal   wmin     = PETSC_MAX_REAL, wmin_all;
  PetscMPIInt size;
  PetscCallMPI(MPI_Allreduce(local, total, 3, MPI_LONG_LONG, MPI_SUM, comm));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  for (int a = 0; a < dim; ++a) wmin = PetscMin(wmin, pg.sub_hi[a] - pg.sub_lo[a]);
  PetscCallMPI(MPI_Allreduce(&wmin, &wmin_all, 1, MPIU_REAL, MPI_MIN, comm));
  PetscCall(PetscPrintf(comm,
                        "%zu particles on %d ranks (process grid %d x %d x %d), halo %.4g m, narrowest subdomain %.4g m: %lld ghosts, %lld "
                        "of them periodic images, %lld in the layer's edges and corners\n",
                        all.size(), (int)size, (int)pg.procs[0], (int)pg.procs[1], (int)pg.procs[2], (double)h, (double)wmin_all, total[0],
                        total[1], total[2]));
  PetscCall(Check(comm, bad_shift == 0, "every ghost's periodic offset is 0 or +-len along each axis (others)", bad_shift));
  PetscCall(Check(comm, duplicate == 0, "no image is received twice (duplicates)", duplicate));
  PetscCall(Check(comm, missing == 0, "every image within the halo of the subdomain is a ghost (missing)", missing));
  PetscCall(Check(comm, extra == 0, "no other image is a ghost (extra)", extra));
  PetscCall(Check(comm, wrong_body == 0, "each ghost's body is its owner's, bit for bit (wrong)", wrong_body));
  {
    bool periodic = false, two_axes;
    int  split    = 0;
    for (int a = 0; a < dim; ++a) {
      periodic = periodic || dom.periodic[a];
      split += (pg.procs[a] > 1 || dom.periodic[a]) ? 1 : 0;
    }
    two_axes = split >= 2;
    PetscCall(Check(comm, total[0] > 0 || (size == 1 && !periodic), "the scene has ghosts (ghosts)", local[0]));
    PetscCall(Check(comm, total[1] > 0 || !periodic, "the scene has periodic images where an axis is periodic (images)", local[1]));
    PetscCall(Check(comm, total[2] > 0 || !two_axes, "the scene has ghosts in the edges and corners of the layer (count)", local[2]));
  }
  PetscFunctionReturn(0);
}

// After ParticlesGhostsUpdate: each ghost (the same set as before) holds its owner's current body, bit for bit.
PetscErrorCode CheckRefresh(MPI_Comm comm, Dem &dem, const std::vector<PetscInt64> &ids_before)
{
  const GhostExchange        &gx     = dem.ghosts;
  const PetscInt              nlocal = (PetscInt)dem.bodies.size() - gx.n;
  std::map<PetscInt64, Owned> all;
  long long                   wrong = 0, changed = 0;

  PetscFunctionBeginUser;
  PetscCall(GatherOwned(comm, dem, nlocal, &all));
  for (PetscInt g = 0; g < gx.n; ++g) {
    const auto it = all.find(gx.id[(std::size_t)g]);
    if (gx.id[(std::size_t)g] != ids_before[(std::size_t)g] || it == all.end()) ++changed;
    else if (std::memcmp(&dem.bodies[(std::size_t)(nlocal + g)], &it->second.body, sizeof(ParticleBody))) ++wrong;
  }
  PetscCall(Check(comm, changed == 0, "the update keeps the ghosts and their order (changed)", changed));
  PetscCall(Check(comm, wrong == 0, "each ghost holds its owner's new body, bit for bit (wrong)", wrong));
  PetscFunctionReturn(0);
}

// Moves and spins every local body by amounts that depend on its id, then refreshes the ghosts.
PetscErrorCode ChangeBodies(Dem *dem)
{
  const PetscInt nlocal = (PetscInt)dem->bodies.size() - dem->ghosts.n;
  PetscInt64    *ids;

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetField(dem->swarm, field::id, NULL, NULL, (void **)&ids));
  for (PetscInt i = 0; i < nlocal; ++i) {
    ParticleBody   &b = dem->bodies[(std::size_t)i];
    const PetscReal s = std::sin((double)ids[i]);
    b.x.x += 1e-5 * s;
    b.x.y -= 2e-5 * s;
    b.v.x += 0.25 * s;
    b.w.z -= 3.0 * s;
    b.m *= 1.0 + 1e-3 * s;
  }
  PetscCall(DMSwarmRestoreField(dem->swarm, field::id, NULL, NULL, (void **)&ids));
  PetscCall(ParticlesGhostsUpdate(dem));
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv)
{
  component::DemScene sc;
  PetscInt            count = 1000, seed = 5;
  PetscInt64          before, after;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-count", &count, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-seed", &seed, NULL));
  PetscCall(component::DemSceneCreate(PETSC_COMM_WORLD, &sc));
  const MPI_Comm       comm  = sc.comm;
  const Domain        &dom   = sc.dom;
  const Grids         &grids = sc.grids;
  const ParticleProps &props = sc.props;
  Dem                 *dem   = sc.dem;
  DM                   swarm = sc.swarm;
  dem->swarm                 = swarm;
  PetscCall(PlaceParticles(dom, grids.particle, props, dem->halo, count, seed, swarm));

  // the rebuild's pieces up to the ghosts (DemRebuild without the history sync and the neighbour lists)
  PetscCall(ParticlesGlobalCount(swarm, &before));
  PetscCall(ParticlesMigrate(dem));
  PetscCall(ParticlesGlobalCount(swarm, &after));
  {
    PetscInt nlocal;
    PetscCall(DMSwarmGetLocalSize(swarm, &nlocal));
    PetscCall(Check(comm, before == count && after == count, "every placed particle is kept by one rank (count)", (long long)nlocal));
  }
  PetscCall(ParticlesSortLocal(dem));
  PetscCall(ParticlesPackBodies(dem));
  PetscCall(ParticlesGhostsBuild(dem));
  PetscCall(CheckGhosts(comm, dom, grids.particle, *dem));

  PetscCall(PetscPrintf(comm, "after the owners' bodies change and ParticlesGhostsUpdate:\n"));
  {
    const std::vector<PetscInt64> ids = dem->ghosts.id;
    PetscCall(ChangeBodies(dem));
    PetscCall(CheckRefresh(comm, *dem, ids));
  }

  PetscCall(component::DemSceneDestroy(&sc));
  PetscCall(PetscFinalize());
  return 0;
}
