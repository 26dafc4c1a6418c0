// What the run-time guards (src/guards) ask of the contact stage when a limit is broken (the contact with the largest
// overlap), and the mechanical energy of the system, springs included. Collective; run only at guard checks, never
// in the step.
#include "dem_impl.hpp"
#include "fluidbed/kernels/periodic.hpp"
#include "fluidbed/kernels/verlet.hpp"

namespace fluidbed {

using kernels::Vec3;

PetscErrorCode DemLocateMaxOverlap(Dem *dem, ParticleSite *site)
{
  const Domain        &dom    = *dem->dom;
  const NeighbourList &nl     = dem->nl;
  const PetscInt       nlocal = (PetscInt)dem->bodies.size() - dem->ghosts.n;
  PetscReal            period[3];

  PetscFunctionBeginUser;
  for (int a = 0; a < 3; ++a) period[a] = dom.periodic[a] ? dom.len[a] : 0.0;
  *site       = ParticleSite{};
  site->value = -1.0;
  for (PetscInt i = 0; i < nlocal && i + 1 < (PetscInt)nl.pair_start.size(); ++i) {
    const ParticleBody &bi       = dem->bodies[(std::size_t)i];
    auto                consider = [&](PetscReal rel, PetscInt64 partner) {
      if (rel > site->value) {
        site->value   = rel;
        site->id      = dem->body_id[(std::size_t)i];
        site->partner = partner;
        site->x[0]    = bi.x.x;
        site->x[1]    = bi.x.y;
        site->x[2]    = bi.x.z;
      }
    };
    for (PetscInt q = nl.pair_start[(std::size_t)i]; q < nl.pair_start[(std::size_t)i + 1]; ++q) {
      const PetscInt      j  = nl.pairs[(std::size_t)q].partner;
      const ParticleBody &bj = dem->bodies[(std::size_t)j];
      Vec3                d  = bj.x - bi.x;
      d.x                    = kernels::min_image(d.x, period[0]);
      d.y                    = kernels::min_image(d.y, period[1]);
      d.z                    = kernels::min_image(d.z, period[2]);
      consider((bi.r + bj.r - kernels::norm(d)) / (2.0 * PetscMin(bi.r, bj.r)), dem->body_id[(std::size_t)j]);
    }
    for (PetscInt k = nl.wall_start[(std::size_t)i]; k < nl.wall_start[(std::size_t)i + 1]; ++k) {
      const int       face = (int)nl.walls[(std::size_t)k].face;
      const PetscReal gap  = dom.WallGap(face, &bi.x.x);
      consider((bi.r - gap) / (2.0 * bi.r), WallKey(face));
    }
  }
  PetscCall(ParticleSiteReduce(PetscObjectComm((PetscObject)dem->swarm), site));
  PetscFunctionReturn(0);
}

PetscErrorCode DemMechanicalEnergy(Dem *dem, PetscReal *energy)
{
  const Domain        &dom    = *dem->dom;
  const NeighbourList &nl     = dem->nl;
  const PetscInt       nlocal = (PetscInt)nl.start.size() - 1;
  ParticleArrays       p;
  PetscReal            e = 0.0;

  PetscFunctionBeginUser;
  PetscCall(ParticleArraysGet(dem->swarm, &p));
  for (PetscInt i = 0; i < p.n; ++i) {
    const PetscReal m = dem->props->Mass(p.d[i]), I = kernels::sphere_inertia(m, p.d[i]);
    const Vec3      v{p.v[3 * i], p.v[3 * i + 1], p.v[3 * i + 2]}, w{p.w[3 * i], p.w[3 * i + 1], p.w[3 * i + 2]};
    e += 0.5 * m * kernels::norm2(v) + 0.5 * I * kernels::norm2(w);
    for (PetscInt a = 0; a < p.dim; ++a) e -= m * dem->body_force_factor * dom.gravity[a] * (p.x[p.dim * i + a] - dom.lo[a]);
  }
  PetscCall(ParticleArraysRestore(dem->swarm, &p));
  // the springs of the contacts in touch: a pair of local particles is listed once, a pair with a ghost on both
  // ranks (half each)
  for (PetscInt i = 0; i < nlocal; ++i) {
    for (PetscInt q = nl.pair_start[(std::size_t)i]; q < nl.pair_start[(std::size_t)i + 1]; ++q) {
      const ContactPair &pr = nl.pairs[(std::size_t)q];
      if (pr.slot < 0) continue;
      e += (pr.partner < nlocal ? 1.0 : 0.5) * dem->contact.elastic_energy(*dem, nl.PairHistory(q), false);
    }
    for (PetscInt k = nl.wall_start[(std::size_t)i]; k < nl.wall_start[(std::size_t)i + 1]; ++k) {
      const WallContact &wc = nl.walls[(std::size_t)k];
      if (wc.slot >= 0) e += dem->contact.elastic_energy(*dem, nl.WallHistory(k), true);
    }
  }
  PetscCallMPI(MPI_Allreduce(&e, energy, 1, MPIU_REAL, MPI_SUM, PetscObjectComm((PetscObject)dem->swarm)));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
