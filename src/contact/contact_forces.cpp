// Contact forces and torques on the local particles (seed eq. 2.3-2.10) plus gravity: gets the swarm fields,
// loops over walls and neighbour lists, calls the kernel, restores. Each particle sums walls first (in face
// order) and then partners in increasing id, so the result does not depend on the decomposition.
#include "fluidbed/dem.hpp"
#include "fluidbed/kernels/periodic.hpp"

#include <string>

namespace fluidbed {

using kernels::Vec3;

namespace {

// One history slot: xi_t (3), overlap of the previous step, normal dashpot force of the previous step.
struct SlotHistory {
  Vec3      xi;
  PetscReal overlap = 0, damping = 0;
};

inline PetscReal *SlotPtr(const ParticleArrays &p, PetscInt i, PetscInt s)
{
  return &p.chist[kHistoryStride * (p.K * i + s)];
}
inline SlotHistory LoadSlot(const ParticleArrays &p, PetscInt i, PetscInt s)
{
  const PetscReal *q = SlotPtr(p, i, s);
  return {{q[0], q[1], q[2]}, q[3], q[4]};
}
inline void StoreSlot(const ParticleArrays &p, PetscInt i, PetscInt s, const SlotHistory &h)
{
  PetscReal *q = SlotPtr(p, i, s);
  q[0]         = h.xi.x;
  q[1]         = h.xi.y;
  q[2]         = h.xi.z;
  q[3]         = h.overlap;
  q[4]         = h.damping;
}

// A free history slot of particle i for a new contact with key.
PetscErrorCode AllocSlot(const ParticleArrays &p, PetscInt i, PetscInt64 key, PetscInt *slot)
{
  PetscFunctionBeginUser;
  for (PetscInt s = 0; s < p.K; ++s)
    if (p.ckey[p.K * i + s] == kFreeSlot) {
      p.ckey[p.K * i + s] = key;
      StoreSlot(p, i, s, SlotHistory{});
      *slot = s;
      PetscFunctionReturn(0);
    }
  {
    std::string keys;
    for (PetscInt s = 0; s < p.K; ++s) keys += " " + std::to_string((long long)p.ckey[p.K * i + s]);
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
            "particle %lld has more than %d simultaneous contacts (partners:%s; new %lld): raise -dem_max_contacts", (long long)p.id[i],
            (int)p.K, keys.c_str(), (long long)key);
  }
}

PetscInt FindSlot(const ParticleArrays &p, PetscInt i, PetscInt64 key)
{
  for (PetscInt s = 0; s < p.K; ++s)
    if (p.ckey[p.K * i + s] == key) return s;
  return -1;
}

struct WallFace {
  int       face, axis;
  PetscReal plane; // coordinate of the wall
  Vec3      n;     // unit normal from the particle into the wall
};

// What one contact adds to body i: force, n x f_t (the torque on i is r_i n x f_t, on j r_j n x f_t), and the
// dashpot impulse correction. Seen from j the contribution is Mirror(c), bit for bit what j would compute.
using Contribution = ContactContribution;
inline Contribution Mirror(const Contribution &c)
{
  return {-c.force, c.n_cross_ft, -c.impulse};
}
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

void FreeSlot(const ParticleArrays &p, PetscInt i, PetscInt s)
{
  p.ckey[p.K * i + s] = kFreeSlot;
  StoreSlot(p, i, s, SlotHistory{});
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

} // namespace

PetscErrorCode DemSyncPairHistory(Dem *dem)
{
  NeighbourList &nl     = dem->nl;
  const PetscInt nlocal = (PetscInt)nl.start.size() - 1;
  ParticleArrays p;

  PetscFunctionBeginUser;
  if (nlocal <= 0) PetscFunctionReturn(0);
  PetscCall(ParticleArraysGet(dem->swarm, &p));
  for (PetscInt i = 0; i < nlocal; ++i) {
    const PetscInt64 id = dem->body_id[(std::size_t)i];
    for (PetscInt e = nl.start[(std::size_t)i]; e < nl.start[(std::size_t)i + 1]; ++e) {
      NeighbourEntry &ne = nl.entries[(std::size_t)e];
      const PetscInt  j  = ne.partner;
      if (j >= nlocal || dem->body_id[(std::size_t)j] < id) continue; // not a local pair evaluated from i's side
      NeighbourEntry &me = nl.entries[(std::size_t)ne.mirror];
      if (ne.slot >= 0) {
        if (me.slot < 0) PetscCall(AllocSlot(p, j, id, &me.slot));
        StoreSlot(p, j, me.slot, Mirror(LoadSlot(p, i, ne.slot)));
      } else if (me.slot >= 0) {
        FreeSlot(p, j, me.slot);
        me.slot = -1;
      }
    }
  }
  PetscCall(ParticleArraysRestore(dem->swarm, &p));
  PetscFunctionReturn(0);
}

PetscErrorCode DemContactForces(Dem *dem)
{
  const Domain    &dom       = *dem->dom;
  const DemParams &par       = dem->par;
  const PetscReal  dt        = par.dt;
  const PetscInt   nlocal    = (PetscInt)dem->bodies.size() - dem->ghosts.n;
  const PetscReal  period[3] = {dom.periodic[0] ? dom.len[0] : 0.0, dom.periodic[1] ? dom.len[1] : 0.0, dom.periodic[2] ? dom.len[2] : 0.0};
  const bool       periodic  = dom.periodic[0] || dom.periodic[1] || dom.periodic[2];
  const Vec3       g         = dem->body_force_factor * Vec3{dom.gravity[0], dom.gravity[1], dom.gravity[2]};
  NeighbourList   &nl        = dem->nl;
  auto            &contrib   = dem->contributions;
  ParticleArrays   p;
  WallFace         walls[FACE_COUNT];
  int              nwalls   = 0;
  PetscInt64       contacts = 0;
  PetscReal        max_rel  = dem->stats.max_overlap_rel;

  PetscFunctionBeginUser;
  for (int f = 0; f < 2 * dom.dim; ++f) {
    if (!dom.IsParticleWall(f)) continue;
    const int a = f / 2;
    Vec3      n;
    (&n.x)[a]       = (f % 2) ? 1.0 : -1.0;
    walls[nwalls++] = {f, a, (f % 2) ? dom.hi[a] : dom.lo[a], n};
  }
  dem->impulse.assign(3 * (std::size_t)nlocal, 0.0);
  contrib.resize(nl.entries.size());
  dem->contribution_active.resize(nl.entries.size());

  PetscCall(ParticleArraysGet(dem->swarm, &p));
  // Pass 1: each pair once. A pair of two local particles is evaluated from the side with the smaller id and its
  // contribution mirrored into the partner's entry; only that side's history is kept up to date between
  // rebuilds (DemSyncPairHistory copies it to the partner before particles move). A pair with a ghost is
  // evaluated from the local side (the ghost's owner evaluates its own side). Every entry is written every step.
  for (PetscInt i = 0; i < nlocal; ++i) {
    const ContactBody &bi = dem->bodies[(std::size_t)i];
    const PetscInt64   id = dem->body_id[(std::size_t)i];
    for (PetscInt e = nl.start[(std::size_t)i]; e < nl.start[(std::size_t)i + 1]; ++e) {
      NeighbourEntry &ne      = nl.entries[(std::size_t)e];
      const PetscInt  j       = ne.partner;
      const bool      j_local = j < nlocal;
      if (j_local && dem->body_id[(std::size_t)j] < id) continue; // evaluated from j's side
      const ContactBody &bj = dem->bodies[(std::size_t)j];
      Vec3               d  = bj.x - bi.x;
      if (periodic) {
        d.x = kernels::min_image(d.x, period[0]);
        d.y = kernels::min_image(d.y, period[1]);
        d.z = kernels::min_image(d.z, period[2]);
      }
      const PetscReal dist2  = kernels::norm2(d);
      const PetscReal rsum   = bi.r + bj.r;
      unsigned char   active = 1;
      Contribution    c;
      if (dist2 < rsum * rsum) {
        if (ne.slot < 0) PetscCall(AllocSlot(p, i, dem->body_id[(std::size_t)j], &ne.slot));
        const kernels::ContactKinematics kin =
          kernels::pair_kinematics(d, PetscSqrtReal(dist2), bi.r, bj.r, bi.v, bj.v, bi.w, bj.w, ne.sqrt_meff);
        SlotHistory h = LoadSlot(p, i, ne.slot);
        c             = Evaluate(par.pp, kin, dt, h);
        StoreSlot(p, i, ne.slot, h);
        contacts += j_local ? 2 : 1;
        max_rel = PetscMax(max_rel, kin.overlap / (2.0 * PetscMin(bi.r, bj.r)));
      } else if (ne.slot >= 0) {
        c = EndContribution(par.pp, ne.sqrt_meff, (1.0 / PetscSqrtReal(dist2)) * d, dt, LoadSlot(p, i, ne.slot));
        FreeSlot(p, i, ne.slot);
        ne.slot = -1;
        // the partner's copy of the history (from the last sync) ends with the contact, so it never holds more
        // slots than it has contacts
        if (j_local) {
          NeighbourEntry &me = nl.entries[(std::size_t)ne.mirror];
          if (me.slot >= 0) {
            FreeSlot(p, j, me.slot);
            me.slot = -1;
          }
        }
      } else active = 0; // apart: the entry adds nothing and its contribution is not stored
      dem->contribution_active[(std::size_t)e] = active;
      if (active) contrib[(std::size_t)e] = c;
      if (j_local) {
        dem->contribution_active[(std::size_t)ne.mirror] = active;
        if (active) contrib[(std::size_t)ne.mirror] = Mirror(c);
      }
    }
  }

  // Pass 2: each particle sums walls (in face order), then its pairs in increasing partner id, then gravity.
  for (PetscInt i = 0; i < nlocal; ++i) {
    const ContactBody &bi = dem->bodies[(std::size_t)i];
    Sums               sum;

    // One test decides whether this particle is near any wall or still holds a wall contact.
    bool near_wall = dem->wall_mask[(std::size_t)i] != 0;
    for (int k = 0; k < nwalls; ++k)
      near_wall |= ((walls[k].face % 2) ? walls[k].plane - (&bi.x.x)[walls[k].axis] : (&bi.x.x)[walls[k].axis] - walls[k].plane) < bi.r;
    for (int k = 0; k < nwalls && near_wall; ++k) {
      const WallFace &w   = walls[k];
      const PetscReal xa  = (&bi.x.x)[w.axis];
      const PetscReal gap = (w.face % 2) ? w.plane - xa : xa - w.plane;
      const unsigned  bit = 1u << w.face;
      if (gap < bi.r) {
        PetscInt s;
        if (dem->wall_mask[(std::size_t)i] & bit) s = FindSlot(p, i, WallKey(w.face));
        else {
          PetscCall(AllocSlot(p, i, WallKey(w.face), &s));
          dem->wall_mask[(std::size_t)i] |= (unsigned char)bit;
        }
        const kernels::ContactKinematics kin = kernels::wall_kinematics(w.n, gap, bi.r, bi.v, bi.w, bi.m);
        SlotHistory                      h   = LoadSlot(p, i, s);
        sum.Add(Evaluate(par.pw, kin, dt, h), bi.r);
        StoreSlot(p, i, s, h);
        max_rel = PetscMax(max_rel, kin.overlap / (2.0 * bi.r));
        ++contacts;
      } else if (dem->wall_mask[(std::size_t)i] & bit) {
        const PetscInt s = FindSlot(p, i, WallKey(w.face));
        sum.Add(EndContribution(par.pw, PetscSqrtReal(bi.m), w.n, dt, LoadSlot(p, i, s)), bi.r);
        FreeSlot(p, i, s);
        dem->wall_mask[(std::size_t)i] &= (unsigned char)~bit;
      }
    }
    for (PetscInt e = nl.start[(std::size_t)i]; e < nl.start[(std::size_t)i + 1]; ++e)
      if (dem->contribution_active[(std::size_t)e]) sum.Add(contrib[(std::size_t)e], bi.r);

    sum.F += bi.m * g; // gravity, reduced by buoyancy when the gas is on (eq. 2.1)
    p.f[3 * i]                           = sum.F.x;
    p.f[3 * i + 1]                       = sum.F.y;
    p.f[3 * i + 2]                       = sum.F.z;
    p.t[3 * i]                           = sum.T.x;
    p.t[3 * i + 1]                       = sum.T.y;
    p.t[3 * i + 2]                       = sum.T.z;
    dem->impulse[3 * (std::size_t)i]     = sum.J.x;
    dem->impulse[3 * (std::size_t)i + 1] = sum.J.y;
    dem->impulse[3 * (std::size_t)i + 2] = sum.J.z;
  }
  PetscCall(ParticleArraysRestore(dem->swarm, &p));
  dem->stats.contacts        = contacts;
  dem->stats.max_overlap_rel = max_rel;
  if (dem->external) PetscCall(dem->external(dem->external_ctx, dem->swarm, dem->bodies.data()));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
