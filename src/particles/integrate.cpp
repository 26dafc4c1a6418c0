// Velocity-Verlet loops over the local particles (kernels/verlet.hpp) and the per-step packing of the contact
// bodies with predicted velocities.
#include "fluidbed/particle_system.hpp"
#include "fluidbed/kernels/periodic.hpp"
#include "fluidbed/kernels/verlet.hpp"

#include <cmath>
#include <limits>

namespace fluidbed {

using kernels::Vec3;

namespace {

inline Vec3 Load3(const PetscReal *a, PetscInt i)
{
  return {a[3 * i], a[3 * i + 1], a[3 * i + 2]};
}
inline void Store3(PetscReal *a, PetscInt i, const Vec3 &v)
{
  a[3 * i]     = v.x;
  a[3 * i + 1] = v.y;
  a[3 * i + 2] = v.z;
}

// A particle's mass and the inverses of its mass and moment of inertia, recomputed only when the diameter differs
// from the previous particle's: a monodisperse bed computes them once per loop instead of dividing per particle.
// The values are those of the expressions below whatever the order of the particles.
struct MassTerms {
  const ParticleProps &props;
  PetscReal            d = std::numeric_limits<PetscReal>::quiet_NaN(); // never equal: the first call computes
  PetscReal            m = 0, inv_m = 0, inv_I = 0;

  void Set(PetscReal di)
  {
    if (di == d) return;
    d     = di;
    m     = props.Mass(di);
    inv_m = 1.0 / m;
    inv_I = 1.0 / kernels::sphere_inertia(m, di);
  }
};

// Planar motion (2D grids or -dem_pseudo2d): no out-of-plane velocity, spin only about z.
inline void ConstrainPlanar(Vec3 &v, Vec3 &w)
{
  v.z = 0.0;
  w.x = w.y = 0.0;
}

} // namespace

PetscErrorCode ParticlesKickDrift(ParticleSystem *ps, PetscBool *need_rebuild)
{
  const Domain   &dom = *ps->dom;
  const PetscReal dt = ps->dt, h = 0.5 * dt;
  const bool      planar = dom.dim == 2 || ps->pseudo2d;
  const PetscReal outlet = dom.top_outlet ? dom.hi[1] : PETSC_MAX_REAL;
  ParticleArrays  p;
  PetscBool       rebuild = PETSC_FALSE;
  MassTerms       mt{*ps->props};
  PetscReal       step2  = 0.0; // largest (|v| dt / d)^2 of this step
  bool            finite = true;

  PetscFunctionBeginUser;
  PetscCall(ParticleArraysGet(ps->swarm, &p));
  const PetscInt dim = p.dim;
  for (PetscInt i = 0; i < p.n; ++i) {
    mt.Set(p.d[i]);
    Vec3 v = Load3(p.v, i), w = Load3(p.w, i);
    kernels::kick(v, Load3(p.f, i), mt.inv_m, h);
    kernels::kick(w, Load3(p.t, i), mt.inv_I, h);
    if (planar) ConstrainPlanar(v, w);
    Store3(p.v, i, v);
    Store3(p.w, i, w);
    const PetscReal vv[3] = {v.x, v.y, v.z};
    PetscReal       d2    = 0.0;
    for (PetscInt a = 0; a < dim; ++a) {
      PetscReal x = p.x[dim * i + a] + dt * vv[a];
      if (dom.periodic[a]) {
        if (x >= dom.hi[a]) x -= dom.len[a];
        else if (x < dom.lo[a]) x += dom.len[a];
      }
      p.x[dim * i + a]   = x;
      const PetscReal dx = kernels::min_image(x - ps->x_ref[3 * i + a], dom.periodic[a] ? dom.len[a] : 0.0);
      d2 += dx * dx;
    }
    if (d2 > ps->x_move[(std::size_t)i] * ps->x_move[(std::size_t)i]) rebuild = PETSC_TRUE; // moved its share of the skin
    // a particle past the outlet leaves in this step: the rebuild removes and counts it (ParticlesMigrate)
    if (p.x[dim * i + 1] >= outlet) rebuild = PETSC_TRUE;
    // for the guards: the step's largest move in diameters, and whether the motion is still a number
    const PetscReal v2 = kernels::dot(v, v), s2 = v2 * (dt * dt) / (p.d[i] * p.d[i]);
    step2  = PetscMax(step2, s2);
    finite = finite && std::isfinite(v2 + kernels::dot(w, w));
  }
  PetscCall(ParticleArraysRestore(ps->swarm, &p));
  ps->stats.guard_step_rel = PetscMax(ps->stats.guard_step_rel, PetscSqrtReal(step2));
  if (!finite) ps->stats.nonfinite = PETSC_TRUE;
  *need_rebuild = rebuild;
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesKick(ParticleSystem *ps)
{
  const PetscReal h      = 0.5 * ps->dt;
  const bool      planar = ps->dom->dim == 2 || ps->pseudo2d;
  ParticleArrays  p;
  MassTerms       mt{*ps->props};
  bool            finite = true;

  PetscFunctionBeginUser;
  PetscCall(ParticleArraysGet(ps->swarm, &p));
  for (PetscInt i = 0; i < p.n; ++i) {
    mt.Set(p.d[i]);
    Vec3 v = Load3(p.v, i), w = Load3(p.w, i);
    kernels::kick(v, Load3(p.f, i), mt.inv_m, h);
    v += mt.inv_m * Load3(ps->impulse.data(), i); // exact dashpot impulse (kernels/contact_lsd.hpp)
    kernels::kick(w, Load3(p.t, i), mt.inv_I, h);
    if (planar) ConstrainPlanar(v, w);
    Store3(p.v, i, v);
    Store3(p.w, i, w);
    finite = finite && std::isfinite(kernels::dot(v, v) + kernels::dot(w, w));
  }
  PetscCall(ParticleArraysRestore(ps->swarm, &p));
  if (!finite) ps->stats.nonfinite = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode ParticlesPackBodies(ParticleSystem *ps)
{
  const PetscReal h = 0.5 * ps->dt;
  ParticleArrays  p;
  MassTerms       mt{*ps->props};

  PetscFunctionBeginUser;
  PetscCall(ParticleArraysGet(ps->swarm, &p));
  ps->bodies.resize((std::size_t)(p.n + ps->ghosts.n));
  for (PetscInt i = 0; i < p.n; ++i) {
    ParticleBody &b = ps->bodies[(std::size_t)i];
    mt.Set(p.d[i]);
    b.x = {p.x[p.dim * i], p.x[p.dim * i + 1], p.dim == 3 ? p.x[3 * i + 2] : 0.0};
    b.v = kernels::predicted_velocity(Load3(p.v, i), Load3(p.f, i), mt.inv_m, h);
    b.w = kernels::predicted_velocity(Load3(p.w, i), Load3(p.t, i), mt.inv_I, h);
    b.r = 0.5 * p.d[i];
    b.m = mt.m;
  }
  PetscCall(ParticleArraysRestore(ps->swarm, &p));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
