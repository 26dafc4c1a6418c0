// Verlet neighbour lists built with bins of about one particle diameter (the largest contact cutoff
// 2 r_max + skin), not the 3 d particle cells: each particle then tests about 40 candidates instead of ~350.
// Lists are full (each pair appears for both particles) and sorted by partner id, which fixes the order in
// which contact forces are summed (see dem.hpp).
#include "dem_impl.hpp"

#include "history_slots.hpp"

#include <algorithm>
#include <cmath>

namespace fluidbed {

PetscErrorCode DemNeighbourBuild(Dem *dem)
{
  const Domain       &dom    = *dem->dom;
  const ParticleGrid &pg     = *dem->pgrid;
  const int           dim    = (int)dom.dim;
  const PetscInt      ntotal = (PetscInt)dem->bodies.size();
  const PetscInt      nlocal = ntotal - dem->ghosts.n;
  const PetscReal     skin   = dem->skin;
  NeighbourList      &nl     = dem->nl;
  NeighbourScratch   &w      = dem->nl_scratch;
  ParticleArrays      p;
  using BinnedBody = NeighbourScratch::BinnedBody;
  using Candidate  = NeighbourScratch::Candidate;

  PetscFunctionBeginUser;
  // Binning positions: ghosts at their periodic image next to this subdomain.
  std::vector<kernels::Vec3> &pos = w.pos;
  pos.resize((std::size_t)ntotal);
  w.mass.resize((std::size_t)ntotal);
  for (PetscInt k = 0; k < ntotal; ++k) {
    pos[(std::size_t)k]    = dem->bodies[(std::size_t)k].x;
    w.mass[(std::size_t)k] = dem->bodies[(std::size_t)k].m;
    if (k >= nlocal) {
      const PetscReal *s = &dem->ghosts.shift[3 * (std::size_t)(k - nlocal)];
      pos[(std::size_t)k] += kernels::Vec3{s[0], s[1], s[2]};
    }
  }
  dem->body_id.resize((std::size_t)ntotal);

  // Each body's share of its pairs' skin: half of -dem_skin or, with the adaptive skin, its speed times twice the
  // last interval between rebuilds, between the halves of -dem_skin_min and -dem_skin. A pair is listed when its gap
  // is below the sum of the two shares and the lists hold until a particle has moved its own share, so every contact
  // stays listed; slow particles in a dense bed keep short lists and the fast ones of a dilute jet long ones, so
  // the lists last until the fastest particle has moved half of -dem_skin. A particle that kept its speed would
  // move half its share in the last interval. Ghosts compute their shares from the same velocities as their owners,
  // so the lists stay symmetric across ranks.
  std::vector<PetscReal> &share = w.share;
  share.assign((std::size_t)ntotal, 0.5 * skin);
  if (dem->par.skin_adaptive && dem->rebuild_interval > 0) {
    const PetscReal lo = 0.5 * dem->par.skin_min * dem->props->d_max, T = 2.0 * (PetscReal)dem->rebuild_interval * dem->dt;
    for (PetscInt k = 0; k < ntotal; ++k)
      share[(std::size_t)k] = PetscMin(PetscMax(kernels::norm(dem->bodies[(std::size_t)k].v) * T, lo), 0.5 * skin);
  }

  // Bins covering the subdomain plus the halo plus drift.
  const PetscReal bin_min = 2.0 * 0.5 * dem->props->d_max + skin;
  PetscReal       origin[3], width[3];
  PetscInt        nb[3];
  for (int a = 0; a < 3; ++a) {
    if (a < dim) {
      origin[a]         = pg.sub_lo[a] - dem->halo - skin;
      const PetscReal L = (pg.sub_hi[a] - pg.sub_lo[a]) + 2.0 * (dem->halo + skin);
      nb[a]             = PetscMax(1, (PetscInt)std::floor(L / bin_min));
      width[a]          = L / nb[a];
    } else {
      origin[a] = -1.0;
      nb[a]     = 1;
      width[a]  = 1e300;
    }
  }
  auto bin_of = [&](const kernels::Vec3 &x, PetscInt c[3]) {
    const PetscReal xx[3] = {x.x, x.y, x.z};
    for (int a = 0; a < 3; ++a) c[a] = a < dim ? PetscMin(PetscMax((PetscInt)std::floor((xx[a] - origin[a]) / width[a]), 0), nb[a] - 1) : 0;
  };
  const PetscInt         nbins     = nb[0] * nb[1] * nb[2];
  std::vector<PetscInt> &bin_start = w.bin_start, &bin_body = w.bin_body, &body_bin = w.body_bin;
  bin_start.assign((std::size_t)nbins + 1, 0);
  bin_body.resize((std::size_t)ntotal);
  body_bin.resize((std::size_t)ntotal);
  for (PetscInt k = 0; k < ntotal; ++k) {
    PetscInt c[3];
    bin_of(pos[(std::size_t)k], c);
    body_bin[(std::size_t)k] = c[0] + nb[0] * (c[1] + nb[1] * c[2]);
    bin_start[(std::size_t)body_bin[(std::size_t)k] + 1]++;
  }
  for (PetscInt b = 0; b < nbins; ++b) bin_start[(std::size_t)b + 1] += bin_start[(std::size_t)b];
  w.fill.assign(bin_start.begin(), bin_start.end() - 1);
  for (PetscInt k = 0; k < ntotal; ++k) bin_body[(std::size_t)w.fill[(std::size_t)body_bin[(std::size_t)k]]++] = k;
  // The bodies in bin order, each with its reach r + share: the candidate loop below then reads one bin's
  // candidates from consecutive memory.
  std::vector<BinnedBody> &binned = w.binned;
  binned.resize((std::size_t)ntotal);
  for (PetscInt q = 0; q < ntotal; ++q) {
    const PetscInt       k = bin_body[(std::size_t)q];
    const kernels::Vec3 &x = pos[(std::size_t)k];
    binned[(std::size_t)q] = {x.x, x.y, x.z, dem->bodies[(std::size_t)k].r + share[(std::size_t)k]};
  }

  PetscCall(ParticleArraysGet(dem->swarm, &p));
  for (PetscInt i = 0; i < nlocal; ++i) dem->body_id[(std::size_t)i] = p.id[i];
  for (PetscInt g = 0; g < dem->ghosts.n; ++g) dem->body_id[(std::size_t)(nlocal + g)] = dem->ghosts.id[(std::size_t)g];

  // Each pair within its cutoff found once: each body (ghosts too) tests the bodies after it in its own bin and those
  // of the bins after its own in the 3 x 3 x 3 stencil (z, then y, then x), half the stencil. The three bins along x
  // of a row are consecutive in the binning, and so are their bodies, so this is five ranges of candidates (two in
  // 2D). The test is symmetric in the two bodies bit for bit (the same squares, the same sum of reaches), so the lists
  // are those of testing every body against the whole stencil. Pairs of two ghosts are not kept.
  auto &found_pairs = w.found_pairs;
  found_pairs.clear();
  {
    auto test_range = [&](PetscInt k, const BinnedBody &A, PetscInt q0, PetscInt q1) {
      for (PetscInt q = q0; q < q1; ++q) {
        const BinnedBody &B  = binned[(std::size_t)q];
        const PetscReal   dx = B.x - A.x, dy = B.y - A.y, dz = B.z - A.z, cut = A.reach + B.reach;
        if (dx * dx + dy * dy + dz * dz < cut * cut) {
          const PetscInt m = bin_body[(std::size_t)q];
          if (k < nlocal || m < nlocal) found_pairs.push_back({k, m});
        }
      }
    };
    for (PetscInt qa = 0; qa < ntotal; ++qa) {
      const PetscInt    k         = bin_body[(std::size_t)qa];
      const BinnedBody &A         = binned[(std::size_t)qa];
      const PetscInt    bk        = body_bin[(std::size_t)k];
      const PetscInt    c[3]      = {bk % nb[0], (bk / nb[0]) % nb[1], bk / (nb[0] * nb[1])};
      auto              row_range = [&](PetscInt cy, PetscInt cz, PetscInt *q0, PetscInt *q1) {
        const PetscInt row = nb[0] * (cy + nb[1] * cz);
        *q0                = bin_start[(std::size_t)(row + PetscMax(c[0] - 1, 0))];
        *q1                = bin_start[(std::size_t)(row + PetscMin(c[0] + 1, nb[0] - 1)) + 1];
      };
      PetscInt q0, q1;
      row_range(c[1], c[2], &q0, &q1);
      test_range(k, A, qa + 1, q1); // the rest of its own bin, and the next bin along x
      if (c[1] + 1 < nb[1]) {
        row_range(c[1] + 1, c[2], &q0, &q1);
        test_range(k, A, q0, q1);
      }
      if (dim == 3 && c[2] + 1 < nb[2])
        for (PetscInt cy = PetscMax(c[1] - 1, 0); cy <= PetscMin(c[1] + 1, nb[1] - 1); ++cy) {
          row_range(cy, c[2] + 1, &q0, &q1);
          test_range(k, A, q0, q1);
        }
    }
  }
  // Each local particle's partners (CSR, in the order found); a pair of two local particles has a place in both
  // lists, and mirror names the other place.
  std::vector<PetscInt> &near_start = w.near_start, &near = w.near, &mirror = w.mirror;
  near_start.assign((std::size_t)nlocal + 1, 0);
  for (const auto &pr : found_pairs) {
    if (pr.first < nlocal) near_start[(std::size_t)pr.first + 1]++;
    if (pr.second < nlocal) near_start[(std::size_t)pr.second + 1]++;
  }
  for (PetscInt i = 0; i < nlocal; ++i) near_start[(std::size_t)i + 1] += near_start[(std::size_t)i];
  near.resize((std::size_t)near_start[(std::size_t)nlocal]);
  mirror.resize(near.size());
  w.fill.assign(near_start.begin(), near_start.end() - 1);
  for (const auto &pr : found_pairs) {
    const PetscInt a = pr.first < nlocal ? w.fill[(std::size_t)pr.first]++ : -1;
    const PetscInt b = pr.second < nlocal ? w.fill[(std::size_t)pr.second]++ : -1;
    if (a >= 0) {
      near[(std::size_t)a]   = pr.second;
      mirror[(std::size_t)a] = b;
    }
    if (b >= 0) {
      near[(std::size_t)b]   = pr.first;
      mirror[(std::size_t)b] = a;
    }
  }

  // Full lists sorted by partner id; a particle's own pairs (ghost partners and local partners of larger id) are
  // appended to the half list in the same order.
  const std::size_t nentries = near.size();
  nl.start.assign((std::size_t)nlocal + 1, 0);
  nl.pair_start.assign((std::size_t)nlocal + 1, 0);
  nl.entries.resize(nentries);
  nl.pairs.clear();
  w.partner.resize(nentries);
  w.entry_id.resize(nentries);
  w.entry_of_near.resize(nentries);
  std::vector<Candidate> &found = w.found;
  std::size_t             ne    = 0;
  for (PetscInt i = 0; i < nlocal; ++i) {
    const PetscInt64 id = dem->body_id[(std::size_t)i];
    found.clear();
    for (PetscInt e = near_start[(std::size_t)i]; e < near_start[(std::size_t)i + 1]; ++e)
      found.push_back({dem->body_id[(std::size_t)near[(std::size_t)e]], e});
    std::sort(found.begin(), found.end(), [](const Candidate &a, const Candidate &b) { return a.id < b.id; }); // ids are unique
    for (const Candidate &c : found) {
      const PetscInt j                     = near[(std::size_t)c.near];
      w.partner[ne]                        = j;
      w.entry_id[ne]                       = c.id;
      w.entry_of_near[(std::size_t)c.near] = (PetscInt)ne;
      if (j < nlocal && c.id < id) nl.entries[ne] = -1; // the partner's pair: linked below
      else {
        nl.entries[ne] = 2 * (PetscInt)nl.pairs.size();
        nl.pairs.push_back({j, -1, -1, -1, kernels::sqrt_effective_mass(w.mass[(std::size_t)i], w.mass[(std::size_t)j])});
      }
      ++ne;
    }
    nl.start[(std::size_t)i + 1]      = (PetscInt)ne;
    nl.pair_start[(std::size_t)i + 1] = (PetscInt)nl.pairs.size();
  }
  const std::vector<PetscInt> &partner = w.partner;

  // Each local pair appears in both particles' lists: point the partner side's entry at the pair, which the other
  // place of the pair in near names.
  for (std::size_t e = 0; e < nentries; ++e) {
    const PetscInt x = w.entry_of_near[e];
    if (nl.entries[(std::size_t)x] >= 0) continue;
    const PetscInt owner = mirror[e] >= 0 ? nl.entries[(std::size_t)w.entry_of_near[(std::size_t)mirror[e]]] : -1;
    PetscCheck(owner >= 0 && owner % 2 == 0, PETSC_COMM_SELF, PETSC_ERR_PLIB, "neighbour lists are not symmetric");
    nl.entries[(std::size_t)x] = owner + 1;
  }

  // Attach each listed pair to its history slots (the pair's copy of the evaluating side's history is loaded from
  // the slot); free slots of partners no longer listed (they left the system or moved beyond the cutoff); list
  // the walls each particle holds a slot for or may reach before the next rebuild (it moves less than half the
  // skin until then).
  const PetscInt K = p.K;
  nl.hs            = p.hs;
  nl.pair_hist.assign((std::size_t)(nl.hs * (PetscInt)nl.pairs.size()), 0.0);
  nl.wall_start.assign((std::size_t)nlocal + 1, 0);
  nl.walls.clear();
  nl.wall_hist.clear();
  constexpr PetscInt kSlotPrefetch = 4; // particles ahead: their held slots are fetched while this one's are read
  for (PetscInt i = 0; i < nlocal; ++i) {
    PetscInt64 *key = &p.ckey[K * i];
    PetscInt    wall_slot[FACE_COUNT];
    if (i + 2 * kSlotPrefetch < nlocal) // the keys of the particle eight ahead, which the slot prefetch reads four particles later
      for (PetscInt s = 0; s < K; s += 8) __builtin_prefetch(key + K * 2 * kSlotPrefetch + s);
    if (i + kSlotPrefetch < nlocal) {
      const PetscInt64 *ahead = key + K * kSlotPrefetch;
      for (PetscInt s = 0; s < K; ++s)
        if (ahead[s] >= 0) __builtin_prefetch(SlotHistory(p, i + kSlotPrefetch, s));
    }
    for (int f = 0; f < FACE_COUNT; ++f) wall_slot[f] = -1;
    // Each held slot: a wall's, or a partner's found among the entries (sorted by id) by bisection, or freed.
    const PetscInt e0 = nl.start[(std::size_t)i], e1 = nl.start[(std::size_t)i + 1];
    for (PetscInt s = 0; s < K; ++s) {
      if (key[s] <= -2) {
        if (-2 - key[s] < FACE_COUNT) wall_slot[-2 - key[s]] = s;
        continue;
      }
      if (key[s] < 0) continue; // free
      const auto     at = std::lower_bound(w.entry_id.begin() + e0, w.entry_id.begin() + e1, key[s]);
      const PetscInt lo = (PetscInt)(at - w.entry_id.begin());
      if (lo == e1 || w.entry_id[(std::size_t)lo] != key[s]) {
        HistorySlotFree(p, i, s); // the partner is no longer listed (it left, or moved beyond the cutoff)
        continue;
      }
      const PetscInt q  = nl.entries[(std::size_t)lo] / 2;
      ContactPair   &pr = nl.pairs[(std::size_t)q];
      if (nl.entries[(std::size_t)lo] % 2) pr.partner_slot = s;
      else {
        pr.slot = s;
        HistoryCopy(p.hs, SlotHistory(p, i, s), nl.PairHistory(q));
      }
    }
    const ParticleBody &b = dem->bodies[(std::size_t)i];
    for (int f = 0; f < 2 * dim; ++f) {
      if (!dom.IsParticleWall(f)) continue;
      const PetscReal gap = dom.WallGap(f, &b.x.x);
      if (wall_slot[f] < 0 && !(gap < b.r + 2.0 * share[(std::size_t)i])) continue;
      nl.walls.push_back({f, wall_slot[f]});
      nl.wall_hist.resize(nl.wall_hist.size() + (std::size_t)nl.hs, 0.0);
      if (wall_slot[f] >= 0) HistoryCopy(p.hs, SlotHistory(p, i, wall_slot[f]), nl.WallHistory((PetscInt)nl.walls.size() - 1));
    }
    nl.wall_start[(std::size_t)i + 1] = (PetscInt)nl.walls.size();
  }

  // Each particle is summed once the last of the partners that evaluate its pairs (in storage order) has
  // evaluated them, while their contributions are still in cache.
  {
    std::vector<PetscInt> &ready = w.ready;
    ready.resize((std::size_t)nlocal);
    nl.finish_start.assign((std::size_t)nlocal + 1, 0);
    for (PetscInt i = 0; i < nlocal; ++i) {
      PetscInt r = i;
      for (PetscInt e = nl.start[(std::size_t)i]; e < nl.start[(std::size_t)i + 1]; ++e)
        if (nl.entries[(std::size_t)e] % 2) r = PetscMax(r, partner[(std::size_t)e]);
      ready[(std::size_t)i] = r;
      nl.finish_start[(std::size_t)r + 1]++;
    }
    for (PetscInt i = 0; i < nlocal; ++i) nl.finish_start[(std::size_t)i + 1] += nl.finish_start[(std::size_t)i];
    w.fill.assign(nl.finish_start.begin(), nl.finish_start.end() - 1);
    nl.finish.resize((std::size_t)nlocal);
    for (PetscInt i = 0; i < nlocal; ++i) nl.finish[(std::size_t)w.fill[(std::size_t)ready[(std::size_t)i]]++] = i;

    // A pair's contribution is read by its particles once pair_start[ready + 1] pairs are visited, and at most
    // kLanePairsVisited + max_pairs pairs later (the force loop's lanes); its place in the ring is taken again by pair
    // q + kContributionRing.
    nl.max_pairs = 0;
    for (PetscInt i = 0; i < nlocal; ++i)
      nl.max_pairs = PetscMax(nl.max_pairs, nl.pair_start[(std::size_t)i + 1] - nl.pair_start[(std::size_t)i]);
    const PetscInt delay = kLanePairsVisited + nl.max_pairs;
    nl.ncontrib          = kContributionRing;
    w.pair_out.resize(nl.pairs.size());
    for (PetscInt i = 0; i < nlocal; ++i)
      for (PetscInt q = nl.pair_start[(std::size_t)i]; q < nl.pair_start[(std::size_t)i + 1]; ++q) {
        ContactPair   &pr   = nl.pairs[(std::size_t)q];
        const PetscInt last = PetscMax(ready[(std::size_t)i], pr.partner < nlocal ? ready[(std::size_t)pr.partner] : i);
        pr.out              = nl.pair_start[(std::size_t)last + 1] + delay <= q + kContributionRing ? q % kContributionRing : nl.ncontrib++;
        w.pair_out[(std::size_t)q] = pr.out;
      }
    // the partner side's entries name pairs far away in nl.pairs: read their places from the compact copy
    for (PetscInt &c : nl.entries) c = 2 * w.pair_out[(std::size_t)(c / 2)] + c % 2;
  }
  dem->x_ref.resize(3 * (std::size_t)nlocal);
  dem->x_move.assign(share.begin(), share.begin() + nlocal);
  for (PetscInt i = 0; i < nlocal; ++i)
    for (PetscInt a = 0; a < 3; ++a) dem->x_ref[3 * (std::size_t)i + a] = a < p.dim ? p.x[p.dim * i + a] : 0.0;
  PetscCall(ParticleArraysRestore(dem->swarm, &p));
  dem->stats.rebuilds++;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
