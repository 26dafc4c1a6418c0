// Momentum predictor on the staggered grid and the explicit time-step limits.
//
// For each velocity face (component a) the control volume spans the two cells that share the face. Its faces carry
// the volume flux F = the average of the two neighbouring cell-face fluxes eps_f u A (so a discretely
// divergence-free eps u gives a divergence-free transport field for the momentum volumes too), and the transported
// velocity is the TVD-limited upwind value (kernels/fluid_flux.hpp). The viscous term is mu div(eps grad u_a), with
// eps at the cell centre (faces normal to a) or averaged over the four cells around the edge (other faces).
#include <type_traits>
#include <utility>

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

// Calls fn(std::integral_constant<int, b>) for b = 0, ..., N - 1 in that order: loops over directions whose bounds
// and branches the compiler resolves (the sums keep their order, so the results are those of the plain loops).
template <class Fn, int... B>
inline void StaticForImpl(Fn &&fn, std::integer_sequence<int, B...>)
{
  (fn(std::integral_constant<int, B>{}), ...);
}
template <int N, class Fn>
inline void StaticFor(Fn &&fn)
{
  StaticForImpl(fn, std::make_integer_sequence<int, N>{});
}

// The convective transport F v through the faces of the control volumes of velocity component A, each computed
// once although it is the upper face of one control volume and the lower face of the next: F the mean of the two
// cell-face fluxes it lies between, v the TVD-limited upwind value. G[b * N + p] is the face normal to b
// - b = A: at the centre of the cell at offset p (the upper face of the control volume of the A-face of that cell);
// - b != A: between the A-faces of the cells p and p - A, on their lower b-faces (the lower face of the control
//   volume of the A-face of cell p).
// U holds DIM components per cell (da_u), so its offsets are known to the compiler.
template <kernels::Limiter L, int DIM, int A>
void ControlVolumeTransport(const Fluid *f, const DMDAField &U, const PetscReal *flux, PetscInt N, PetscReal *G)
{
  constexpr PetscInt dof = DIM;
  const PetscInt     sa  = U.stride(A);
  const PetscReal   *u   = U.a + A; // u[p * dof]: component A at the cell at offset p
  StaticFor<DIM>([&](auto bc) {
    constexpr int    b  = decltype(bc)::value;
    const PetscInt   sb = U.stride(b);
    const PetscReal *Fb = flux + b * N;
    PetscReal       *Gb = G + b * N;
    PetscInt         lo[3], hi[3];
    OwnedBox(f, lo, hi);
    if constexpr (b == A) {
      lo[A] -= 1; // the lower face of the first control volume is the centre of the cell below it
      ForEachCellInBox(U, lo, hi, [&](PetscInt p) {
        const PetscReal F = 0.5 * (Fb[p] + Fb[p + sa]);
        Gb[p]             = F * kernels::upwind_face_value<L>(F, u[(p - sa) * dof], u[p * dof], u[(p + sa) * dof], u[(p + 2 * sa) * dof]);
      });
    } else {
      hi[b] += 1; // the upper face of the last control volume
      ForEachCellInBox(U, lo, hi, [&](PetscInt p) {
        const PetscReal F = 0.5 * (Fb[p - sa] + Fb[p]);
        Gb[p]             = F * kernels::upwind_face_value<L>(F, u[(p - 2 * sb) * dof], u[(p - sb) * dof], u[p * dof], u[(p + sb) * dof]);
      });
      if (f->periodic[b]) return;
      // on the boundary the carried value is the boundary's when the flow comes in, the interior's when it leaves
      for (int side = 0; side < 2; ++side) {
        const PetscInt e = side ? f->n[b] : 0;
        if (e < lo[b] || e >= hi[b]) continue; // not on this rank
        PetscInt plo[3] = {lo[0], lo[1], lo[2]}, phi[3] = {hi[0], hi[1], hi[2]};
        plo[b]               = e;
        phi[b]               = e + 1;
        const PetscReal wall = f->wall_velocity[2 * b + side][A];
        ForEachCellInBox(U, plo, phi, [&](PetscInt p) {
          const PetscReal F = 0.5 * (Fb[p - sa] + Fb[p]);
          Gb[p]             = F * (side ? (F < 0 ? wall : u[(p - sb) * dof]) : (F > 0 ? wall : u[p * dof]));
        });
      }
    }
  });
}

// The predicted velocity of component A on the faces this rank owns, boundary faces excepted (set by the boundary
// conditions), from the transport G of ControlVolumeTransport. The fluid's constants are read once into locals:
// the stores into Un could alias them, which made the compiler load them again for every face.
template <int DIM, int A>
void PredictComponent(const Fluid *f, PetscReal dt, const DMDAField &U, const DMDAField &E0, const DMDAField &E, const DMDAField &S,
                      const DMDAField &B, const DMDAField &Un, const PetscReal *G, PetscInt N)
{
  constexpr PetscInt dof = DIM; // U, S and Un: da_u and da_c, one component per direction
  const PetscInt     sa = U.stride(A), ssa = S.stride(A);
  const PetscReal    nu = f->mu / f->rho, rho_g = f->rho * f->dom->gravity[A];
  const PetscReal    rho = f->rho, vol = f->vol, body_force = f->body_force[A];
  const bool         model_b = f->model == FLUID_MODEL_B, has_drag = f->has_drag;
  const PetscReal   *u = U.a + A, *e0 = E0.a, *e = E.a, *s = S.a + A, *be = B.a;
  PetscReal         *un = Un.a + A;
  PetscReal          coef[3];
  PetscInt           st[3], lo[3], hi[3];
  const PetscReal   *Gs[3];
  for (int b = 0; b < 3; ++b) {
    coef[b] = f->area[b] / f->h[b];
    st[b]   = U.stride(b);
    Gs[b]   = G + b * N;
  }
  OwnedBox(f, lo, hi);
  if (!f->periodic[A]) lo[A] = PetscMax(lo[A], 1); // boundary face: set by the boundary conditions
  for (PetscInt k = lo[2]; k < hi[2]; ++k)
    for (PetscInt j = lo[1]; j < hi[1]; ++j) {
      PetscInt p = U.cell(lo[0], j, k), ps = S.cell(lo[0], j, k), q = Un.cell(lo[0], j, k);
      for (PetscInt i = lo[0]; i < hi[0]; ++i, ++p, ++ps, ++q) {
        const PetscInt l    = p - sa; // the cell below the face
        PetscReal      conv = 0, visc = 0;
        StaticFor<DIM>([&](auto bc) {
          constexpr int    b  = decltype(bc)::value;
          const PetscReal *Gb = Gs[b];
          if constexpr (b == A) {
            // faces of the control volume at the centres of cells P (upper) and L (lower)
            conv += Gb[p] - Gb[l];
            visc += coef[A] * (e0[p] * (u[(p + sa) * dof] - u[p * dof]) - e0[l] * (u[p * dof] - u[l * dof]));
          } else {
            // faces of the control volume on the b-faces of cells L and P (lower) and their upper neighbours
            const PetscInt sb = st[b];
            conv += Gb[p + sb] - Gb[p];
            const PetscReal elo = 0.25 * (e0[l] + e0[p] + e0[l - sb] + e0[p - sb]);
            const PetscReal ehi = 0.25 * (e0[l] + e0[p] + e0[l + sb] + e0[p + sb]);
            visc += coef[b] * (ehi * (u[(p + sb) * dof] - u[p * dof]) - elo * (u[p * dof] - u[(p - sb) * dof]));
          }
        });
        const PetscReal eps_old = 0.5 * (e0[l] + e0[p]), eps_new = 0.5 * (e[l] + e[p]);
        const PetscReal gravity = rho_g * (model_b ? 1.0 : eps_new);
        const PetscReal source  = 0.5 * (s[(ps - ssa) * dof] + s[ps * dof]) + body_force;
        const PetscReal m       = eps_old * u[p * dof] + dt * ((nu * visc - conv) / vol + (source + gravity) / rho);
        const PetscReal beta    = has_drag ? 0.5 * (be[l] + be[p]) : 0.0; // implicit drag: m = (eps + dt beta / rho) u*
        un[q * dof]             = m / (eps_new + dt * beta / rho);
      }
    }
}

template <kernels::Limiter L, int DIM>
void Predict(Fluid *f, PetscReal dt, const DMDAField &U, const DMDAField &E0, const DMDAField &E, const DMDAField &S, const DMDAField &B,
             const DMDAField &Un)
{
  const PetscInt N    = U.m[0] * U.m[1] * U.m[2];
  PetscReal     *flux = FluidWork(f, (std::size_t)(2 * DIM * N)), *G = flux + DIM * N;
  FaceFluxes(f, U, E0, N, flux);
  StaticFor<DIM>([&](auto ac) {
    constexpr int A = decltype(ac)::value;
    ControlVolumeTransport<L, DIM, A>(f, U, flux, N, G);
    PredictComponent<DIM, A>(f, dt, U, E0, E, S, B, Un, G, N);
  });
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
  // one velocity component per direction in U, S and Un (the predictor's offsets count on it)
  PetscCheck(U.dof == f->dim && S.dof == f->dim && Un.dof == f->dim, f->comm, PETSC_ERR_PLIB,
             "the velocity layouts do not hold %d components", (int)f->dim);
  kernels::with_limiter(f->limiter, [&](auto lc) {
    constexpr kernels::Limiter L = decltype(lc)::value;
    if (f->dim == 2) Predict<L, 2>(f, dt, U, E0, E, S, B, Un);
    else Predict<L, 3>(f, dt, U, E0, E, S, B, Un);
  });
  PetscCall(DMDAFieldRestore(f->u, &Un));
  PetscCall(DMDAFieldRestore(f->drag_loc, &B));
  PetscCall(DMDAFieldRestore(f->source_loc, &S));
  PetscCall(DMDAFieldRestore(f->eps_loc, &E));
  PetscCall(DMDAFieldRestore(f->eps_old_loc, &E0));
  PetscCall(DMDAFieldRestore(f->u_loc, &U));
  PetscFunctionReturn(0);
}

namespace {

// The largest convective and viscous rates of the owned cells (loc[0], loc[1]) and the largest face speed, for a grid
// of DIM dimensions (U holds DIM components per cell).
template <int DIM>
void MaxCellRates(const Fluid *f, const DMDAField &U, const DMDAField &E, const kernels::StepRateGrid &grid, PetscReal loc[2],
                  PetscReal *max_speed)
{
  constexpr PetscInt dof = DIM;
  const PetscReal   *u = U.a, *e = E.a;
  PetscInt           su[3], se[3];
  for (int a = 0; a < 3; ++a) {
    su[a] = U.stride(a);
    se[a] = E.stride(a);
  }
  PetscReal conv = loc[0], visc = loc[1], top = *max_speed; // in registers through the loop
  ForEachOwnedOffset(f, U, E, [&](PetscInt pu, PetscInt pe) {
    PetscReal speed[3] = {0, 0, 0}, emin = e[pe], emax = e[pe];
    for (int a = 0; a < DIM; ++a) {
      speed[a] = PetscMax(PetscAbsReal(u[pu * dof + a]), PetscAbsReal(u[(pu + su[a]) * dof + a]));
      for (int d = -1; d <= 1; d += 2) {
        emin = PetscMin(emin, e[pe + d * se[a]]);
        emax = PetscMax(emax, e[pe + d * se[a]]);
      }
      top = PetscMax(top, speed[a]);
    }
    const kernels::StepRates r = kernels::explicit_step_rates<DIM>(grid, speed, emax / emin);
    conv                       = PetscMax(conv, r.conv);
    visc                       = PetscMax(visc, r.visc);
  });
  loc[0]     = conv;
  loc[1]     = visc;
  *max_speed = top;
}

} // namespace

PetscErrorCode FluidStepRates(Fluid *f, kernels::StepRates *rates)
{
  DMDAField       U, E;
  PetscReal       loc[2] = {0, 0}, glob[2], max_speed = 0, gmax;
  const PetscReal nu  = f->mu / f->rho;
  const PetscReal psi = kernels::limiter_psi_max(f->limiter);

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(f->da_u, f->u_loc, PETSC_TRUE, &U));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &E));
  PetscCheck(U.dof == f->dim, f->comm, PETSC_ERR_PLIB, "the velocity layout does not hold %d components", (int)f->dim);
  {
    const kernels::StepRateGrid grid = kernels::step_rate_grid((int)f->dim, f->h, nu, psi);
    if (f->dim == 2) MaxCellRates<2>(f, U, E, grid, loc, &max_speed);
    else MaxCellRates<3>(f, U, E, grid, loc, &max_speed);
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
