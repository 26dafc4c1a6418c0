// Momentum predictor on the staggered grid and the explicit time-step limits.
//
// For each velocity face (component a) the control volume spans the two cells that share the face. Its faces carry
// the volume flux F = the average of the two neighbouring cell-face fluxes eps_f u A (so a discretely
// divergence-free eps u gives a divergence-free transport field for the momentum volumes too), and the transported
// velocity is the TVD-limited upwind value (kernels/fluid_flux.hpp). The viscous term is mu div(eps grad u_a), with
// eps at the cell centre (faces normal to a) or averaged over the four cells around the edge (other faces).
#include "fluid_impl.hpp"

namespace fluidbed {

namespace {

// The volume flux eps_f u_b A_b through the lower b-face of each cell at the old void fraction, flux[b * N + p] for
// the cell at offset p of the ghosted layout of U and E0 (N cells): the owned cells and one layer around them, all
// that the control volumes of the owned faces touch.
void FaceFluxes(const Fluid *f, const DMDAField &U, const DMDAField &E0, PetscInt N, PetscReal *flux)
{
  const PetscInt dof = U.dof;
  for (int b = 0; b < f->dim; ++b) {
    const PetscInt   sb = U.stride(b);
    const PetscReal *e0 = E0.a, *u = U.a + b;
    PetscReal       *Fb = flux + b * N;
    PetscInt         lo[3], hi[3];
    OwnedBox(f, lo, hi);
    for (int d = 0; d < f->dim; ++d) lo[d] -= 1;
    hi[b] += 1;
    ForEachCellInBox(U, lo, hi, [&](PetscInt p) { Fb[p] = 0.5 * (e0[p - sb] + e0[p]) * u[p * dof] * f->area[b]; });
  }
}

// The convective transport F v through the faces of the control volumes of velocity component a, each computed
// once although it is the upper face of one control volume and the lower face of the next: F the mean of the two
// cell-face fluxes it lies between, v the TVD-limited upwind value. G[b * N + p] is the face normal to b
// - b = a: at the centre of the cell at offset p (the upper face of the control volume of the a-face of that cell);
// - b != a: between the a-faces of the cells p and p - a, on their lower b-faces (the lower face of the control
//   volume of the a-face of cell p).
template <kernels::Limiter L>
void ControlVolumeTransport(const Fluid *f, const DMDAField &U, const PetscReal *flux, PetscInt N, int a, PetscReal *G)
{
  const PetscInt   dof = U.dof, sa = U.stride(a);
  const PetscReal *u = U.a + a; // u[p * dof]: component a at the cell at offset p
  for (int b = 0; b < f->dim; ++b) {
    const PetscInt   sb = U.stride(b);
    const PetscReal *Fb = flux + b * N;
    PetscReal       *Gb = G + b * N;
    PetscInt         lo[3], hi[3];
    OwnedBox(f, lo, hi);
    if (b == a) {
      lo[a] -= 1; // the lower face of the first control volume is the centre of the cell below it
      ForEachCellInBox(U, lo, hi, [&](PetscInt p) {
        const PetscReal F = 0.5 * (Fb[p] + Fb[p + sa]);
        Gb[p]             = F * kernels::upwind_face_value<L>(F, u[(p - sa) * dof], u[p * dof], u[(p + sa) * dof], u[(p + 2 * sa) * dof]);
      });
      continue;
    }
    hi[b] += 1; // the upper face of the last control volume
    ForEachCellInBox(U, lo, hi, [&](PetscInt p) {
      const PetscReal F = 0.5 * (Fb[p - sa] + Fb[p]);
      Gb[p]             = F * kernels::upwind_face_value<L>(F, u[(p - 2 * sb) * dof], u[(p - sb) * dof], u[p * dof], u[(p + sb) * dof]);
    });
    if (f->periodic[b]) continue;
    // on the boundary the carried value is the boundary's when the flow comes in, the interior's when it leaves
    for (int side = 0; side < 2; ++side) {
      const PetscInt e = side ? f->n[b] : 0;
      if (e < lo[b] || e >= hi[b]) continue; // not on this rank
      PetscInt plo[3] = {lo[0], lo[1], lo[2]}, phi[3] = {hi[0], hi[1], hi[2]};
      plo[b]               = e;
      phi[b]               = e + 1;
      const PetscReal wall = f->wall_velocity[2 * b + side][a];
      ForEachCellInBox(U, plo, phi, [&](PetscInt p) {
        const PetscReal F = 0.5 * (Fb[p - sa] + Fb[p]);
        Gb[p]             = F * (side ? (F < 0 ? wall : u[(p - sb) * dof]) : (F > 0 ? wall : u[p * dof]));
      });
    }
  }
}

// The predicted velocity of component a on the faces this rank owns, boundary faces excepted (set by the boundary
// conditions), from the transport G of ControlVolumeTransport.
void PredictComponent(const Fluid *f, PetscReal dt, int a, const DMDAField &U, const DMDAField &E0, const DMDAField &E, const DMDAField &S,
                      const DMDAField &B, const DMDAField &Un, const PetscReal *G, PetscInt N)
{
  const int        dim = (int)f->dim;
  const PetscInt   dof = U.dof, sa = U.stride(a), sdof = S.dof, ssa = S.stride(a);
  const PetscReal  nu = f->mu / f->rho, rho_g = f->rho * f->dom->gravity[a];
  const PetscReal *u = U.a + a, *e0 = E0.a, *e = E.a, *s = S.a + a, *be = B.a;
  PetscReal       *un = Un.a + a;
  PetscReal        coef[3];
  PetscInt         st[3], lo[3], hi[3];
  for (int b = 0; b < 3; ++b) {
    coef[b] = f->area[b] / f->h[b];
    st[b]   = U.stride(b);
  }
  OwnedBox(f, lo, hi);
  if (!f->periodic[a]) lo[a] = PetscMax(lo[a], 1); // boundary face: set by the boundary conditions
  for (PetscInt k = lo[2]; k < hi[2]; ++k)
    for (PetscInt j = lo[1]; j < hi[1]; ++j) {
      PetscInt p = U.cell(lo[0], j, k), ps = S.cell(lo[0], j, k), q = Un.cell(lo[0], j, k);
      for (PetscInt i = lo[0]; i < hi[0]; ++i, ++p, ++ps, ++q) {
        const PetscInt l    = p - sa; // the cell below the face
        PetscReal      conv = 0, visc = 0;
        for (int b = 0; b < dim; ++b) {
          const PetscReal *Gb = G + b * N;
          const PetscInt   sb = st[b];
          if (b == a) {
            // faces of the control volume at the centres of cells P (upper) and L (lower)
            conv += Gb[p] - Gb[l];
            visc += coef[a] * (e0[p] * (u[(p + sa) * dof] - u[p * dof]) - e0[l] * (u[p * dof] - u[l * dof]));
          } else {
            // faces of the control volume on the b-faces of cells L and P (lower) and their upper neighbours
            conv += Gb[p + sb] - Gb[p];
            const PetscReal elo = 0.25 * (e0[l] + e0[p] + e0[l - sb] + e0[p - sb]);
            const PetscReal ehi = 0.25 * (e0[l] + e0[p] + e0[l + sb] + e0[p + sb]);
            visc += coef[b] * (ehi * (u[(p + sb) * dof] - u[p * dof]) - elo * (u[p * dof] - u[(p - sb) * dof]));
          }
        }
        const PetscReal eps_old = 0.5 * (e0[l] + e0[p]), eps_new = 0.5 * (e[l] + e[p]);
        const PetscReal gravity = rho_g * (f->model == FLUID_MODEL_B ? 1.0 : eps_new);
        const PetscReal source  = 0.5 * (s[(ps - ssa) * sdof] + s[ps * sdof]) + f->body_force[a];
        const PetscReal m       = eps_old * u[p * dof] + dt * ((nu * visc - conv) / f->vol + (source + gravity) / f->rho);
        const PetscReal beta    = f->has_drag ? 0.5 * (be[l] + be[p]) : 0.0; // implicit drag: m = (eps + dt beta / rho) u*
        un[q * dof]             = m / (eps_new + dt * beta / f->rho);
      }
    }
}

template <kernels::Limiter L>
void Predict(Fluid *f, PetscReal dt, const DMDAField &U, const DMDAField &E0, const DMDAField &E, const DMDAField &S, const DMDAField &B,
             const DMDAField &Un)
{
  const PetscInt N    = U.m[0] * U.m[1] * U.m[2];
  PetscReal     *flux = FluidWork(f, (std::size_t)(2 * f->dim * N)), *G = flux + f->dim * N;
  FaceFluxes(f, U, E0, N, flux);
  for (int a = 0; a < f->dim; ++a) {
    ControlVolumeTransport<L>(f, U, flux, N, a, G);
    PredictComponent(f, dt, a, U, E0, E, S, B, Un, G, N);
  }
}

} // namespace

PetscErrorCode FluidPredictor(Fluid *f, PetscReal dt)
{
  DMDAField U, E0, E, S, B, Un;

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(f->da_u, f->u_loc, PETSC_TRUE, &U));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_old_loc, PETSC_TRUE, &E0));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &E));
  PetscCall(DMDAFieldGet(f->da_c, f->source_loc, PETSC_TRUE, &S));
  PetscCall(DMDAFieldGet(f->da_s, f->drag_loc, PETSC_TRUE, &B));
  PetscCall(DMDAFieldGet(f->da_u, f->u, PETSC_FALSE, &Un));
  // U, E0, E and B share one ghosted layout (da_u and da_s: the same grid, stencil and ghosts), so one cell offset
  // addresses them all
  PetscCheck(SameLayout(U, E0) && SameLayout(U, E) && SameLayout(U, B), f->comm, PETSC_ERR_PLIB,
             "the velocity and scalar ghosted layouts differ");
  switch (f->limiter) {
  case kernels::Limiter::Upwind:
    Predict<kernels::Limiter::Upwind>(f, dt, U, E0, E, S, B, Un);
    break;
  case kernels::Limiter::VanLeer:
    Predict<kernels::Limiter::VanLeer>(f, dt, U, E0, E, S, B, Un);
    break;
  case kernels::Limiter::Koren:
    Predict<kernels::Limiter::Koren>(f, dt, U, E0, E, S, B, Un);
    break;
  case kernels::Limiter::Minmod:
    Predict<kernels::Limiter::Minmod>(f, dt, U, E0, E, S, B, Un);
    break;
  case kernels::Limiter::Superbee:
    Predict<kernels::Limiter::Superbee>(f, dt, U, E0, E, S, B, Un);
    break;
  }
  PetscCall(DMDAFieldRestore(f->u, &Un));
  PetscCall(DMDAFieldRestore(f->drag_loc, &B));
  PetscCall(DMDAFieldRestore(f->source_loc, &S));
  PetscCall(DMDAFieldRestore(f->eps_loc, &E));
  PetscCall(DMDAFieldRestore(f->eps_old_loc, &E0));
  PetscCall(DMDAFieldRestore(f->u_loc, &U));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidStepRates(Fluid *f, kernels::StepRates *rates)
{
  DMDAField       U, E;
  PetscReal       loc[2] = {0, 0}, glob[2], max_speed = 0, gmax;
  const PetscReal nu  = f->mu / f->rho;
  const PetscReal psi = kernels::limiter_psi_max(f->limiter);

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(f->da_u, f->u_loc, PETSC_TRUE, &U));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &E));
  {
    const int                   dim = (int)f->dim;
    const PetscInt              dof = U.dof;
    const PetscReal            *u = U.a, *e = E.a;
    const kernels::StepRateGrid grid = kernels::step_rate_grid(dim, f->h, nu, psi);
    PetscInt                    su[3], se[3];
    for (int a = 0; a < 3; ++a) {
      su[a] = U.stride(a);
      se[a] = E.stride(a);
    }
    ForEachOwnedOffset(f, U, E, [&](PetscInt pu, PetscInt pe) {
      PetscReal speed[3] = {0, 0, 0}, emin = e[pe], emax = e[pe];
      for (int a = 0; a < dim; ++a) {
        speed[a] = PetscMax(PetscAbsReal(u[pu * dof + a]), PetscAbsReal(u[(pu + su[a]) * dof + a]));
        for (int d = -1; d <= 1; d += 2) {
          emin = PetscMin(emin, e[pe + d * se[a]]);
          emax = PetscMax(emax, e[pe + d * se[a]]);
        }
        max_speed = PetscMax(max_speed, speed[a]);
      }
      const kernels::StepRates r = kernels::explicit_step_rates(grid, speed, emax / emin);
      loc[0]                     = PetscMax(loc[0], r.conv);
      loc[1]                     = PetscMax(loc[1], r.visc);
    });
  }
  PetscCall(DMDAFieldRestore(f->eps_loc, &E));
  PetscCall(DMDAFieldRestore(f->u_loc, &U));
  // a moving wall drives the cells next to it before they move
  for (int face = 0; face < 2 * f->dim; ++face) {
    if (f->periodic[face / 2] || f->bc[face] != FLUID_BC_NOSLIP) continue;
    PetscReal speed[3] = {0, 0, 0};
    for (int a = 0; a < f->dim; ++a) speed[a] = f->wall_velocity[face][a];
    loc[0] = PetscMax(loc[0], kernels::explicit_step_rates((int)f->dim, speed, f->h, 0.0, psi, 1.0).conv);
  }
  PetscCallMPI(MPI_Allreduce(loc, glob, 2, MPIU_REAL, MPI_MAX, f->comm));
  PetscCallMPI(MPI_Allreduce(&max_speed, &gmax, 1, MPIU_REAL, MPI_MAX, f->comm));
  rates->conv        = glob[0];
  rates->visc        = glob[1];
  f->stats.max_speed = gmax;
  PetscFunctionReturn(0);
}

// The convective rate an inlet still ramping up (-inlet_ramp_time) will reach at its full speed: the full
// superficial velocity through the least void fraction of the bottom row, with that void fraction's inverse bounding
// the ratio of the rates (eps_max <= 1). Zero once the ramp is over. Steps chosen from the limits (FluidMaxTimeStep)
// then stay stable as the inflow grows.
PetscErrorCode FluidInletRampRate(Fluid *f, PetscReal *conv)
{
  PetscReal loc = 0;

  PetscFunctionBeginUser;
  *conv = 0;
  // the same on every rank: no reduction once the ramp is over, or without one
  if (!(FluidInletScale(f, f->time) < 1) || f->periodic[1]) PetscFunctionReturn(0);
  if (f->xs[1] == 0) { // the ranks holding the bottom row
    DMDAField e;
    PetscReal vmax = 0, emin = 1;
    for (PetscReal v : f->inlet.velocity) vmax = PetscMax(vmax, PetscAbsReal(v));
    PetscCall(DMDAFieldGet(f->da_p, f->eps, PETSC_FALSE, &e));
    for (PetscInt k = f->xs[2]; k < f->xs[2] + f->xm[2]; ++k)
      for (PetscInt i = f->xs[0]; i < f->xs[0] + f->xm[0]; ++i) emin = PetscMin(emin, e(i, 0, k));
    PetscCall(DMDAFieldRestore(f->eps, &e));
    const PetscReal speed[3] = {0, vmax / emin, 0};
    loc = kernels::explicit_step_rates((int)f->dim, speed, f->h, 0.0, kernels::limiter_psi_max(f->limiter), 1.0 / emin).conv;
  }
  PetscCallMPI(MPI_Allreduce(&loc, conv, 1, MPIU_REAL, MPI_MAX, f->comm));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
