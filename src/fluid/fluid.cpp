// The gas phase: options, fields, the step (predictor, pressure, correction) and the fields the coupling uses.
#include "fluid_impl.hpp"
#include "fluidbed/files.hpp"
#include "fluidbed/options.hpp"

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <string>

namespace fluidbed {

const char *const FluidModelTypes[]   = {"B", "A", "FluidModel", "FLUID_MODEL_", NULL};
const char *const FluidLimiterTypes[] = {"upwind", "vanleer", "koren", "minmod", "superbee", "Limiter", "LIMITER_", NULL};

namespace {

// A DMDA with the fine grid's layout (sizes, process grid, ownership); ghosted: DM_BOUNDARY_GHOSTED on the
// non-periodic directions, so that every rank has ghost layers beyond the boundaries.
PetscErrorCode CreateLayoutDA(Fluid *f, PetscInt dof, DMDAStencilType st, PetscInt sw, PetscBool ghosted, DM *da)
{
  const std::vector<PetscInt> *own = f->grid->own;
  DMBoundaryType               bt[3];
  PetscInt                     procs[3] = {1, 1, 1};

  PetscFunctionBeginUser;
  for (int a = 0; a < 3; ++a) {
    bt[a] = f->periodic[a] ? DM_BOUNDARY_PERIODIC : (ghosted ? DM_BOUNDARY_GHOSTED : DM_BOUNDARY_NONE);
    if (a < f->dim) procs[a] = (PetscInt)own[a].size();
  }
  const PetscInt *const owned[3] = {own[0].data(), own[1].data(), own[2].data()};
  PetscCall(DMDACreateLayout(f->comm, f->dim, bt, st, f->n, procs, owned, dof, sw, da));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidReadOptions(Fluid *f)
{
  PetscInt  n;
  PetscBool set;
  PetscEnum model = (PetscEnum)f->model, lim = (PetscEnum)f->limiter;

  PetscFunctionBeginUser;
  PetscOptionsBegin(f->comm, "fluid_", "Gas phase: volume-averaged incompressible flow (seed eq. 2.19-2.20)", "Fluid");
  PetscCall(OptionsEnum(PetscOptionsObject, "-model", "Momentum equation: B (-grad p, rho_g g; the seed's) or A (-eps grad p, eps rho_g g)",
                        FluidModelTypes, &model, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-rho", "Gas density", "kg/m^3", Positive(1e5), &f->rho, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-mu", "Gas dynamic viscosity", "Pa s", Positive(1e3), &f->mu, NULL));
  PetscCall(OptionsEnum(PetscOptionsObject, "-limiter", "TVD limiter of the convective fluxes", FluidLimiterTypes, &lim, NULL));
  PetscCall(
    OptionsBool(PetscOptionsObject, "-deps_dt", "Keep d(eps)/dt in the continuity equation (the seed drops it)", &f->deps_dt, NULL));
  n = 3;
  PetscCall(OptionsRealArray(PetscOptionsObject, "-body_force",
                             "Uniform momentum source fx,fy,fz added to the coupling's (e.g. a mean pressure gradient)", "N/m^3",
                             Closed(-1e9, 1e9), f->body_force, &n, PETSC_TRUE, NULL));
  n = 3;
  PetscCall(OptionsRealArray(PetscOptionsObject, "-initial_velocity", "Initial superficial gas velocity ux,uy,uz", "m/s", Closed(-1e4, 1e4),
                             f->initial_velocity, &n, PETSC_TRUE, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-dt", "Fixed gas time step (0: from the CFL and viscous limits at every step)", "s",
                        NonNegative(1e3), &f->dt_fixed, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-cfl", "Fraction of the combined convective + viscous explicit limit used as the step", "",
                        Closed(0.01, 1.0), &f->cfl, NULL));
  PetscCall(OptionsInt(PetscOptionsObject, "-pc_reuse",
                       "Rebuild the pressure preconditioner only every N solves while the matrix changes (model A eps, implicit drag)", 1,
                       1000000, &f->pc_reuse, NULL));
  PetscCall(OptionsBool(PetscOptionsObject, "-output_cells", "Write fluid_cells.csv (cell fields in natural ordering) at the end",
                        &f->output_cells, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-eps", "Frozen uniform void fraction when no particles are coupled", "",
                        {0.0, 1.0, true, false}, &f->eps_uniform, NULL));
  n = 5;
  PetscCall(OptionsRealArray(PetscOptionsObject, "-eps_sphere", "Frozen sphere (circle in 2D) of void fraction: centre x,y,z, radius, eps",
                             "m,m,m,m,-", Closed(-100.0, 100.0), f->eps_sphere, &n, PETSC_TRUE, &f->has_sphere));
  n = 3;
  PetscCall(OptionsRealArray(PetscOptionsObject, "-eps_sphere_velocity",
                             "Velocity of the frozen sphere: its void fraction field moves with it", "m/s", Closed(-1e3, 1e3),
                             f->sphere_velocity, &n, PETSC_TRUE, NULL));
  n = 2;
  PetscCall(OptionsRealArray(PetscOptionsObject, "-eps_packed_bed",
                             "Frozen packed bed: the cells below height get void fraction eps: height,eps", "m,-", Closed(0.0, 100.0),
                             f->eps_bed, &n, PETSC_TRUE, &f->has_bed));
  PetscOptionsEnd();
  f->model   = (FluidModel)model;
  f->limiter = (kernels::Limiter)lim;
  PetscCheck(!f->has_sphere || (f->eps_sphere[4] > 0 && f->eps_sphere[4] <= 1), f->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "-fluid_eps_sphere: void fraction %.6g is out of range: allowed (0, 1]", (double)f->eps_sphere[4]);
  PetscCheck(!f->has_sphere || f->eps_sphere[3] > 0, f->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "-fluid_eps_sphere: radius %.6g m is out of range: allowed (0, inf)", (double)f->eps_sphere[3]);
  PetscCheck(!f->has_bed || (f->eps_bed[1] > 0 && f->eps_bed[1] <= 1), f->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "-fluid_eps_packed_bed: void fraction %.6g is out of range: allowed (0, 1]", (double)f->eps_bed[1]);
  (void)set;
  PetscFunctionReturn(0);
}

// Frozen void fraction at time t: uniform, then the packed bed, then the sphere (centre moving with its velocity).
PetscErrorCode SetFrozenVoidFraction(Fluid *f, PetscReal t)
{
  DMDAField e;

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(f->da_p, f->eps, PETSC_FALSE, &e));
  ForEachOwnedCell(f, [&](PetscInt i, PetscInt j, PetscInt k) {
    const PetscInt c[3] = {i, j, k};
    PetscReal      x[3], r2 = 0;
    PetscScalar    val = f->eps_uniform;
    for (int a = 0; a < 3; ++a) x[a] = f->dom->lo[a] + (c[a] + 0.5) * f->h[a];
    if (f->has_bed && x[1] < f->dom->lo[1] + f->eps_bed[0]) val = f->eps_bed[1];
    for (int a = 0; a < f->dim; ++a) {
      const PetscReal d = x[a] - (f->eps_sphere[a] + f->sphere_velocity[a] * t);
      r2 += d * d;
    }
    if (f->has_sphere && r2 < f->eps_sphere[3] * f->eps_sphere[3]) val = f->eps_sphere[4];
    e(i, j, k) = val;
  });
  PetscCall(DMDAFieldRestore(f->eps, &e));
  PetscFunctionReturn(0);
}

PetscErrorCode ScatterScalars(Fluid *f)
{
  PetscFunctionBeginUser;
  PetscCall(DMGlobalToLocal(f->da_s, f->eps, INSERT_VALUES, f->eps_loc));
  PetscCall(FluidFillGhosts(f, f->eps_loc, 0));
  PetscCall(DMGlobalToLocal(f->da_s, f->eps_old, INSERT_VALUES, f->eps_old_loc));
  PetscCall(FluidFillGhosts(f, f->eps_old_loc, 0));
  PetscCall(DMGlobalToLocal(f->da_c, f->source, INSERT_VALUES, f->source_loc));
  PetscCall(DMGlobalToLocal(f->da_s, f->drag, INSERT_VALUES, f->drag_loc));
  PetscCall(FluidFillGhosts(f, f->drag_loc, 0));
  {
    PetscReal m;
    PetscCall(VecMax(f->drag, NULL, &m));
    f->has_drag = m > 0 ? PETSC_TRUE : PETSC_FALSE;
  }
  PetscFunctionReturn(0);
}

// Initial velocity: the superficial velocity divided by the face void fraction on the interior faces.
PetscErrorCode SetInitialVelocity(Fluid *f)
{
  DMDAField u, e;

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(f->da_u, f->u, PETSC_FALSE, &u));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &e));
  ForEachOwnedCell(f, [&](PetscInt i, PetscInt j, PetscInt k) {
    const PetscInt c[3] = {i, j, k};
    for (int a = 0; a < f->dim; ++a) u(i, j, k, a) = f->initial_velocity[a] / FaceEps(e, c, a);
  });
  PetscCall(DMDAFieldRestore(f->eps_loc, &e));
  PetscCall(DMDAFieldRestore(f->u, &u));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FluidCreate(MPI_Comm comm, const Domain &domain, const FluidGrid &grid, PhaseLog *log, Fluid **fluid)
{
  Fluid *f = new Fluid;

  PetscFunctionBeginUser;
  *fluid  = f;
  f->comm = comm;
  f->dom  = &domain;
  f->grid = &grid;
  f->log  = log;
  f->dim  = domain.dim;
  for (int a = 0; a < 3; ++a) {
    f->n[a]        = a < f->dim ? grid.n[a] : 1;
    f->h[a]        = a < f->dim ? grid.h[a] : domain.len[2];
    f->periodic[a] = (PetscBool)(a < f->dim && domain.periodic[a]);
  }
  for (int a = 0; a < 3; ++a) f->area[a] = f->h[(a + 1) % 3] * f->h[(a + 2) % 3];
  f->vol = f->h[0] * f->h[1] * f->h[2];
  PetscCall(FluidReadOptions(f));
  PetscCall(FluidReadBoundaryOptions(f));

  // The gas stencil is 2 cells wide: PETSc's DMDA stops a rank that owns fewer, on that rank alone (the others
  // wait for it). Every rank holds all ownership ranges, so every rank checks them.
  for (int a = 0; a < f->dim; ++a)
    for (std::size_t r = 0; r < grid.own[a].size(); ++r)
      PetscCheck((grid.own[a].size() == 1 && !f->periodic[a]) || grid.own[a][r] >= 2, comm, PETSC_ERR_USER_INPUT,
                 "-grid_n%c %d split over %d ranks along %c leaves %d fluid cell(s) to a rank; the gas needs at least 2 per rank: use "
                 "fewer ranks, more -grid_n%c cells or another -pgrid_processors",
                 "xyz"[a], (int)f -> n[a], (int)grid.own[a].size(), "xyz"[a], (int)grid.own[a][r], "xyz"[a]);

  PetscCall(CreateLayoutDA(f, 1, DMDA_STENCIL_BOX, 2, PETSC_TRUE, &f->da_s));
  PetscCall(CreateLayoutDA(f, f->dim, DMDA_STENCIL_BOX, 2, PETSC_TRUE, &f->da_u));
  PetscCall(CreateLayoutDA(f, f->dim, DMDA_STENCIL_STAR, 1, PETSC_FALSE, &f->da_c));
  PetscCall(CreateLayoutDA(f, 1, DMDA_STENCIL_STAR, 1, PETSC_FALSE, &f->da_p));
  PetscCall(PetscObjectSetName((PetscObject)f->da_p, "fluid_pressure_grid"));
  PetscCall(DMDAGetCorners(f->da_p, &f->xs[0], &f->xs[1], &f->xs[2], &f->xm[0], &f->xm[1], &f->xm[2]));
  if (f->dim == 2) {
    f->xs[2] = 0;
    f->xm[2] = 1;
  }
  PetscCall(DMCreateGlobalVector(f->da_u, &f->u));
  PetscCall(PetscObjectSetName((PetscObject)f->u, "face_velocity"));
  PetscCall(DMCreateLocalVector(f->da_u, &f->u_loc));
  PetscCall(DMCreateGlobalVector(f->da_p, &f->eps));
  PetscCall(PetscObjectSetName((PetscObject)f->eps, "void_fraction"));
  PetscCall(VecDuplicate(f->eps, &f->eps_old));
  PetscCall(VecDuplicate(f->eps, &f->phi));
  PetscCall(VecDuplicate(f->eps, &f->rhs));
  PetscCall(VecDuplicate(f->eps, &f->p));
  PetscCall(VecDuplicate(f->eps, &f->u_top));
  PetscCall(PetscObjectSetName((PetscObject)f->p, "pressure"));
  PetscCall(DMCreateLocalVector(f->da_s, &f->eps_loc));
  PetscCall(VecDuplicate(f->eps_loc, &f->eps_old_loc));
  PetscCall(VecDuplicate(f->eps_loc, &f->u_top_loc));
  PetscCall(DMCreateLocalVector(f->da_p, &f->phi_loc));
  PetscCall(DMCreateGlobalVector(f->da_c, &f->source));
  PetscCall(PetscObjectSetName((PetscObject)f->source, "momentum_source"));
  PetscCall(VecDuplicate(f->source, &f->cell_u));
  PetscCall(PetscObjectSetName((PetscObject)f->cell_u, "cell_velocity"));
  PetscCall(DMCreateLocalVector(f->da_c, &f->source_loc));
  PetscCall(VecDuplicate(f->eps, &f->drag));
  PetscCall(PetscObjectSetName((PetscObject)f->drag, "drag_coefficient"));
  PetscCall(VecDuplicate(f->eps_loc, &f->drag_loc));
  PetscCall(VecSet(f->eps, 1.0));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSetUp(Fluid *f)
{
  PetscReal dt_max;

  PetscFunctionBeginUser;
  PetscCall(SetFrozenVoidFraction(f, 0.0));
  PetscCall(VecCopy(f->eps, f->eps_old));
  PetscCall(ScatterScalars(f));
  PetscCall(SetInitialVelocity(f));
  PetscCall(FluidSetBoundaryFaces(f, 0.0, PETSC_FALSE));
  PetscCall(FluidScatterVelocity(f));
  PetscCall(FluidPressureCreate(f));
  PetscCall(FluidMaxTimeStep(f, &dt_max)); // the step limits of the initial state (stats.dt_conv, dt_visc)
  PetscCall(FluidFlowRates(f, &f->stats.inflow, &f->stats.outflow));
  if (f->dt_fixed > 0) {
    PetscCheck(f->dt_fixed <= dt_max * (1 + 1e-12), f->comm, PETSC_ERR_USER_INPUT,
               "-fluid_dt %.6g s exceeds the gas time-step limit %.6g s (convective %.6g s, viscous %.6g s at -fluid_cfl %.6g)",
               (double)f->dt_fixed, (double)dt_max, (double)f->stats.dt_conv, (double)f->stats.dt_visc, (double)f->cfl);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidMaxTimeStep(Fluid *f, PetscReal *dt)
{
  kernels::StepRates r;

  PetscFunctionBeginUser;
  // the void fraction the coupling may have written since the last step
  PetscCall(DMGlobalToLocal(f->da_s, f->eps, INSERT_VALUES, f->eps_loc));
  PetscCall(FluidFillGhosts(f, f->eps_loc, 0));
  PetscCall(FluidStepRates(f, &r));
  {
    PetscReal ramp;
    PetscCall(FluidInletRampRate(f, &ramp));
    r.conv = PetscMax(r.conv, ramp);
  }
  f->stats.dt_conv = r.conv > 0 ? f->cfl / r.conv : PETSC_MAX_REAL;
  f->stats.dt_visc = r.visc > 0 ? f->cfl / r.visc : PETSC_MAX_REAL;
  *dt              = f->cfl / (r.conv + r.visc);
  PetscFunctionReturn(0);
}

PetscReal FluidFixedTimeStep(const Fluid *f)
{
  return f->dt_fixed;
}

PetscReal FluidCfl(const Fluid *f)
{
  return f->cfl;
}

PetscErrorCode FluidStep(Fluid *f, PetscReal dt)
{
  PetscFunctionBeginUser;
  PetscCall(PhaseBegin(f->log, PHASE_FLUID));
  if (f->has_sphere && (f->sphere_velocity[0] != 0 || f->sphere_velocity[1] != 0 || f->sphere_velocity[2] != 0))
    PetscCall(SetFrozenVoidFraction(f, f->time + dt)); // gas-only scenes: the void fraction at the end of the step
  PetscCall(ScatterScalars(f));
  PetscCall(FluidScatterVelocity(f));
  {
    // In coupled runs the step is fixed (DEM step x -couple_substeps) while the gas speeds up in jets and bubbles:
    // measure how close it is to the explicit limit (the Courant guard, src/guards, warns and stops on it).
    kernels::StepRates r;
    PetscCall(FluidStepRates(f, &r));
    f->stats.courant = dt * (r.conv + r.visc);
    if (f->stats.courant > f->stats.courant_max) {
      f->stats.courant_max      = f->stats.courant;
      f->stats.courant_max_time = f->time;
    }
  }
  PetscCall(FluidPredictor(f, dt));
  PetscCall(FluidSetBoundaryFaces(f, dt, PETSC_TRUE));
  PetscCall(FluidScatterVelocity(f));
  PetscCall(PhaseEnd(f->log, PHASE_FLUID));

  PetscCall(PhaseBegin(f->log, PHASE_PRESSURE));
  PetscCall(FluidPressureSolve(f, dt));
  PetscCall(PhaseEnd(f->log, PHASE_PRESSURE));

  PetscCall(PhaseBegin(f->log, PHASE_FLUID));
  PetscCall(FluidCorrect(f, dt));
  PetscCall(FluidScatterVelocity(f));
  PetscCall(FluidDivergence(f, dt, &f->stats.max_div));
  PetscCall(FluidFlowRates(f, &f->stats.inflow, &f->stats.outflow));
  PetscCall(VecCopy(f->eps, f->eps_old));
  PetscCall(VecAXPBY(f->p, f->rho / dt, 0.0, f->phi));
  f->stats.dt = dt;
  f->stats.steps++;
  f->time += dt;
  PetscCall(PhaseEnd(f->log, PHASE_FLUID));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetVoidFraction(Fluid *f, Vec *eps)
{
  PetscFunctionBeginUser;
  *eps = f->eps;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetMomentumSource(Fluid *f, Vec *source)
{
  PetscFunctionBeginUser;
  *source = f->source;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetDragCoefficient(Fluid *f, Vec *beta)
{
  PetscFunctionBeginUser;
  *beta = f->drag;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetPressure(Fluid *f, Vec *p)
{
  PetscFunctionBeginUser;
  *p = f->p;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetPressureMatrix(Fluid *f, Mat *A)
{
  PetscFunctionBeginUser;
  *A = f->A;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetPressureStencilMatrix(Fluid *f, Mat *A)
{
  PetscFunctionBeginUser;
  *A = f->op.A;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetCellDMs(Fluid *f, DM *scalar, DM *vector)
{
  PetscFunctionBeginUser;
  if (scalar) *scalar = f->da_p;
  if (vector) *vector = f->da_c;
  PetscFunctionReturn(0);
}

const FluidStats &FluidGetStats(const Fluid *f)
{
  return f->stats;
}
PetscBool FluidWantsCellsCSV(const Fluid *f)
{
  return f->output_cells;
}

PetscErrorCode FluidGetCellVelocity(Fluid *f, Vec *velocity)
{
  DMDAField u, c;

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(f->da_u, f->u_loc, PETSC_TRUE, &u));
  PetscCall(DMDAFieldGet(f->da_c, f->cell_u, PETSC_FALSE, &c));
  {
    const PetscInt st[3] = {u.stride(0), u.stride(1), u.stride(2)}, dof = u.dof;
    ForEachOwnedOffset(f, u, c, [&](PetscInt p, PetscInt q) {
      for (int a = 0; a < f->dim; ++a) c.a[q * c.dof + a] = 0.5 * (u.a[p * dof + a] + u.a[(p + st[a]) * dof + a]);
    });
  }
  PetscCall(DMDAFieldRestore(f->cell_u, &c));
  PetscCall(DMDAFieldRestore(f->u_loc, &u));
  *velocity = f->cell_u;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidView(Fluid *f, PetscViewer viewer)
{
  const char *model = f->model == FLUID_MODEL_B ? "B (-grad p, rho_g g)" : "A (-eps grad p, eps rho_g g)";
  std::string bcs;
  PetscReal   dt = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, "Gas: rho %.6g kg/m^3, mu %.4g Pa s, model %s, %s limiter, d(eps)/dt %s\n", (double)f->rho,
                                   (double)f->mu, model, FluidLimiterTypes[(int)f->limiter], f->deps_dt ? "kept" : "dropped (seed)"));
  for (int face = 0; face < 2 * f->dim; ++face) {
    if (!bcs.empty()) bcs += ", ";
    bcs += std::string(FluidFaceKeys[face]) + " " + (f->periodic[face / 2] ? "periodic" : FluidBCTypes[f->bc[face]]);
  }
  PetscCall(PetscViewerASCIIPrintf(viewer, "Gas boundaries: %s\n", bcs.c_str()));
  if (f->inflow_rate != 0 || !f->inlet.openings.empty())
    PetscCall(PetscViewerASCIIPrintf(viewer, "Gas inlet: %s, inflow %.6g m^3/s (%.6g m/s superficial over the bottom)\n",
                                     f->inlet.summary.c_str(), (double)f->inflow_rate,
                                     (double)(f->inflow_rate / (f->dom->len[0] * f->dom->len[2]))));
  if (f->inlet_ramp > 0)
    PetscCall(PetscViewerASCIIPrintf(viewer,
                                     "  ramped up linearly over the first %.6g s (-inlet_ramp_time); the gas step limits count the "
                                     "inlet at full speed\n",
                                     (double)f->inlet_ramp));
  const std::vector<kernels::JetCells> &jets = f->inlet.openings;
  for (std::size_t s = 0; s < jets.size(); ++s)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  slit %d: x = %.6g..%.6g mm (cells %ld..%ld), %.6g m/s\n", (int)s + 1,
                                     1e3 * (f->dom->lo[0] + jets[s].first * f->h[0]), 1e3 * (f->dom->lo[0] + jets[s].last * f->h[0]),
                                     jets[s].first, jets[s].last - 1, jets[s].velocity));
  PetscCall(FluidMaxTimeStep(f, &dt));
  {
    char conv[32] = "inf (gas at rest)";
    if (f->stats.dt_conv < PETSC_MAX_REAL) PetscCall(PetscSNPrintf(conv, sizeof(conv), "%.4g s", (double)f->stats.dt_conv));
    PetscCall(PetscViewerASCIIPrintf(
      viewer, "Gas time step limits (-fluid_cfl %.3g, %s limiter): convective %s, viscous %.4g s, combined %.4g s; %s %.4g s\n",
      (double)f->cfl, FluidLimiterTypes[(int)f->limiter], conv, (double)f->stats.dt_visc, (double)dt,
      f->dt_fixed > 0 ? "fixed step (-fluid_dt)" : "step follows the limits, now", (double)(f->dt_fixed > 0 ? f->dt_fixed : dt)));
  }
  {
    const char *ktype, *ptype;
    PetscCall(FluidSolverNames(f, &ktype, &ptype));
    PetscCall(PetscViewerASCIIPrintf(viewer, "Pressure: %s Poisson equation, %s + %s (-fluid_p_ksp_type, -fluid_p_pc_type)%s\n",
                                     f->model == FLUID_MODEL_B ? "constant-coefficient" : "variable-coefficient (eps)", ktype, ptype,
                                     f->has_dirichlet ? ", p = 0 at the outlet" : ", pure Neumann (constant null space)"));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidAddSummary(Fluid *f, JsonWriter *json)
{
  const FluidStats &s = f->stats;
  JsonWriter        g;
  const char       *kt, *pt;

  PetscFunctionBeginUser;
  PetscCall(FluidSolverNames(f, &kt, &pt));
  g.String("model", FluidModelTypes[f->model]);
  g.Integer("steps", (long long)s.steps);
  g.Number("dt_last", s.dt);
  g.Number("dt_conv", s.dt_conv);
  g.Number("dt_visc", s.dt_visc);
  g.String("ksp_type", kt);
  g.String("pc_type", pt);
  g.Integer("pressure_solves", (long long)s.solves);
  g.Integer("pressure_pc_setups", (long long)s.pc_setups);
  {
    PC        pc;
    PetscBool is_fp;
    PetscInt  setups = 0, jacobi_setups = 0;
    PetscReal contrast_max = 0;
    PetscCall(KSPGetPC(f->ksp, &pc));
    PetscCall(PCFastPoissonGetStats(pc, &is_fp, &setups, &jacobi_setups, &contrast_max));
    if (is_fp) {
      g.Number("pressure_pc_contrast_max", contrast_max);
      g.Integer("pressure_pc_jacobi_setups", (long long)jacobi_setups);
    }
  }
  g.Number("pressure_iterations_per_solve", s.solves ? (double)s.ksp_its_total / (double)s.solves : 0.0);
  g.Number("pressure_time_per_solve", s.solves ? s.ksp_time_total / (double)s.solves : 0.0);
  g.Integer("pressure_iterations_last", (long long)s.ksp_its);
  g.Number("pressure_residual_last", s.ksp_rnorm);
  g.Number("pressure_time_last", s.ksp_time);
  g.Number("max_div", s.max_div);
  g.Number("max_speed", s.max_speed);
  g.Number("courant_max", s.courant_max);
  g.Number("courant_max_time", s.courant_max_time);
  g.Number("inflow", s.inflow);
  g.Number("outflow", s.outflow);
  json->Object("fluid", g);
  PetscFunctionReturn(0);
}

PetscErrorCode FluidWriteCellsCSV(Fluid *f, const char *path)
{
  constexpr int          kCols = 12; // index, eps, p, u, v, w, ufx, ufy, ufz + padding
  PetscMPIInt            rank, size;
  DMDAField              u, e, p;
  Vec                    cu;
  DMDAField              c;
  std::vector<PetscReal> rows;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(f->comm, &rank));
  PetscCallMPI(MPI_Comm_size(f->comm, &size));
  PetscCall(FluidGetCellVelocity(f, &cu));
  PetscCall(DMDAFieldGet(f->da_u, f->u_loc, PETSC_TRUE, &u));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &e));
  PetscCall(DMDAFieldGet(f->da_p, f->p, PETSC_FALSE, &p));
  PetscCall(DMDAFieldGet(f->da_c, cu, PETSC_FALSE, &c));
  ForEachOwnedCell(f, [&](PetscInt i, PetscInt j, PetscInt k) {
    PetscReal r[kCols] = {0};
    r[0]               = (PetscReal)(i + f->n[0] * (j + f->n[1] * k)); // natural index, exact below 2^53
    r[1]               = e(i, j, k);
    r[2]               = p(i, j, k);
    for (int a = 0; a < f->dim; ++a) {
      r[3 + a] = c(i, j, k, a);
      r[6 + a] = u(i, j, k, a);
    }
    rows.insert(rows.end(), r, r + kCols);
  });
  PetscCall(DMDAFieldRestore(cu, &c));
  PetscCall(DMDAFieldRestore(f->p, &p));
  PetscCall(DMDAFieldRestore(f->eps_loc, &e));
  PetscCall(DMDAFieldRestore(f->u_loc, &u));

  int              nloc = (int)rows.size();
  std::vector<int> counts(size), displs(size, 0);
  PetscCallMPI(MPI_Gather(&nloc, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, f->comm));
  std::vector<PetscReal> all;
  if (!rank) {
    for (int q = 1; q < size; ++q) displs[q] = displs[q - 1] + counts[q - 1];
    all.resize((std::size_t)(displs[size - 1] + counts[size - 1]));
  }
  PetscCallMPI(MPI_Gatherv(rows.data(), nloc, MPIU_REAL, all.data(), counts.data(), displs.data(), MPIU_REAL, 0, f->comm));
  OutputFile out;
  PetscCall(OutputFileOpen(f->comm, path, OutputFile::REPLACE, &out));
  if (!rank) {
    const std::size_t        ncell = all.size() / kCols;
    std::vector<std::size_t> order(ncell);
    for (std::size_t q = 0; q < ncell; ++q) order[(std::size_t)all[q * kCols]] = q;
    OutputFilePrintf(&out, "i,j,k,x,y,z,eps,p,u,v,w,ufx,ufy,ufz\n");
    for (std::size_t q = 0; q < ncell; ++q) {
      const PetscReal *r  = &all[order[q] * kCols];
      const long       id = (long)q, i = id % f->n[0], j = (id / f->n[0]) % f->n[1], k = id / (f->n[0] * f->n[1]);
      const long       ijk[3] = {i, j, k};
      OutputFilePrintf(&out, "%ld,%ld,%ld", i, j, k);
      for (int a = 0; a < 3; ++a)
        OutputFilePrintf(&out, ",%.10g", (double)(f->dom->lo[a] + (ijk[a] + 0.5) * (a < f->dim ? f->h[a] : f->dom->len[2])));
      for (int col = 1; col < 9; ++col) OutputFilePrintf(&out, ",%.17g", (double)r[col]);
      OutputFilePrintf(&out, "\n");
    }
  }
  PetscCall(OutputFileClose(f->comm, &out));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDestroy(Fluid **fluid)
{
  Fluid *f = *fluid;

  PetscFunctionBeginUser;
  if (!f) PetscFunctionReturn(0);
  PetscCall(FluidPressureDestroy(f));
  Vec *vecs[] = {&f->u,        &f->u_loc,  &f->eps, &f->eps_old, &f->eps_loc, &f->eps_old_loc, &f->source, &f->source_loc, &f->drag,
                 &f->drag_loc, &f->cell_u, &f->phi, &f->phi_loc, &f->rhs,     &f->p,           &f->u_top,  &f->u_top_loc};
  for (Vec *v : vecs) PetscCall(VecDestroy(v));
  PetscCall(DMDestroy(&f->da_s));
  PetscCall(DMDestroy(&f->da_u));
  PetscCall(DMDestroy(&f->da_c));
  PetscCall(DMDestroy(&f->da_p));
  delete f;
  *fluid = nullptr;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
