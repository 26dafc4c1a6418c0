// The linear spring-dashpot contact model (-dem_contact_model lsd, seed eq. 2.3-2.10, kernels/contact_lsd.hpp):
// forces and torques on the local particles plus gravity. Gets the swarm fields, loops over walls and neighbour
// lists, calls the kernel, restores. Each particle sums walls first (in face
// order) and then partners in increasing id, so the result does not depend on the decomposition.
//
// One sweep over the particles in storage order: each evaluates the pairs it holds in the half list (their
// histories are kept there, next to the list, between rebuilds), and every particle whose pairs are then all
// evaluated sums its walls and contributions (dem.hpp, NeighbourList). The swarm's history slots are taken and
// freed in the same order as when every pair was evaluated first and the particles summed afterwards, so they and
// the checkpoints written from them are unchanged too.
#include "dem_impl.hpp"
#include "fluidbed/kernels/periodic.hpp"

#include "history_slots.hpp"

#include <cstdint>

namespace fluidbed {

using kernels::Vec3;

namespace {

// One contact's history between steps, as five reals: xi_t (3), the overlap and the normal dashpot force of the
// previous step (the last two for the exact dashpot impulse).
struct SlotHistory {
  Vec3      xi;
  PetscReal overlap = 0, damping = 0;
};
constexpr PetscInt kLsdHistory = 5;

inline SlotHistory Load(const PetscReal *q)
{
  return {{q[0], q[1], q[2]}, q[3], q[4]};
}
inline void Store(const SlotHistory &h, PetscReal *q)
{
  q[0] = h.xi.x;
  q[1] = h.xi.y;
  q[2] = h.xi.z;
  q[3] = h.overlap;
  q[4] = h.damping;
}

struct WallFace {
  int       face, axis;
  PetscReal plane; // coordinate of the wall
  Vec3      n;     // unit normal from the particle into the wall
};

// What one contact adds to body i: force, n x f_t (the torque on i is r_i n x f_t, on j r_j n x f_t), and the
// dashpot impulse correction. Seen from j the contribution is {-force, n x f_t, -impulse}, bit for bit what j
// would compute.
using Contribution = ContactContribution;
inline SlotHistory Mirror(const SlotHistory &h)
{
  return {-h.xi, h.overlap, h.damping};
}

// Eq. 2.3-2.10 for one contact in contact; updates the slot history h.
[[gnu::always_inline]] inline Contribution Evaluate(const kernels::LsdModel &m, const kernels::ContactKinematics &kin, PetscReal dt,
                                                    SlotHistory &h)
{
  const kernels::ContactForce cf = kernels::lsd_contact(m, kin, dt, h.xi);
  const Vec3 J = kernels::damping_impulse_correction(cf.eta_n, h.overlap, kin.overlap, h.damping, cf.damping_n, 0.5 * dt, kin.n);
  h.overlap    = kin.overlap;
  h.damping    = cf.damping_n;
  return {cf.normal + cf.tangential, kernels::cross(kin.n, cf.tangential), J};
}

// The contact ended inside this step: only the dashpot impulse, closed with the overlap back at zero.
inline Contribution EndContribution(const kernels::LsdModel &m, PetscReal sqrt_meff, const Vec3 &n, PetscReal dt, const SlotHistory &h)
{
  return {Vec3{}, Vec3{}, kernels::damping_impulse_correction(m.damp_n * sqrt_meff, h.overlap, 0.0, h.damping, 0.0, 0.5 * dt, n)};
}

struct Sums {
  Vec3 F, T, J;
  void Add(const Contribution &c, PetscReal r)
  {
    F += c.force;
    T += r * c.n_cross_ft;
    J += c.impulse;
  }
};

// The state of one force evaluation, shared by the per-particle steps below.
struct ForceLoop {
  Dem                *dem;
  NeighbourList      *nl;
  ParticleArrays      p;
  PetscInt            nlocal;
  PetscReal           dt;
  bool                periodic;
  PetscReal           period[3];
  Vec3                g;
  const WallFace     *wall_of_face; // indexed by face
  Contribution       *contrib;      // per pair, at ContactPair::out
  unsigned char      *touching;     // per place of contrib: 1 when this step's contribution there is not zero
  const ParticleBody *bodies;
  PetscInt            npairs;
  PetscInt64          contacts;
  PetscReal           max_rel;
};

constexpr PetscInt  kPrefetchPairs = 8;
constexpr PetscReal kSign[2]       = {1.0, -1.0}; // by the entry's mirror bit

// Evaluates the pairs particle i holds in the half list (the smaller id of two local particles, the local side
// of a pair with a ghost). The pair's history lives in the list; the swarm's slots are taken and freed here as
// contacts begin and end (DemSyncPairHistory stores the histories in them before particles move).
[[gnu::always_inline]] inline PetscErrorCode EvaluatePairs(ForceLoop &L, PetscInt i)
{
  const ParticleBody      &bi     = L.bodies[i];
  const PetscInt           nlocal = L.nlocal;
  const PetscReal          dt     = L.dt;
  const kernels::LsdModel &pp     = L.dem->par.pp;
  const PetscInt           q0 = L.nl->pair_start[(std::size_t)i], q1 = L.nl->pair_start[(std::size_t)i + 1];
  ContactPair             *pairs = L.nl->pairs.data();
  PetscReal               *hq    = L.nl->pair_hist.data() + kLsdHistory * (std::size_t)q0; // pair q's history

  PetscFunctionBeginUser;
  for (PetscInt q = q0; q < q1; ++q, hq += kLsdHistory) {
    if (q + kPrefetchPairs < L.npairs) { // the partner of a pair a few ahead: its body is a likely cache miss
      const char *b = reinterpret_cast<const char *>(&L.bodies[pairs[q + kPrefetchPairs].partner]);
      __builtin_prefetch(b);
      __builtin_prefetch(b + sizeof(ParticleBody) - 1);
    }
    ContactPair        &pr      = pairs[q];
    const PetscInt      j       = pr.partner;
    const bool          j_local = j < nlocal;
    const ParticleBody &bj      = L.bodies[j];
    Vec3                d       = bj.x - bi.x;
    if (L.periodic) {
      d.x = kernels::min_image(d.x, L.period[0]);
      d.y = kernels::min_image(d.y, L.period[1]);
      d.z = kernels::min_image(d.z, L.period[2]);
    }
    const PetscReal dist2 = kernels::norm2(d);
    const PetscReal rsum  = bi.r + bj.r;
    Contribution    c; // the contact's, or the closing dashpot impulse of a contact that just ended
    if (!(dist2 < rsum * rsum) && pr.slot < 0) {
      // Apart, as at the last step: its contribution is zero, and the particles skip it instead of adding it (the
      // same sums, SumParticle). Most listed pairs are apart, so this saves their stores and their sums.
      L.touching[pr.out] = 0;
      continue;
    }
    if (dist2 < rsum * rsum) {
      SlotHistory h;
      if (pr.slot < 0) PetscCall(HistorySlotTake(L.p, i, L.dem->body_id[(std::size_t)j], &pr.slot));
      else h = Load(hq);
      const kernels::ContactKinematics kin =
        kernels::pair_kinematics(d, PetscSqrtReal(dist2), bi.r, bj.r, bi.v, bj.v, bi.w, bj.w, pr.sqrt_meff);
      c = Evaluate(pp, kin, dt, h);
      Store(h, hq);
      L.contacts += j_local ? 2 : 1;
      L.max_rel = PetscMax(L.max_rel, kin.overlap / (2.0 * PetscMin(bi.r, bj.r)));
    } else { // apart now, in contact at the last step
      c = EndContribution(pp, pr.sqrt_meff, (1.0 / PetscSqrtReal(dist2)) * d, dt, Load(hq));
      HistorySlotFree(L.p, i, pr.slot);
      pr.slot = -1;
      // the partner's copy of the history (from the last sync) ends with the contact, so it never holds more
      // slots than it has contacts
      if (pr.partner_slot >= 0) {
        HistorySlotFree(L.p, j, pr.partner_slot);
        pr.partner_slot = -1;
      }
    }
    L.contrib[pr.out]  = c;
    L.touching[pr.out] = 1;
  }
  PetscFunctionReturn(0);
}

// The walls of particle i's list, summed into sum in face order: the others were more than r + 2 s away at the last
// rebuild (s: the particle's share of the skin), and no particle moves its share before the next (ParticlesKickDrift).
// Out of line: most particles have no wall near, and the pair sums of SumParticle keep their registers without this
// code.
[[gnu::noinline]] PetscErrorCode SumWalls(ForceLoop &L, PetscInt i, Sums *sum)
{
  const ParticleBody &bi = L.bodies[i];
  const PetscReal     dt = L.dt;
  NeighbourList      &nl = *L.nl;

  PetscFunctionBeginUser;
  for (PetscInt k = nl.wall_start[(std::size_t)i]; k < nl.wall_start[(std::size_t)i + 1]; ++k) {
    WallContact    &wc  = nl.walls[(std::size_t)k];
    PetscReal      *hk  = nl.WallHistory(k);
    const WallFace &w   = L.wall_of_face[wc.face];
    const PetscReal xa  = (&bi.x.x)[w.axis];
    const PetscReal gap = (w.face % 2) ? w.plane - xa : xa - w.plane;
    if (gap < bi.r) {
      SlotHistory h;
      if (wc.slot < 0) PetscCall(HistorySlotTake(L.p, i, WallKey(w.face), &wc.slot));
      else h = Load(hk);
      const kernels::ContactKinematics kin = kernels::wall_kinematics(w.n, gap, bi.r, bi.v, bi.w, bi.m);
      sum->Add(Evaluate(L.dem->par.pw, kin, dt, h), bi.r);
      Store(h, hk);
      L.max_rel = PetscMax(L.max_rel, kin.overlap / (2.0 * bi.r));
      ++L.contacts;
    } else if (wc.slot >= 0) {
      sum->Add(EndContribution(L.dem->par.pw, PetscSqrtReal(bi.m), w.n, dt, Load(hk)), bi.r);
      HistorySlotFree(L.p, i, wc.slot);
      wc.slot = -1;
    }
  }
  PetscFunctionReturn(0);
}

// Particle i's force, torque and impulse correction: walls (in face order), then its pairs in increasing partner
// id, then gravity. All its pairs have been evaluated.
[[gnu::always_inline]] inline PetscErrorCode SumParticle(ForceLoop &L, PetscInt i)
{
  const ParticleBody &bi = L.bodies[i];
  NeighbourList      &nl = *L.nl;
  Sums                sum;

  PetscFunctionBeginUser;
  if (nl.wall_start[(std::size_t)i] < nl.wall_start[(std::size_t)i + 1]) PetscCall(SumWalls(L, i, &sum));
  // Pairs apart are skipped. Their contribution would be zero; the sums start at +0 and, with round-to-nearest, a
  // sum is -0 only when both terms are, so they never become -0: adding a zero (of either sign) would leave them
  // unchanged bit for bit, so skipping the pair gives the same sums as adding it. A pair evaluated by the partner
  // adds {-force, n x f_t, -impulse}: -1 * x is -x. An entry is never negative: unsigned, its halves are a shift and
  // a mask (no sign fix-ups in this hot loop).
  for (PetscInt e = nl.start[(std::size_t)i]; e < nl.start[(std::size_t)i + 1]; ++e) {
    const auto code = (std::uint32_t)nl.entries[(std::size_t)e];
    if (!L.touching[code >> 1]) continue; // a zero contribution: skipping it is adding it (above)
    const Contribution &c = L.contrib[code >> 1];
    const PetscReal     s = kSign[code & 1u];
    sum.F += s * c.force;
    sum.T += bi.r * c.n_cross_ft;
    sum.J += s * c.impulse;
  }

  sum.F += bi.m * L.g; // gravity, reduced by buoyancy when the gas is on (eq. 2.1)
  PetscReal *f = &L.p.f[3 * i], *t = &L.p.t[3 * i], *J = &L.dem->impulse[3 * (std::size_t)i];
  f[0] = sum.F.x;
  f[1] = sum.F.y;
  f[2] = sum.F.z;
  t[0] = sum.T.x;
  t[1] = sum.T.y;
  t[2] = sum.T.z;
  J[0] = sum.J.x;
  J[1] = sum.J.y;
  J[2] = sum.J.z;
  PetscFunctionReturn(0);
}

// ContactModel::forces of the linear spring-dashpot.
PetscErrorCode LsdForces(Dem *dem)
{
  const Domain  &dom    = *dem->dom;
  NeighbourList &nl     = dem->nl;
  const PetscInt nlocal = (PetscInt)dem->bodies.size() - dem->ghosts.n;
  WallFace       wall_of_face[FACE_COUNT];
  ForceLoop      L;

  PetscFunctionBeginUser;
  for (int f = 0; f < FACE_COUNT; ++f) {
    const int a = f / 2;
    Vec3      n;
    (&n.x)[a]       = (f % 2) ? 1.0 : -1.0;
    wall_of_face[f] = {f, a, (f % 2) ? dom.hi[a] : dom.lo[a], n};
  }
  dem->impulse.resize(3 * (std::size_t)nlocal); // every entry is set below
  dem->contributions.resize((std::size_t)nl.ncontrib);
  dem->touching.resize((std::size_t)nl.ncontrib);
  L.dem      = dem;
  L.nl       = &nl;
  L.nlocal   = nlocal;
  L.dt       = dem->dt;
  L.periodic = dom.periodic[0] || dom.periodic[1] || dom.periodic[2];
  for (int a = 0; a < 3; ++a) L.period[a] = dom.periodic[a] ? dom.len[a] : 0.0;
  L.g            = dem->body_force_factor * Vec3{dom.gravity[0], dom.gravity[1], dom.gravity[2]};
  L.wall_of_face = wall_of_face;
  L.contrib      = dem->contributions.data();
  L.touching     = dem->touching.data();
  L.bodies       = dem->bodies.data();
  L.npairs       = (PetscInt)nl.pairs.size();
  L.contacts     = 0;
  L.max_rel      = 0.0;

  PetscCall(ParticleArraysGet(dem->swarm, &L.p));
  PetscCheck(L.p.hs == kLsdHistory && nl.hs == kLsdHistory, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "lsd contacts keep %d history reals, the swarm and lists hold %d and %d", (int)kLsdHistory, (int)L.p.hs, (int)nl.hs);
  // Each pair once, in the storage order of the particles that evaluate it; each particle summed right after
  // the last of its pairs is evaluated. Its sums do not depend on when that is, and each particle's slots are
  // taken and freed in the same order: by its pairs (in the order they are evaluated), then by its walls.
  for (PetscInt i = 0; i < nlocal; ++i) {
    PetscCall(EvaluatePairs(L, i));
    for (PetscInt k = nl.finish_start[(std::size_t)i]; k < nl.finish_start[(std::size_t)i + 1]; ++k)
      PetscCall(SumParticle(L, nl.finish[(std::size_t)k]));
  }
  PetscCall(ParticleArraysRestore(dem->swarm, &L.p));
  dem->stats.contacts          = L.contacts;
  dem->stats.max_overlap_rel   = PetscMax(dem->stats.max_overlap_rel, L.max_rel);
  dem->stats.guard_overlap_rel = PetscMax(dem->stats.guard_overlap_rel, L.max_rel);
  PetscFunctionReturn(0);
}

void LsdMirror(const PetscReal *h, PetscReal *out)
{
  Store(Mirror(Load(h)), out);
}

PetscReal LsdElasticEnergy(const Dem &dem, const PetscReal *h, bool wall)
{
  const SlotHistory a = Load(h);
  return kernels::lsd_elastic_energy(wall ? dem.par.pw : dem.par.pp, a.overlap, a.xi);
}

} // namespace

PetscErrorCode ContactModelCreateLsd(ContactModel *model)
{
  PetscFunctionBeginUser;
  model->name           = "lsd";
  model->history_size   = kLsdHistory;
  model->forces         = LsdForces;
  model->mirror         = LsdMirror;
  model->elastic_energy = LsdElasticEnergy;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
