// The linear spring-dashpot contact model (-dem_contact_model lsd, seed eq. 2.3-2.10, kernels/contact_lsd.hpp):
// forces and torques on the local particles plus gravity. Gets the swarm fields, loops over walls and neighbour
// lists, calls the kernel, restores. Each particle sums walls first (in face
// order) and then partners in increasing id, so the result does not depend on the decomposition.
//
// One sweep over the particles in storage order: each visits the pairs it holds in the half list (their histories
// are kept there, next to the list, between rebuilds) and gathers those in contact into SIMD lanes; once 64 are
// gathered (or 512 pairs visited) the lanes are evaluated, and every particle whose pairs are then all evaluated sums
// its walls and contributions (dem.hpp, NeighbourList). The swarm's history slots are taken and freed in the same
// order as when every pair was evaluated first and the particles summed afterwards, so they and the checkpoints
// written from them are unchanged too.
#include "dem_impl.hpp"
#include "fluidbed/kernels/periodic.hpp"

#include "history_slots.hpp"

#include <cstdint>

// Functions built for AVX-512, AVX2 and the baseline on x86-64, the loader picking the widest the core has (GCC's
// function multiversioning); one build elsewhere.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FLUIDBED_SIMD_CLONES [[gnu::target_clones("avx512f", "avx2", "default")]]
#else
#define FLUIDBED_SIMD_CLONES
#endif

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
  int  face;
  Vec3 n; // unit normal from the particle into the wall
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

// Touching pairs gathered for evaluation in SIMD lanes, a structure of arrays: what eq. 2.3-2.10 take from the
// pair's bodies, the pair's history (in, and out in the same places), its contribution and relative overlap out,
// and where the contribution and the history go.
struct PairLanes {
  enum Field {
    DX,
    DY,
    DZ,
    DIST2,
    RSUM,
    RMIN,
    DVX,
    DVY,
    DVZ,
    WX,
    WY,
    WZ,
    SQRT_MEFF,
    XIX,
    XIY,
    XIZ,
    OVERLAP,
    DAMPING,
    FX,
    FY,
    FZ,
    CX,
    CY,
    CZ,
    JX,
    JY,
    JZ,
    REL,
    NFIELD
  };
  // kCap lanes per field: the rows 1.6 kB apart (not a power of two, so that the fields do not share cache sets)
  static constexpr PetscInt kCap = 200;
  PetscInt                  n    = 0;
  alignas(64) PetscReal f[NFIELD][kCap];
  PetscInt   out[kCap];  // the pair's place in the contributions
  PetscReal *hist[kCap]; // the pair's history in the list
};
// The lanes are evaluated once this many are gathered, or once this many pairs have been visited since the last
// evaluation; the contribution ring allows for the second (kLanePairsVisited, dem_impl.hpp). A particle with more
// pairs in contact than the lanes hold has them evaluated in turns.
constexpr PetscInt kLanes = 64;
static_assert(kLanes < PairLanes::kCap, "the lanes hold a particle's pairs beyond kLanes");

// The state of one force evaluation, shared by the per-particle steps below.
struct ForceLoop {
  Dem                *dem;
  const Domain       *dom;
  NeighbourList      *nl;
  ParticleArrays      p;
  PetscInt            nlocal;
  PetscReal           dt;
  bool                periodic;
  PetscReal           period[3];
  Vec3                g;
  const WallFace     *wall_of_face; // indexed by face
  Contribution       *contrib;      // per pair, at ContactPair::out
  unsigned char      *touching;     // per place of contrib, when the sums skip pairs apart: 1 when written this step
  PetscInt64          gathered;     // pairs in contact evaluated in the lanes
  const ParticleBody *bodies;
  PetscInt            npairs;
  PetscInt64          contacts;
  PetscReal           max_rel;
  PairLanes           lanes;
};

// The partner's body is prefetched this many pairs ahead: 16 measured 5-8% faster in the contact stage than 8 or 32
// (settled 750 bed, spouting 550 bed; docs/performance.md), and without it the stage takes 15-20% longer.
constexpr PetscInt  kPrefetchPairs = 16;
constexpr PetscReal kSign[2]       = {1.0, -1.0}; // by the entry's mirror bit

// Eq. 2.3-2.10 for the gathered pairs, one per lane: the same kernel and the same operations as Evaluate for one
// contact, so the results are bit for bit those of evaluating each pair alone (the build does not contract a * b + c
// into fused multiply-adds, -ffp-contract=off). Built for AVX-512, AVX2 and the baseline; the loader picks the widest the
// core has.
FLUIDBED_SIMD_CLONES void EvaluateLanes(const kernels::LsdModel &m, PetscReal dt, PetscInt n, PetscReal (*f)[PairLanes::kCap])
{
  using F                        = PairLanes;
  const PetscReal *__restrict dx = f[F::DX], *__restrict dy = f[F::DY], *__restrict dz = f[F::DZ], *__restrict dist2 = f[F::DIST2];
  const PetscReal *__restrict rsum = f[F::RSUM], *__restrict rmin = f[F::RMIN], *__restrict sqrt_meff = f[F::SQRT_MEFF];
  const PetscReal *__restrict dvx = f[F::DVX], *__restrict dvy = f[F::DVY], *__restrict dvz = f[F::DVZ];
  const PetscReal *__restrict wx = f[F::WX], *__restrict wy = f[F::WY], *__restrict wz = f[F::WZ];
  PetscReal *__restrict xix = f[F::XIX], *__restrict xiy = f[F::XIY], *__restrict xiz = f[F::XIZ];
  PetscReal *__restrict ov = f[F::OVERLAP], *__restrict damp = f[F::DAMPING];
  PetscReal *__restrict fx = f[F::FX], *__restrict fy = f[F::FY], *__restrict fz = f[F::FZ];
  PetscReal *__restrict cx = f[F::CX], *__restrict cy = f[F::CY], *__restrict cz = f[F::CZ];
  PetscReal *__restrict jx = f[F::JX], *__restrict jy = f[F::JY], *__restrict jz = f[F::JZ], *__restrict rel = f[F::REL];
#pragma GCC ivdep
  for (PetscInt k = 0; k < n; ++k) {
    const kernels::ContactKinematics kin = kernels::pair_kinematics_from({dx[k], dy[k], dz[k]}, std::sqrt(dist2[k]), rsum[k],
                                                                         {dvx[k], dvy[k], dvz[k]}, {wx[k], wy[k], wz[k]}, sqrt_meff[k]);
    SlotHistory                      h{{xix[k], xiy[k], xiz[k]}, ov[k], damp[k]};
    const Contribution               c = Evaluate(m, kin, dt, h);
    xix[k]                             = h.xi.x;
    xiy[k]                             = h.xi.y;
    xiz[k]                             = h.xi.z;
    ov[k]                              = h.overlap;
    damp[k]                            = h.damping;
    fx[k]                              = c.force.x;
    fy[k]                              = c.force.y;
    fz[k]                              = c.force.z;
    cx[k]                              = c.n_cross_ft.x;
    cy[k]                              = c.n_cross_ft.y;
    cz[k]                              = c.n_cross_ft.z;
    jx[k]                              = c.impulse.x;
    jy[k]                              = c.impulse.y;
    jz[k]                              = c.impulse.z;
    rel[k]                             = kin.overlap / (2.0 * rmin[k]);
  }
}

// Evaluates the gathered lanes and puts their contributions and histories in place.
void FlushLanes(ForceLoop &L)
{
  PairLanes &b = L.lanes;
  using F      = PairLanes;
  EvaluateLanes(L.dem->par.pp, L.dt, b.n, b.f);
  const auto &f = b.f;
  for (PetscInt k = 0; k < b.n; ++k) {
    L.contrib[b.out[k]] = {
      {f[F::FX][k], f[F::FY][k], f[F::FZ][k]}, {f[F::CX][k], f[F::CY][k], f[F::CZ][k]}, {f[F::JX][k], f[F::JY][k], f[F::JZ][k]}};
    Store({{f[F::XIX][k], f[F::XIY][k], f[F::XIZ][k]}, f[F::OVERLAP][k], f[F::DAMPING][k]}, b.hist[k]);
    L.max_rel = PetscMax(L.max_rel, f[F::REL][k]);
  }
  L.gathered += b.n;
  b.n = 0;
}

// A contact begins: takes the pair's history slot; its history starts at zero. Out of line, like ContactEnds: both
// are rare, and the gather loop keeps its registers without their code.
[[gnu::noinline]] PetscErrorCode ContactBegins(ForceLoop &L, PetscInt i, ContactPair &pr, PetscInt k)
{
  using F = PairLanes;

  PetscFunctionBeginUser;
  PetscCall(HistorySlotTake(L.p, i, L.dem->body_id[(std::size_t)pr.partner], &pr.slot));
  L.lanes.f[F::XIX][k] = L.lanes.f[F::XIY][k] = L.lanes.f[F::XIZ][k] = L.lanes.f[F::OVERLAP][k] = L.lanes.f[F::DAMPING][k] = 0.0;
  PetscFunctionReturn(0);
}

// Apart now, in contact at the last step: the closing dashpot impulse; the pair's slots are freed.
[[gnu::noinline]] void ContactEnds(ForceLoop &L, PetscInt i, ContactPair &pr, const Vec3 &d, PetscReal dist2, const PetscReal *hq)
{
  L.contrib[pr.out] = EndContribution(L.dem->par.pp, pr.sqrt_meff, (1.0 / PetscSqrtReal(dist2)) * d, L.dt, Load(hq));
  if (L.touching) L.touching[pr.out] = 1;
  HistorySlotFree(L.p, i, pr.slot);
  pr.slot = -1;
  // the partner's copy of the history (from the last sync) ends with the contact, so it never holds more slots
  // than it has contacts
  if (pr.partner_slot >= 0) {
    HistorySlotFree(L.p, pr.partner, pr.partner_slot);
    pr.partner_slot = -1;
  }
}

// Visits the pairs particle i holds in the half list (the smaller id of two local particles, the local side of a
// pair with a ghost) and gathers those in contact into the lanes. The pair's history lives in the list; the swarm's
// slots are taken and freed here as contacts begin and end (DemSyncPairHistory stores the histories in them before
// particles move). kSkipApart: see LsdForces.
template <bool kSkipApart>
[[gnu::always_inline]] inline PetscErrorCode GatherPairs(ForceLoop &L, PetscInt i)
{
  using F                    = PairLanes;
  const ParticleBody &bi     = L.bodies[i];
  const PetscInt      nlocal = L.nlocal;
  const PetscInt      q0 = L.nl->pair_start[(std::size_t)i], q1 = L.nl->pair_start[(std::size_t)i + 1];
  ContactPair        *pairs = L.nl->pairs.data();
  PetscReal          *hq    = L.nl->pair_hist.data() + kLsdHistory * (std::size_t)q0; // pair q's history
  PairLanes          &b     = L.lanes;
  auto               &f     = b.f;

  PetscFunctionBeginUser;
  for (PetscInt q = q0; q < q1; ++q, hq += kLsdHistory) {
    if (q + kPrefetchPairs < L.npairs) { // the partner of a pair a few ahead: its body is a likely cache miss
      const char *pb = reinterpret_cast<const char *>(&L.bodies[pairs[q + kPrefetchPairs].partner]);
      __builtin_prefetch(pb);
      __builtin_prefetch(pb + sizeof(ParticleBody) - 1);
    }
    ContactPair        &pr = pairs[q];
    const PetscInt      j  = pr.partner;
    const ParticleBody &bj = L.bodies[j];
    Vec3                d  = bj.x - bi.x;
    if (L.periodic) {
      d.x = kernels::min_image(d.x, L.period[0]);
      d.y = kernels::min_image(d.y, L.period[1]);
      d.z = kernels::min_image(d.z, L.period[2]);
    }
    const PetscReal dist2 = kernels::norm2(d);
    const PetscReal rsum  = bi.r + bj.r;
    if (dist2 < rsum * rsum) {
      // A particle with more contacts than the lanes hold: not reached while -dem_max_contacts is at most 128 (the
      // lanes then hold at most kLanes - 1 + 128 < kCap), kept for larger limits (checked bit for bit with kCap = 65).
      if (__builtin_expect(b.n == PairLanes::kCap, 0)) FlushLanes(L);
      const PetscInt k = b.n++;
      if (__builtin_expect(pr.slot < 0, 0)) PetscCall(ContactBegins(L, i, pr, k));
      else {
        f[F::XIX][k]     = hq[0];
        f[F::XIY][k]     = hq[1];
        f[F::XIZ][k]     = hq[2];
        f[F::OVERLAP][k] = hq[3];
        f[F::DAMPING][k] = hq[4];
      }
      const Vec3 dv = bi.v - bj.v, ws = bi.r * bi.w + bj.r * bj.w; // as pair_kinematics forms them
      f[F::DX][k]        = d.x;
      f[F::DY][k]        = d.y;
      f[F::DZ][k]        = d.z;
      f[F::DIST2][k]     = dist2;
      f[F::RSUM][k]      = rsum;
      f[F::RMIN][k]      = PetscMin(bi.r, bj.r);
      f[F::DVX][k]       = dv.x;
      f[F::DVY][k]       = dv.y;
      f[F::DVZ][k]       = dv.z;
      f[F::WX][k]        = ws.x;
      f[F::WY][k]        = ws.y;
      f[F::WZ][k]        = ws.z;
      f[F::SQRT_MEFF][k] = pr.sqrt_meff;
      b.out[k]           = pr.out;
      b.hist[k]          = hq;
      if (kSkipApart) L.touching[pr.out] = 1;
      L.contacts += j < nlocal ? 2 : 1;
    } else if (__builtin_expect(pr.slot >= 0, 0)) ContactEnds(L, i, pr, d, dist2, hq);
    else {
      // Apart, as at the last step: its contribution is zero; written, SumParticle adds it without a test, else the
      // place is marked and SumParticle skips it.
      if (kSkipApart) L.touching[pr.out] = 0;
      else L.contrib[pr.out] = Contribution{};
    }
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
    const PetscReal gap = L.dom->WallGap(w.face, &bi.x.x);
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
template <bool kSkipApart>
[[gnu::always_inline]] inline PetscErrorCode SumParticle(ForceLoop &L, PetscInt i)
{
  const ParticleBody &bi = L.bodies[i];
  NeighbourList      &nl = *L.nl;
  Sums                sum;

  PetscFunctionBeginUser;
  if (nl.wall_start[(std::size_t)i] < nl.wall_start[(std::size_t)i + 1]) PetscCall(SumWalls(L, i, &sum));
  // Pairs apart add their zero contribution without a test, or are skipped (kSkipApart): the same sums, since they
  // start at +0 and, with round-to-nearest, a sum is -0 only when both terms are, so they never become -0, and adding
  // a zero (of either sign) leaves them unchanged bit for bit. A pair evaluated by the partner adds {-force, n x f_t,
  // -impulse}: -1 * x is -x. An entry is never negative: unsigned, its halves are a shift and a mask (no sign fix-ups
  // in this hot loop).
  // The nine reals of a contribution (force, n x f_t, impulse) in three vectors of four, each entry multiplied by
  // (s, s, s, r), (r, r, s, s) and s: the same products and sums as sum.F += s f, sum.T += r n x f_t, sum.J += s J.
  using V4 = double __attribute__((vector_size(32)));
  static_assert(sizeof(Contribution) == 9 * sizeof(double), "a contribution is nine reals");
  const double r     = bi.r;
  const V4     mA[2] = {{1.0, 1.0, 1.0, r}, {-1.0, -1.0, -1.0, r}}, mB[2] = {{r, r, 1.0, 1.0}, {r, r, -1.0, -1.0}};
  V4           A = {sum.F.x, sum.F.y, sum.F.z, sum.T.x}, B = {sum.T.y, sum.T.z, sum.J.x, sum.J.y};
  double       C = sum.J.z;
  for (PetscInt e = nl.start[(std::size_t)i]; e < nl.start[(std::size_t)i + 1]; ++e) {
    const auto code = (std::uint32_t)nl.entries[(std::size_t)e];
    if (kSkipApart && !L.touching[code >> 1]) continue;
    const double  *c = &L.contrib[code >> 1].force.x;
    const unsigned m = code & 1u;
    V4             a, b;
    __builtin_memcpy(&a, c, sizeof a);
    __builtin_memcpy(&b, c + 4, sizeof b);
    A += mA[m] * a;
    B += mB[m] * b;
    C += kSign[m] * c[8];
  }
  sum.F = {A[0], A[1], A[2]};
  sum.T = {A[3], B[0], B[1]};
  sum.J = {B[2], B[3], C};

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

// Below this share of listed pairs in contact the sums skip the pairs apart (LsdForces).
constexpr PetscReal kZeroApartShare = 0.25;

template <bool kSkipApart>
[[gnu::always_inline]] inline PetscErrorCode ForceSweep(ForceLoop &L)
{
  PetscFunctionBeginUser;
  // Each pair once, in the storage order of the particles that evaluate it; each particle summed once the lanes that
  // hold the last of its pairs are evaluated. Its sums do not depend on when that is, and each particle's slots are
  // taken and freed in the same order: by its pairs (in the order they are visited), then by its walls.
  PetscInt summed = 0, visited = 0; // particles [0, summed) are summed; pairs visited since the lanes were last evaluated
  for (PetscInt i = 0; i < L.nlocal; ++i) {
    PetscCall(GatherPairs<kSkipApart>(L, i));
    visited += L.nl->pair_start[(std::size_t)i + 1] - L.nl->pair_start[(std::size_t)i];
    if (i + 1 < L.nlocal && L.lanes.n < kLanes && visited < kLanePairsVisited) continue;
    FlushLanes(L);
    for (PetscInt k = L.nl->finish_start[(std::size_t)summed]; k < L.nl->finish_start[(std::size_t)i + 1]; ++k)
      PetscCall(SumParticle<kSkipApart>(L, L.nl->finish[(std::size_t)k]));
    summed  = i + 1;
    visited = 0;
  }
  PetscFunctionReturn(0);
}

// ContactModel::forces of the linear spring-dashpot. Built for AVX-512, AVX2 and the baseline like EvaluateLanes: the
// particles' sums run in vectors of four reals.
FLUIDBED_SIMD_CLONES PetscErrorCode LsdForces(Dem *dem)
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
    wall_of_face[f] = {f, n};
  }
  dem->impulse.resize(3 * (std::size_t)nlocal); // every entry is set below
  dem->contributions.resize((std::size_t)nl.ncontrib);
  L.dem      = dem;
  L.dom      = &dom;
  L.nl       = &nl;
  L.nlocal   = nlocal;
  L.dt       = dem->dt;
  L.periodic = dom.periodic[0] || dom.periodic[1] || dom.periodic[2];
  for (int a = 0; a < 3; ++a) L.period[a] = dom.periodic[a] ? dom.len[a] : 0.0;
  L.g            = dem->body_force_factor * Vec3{dom.gravity[0], dom.gravity[1], dom.gravity[2]};
  L.wall_of_face = wall_of_face;
  L.contrib      = dem->contributions.data();
  L.bodies       = dem->bodies.data();
  L.npairs       = (PetscInt)nl.pairs.size();
  L.contacts     = 0;
  L.gathered     = 0;
  L.max_rel      = 0.0;

  PetscCall(ParticleArraysGet(dem->swarm, &L.p));
  PetscCheck(L.p.hs == kLsdHistory && nl.hs == kLsdHistory, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "lsd contacts keep %d history reals, the swarm and lists hold %d and %d", (int)kLsdHistory, (int)L.p.hs, (int)nl.hs);
  // The pairs apart either write a zero contribution that the particles' sums add without a test, or are marked and
  // skipped by the sums: the same sums bit for bit (SumParticle). Writing the zeros saves the sums a branch they
  // cannot predict where many listed pairs touch (a dense bed: the contact stage 11-17% faster on the settled 750
  // bed); skipping saves the writes and the additions where few do (a bubbling bed: 9-11% faster on the Muller bed).
  // Chosen by the share of listed pairs in contact at the last evaluation.
  if (dem->contact_share < kZeroApartShare) {
    dem->touching.resize((std::size_t)nl.ncontrib);
    L.touching = dem->touching.data();
    PetscCall(ForceSweep<true>(L));
  } else {
    L.touching = nullptr;
    PetscCall(ForceSweep<false>(L));
  }
  dem->contact_share = L.npairs ? (PetscReal)L.gathered / (PetscReal)L.npairs : 1.0;
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
