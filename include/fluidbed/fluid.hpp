// The gas phase (seed eq. 2.19-2.20): volume-averaged incompressible flow on the fine fluid DMDA, advanced by a
// fractional-step projection whose pressure equation is a PETSc KSP solve (prefix -fluid_p_). docs/fluid.md has
// the discretisation, the boundary conditions and the verification figures.
//
// Fields the coupling exchanges, all cell-centred on the fine grid's layout (natural DMDA ordering, owned cells):
//   void fraction eps (dof 1, the coupling writes it before FluidStep; the previous one is kept for -fluid_deps_dt),
//   momentum source (dof dim, N/m^3: the drag reaction f_drag / V_fg of eq. 2.20-2.21, the coupling fills it),
//   cell velocity (dof dim, m/s: interstitial gas velocity averaged from the faces, for the drag),
//   pressure (dof 1, Pa).
#pragma once

#include <petscdmda.h>

#include <array>
#include <vector>

#include "fluidbed/domain.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/phases.hpp"

namespace fluidbed {

struct Fluid;
struct JsonWriter;

// What a step did, for monitor.csv and summary.json. Flow rates in m^3/s through the whole face (in 2D through the
// -domain_lz deep slab).
struct FluidStats {
  PetscInt64 steps = 0;
  PetscReal  dt = 0, dt_conv = 0, dt_visc = 0; // last step and its limits (s)
  PetscInt   ksp_its   = 0;                    // last pressure solve
  PetscReal  ksp_rnorm = 0;                    // its final residual norm (KSP's norm type; CG: unpreconditioned by default)
  PetscReal  rhs_scale = 0;                    // ||b||_2 / V of its right-hand side (1/s): div(eps u) <= rtol x this in every cell
  PetscReal  ksp_time  = 0;                    // its wall time (s), PC set-up included
  PetscInt64 solves = 0, ksp_its_total = 0, pc_setups = 0;
  PetscReal  ksp_time_total = 0;
  PetscReal  max_div        = 0;           // max over cells of |div(eps u) + d(eps)/dt| after the projection (1/s)
  PetscReal  max_speed      = 0;           // m/s, largest face velocity
  PetscReal  courant = 0, courant_max = 0; // dt x the combined explicit rate at the last step and its maximum (stable <= 1)
  PetscReal  courant_max_time = 0;         // s, when the maximum occurred
  PetscReal  inflow = 0, outflow = 0;      // m^3/s through the bottom (in) and the top (out)
  PetscInt   ksp_reason   = 0;             // KSPConvergedReason of the last pressure solve (< 0: it did not converge)
  PetscInt64 ksp_failures = 0;             // pressure solves that did not converge (the pressure guard stops the run at the first)
};

// Reads the -fluid_*, -fluid_bc_* and -inlet_* options and creates the fields; grid is the fine fluid grid.
PetscErrorCode FluidCreate(MPI_Comm comm, const Domain &domain, const FluidGrid &grid, PhaseLog *log, Fluid **fluid);
// The run's -output_dir: the default parent of -fluid_p_dump_dir (the pressure systems written for solver studies).
PetscErrorCode FluidSetOutputDirectory(Fluid *fluid, const char *dir);
// Initial fields (frozen void fraction from the options, initial velocity), the pressure matrix and its KSP.
PetscErrorCode FluidSetUp(Fluid *fluid);
// Largest stable step for the current velocity and void fraction (CFL and viscous limits), s.
PetscErrorCode FluidMaxTimeStep(Fluid *fluid, PetscReal *dt);
// The fixed step of -fluid_dt, or 0 when the step follows the limits.
PetscReal FluidFixedTimeStep(const Fluid *fluid);
// -fluid_cfl: the fraction of the explicit limit FluidMaxTimeStep returns (Courant number of a step of that length).
PetscReal FluidCfl(const Fluid *fluid);
// Prints the gas properties, boundary conditions and the time-step limits.
PetscErrorCode FluidView(Fluid *fluid, PetscViewer viewer);
// One step of length dt: momentum predictor, pressure solve, correction.
PetscErrorCode FluidStep(Fluid *fluid, PetscReal dt);
PetscErrorCode FluidDestroy(Fluid **fluid);

// Borrowed vectors (do not destroy). The void fraction and the momentum source are read at the next FluidStep.
PetscErrorCode FluidGetVoidFraction(Fluid *fluid, Vec *eps);
PetscErrorCode FluidGetMomentumSource(Fluid *fluid, Vec *source);
// Implicit interphase drag (dof 1, N s/m^4, cell-centred): with it the gas feels source - beta u, u taken at the
// end of the step (partial elimination into the projection), which keeps dense beds stable for gas steps far
// longer than the gas-particle relaxation time eps rho_g / beta. Zero unless the coupling sets it.
PetscErrorCode FluidGetDragCoefficient(Fluid *fluid, Vec *beta);
PetscErrorCode FluidGetCellVelocity(Fluid *fluid, Vec *velocity); // computed from the faces at each call
PetscErrorCode FluidGetPressure(Fluid *fluid, Vec *p);
// The pressure operator as last assembled (the set-up's until a solve reassembles it), borrowed: for tests.
PetscErrorCode FluidGetPressureMatrix(Fluid *fluid, Mat *A);
// The same operator's stencil form, which the solver multiplies by (-fluid_p_stencil_mult; NULL where it is off),
// borrowed: for tests.
PetscErrorCode FluidGetPressureStencilMatrix(Fluid *fluid, Mat *A);
// The DMDAs of the cell fields above: dof 1 (eps, pressure) and dof dim (velocity, source).
PetscErrorCode    FluidGetCellDMs(Fluid *fluid, DM *scalar, DM *vector);
const FluidStats &FluidGetStats(const Fluid *fluid);

// HDF5 under /fluid: cell velocity, pressure and void fraction (snapshots); with `full` (checkpoints) also the face
// velocities, the previous void fraction, the momentum source, the outlet faces and the gas clock. Natural
// ordering, so a checkpoint loads on any number of ranks.
PetscErrorCode FluidWriteHDF5(Fluid *fluid, PetscViewer viewer, PetscBool full);
// The bytes of data FluidWriteHDF5 writes: the size of a file to make room for.
PetscErrorCode FluidHDF5Bytes(Fluid *fluid, PetscBool full, PetscInt64 *bytes);
PetscErrorCode FluidReadHDF5(Fluid *fluid, PetscViewer viewer);
// Gas density (kg/m^3) and viscosity (Pa s), for the drag; whether the momentum equation is the seed's Model B.
PetscErrorCode FluidGetGasProperties(const Fluid *fluid, PetscReal *rho, PetscReal *mu);
PetscBool      FluidIsModelB(const Fluid *fluid);
// The inlet slits (-inlet_jets) in the order given, each as the x range [x_lo, x_hi] of its bottom cells (m).
PetscErrorCode FluidGetJetSlots(const Fluid *fluid, std::vector<std::array<PetscReal, 2>> *slots);
// The gas condition of a face as -fluid_bc_<face> names it (noslip, freeslip, outlet, pressure), or "periodic".
const char *FluidBoundaryType(const Fluid *fluid, Face face);

// For the run-time guards. Whether the face velocities, pressure and void fraction are all finite (collective), and
// where not: the first non-finite cell in natural ordering (-1 if none) and the field's name.
PetscErrorCode FluidCheckFinite(Fluid *fluid, PetscBool *finite, PetscInt64 *cell, const char **field);
// The cell (natural index) whose lower face carries the largest gas speed, and that speed (collective).
PetscErrorCode FluidLocateMaxSpeed(Fluid *fluid, PetscInt64 *cell, PetscReal *speed);
// The pressure solver's type names and iteration limit, for messages.
PetscErrorCode FluidPressureSolverInfo(Fluid *fluid, const char **ksp, const char **pc, PetscInt *max_it);

// fluid_cells.csv in natural ordering, written by rank 0: i,j,k,x,y,z,eps,p,u,v,w (cell averages),
// ufx,ufy,ufz (velocities on the cell's lower x, y, z faces).
PetscErrorCode FluidWriteCellsCSV(Fluid *fluid, const char *path);
// The gas keys of summary.json: steps, time step and limits, pressure iterations and time per solve, flow rates.
PetscErrorCode FluidAddSummary(Fluid *fluid, JsonWriter *json);
// Whether -fluid_output_cells asks for that file.
PetscBool FluidWantsCellsCSV(const Fluid *fluid);

} // namespace fluidbed
