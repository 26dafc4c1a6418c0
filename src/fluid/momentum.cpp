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

struct Cell {
  PetscInt c[3];
  Cell     operator()(int a, PetscInt d) const
  {
    Cell q = *this;
    q.c[a] += d;
    return q;
  }
};

} // namespace

PetscErrorCode FluidPredictor(Fluid *f, PetscReal dt)
{
  FieldView              U, E0, E, S, Un;
  const PetscReal        nu  = f->mu / f->rho;
  const kernels::Limiter lim = f->limiter;
  const int              dim = (int)f->dim;

  PetscFunctionBeginUser;
  PetscCall(FieldGet(f->da_u, f->u_loc, PETSC_TRUE, &U));
  PetscCall(FieldGet(f->da_s, f->eps_old_loc, PETSC_TRUE, &E0));
  PetscCall(FieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &E));
  PetscCall(FieldGet(f->da_c, f->source_loc, PETSC_TRUE, &S));
  FieldView B;
  PetscCall(FieldGet(f->da_s, f->drag_loc, PETSC_TRUE, &B));
  PetscCall(FieldGet(f->da_u, f->u, PETSC_FALSE, &Un));
  // volume flux through the lower b-face of cell q, at the old void fraction
  auto flux = [&](const Cell &q, int b) { return FaceEps(E0, q.c, b) * U.at(q.c, b) * f->area[b]; };
  ForEachOwnedCell(f, [&](PetscInt i, PetscInt j, PetscInt k) {
    const Cell P = {{i, j, k}};
    for (int a = 0; a < dim; ++a) {
      if (!f->periodic[a] && P.c[a] == 0) continue; // boundary face: set by the boundary conditions
      const Cell L    = P(a, -1);
      auto       u    = [&](const Cell &q) { return U.at(q.c, a); };
      PetscReal  conv = 0, visc = 0;
      for (int b = 0; b < dim; ++b) {
        if (b == a) {
          // faces of the control volume at the centres of cells P (upper) and L (lower)
          const PetscReal Fhi = 0.5 * (flux(P, a) + flux(P(a, 1), a)), Flo = 0.5 * (flux(L, a) + flux(P, a));
          const PetscReal vhi = kernels::upwind_face_value(lim, Fhi, u(P(a, -1)), u(P), u(P(a, 1)), u(P(a, 2)));
          const PetscReal vlo = kernels::upwind_face_value(lim, Flo, u(P(a, -2)), u(P(a, -1)), u(P), u(P(a, 1)));
          conv += Fhi * vhi - Flo * vlo;
          visc += f->area[a] / f->h[a] * (E0.at(P.c) * (u(P(a, 1)) - u(P)) - E0.at(L.c) * (u(P) - u(L)));
        } else {
          // faces of the control volume on the b-faces of cells L and P (lower) and their upper neighbours
          const PetscReal Flo = 0.5 * (flux(L, b) + flux(P, b)), Fhi = 0.5 * (flux(L(b, 1), b) + flux(P(b, 1), b));
          PetscReal       vlo = kernels::upwind_face_value(lim, Flo, u(P(b, -2)), u(P(b, -1)), u(P), u(P(b, 1)));
          PetscReal       vhi = kernels::upwind_face_value(lim, Fhi, u(P(b, -1)), u(P), u(P(b, 1)), u(P(b, 2)));
          if (!f->periodic[b]) {
            // on the boundary the carried value is the boundary's when the flow comes in, the interior's when it leaves
            if (P.c[b] == 0) vlo = Flo > 0 ? f->wall_velocity[2 * b][a] : u(P);
            if (P.c[b] == f->n[b] - 1) vhi = Fhi < 0 ? f->wall_velocity[2 * b + 1][a] : u(P);
          }
          conv += Fhi * vhi - Flo * vlo;
          const PetscReal elo = 0.25 * (E0.at(L.c) + E0.at(P.c) + E0.at(L(b, -1).c) + E0.at(P(b, -1).c));
          const PetscReal ehi = 0.25 * (E0.at(L.c) + E0.at(P.c) + E0.at(L(b, 1).c) + E0.at(P(b, 1).c));
          visc += f->area[b] / f->h[b] * (ehi * (u(P(b, 1)) - u(P)) - elo * (u(P) - u(P(b, -1))));
        }
      }
      const PetscReal eps_old = FaceEps(E0, P.c, a), eps_new = FaceEps(E, P.c, a);
      const PetscReal gravity = f->rho * f->dom->gravity[a] * (f->model == FLUID_MODEL_B ? 1.0 : eps_new);
      const PetscReal source  = 0.5 * (S.at(L.c, a) + S.at(P.c, a)) + f->body_force[a];
      const PetscReal m       = eps_old * u(P) + dt * ((nu * visc - conv) / f->vol + (source + gravity) / f->rho);
      const PetscReal beta    = f->has_drag ? FaceEps(B, P.c, a) : 0.0; // implicit drag: m = (eps + dt beta / rho) u*
      Un.at(P.c, a)           = m / (eps_new + dt * beta / f->rho);
    }
  });
  PetscCall(FieldRestore(f->u, &Un));
  PetscCall(FieldRestore(f->drag_loc, &B));
  PetscCall(FieldRestore(f->source_loc, &S));
  PetscCall(FieldRestore(f->eps_loc, &E));
  PetscCall(FieldRestore(f->eps_old_loc, &E0));
  PetscCall(FieldRestore(f->u_loc, &U));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidStepRates(Fluid *f, kernels::StepRates *rates)
{
  FieldView       U, E;
  PetscReal       loc[2] = {0, 0}, glob[2], max_speed = 0, gmax;
  const PetscReal nu  = f->mu / f->rho;
  const PetscReal psi = kernels::limiter_psi_max(f->limiter);

  PetscFunctionBeginUser;
  PetscCall(FieldGet(f->da_u, f->u_loc, PETSC_TRUE, &U));
  PetscCall(FieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &E));
  ForEachOwnedCell(f, [&](PetscInt i, PetscInt j, PetscInt k) {
    const Cell P        = {{i, j, k}};
    PetscReal  speed[3] = {0, 0, 0}, emin = E.at(P.c), emax = E.at(P.c);
    for (int a = 0; a < f->dim; ++a) {
      speed[a] = PetscMax(PetscAbsReal(U.at(P.c, a)), PetscAbsReal(U.at(P(a, 1).c, a)));
      for (int d = -1; d <= 1; d += 2) {
        emin = PetscMin(emin, E.at(P(a, d).c));
        emax = PetscMax(emax, E.at(P(a, d).c));
      }
      max_speed = PetscMax(max_speed, speed[a]);
    }
    const kernels::StepRates r = kernels::explicit_step_rates((int)f->dim, speed, f->h, nu, psi, emax / emin);
    loc[0]                     = PetscMax(loc[0], r.conv);
    loc[1]                     = PetscMax(loc[1], r.visc);
  });
  PetscCall(FieldRestore(f->eps_loc, &E));
  PetscCall(FieldRestore(f->u_loc, &U));
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

} // namespace fluidbed
