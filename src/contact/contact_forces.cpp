// Contact forces and torques on the local particles (seed eq. 2.3-2.10) plus gravity: gets the swarm fields,
// loops over walls and neighbour lists, calls the kernel, restores. Each particle sums walls first (in face
// order) and then partners in increasing id, so the result does not depend on the decomposition.
#include "fluidbed/dem.hpp"
#include "fluidbed/kernels/periodic.hpp"

namespace fluidbed {

using kernels::Vec3;

namespace {

// One history slot: xi_t (3), overlap of the previous step, normal dashpot force of the previous step.
struct SlotHistory {
  Vec3      xi;
  PetscReal overlap = 0, damping = 0;
};

inline PetscReal *SlotPtr(const ParticleArrays &p, PetscInt i, PetscInt s) { return &p.chist[kHistoryStride * (p.K * i + s)]; }
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
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "particle %lld has more than %d simultaneous contacts: raise -dem_max_contacts", (long long)p.id[i],
          (int)p.K);
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

// Everything one contact adds to body i, from its kinematics and its history slot.
struct ContactSums {
  Vec3      F, T, J; // force, torque, dashpot impulse correction
  PetscInt64 contacts = 0;
  PetscReal max_rel   = 0;
};

inline void AddContact(const kernels::LsdModel &m, const kernels::ContactKinematics &kin, PetscReal r_i, PetscReal d_ref, PetscReal dt,
                       const ParticleArrays &p, PetscInt i, PetscInt s, ContactSums &sum)
{
  SlotHistory                 h  = LoadSlot(p, i, s);
  const kernels::ContactForce cf = kernels::lsd_contact(m, kin, dt, h.xi);
  sum.J += kernels::damping_impulse_correction(m.damp_n * PetscSqrtReal(kin.m_eff), h.overlap, kin.overlap, h.damping, cf.damping_n, 0.5 * dt, kin.n);
  h.overlap = kin.overlap;
  h.damping = cf.damping_n;
  StoreSlot(p, i, s, h);
  sum.F += cf.normal;
  sum.F += cf.tangential;
  sum.T += r_i * kernels::cross(kin.n, cf.tangential);
  sum.max_rel = PetscMax(sum.max_rel, kin.overlap / d_ref);
  ++sum.contacts;
}

// The contact ended inside this step: close its dashpot impulse (overlap back to zero) and free the slot.
inline void EndContact(const kernels::LsdModel &m, PetscReal m_eff, const Vec3 &n, PetscReal dt, const ParticleArrays &p, PetscInt i, PetscInt s,
                       ContactSums &sum)
{
  const SlotHistory h = LoadSlot(p, i, s);
  sum.J += kernels::damping_impulse_correction(m.damp_n * PetscSqrtReal(m_eff), h.overlap, 0.0, h.damping, 0.0, 0.5 * dt, n);
  p.ckey[p.K * i + s] = kFreeSlot;
  StoreSlot(p, i, s, SlotHistory{});
}

} // namespace

PetscErrorCode DemContactForces(Dem *dem)
{
  const Domain        &dom = *dem->dom;
  const DemParams     &par = dem->par;
  const PetscReal      dt  = par.dt;
  const PetscInt       nlocal = (PetscInt)dem->bodies.size() - dem->ghosts.n;
  const PetscReal      period[3] = {dom.periodic[0] ? dom.len[0] : 0.0, dom.periodic[1] ? dom.len[1] : 0.0, dom.periodic[2] ? dom.len[2] : 0.0};
  const Vec3           g = dem->body_force_factor * Vec3{dom.gravity[0], dom.gravity[1], dom.gravity[2]};
  const NeighbourList &nl = dem->nl;
  ParticleArrays       p;
  WallFace             walls[FACE_COUNT];
  int                  nwalls   = 0;
  PetscInt64           contacts = 0;
  PetscReal            max_rel  = dem->stats.max_overlap_rel;

  PetscFunctionBeginUser;
  for (int f = 0; f < 2 * dom.dim; ++f) {
    if (!dom.IsParticleWall(f)) continue;
    const int a = f / 2;
    Vec3      n;
    (&n.x)[a]       = (f % 2) ? 1.0 : -1.0;
    walls[nwalls++] = {f, a, (f % 2) ? dom.hi[a] : dom.lo[a], n};
  }
  dem->impulse.assign(3 * (std::size_t)nlocal, 0.0);

  PetscCall(ParticleArraysGet(dem->swarm, &p));
  for (PetscInt i = 0; i < nlocal; ++i) {
    const ContactBody &bi = dem->bodies[(std::size_t)i];
    ContactSums        sum;

    for (int k = 0; k < nwalls; ++k) {
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
        AddContact(par.pw, kernels::wall_kinematics(w.n, gap, bi.r, bi.v, bi.w, bi.m), bi.r, 2.0 * bi.r, dt, p, i, s, sum);
      } else if (dem->wall_mask[(std::size_t)i] & bit) {
        EndContact(par.pw, bi.m, w.n, dt, p, i, FindSlot(p, i, WallKey(w.face)), sum);
        dem->wall_mask[(std::size_t)i] &= (unsigned char)~bit;
      }
    }

    for (PetscInt e = nl.start[(std::size_t)i]; e < nl.start[(std::size_t)i + 1]; ++e) {
      const PetscInt     j  = nl.partner[(std::size_t)e];
      const ContactBody &bj = dem->bodies[(std::size_t)j];
      Vec3               d  = bj.x - bi.x;
      d.x                   = kernels::min_image(d.x, period[0]);
      d.y                   = kernels::min_image(d.y, period[1]);
      d.z                   = kernels::min_image(d.z, period[2]);
      const PetscReal dist2 = kernels::norm2(d);
      const PetscReal rsum  = bi.r + bj.r;
      PetscInt       &slot  = dem->nl.slot[(std::size_t)e];
      if (dist2 < rsum * rsum) {
        if (slot < 0) PetscCall(AllocSlot(p, i, dem->body_id[(std::size_t)j], &slot));
        AddContact(par.pp, kernels::pair_kinematics(d, PetscSqrtReal(dist2), bi.r, bj.r, bi.v, bj.v, bi.w, bj.w, bi.m, bj.m), bi.r,
                   2.0 * PetscMin(bi.r, bj.r), dt, p, i, slot, sum);
      } else if (slot >= 0) {
        EndContact(par.pp, bi.m * bj.m / (bi.m + bj.m), (1.0 / PetscSqrtReal(dist2)) * d, dt, p, i, slot, sum);
        slot = -1;
      }
    }

    sum.F += bi.m * g; // gravity, reduced by buoyancy when the gas is on (eq. 2.1)
    p.f[3 * i]     = sum.F.x;
    p.f[3 * i + 1] = sum.F.y;
    p.f[3 * i + 2] = sum.F.z;
    p.t[3 * i]     = sum.T.x;
    p.t[3 * i + 1] = sum.T.y;
    p.t[3 * i + 2] = sum.T.z;
    dem->impulse[3 * (std::size_t)i]     = sum.J.x;
    dem->impulse[3 * (std::size_t)i + 1] = sum.J.y;
    dem->impulse[3 * (std::size_t)i + 2] = sum.J.z;
    contacts += sum.contacts;
    max_rel = PetscMax(max_rel, sum.max_rel);
  }
  PetscCall(ParticleArraysRestore(dem->swarm, &p));
  dem->stats.contacts        = contacts;
  dem->stats.max_overlap_rel = max_rel;
  if (dem->external) PetscCall(dem->external(dem->external_ctx, dem->swarm, dem->bodies.data()));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
