// The gas phase's internals, shared by src/fluid/*.cpp.
//
// Staggered (MAC) layout on the fine cell-centred DMDA: pressure, void fraction and sources at cell centres; the
// velocity component a of entry (i,j,k) lives on the lower a-face of cell (i,j,k) (x = i h_x for a = x). The
// upper boundary faces (index n_a along a) are not owned by anyone: they sit in the first ghost layer of the
// ranks at that boundary and are written there by FluidFillGhosts. Non-periodic directions use
// DM_BOUNDARY_GHOSTED so that every rank has ghost layers beyond the walls, filled from the boundary conditions.
#pragma once

#include <petscksp.h>

#include <string>
#include <vector>

#include "fluidbed/dmda_field.hpp"
#include "fluidbed/fast_poisson.hpp"
#include "fluidbed/fluid.hpp"
#include "fluidbed/inlets.hpp"
#include "fluidbed/kernels/fluid_flux.hpp"

namespace fluidbed {

// -fluid_model: B (seed eq. 2.20, -grad p, rho_g g) or A (-eps grad p, eps rho_g g).
enum FluidModel { FLUID_MODEL_B, FLUID_MODEL_A };
extern const char *const FluidModelTypes[];

// -fluid_bc_<face>: the gas boundary condition of a face (periodic faces come from -domain_periodic_*).
enum FluidBC { FLUID_BC_NOSLIP, FLUID_BC_FREESLIP, FLUID_BC_OUTLET, FLUID_BC_PRESSURE };
extern const char *const FluidBCTypes[];
extern const char *const FluidFaceKeys[FACE_COUNT]; // xlo, xhi, ...

extern const char *const FluidLimiterTypes[];

// The gas fields are viewed through the shared DMDAField (include/fluidbed/dmda_field.hpp).

struct FluidField {
  DM  dm  = nullptr; // borrowed
  Vec loc = nullptr; // ghosted local vector
};

struct Fluid {
  MPI_Comm         comm = MPI_COMM_NULL;
  const Domain    *dom  = nullptr;
  const FluidGrid *grid = nullptr;
  PhaseLog        *log  = nullptr;
  PetscInt         dim  = 3;
  PetscInt         n[3]{1, 1, 1};
  PetscReal        h[3]{1, 1, 1}, area[3]{1, 1, 1}, vol = 1; // cell sizes, face areas, cell volume
  PetscBool        periodic[3]{PETSC_FALSE, PETSC_FALSE, PETSC_FALSE};
  PetscInt         xs[3]{0, 0, 0}, xm[3]{1, 1, 1}; // owned cells

  // physics (-fluid_*)
  FluidModel       model = FLUID_MODEL_B;
  PetscReal        rho = 1.205, mu = 1.8e-5; // air, seed Table 2.1
  kernels::Limiter limiter = kernels::Limiter::VanLeer;
  PetscBool        deps_dt = PETSC_FALSE;
  PetscReal        body_force[3]{0, 0, 0};       // N/m^3, added to the momentum source
  PetscReal        initial_velocity[3]{0, 0, 0}; // m/s, superficial
  PetscReal        dt_fixed = 0, cfl = 0.9;
  PetscInt         pc_reuse     = 10; // the operator changes every step in coupled runs; its AMG set-up costs more than a solve
  PetscBool        output_cells = PETSC_TRUE;
  PetscReal        eps_uniform  = 1.0;
  PetscReal        eps_sphere[5]{0, 0, 0, 0, 1};
  PetscBool        has_sphere = PETSC_FALSE;
  PetscReal        sphere_velocity[3]{0, 0, 0}; // m/s: the frozen sphere moves (eps changes every step)
  PetscReal        time = 0;                    // s, gas time (moves the sphere)
  PetscReal        eps_bed[2]{0, 1};
  PetscBool        has_bed = PETSC_FALSE;

  // boundary conditions (-fluid_bc_*, -inlet_*)
  FluidBC   bc[FACE_COUNT]{};
  PetscReal wall_velocity[FACE_COUNT][3]{};
  Inlet     inlet;                       // -inlet_type: the bottom face's profile (inlets.hpp)
  PetscReal inflow_rate   = 0;           // m^3/s, from the inlet profile
  PetscReal inlet_ramp    = 0;           // s: the inflow grows linearly from 0 over this time (0: none)
  PetscBool has_dirichlet = PETSC_FALSE; // a pressure outlet

  // grids and fields
  DM  da_s = nullptr; // scalar, box stencil 2, ghosted: eps, eps_old
  DM  da_u = nullptr; // dof dim, box stencil 2, ghosted: face velocities
  DM  da_c = nullptr; // dof dim, star stencil 1: cell velocity, momentum source
  DM  da_p = nullptr; // scalar, star stencil 1: pressure matrix, phi, rhs
  Vec u = nullptr, u_loc = nullptr;
  Vec eps = nullptr, eps_old = nullptr, eps_loc = nullptr, eps_old_loc = nullptr;
  Vec source = nullptr, source_loc = nullptr;
  // Implicit drag: the coupling's interphase coefficient per unit volume beta (N s/m^4, cell-centred); the gas
  // feels source - beta u at the end of the step. has_drag: some beta is nonzero (the pressure operator then
  // depends on it and on dt).
  Vec       drag = nullptr, drag_loc = nullptr;
  PetscBool has_drag = PETSC_FALSE;
  PetscReal dt_last  = 0; // the step of the last assembly
  Vec       cell_u   = nullptr;
  Vec       phi = nullptr, phi_loc = nullptr, rhs = nullptr, p = nullptr;
  // Velocity of the top boundary face of each top cell (outlets), kept at that cell's entry of a scalar field so
  // that neighbours see it through the ghost exchange; other entries unused.
  Vec u_top = nullptr, u_top_loc = nullptr;

  // pressure solver
  Mat          A          = nullptr;
  MatNullSpace nullspace  = nullptr;
  KSP          ksp        = nullptr;
  PetscInt     assemblies = 0, since_pc = 0;
  // Where each entry of the pressure operator sits in an AIJ matrix's value arrays, in the order the assembly makes
  // them (pressure.cpp, FluidAssembleOperator): >= 0 in the diagonal block, -1 - q at q in the off-diagonal block.
  // Found once by an assembly of tags; later assemblies write the values in place (the pattern never changes).
  std::vector<PetscInt> a_pos;
  PetscBool             a_direct = PETSC_FALSE;
  // The operator's stencil form, which the Krylov method multiplies by instead of the assembled AIJ matrix where
  // -fluid_p_stencil_mult is on (pressure_stencil.cpp; the preconditioner keeps A): the face coefficients c_f A_f / h_f
  // and the diagonal of A's last assembly. face[a * N + p]: the lower a-face of the cell at offset p of the ghosted
  // scalar layout (da_s, the layout of the assembly's eps and drag); diag: the owned rows in natural order within the
  // rank. A is null where the stencil form is off.
  struct StencilOperator {
    Mat                    A = nullptr;
    DMDAField              layout; // the ghosted layout of face (its array unused)
    std::vector<PetscReal> face, diag;
    Vec                    x_loc = nullptr; // x with its ghosts, on several ranks
    PetscLogDouble         flops = 0;       // per product, counted as MatMult of the AIJ matrix counts them
  } op;

  // -fluid_p_dump_*: the pressure systems of selected gas steps written for offline solver studies
  // (scripts/ksp_compare.py); pressure_dump.cpp. Off unless an interval or a list of steps is given.
  struct Dump {
    PetscInt              interval = 0, start_step = 1, count = 0;    // every interval-th eligible step, at most count (0: no limit)
    PetscReal             start_time = 0;                             // s: steps ending before this are not eligible
    std::vector<PetscInt> steps;                                      // and these gas steps (1-based), whatever the interval
    std::string           dir;                                        // empty: <output_dir>/pressure_dump
    PetscInt              eligible = 0, written = 0, by_interval = 0; // by_interval: the dumps -fluid_p_dump_count limits
    PetscBool             now = PETSC_FALSE;                          // this step's system is being dumped
    Mat                   A   = nullptr; // an AIJ copy of a structured (hypre) matrix, which has no binary viewer
    Vec                   x0  = nullptr; // the initial guess, kept across the solve
  } dump;
  std::string output_dir = "output"; // the run's -output_dir (FluidSetOutputDirectory)

  // Scratch arrays on the ghosted cell layout of da_u and da_s (FluidWork): the momentum predictor's face fluxes and
  // control-volume transport, the pressure matrix's face coefficients. Grows once, then is reused every step.
  std::vector<PetscReal> work;

  FluidStats stats;
};

// Calls fn(i, j, k) for every cell this rank owns (x fastest; k = 0 in 2D).
template <class Fn>
inline void ForEachOwnedCell(const Fluid *f, Fn &&fn)
{
  for (PetscInt k = f->xs[2]; k < f->xs[2] + f->xm[2]; ++k)
    for (PetscInt j = f->xs[1]; j < f->xs[1] + f->xm[1]; ++j)
      for (PetscInt i = f->xs[0]; i < f->xs[0] + f->xm[0]; ++i) fn(i, j, k);
}

// The same with the cell's offsets pa and pb in the arrays of views A and B (DMDAField::cell), stepped along the rows
// instead of recomputed: fn(pa, pb).
template <class Fn>
inline void ForEachOwnedOffset(const Fluid *f, const DMDAField &A, const DMDAField &B, Fn &&fn)
{
  for (PetscInt k = f->xs[2]; k < f->xs[2] + f->xm[2]; ++k)
    for (PetscInt j = f->xs[1]; j < f->xs[1] + f->xm[1]; ++j) {
      PetscInt pa = A.cell(f->xs[0], j, k), pb = B.cell(f->xs[0], j, k);
      for (PetscInt i = f->xs[0]; i < f->xs[0] + f->xm[0]; ++i, ++pa, ++pb) fn(pa, pb);
    }
}

// The cells [lo, hi) per direction that this rank owns (k = 0 in 2D).
inline void OwnedBox(const Fluid *f, PetscInt lo[3], PetscInt hi[3])
{
  for (int d = 0; d < 3; ++d) {
    lo[d] = f->xs[d];
    hi[d] = f->xs[d] + f->xm[d];
  }
}

// Calls fn(p) for every cell of the box [lo, hi) (x fastest), p the cell's offset in v's array (DMDAField::cell).
template <class Fn>
inline void ForEachCellInBox(const DMDAField &v, const PetscInt lo[3], const PetscInt hi[3], Fn &&fn)
{
  for (PetscInt k = lo[2]; k < hi[2]; ++k)
    for (PetscInt j = lo[1]; j < hi[1]; ++j) {
      PetscInt p = v.cell(lo[0], j, k);
      for (PetscInt i = lo[0]; i < hi[0]; ++i, ++p) fn(p);
    }
}

// fluid_bc.cpp
PetscErrorCode FluidReadBoundaryOptions(Fluid *f);
PetscErrorCode FluidFillGhosts(Fluid *f, Vec loc, PetscInt kind); // kind: 0 scalar (eps), 1 velocity
// Boundary face velocities for the current eps: walls 0, the inlet's superficial velocity / eps, the outlet's
// (uniform: inflow minus the integral of d(eps)/dt; pressure: the predicted velocity extrapolated when extrapolate).
// The factor of the inlet velocities at time t (-inlet_ramp_time), and the convective rate the inlet will reach
// at full speed while it ramps up (0 after).
PetscReal      FluidInletScale(const Fluid *f, PetscReal t);
PetscErrorCode FluidInletRampRate(Fluid *f, PetscReal *conv);
PetscErrorCode FluidSetBoundaryFaces(Fluid *f, PetscReal dt, PetscBool extrapolate);
PetscErrorCode FluidScatterVelocity(Fluid *f);
PetscErrorCode FluidFlowRates(Fluid *f, PetscReal *in, PetscReal *out);
PetscErrorCode FluidDepsSum(Fluid *f, PetscReal dt, PetscReal *sum); // integral of -d(eps)/dt over the domain with -fluid_deps_dt (m^3/s)

// momentum.cpp
PetscErrorCode FluidPredictor(Fluid *f, PetscReal dt);
PetscErrorCode FluidStepRates(Fluid *f, kernels::StepRates *rates);

// pressure.cpp
PetscErrorCode FluidPressureCreate(Fluid *f);
PetscErrorCode FluidPressureSolve(Fluid *f, PetscReal dt);
PetscErrorCode FluidCorrect(Fluid *f, PetscReal dt);
PetscErrorCode FluidDivergence(Fluid *f, PetscReal dt, PetscReal *max_div);
PetscErrorCode FluidPressureDestroy(Fluid *f);
PetscErrorCode FluidSolverNames(Fluid *f, const char **ksp, const char **pc); // the pressure KSP and PC types
// The face-coefficient operator of the projection for the current eps and drag, assembled into M (any DMDA matrix
// of da_p): the matrix of the solve for the same dt (the drag's dt, 0 without drag). When M is f->A it also keeps the
// face coefficients and diagonals in f->op for the stencil form; no other side effects on f.
PetscErrorCode FluidAssembleOperator(Fluid *f, Mat M, PetscReal dt);

// pressure_stencil.cpp: the stencil form of the pressure operator (Fluid::StencilOperator), a MATSHELL whose product is
// bit for bit the assembled AIJ matrix's, and its release. Created where the grid has no periodic direction.
PetscErrorCode FluidStencilOperatorCreate(Fluid *f);
PetscErrorCode FluidStencilOperatorDestroy(Fluid *f);

// pressure_dump.cpp
PetscErrorCode FluidDumpSetFromOptions(Fluid *f);
// Before the solve of step f->stats.steps + 1 ending at f->time + dt: decides whether it is dumped (f->dump.now) and
// keeps the initial guess f->phi. After it: writes the system (collective).
PetscErrorCode FluidDumpBeforeSolve(Fluid *f, PetscReal dt);
PetscErrorCode FluidDumpAfterSolve(Fluid *f, PetscReal dt, PetscBool pc_rebuilt);
PetscErrorCode FluidDumpDestroy(Fluid *f);

// The projection's face coefficient: ε_f u = ε_f u* - c_f grad(phi) with phi = dt p / rho. c0 is 1 for model B
// (-grad p) and eps_f for model A (-eps grad p); an implicit drag beta_f divides by 1 + dt beta_f / (rho eps_f).
inline PetscReal ProjectionCoefficient(PetscReal c0, PetscReal eps_f, PetscReal beta_f, PetscReal dt, PetscReal rho)
{
  return beta_f == 0 ? c0 : c0 * eps_f / (eps_f + dt * beta_f / rho);
}

// Scratch of at least n values (Fluid::work), uninitialised; valid until the next call.
inline PetscReal *FluidWork(Fluid *f, std::size_t n)
{
  if (f->work.size() < n) f->work.resize(n);
  return f->work.data();
}

// Views on local arrays.
// Whether two views address their cells alike (one cell offset serves both), e.g. da_u and da_s local arrays.
inline bool SameLayout(const DMDAField &x, const DMDAField &y)
{
  for (int d = 0; d < 3; ++d)
    if (x.s[d] != y.s[d] || x.m[d] != y.m[d]) return false;
  return true;
}
inline PetscReal FaceEps(const DMDAField &eps, const PetscInt c[3], int a)
{
  return 0.5 * (eps(c[0] - (a == 0), c[1] - (a == 1), c[2] - (a == 2)) + eps.at(c));
}

} // namespace fluidbed
