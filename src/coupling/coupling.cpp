// Two-grid (and single-grid) gas-particle coupling: see include/fluidbed/coupling.hpp. Gets the fields, loops,
// calls the drag kernel, restores; the drag laws live in kernels/drag_*.hpp.
#include "fluidbed/coupling.hpp"
#include "fluidbed/dmda_field.hpp"
#include "fluidbed/drag_laws.hpp"
#include "fluidbed/options.hpp"

#include <petscviewerhdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace fluidbed {

using kernels::Vec3;

enum CouplingGrid { COUPLING_GRID_TWO, COUPLING_GRID_SINGLE };
static const char *const CouplingGridTypes[] = {"two", "single", "CouplingGrid", "COUPLING_GRID_", NULL};

// Fields on the coupling grid:
//   deposit (dof 2 + dim): solid volume (m^3) | B = sum of V_p K (N s/m) | M = sum of V_p K v_p (N)
//   gas     (dof 2 + dim): void fraction      | (unused)                | gas velocity averaged over the cell's fluid cells (m/s)
// The drag is linearised once per gas step: each particle keeps a = V_p K and b = a v_p (swarm fields drag_coef,
// drag_ref) and feels F = a u - b with u its cell's gas velocity after that gas step (eq. 2.18); the gas gets
// M - B u per cell, implicitly in u (fluid.hpp). Summed over a cell, the particles get B u - M: action and
// reaction cancel exactly.
struct Coupling {
  MPI_Comm        comm      = MPI_COMM_NULL;
  const Domain   *dom       = nullptr;
  const Grids    *grids     = nullptr;
  ParticleSystem *particles = nullptr;
  Fluid          *fluid     = nullptr;
  PhaseLog       *log       = nullptr;
  PetscInt        dim = 3, substeps = 1, gas_substeps = 1;
  PetscReal       drag_gas_local[3]{0, 0, 0}; // this rank's drag on the gas, summed over the gas steps of a DEM step
  CouplingGrid    mode = COUPLING_GRID_TWO;
  PetscInt        n[3]{1, 1, 1}, ratio[3]{1, 1, 1};
  PetscReal       h[3]{1, 1, 1}, cell_volume = 1;
  PetscReal       eps_min       = 0.05;
  PetscBool       divide_eps    = PETSC_TRUE; // Model B drag = Model A drag / eps
  char            drag_name[64] = "ergun_wenyu";
  DragLaw         drag;
  PetscReal       rho_g = 1.205, mu_g = 1.8e-5;

  DM                      da      = nullptr;
  Vec                     deposit = nullptr, deposit_loc = nullptr, gas = nullptr, gas_loc = nullptr;
  PetscInt                until_gas = 1; // DEM steps left before the next gas step; at 1 the linearised drag is refreshed
  std::vector<PetscInt64> order_cell;    // per particle: its coupling cell (flat index) at the last deposit
  std::vector<PetscInt>   order;         // the particles by cell, then id: the summation order of the deposits
  std::vector<PetscInt>   by_id;         // the particles by id, made for the ids in storage order stored_ids
  std::vector<PetscInt64> stored_ids;
  std::vector<PetscInt>   order_local, cell_start; // per particle: its cell's offset in the ghosted block; cells' starts in order
  std::vector<PetscInt>   drag_local;              // per particle: order_local of the last refresh, the cells its drag was linearised in;
                                                   // empty where the storage order is no longer that refresh's
  std::vector<kernels::DragCellTerms> cell_terms;  // the drag law's terms of each ghosted cell's void fraction
  std::vector<PetscReal>              volume;      // per particle (storage order): its volume at the last deposit
  CouplingStats                       stats;
};

namespace {

// The coupling cell of a particle centre, floor((x - lo) / h) clamped to the grid. The conversion truncates towards
// zero, which is the floor wherever the clamp keeps the result (a centre up to a cell below lo truncates to 0 where
// the floor gives -1, and both clamp to 0): the same cells as std::floor, without its call on every particle and
// axis at every gas step (x86-64's baseline has no rounding instruction).
// The per-particle loops below are templates on the dimension D (2 or 3), so that their loops over the axes unroll.
template <int D>
inline void CellOf(const Coupling *c, const Vec3 &x, PetscInt cell[3])
{
  const PetscReal xx[3] = {x.x, x.y, x.z};
  for (int a = 0; a < 3; ++a) {
    if (a >= D) {
      cell[a] = 0;
      continue;
    }
    const PetscInt q = (PetscInt)((xx[a] - c->dom->lo[a]) / c->h[a]);
    cell[a]          = PetscMin(PetscMax(q, 0), c->n[a] - 1);
  }
}

template <class Fn>
void ForOwnedCells(const DMDAField &v, Fn &&fn)
{
  for (PetscInt k = v.s[2]; k < v.s[2] + v.m[2]; ++k)
    for (PetscInt j = v.s[1]; j < v.s[1] + v.m[1]; ++j)
      for (PetscInt i = v.s[0]; i < v.s[0] + v.m[0]; ++i) fn(i, j, k);
}

// The particles' coupling cells (flat index) and the order in which their contributions are summed: by cell, then
// by particle id. Floating-point sums depend on their order, and the swarm's storage order depends on the run's
// history (sorting, migration, restart); summing in this order makes the cell sums, and so the whole coupled run, a
// function of the particles' state alone, so that a restart repeats the uninterrupted run bit for bit.
// The order is a stable counting sort by cell of the particles sorted by id. The id order only changes when the
// swarm's storage does (list rebuilds, migration), so it is kept with the ids it was made for and made again only
// when the ids in storage order differ from those (a comparison of two arrays in order, not a walk through the ids
// in id order).
template <int D>
PetscErrorCode DepositOrder(Coupling *c, DM swarm, PetscInt n, const ParticleBody *bodies)
{
  PetscInt64 *ids;
  PetscInt    gs[3] = {0, 0, 0}, gm[3] = {1, 1, 1};

  PetscFunctionBeginUser;
  PetscCall(DMSwarmGetField(swarm, field::id, NULL, NULL, (void **)&ids));
  const bool same = (PetscInt)c->stored_ids.size() == n && std::equal(c->stored_ids.begin(), c->stored_ids.end(), ids);
  std::swap(c->drag_local, c->order_local); // the last refresh's cells, for the drag of this step
  if (!same) {
    c->drag_local.clear();
    c->stored_ids.assign(ids, ids + n);
    c->by_id.resize(n);
    for (PetscInt p = 0; p < n; ++p) c->by_id[p] = p;
    std::sort(c->by_id.begin(), c->by_id.end(), [&](PetscInt a, PetscInt b) { return ids[a] < ids[b]; });
  }
  PetscCall(DMSwarmRestoreField(swarm, field::id, NULL, NULL, (void **)&ids));

  // counting sort by the cell's index in this rank's ghosted block (particles lie in its owned cells or halo)
  PetscCall(DMDAGetGhostCorners(c->da, &gs[0], &gs[1], &gs[2], &gm[0], &gm[1], &gm[2]));
  if (D == 2) gs[2] = 0, gm[2] = 1;
  const std::size_t ncells = (std::size_t)(gm[0] * gm[1] * gm[2]);
  c->order_cell.resize(n);
  c->volume.resize(n);
  c->order.resize(n);
  c->cell_start.assign(ncells + 1, 0);
  std::vector<PetscInt> &local = c->order_local, &start = c->cell_start;
  local.resize(n);
  for (PetscInt p = 0; p < n; ++p) {
    PetscInt cell[3];
    CellOf<D>(c, bodies[p].x, cell);
    for (int d = 0; d < D; ++d)
      PetscCheck(cell[d] >= gs[d] && cell[d] < gs[d] + gm[d], PETSC_COMM_SELF, PETSC_ERR_PLIB, "particle outside its rank's coupling halo");
    c->order_cell[p] = cell[0] + c->n[0] * (cell[1] + c->n[1] * cell[2]);
    c->volume[p]     = (4.0 / 3.0) * PETSC_PI * bodies[p].r * bodies[p].r * bodies[p].r;
    local[p]         = (cell[0] - gs[0]) + gm[0] * ((cell[1] - gs[1]) + gm[1] * (cell[2] - gs[2]));
    start[(std::size_t)local[p] + 1]++;
  }
  for (std::size_t q = 1; q <= ncells; ++q) start[q] += start[q - 1];
  for (PetscInt p : c->by_id) c->order[start[(std::size_t)local[p]]++] = p;
  for (std::size_t q = ncells; q > 0; --q) start[q] = start[q - 1]; // the fill left each cell's end in its start
  start[0] = 0;
  PetscFunctionReturn(0);
}

// Sums over each coupling cell's particles, in the deposit order, Count values per particle (add(p, sum) adds them to
// sum[0..Count)) into entries first..first+Count of the cell's block in a (ghosted layout, dof entries per cell): in
// registers per cell, the same sums as adding into the array particle by particle without a chain of stores and loads
// through one address, and one pass over the particles for all the values.
template <int Count, class Add>
void SumPerCell(const Coupling *c, PetscScalar *a, PetscInt dof, PetscInt first, Add &&add)
{
  const std::size_t ncells = c->cell_start.size() - 1;
  for (std::size_t q = 0; q < ncells; ++q) {
    const PetscInt begin = c->cell_start[q], end = c->cell_start[q + 1];
    if (begin == end) continue;
    PetscScalar sum[Count] = {};
    for (PetscInt k = begin; k < end; ++k) add(c->order[k], sum);
    for (int i = 0; i < Count; ++i) a[(PetscInt)q * dof + first + i] = sum[i];
  }
}

// The coupling cell (i, j, k) of a flat index i + n0 (j + n1 k). The index fits a PetscInt (the DMDA counts its
// cells in one), so the divisions are of that width, the fewer for D = 2 (k = 0).
template <int D>
inline void CellIjk(const Coupling *c, PetscInt64 flat, PetscInt cell[3])
{
  const PetscInt f = (PetscInt)flat, q = f / c->n[0];
  cell[0] = f - q * c->n[0];
  if (D == 2) {
    cell[1] = q;
    cell[2] = 0;
  } else {
    const PetscInt r = q / c->n[1];
    cell[1]          = q - r * c->n[1];
    cell[2]          = r;
  }
}

// The coupling cell's void fraction (eq. 5.2-5.3) at the particles' current positions: solid volumes summed (in the
// DepositOrder) with halos added to their owners, then the owned cells' eps, then halos.
PetscErrorCode DepositVoidFraction(Coupling *c)
{
  DMDAField dep, d, g;

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(c->deposit_loc));
  PetscCall(DMDAFieldGet(c->da, c->deposit_loc, PETSC_TRUE, &dep));
  SumPerCell<1>(c, dep.a, dep.dof, 0, [&](PetscInt p, PetscScalar *sum) { sum[0] += c->volume[p]; });
  PetscCall(DMDAFieldRestore(c->deposit_loc, &dep));
  PetscCall(VecZeroEntries(c->deposit));
  PetscCall(DMLocalToGlobal(c->da, c->deposit_loc, ADD_VALUES, c->deposit));

  PetscReal  lo[2] = {1.0, 1.0}, hi = 0.0; // least eps after and before the floor, largest eps
  PetscInt64 clamped = 0;
  PetscCall(DMDAFieldGet(c->da, c->deposit, PETSC_FALSE, &d));
  PetscCall(DMDAFieldGet(c->da, c->gas, PETSC_FALSE, &g));
  ForOwnedCells(g, [&](PetscInt i, PetscInt j, PetscInt k) {
    PetscReal eps = 1.0 - d(i, j, k, 0) / c->cell_volume;
    lo[1]         = PetscMin(lo[1], eps);
    if (eps < c->eps_min) {
      eps = c->eps_min;
      ++clamped;
    }
    g(i, j, k, 0) = eps;
    lo[0]         = PetscMin(lo[0], eps);
    hi            = PetscMax(hi, eps);
  });
  PetscCall(DMDAFieldRestore(c->gas, &g));
  PetscCall(DMDAFieldRestore(c->deposit, &d));
  PetscReal glo[2];
  PetscCallMPI(MPI_Allreduce(lo, glo, 2, MPIU_REAL, MPI_MIN, c->comm));
  c->stats.eps_min     = glo[0];
  c->stats.eps_raw_min = glo[1];
  PetscCallMPI(MPI_Allreduce(&hi, &c->stats.eps_max, 1, MPIU_REAL, MPI_MAX, c->comm));
  PetscCallMPI(MPI_Allreduce(&clamped, &c->stats.clamped, 1, MPIU_INT64, MPI_SUM, c->comm));
  PetscCall(DMGlobalToLocal(c->da, c->gas, INSERT_VALUES, c->gas_loc));
  PetscFunctionReturn(0);
}

// The drag of particle p, F = a u - b (eq. 2.18, linearised at the last gas step), added to its force and to sum: u
// (u[0..D)) is the gas velocity of the cell the particle was in when its drag was linearised, the cell whose B and M
// the gas step used (the particle may have crossed into another cell since).
template <int D>
inline void AddDragOf(const PetscScalar *u, PetscInt p, PetscReal a, const PetscReal *b, PetscReal *f, PetscReal sum[3])
{
  for (int d = 0; d < D; ++d) {
    const PetscReal F = a * u[d] - b[3 * p + d];
    f[3 * p + d] += F;
    sum[d] += F;
  }
}

// The same with the cell found from its flat index (the swarm's drag_cell, which moves with the particle).
template <int D>
inline PetscErrorCode AddDrag(const Coupling *c, const DMDAField &gas, PetscInt p, PetscReal a, const PetscReal *b, PetscInt64 flat,
                              PetscReal *f, PetscReal sum[3])
{
  PetscInt cell[3];

  PetscFunctionBeginUser;
  if (a == 0) PetscFunctionReturn(0); // not linearised yet (just inserted): no drag, and its cell is not set
  CellIjk<D>(c, flat, cell);
  PetscCheck(gas.Contains(cell), PETSC_COMM_SELF, PETSC_ERR_PLIB, "particle outside its rank's coupling halo");
  AddDragOf<D>(&gas(cell[0], cell[1], cell[2], 2), p, a, b, f, sum);
  PetscFunctionReturn(0);
}

// The pass over the particles of ParticleDrag: each particle's drag (AddDrag) and, when refresh, its new a and b and
// their sums per cell into deposit_loc.
template <int D>
PetscErrorCode DragPass(Coupling *c, PetscInt n, const ParticleBody *bodies, bool refresh, const DMDAField &gas, PetscReal *f, PetscReal *a,
                        PetscReal *b, PetscInt64 *cells, PetscReal sum_local[3])
{
  DMDAField dep;

  PetscFunctionBeginUser;
  if (!refresh) {
    for (PetscInt p = 0; p < n; ++p) PetscCall(AddDrag<D>(c, gas, p, a[p], b, cells[p], f, sum_local));
    PetscFunctionReturn(0);
  }
  PetscCall(VecZeroEntries(c->deposit_loc));
  PetscCall(DMDAFieldGet(c->da, c->deposit_loc, PETSC_TRUE, &dep));
  // The cells' offsets in the ghosted block (DepositOrder: order_local) address the gas and deposit arrays directly,
  // which share that block. The law's void-fraction terms once per cell that holds particles.
  const PetscInt     dof = gas.dof, *local = c->order_local.data();
  const PetscScalar *g = gas.a;
  c->cell_terms.resize(c->cell_start.size());
  for (std::size_t q = 0; q + 1 < c->cell_start.size(); ++q)
    if (c->cell_start[q + 1] > c->cell_start[q]) c->cell_terms[q] = c->drag.cell(g[(PetscInt)q * dof]);
  // each particle's drag of this step with its old a and b, then its new a and b, in storage order (the particles'
  // data are read in the order they are stored)
  for (PetscInt p = 0; p < n; ++p) {
    // the cell of the last refresh by its offset where the storage order is still that refresh's, else by its index
    if (c->drag_local.empty()) PetscCall(AddDrag<D>(c, gas, p, a[p], b, cells[p], f, sum_local));
    else if (a[p] != 0) AddDragOf<D>(g + c->drag_local[(std::size_t)p] * dof + 2, p, a[p], b, f, sum_local);
    const ParticleBody &bp  = bodies[p];
    const PetscScalar  *gc  = g + local[p] * dof;
    const PetscReal     eps = gc[0];
    const Vec3          u{gc[2], gc[3], D == 3 ? gc[4] : 0.0};
    // eq. 2.11-2.17 at the current slip; Model B divides by eps (the force that includes the dynamic pressure)
    const PetscReal K =
      c->drag.k(c->cell_terms[(std::size_t)local[p]], kernels::DragInput{eps, 2.0 * bp.r, c->rho_g, c->mu_g, kernels::norm(u - bp.v)}) /
      (c->divide_eps ? eps : 1.0);
    a[p]     = c->volume[p] * K;
    cells[p] = c->order_cell[p];
    for (int d = 0; d < 3; ++d) b[3 * p + d] = d < D ? a[p] * (&bp.v.x)[d] : 0.0;
  }
  // their sums per cell (eq. 2.21, 5.1), in the deposit order
  SumPerCell<1 + D>(c, dep.a, dof, 1, [&](PetscInt p, PetscScalar *sum) {
    sum[0] += a[p];
    for (int d = 0; d < D; ++d) sum[1 + d] += b[3 * p + d];
  });
  PetscCall(DMDAFieldRestore(c->deposit_loc, &dep));
  PetscFunctionReturn(0);
}

// Called by the DEM after the contact forces of every step: adds each particle's drag (AddDrag); at the last step
// before a gas step, also refreshes a and b with the current void fraction and predicted velocities and sums B and M
// per cell for the gas (eq. 2.21, 5.1), in the same pass over the particles.
PetscErrorCode ParticleDrag(void *ctx, DM swarm, const ParticleBody *bodies)
{
  Coupling   *c = (Coupling *)ctx;
  PetscInt    n;
  PetscReal  *f, *a, *b, sum_local[3] = {0, 0, 0};
  PetscInt64 *cells;
  DMDAField   gas;
  const bool  refresh = c->until_gas <= 1;

  PetscFunctionBeginUser;
  PetscCall(PhaseBegin(c->log, PHASE_COUPLING));
  PetscCall(DMSwarmGetLocalSize(swarm, &n));
  if (refresh) { // the void fraction at the current positions, before the pass that needs it
    if (c->dim == 2) PetscCall(DepositOrder<2>(c, swarm, n, bodies));
    else PetscCall(DepositOrder<3>(c, swarm, n, bodies));
    PetscCall(DepositVoidFraction(c)); // sets the void fraction of gas_loc; its velocities are those of the last gas step
  }
  PetscCall(DMSwarmGetField(swarm, field::force, NULL, NULL, (void **)&f));
  PetscCall(DMSwarmGetField(swarm, field::drag_coef, NULL, NULL, (void **)&a));
  PetscCall(DMSwarmGetField(swarm, field::drag_ref, NULL, NULL, (void **)&b));
  PetscCall(DMSwarmGetField(swarm, field::drag_cell, NULL, NULL, (void **)&cells));
  PetscCall(DMDAFieldGet(c->da, c->gas_loc, PETSC_TRUE, &gas));
  if (c->dim == 2) PetscCall(DragPass<2>(c, n, bodies, refresh, gas, f, a, b, cells, sum_local));
  else PetscCall(DragPass<3>(c, n, bodies, refresh, gas, f, a, b, cells, sum_local));
  PetscCall(DMDAFieldRestore(c->gas_loc, &gas));
  PetscCall(DMSwarmRestoreField(swarm, field::drag_cell, NULL, NULL, (void **)&cells));
  PetscCall(DMSwarmRestoreField(swarm, field::drag_ref, NULL, NULL, (void **)&b));
  PetscCall(DMSwarmRestoreField(swarm, field::drag_coef, NULL, NULL, (void **)&a));
  PetscCall(DMSwarmRestoreField(swarm, field::force, NULL, NULL, (void **)&f));
  PetscCallMPI(MPI_Allreduce(sum_local, c->stats.drag_particles, 3, MPIU_REAL, MPI_SUM, c->comm));
  if (refresh) {
    PetscCall(VecZeroEntries(c->deposit));
    PetscCall(DMLocalToGlobal(c->da, c->deposit_loc, ADD_VALUES, c->deposit)); // component 0 (volume) is not used
  }
  c->until_gas--;
  PetscCall(PhaseEnd(c->log, PHASE_COUPLING));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode CouplingCreate(MPI_Comm comm, const Domain &dom, const Grids &grids, ParticleSystem *particles, Fluid *fluid, PhaseLog *log,
                              Coupling **out)
{
  Coupling *c = new Coupling;

  PetscFunctionBeginUser;
  c->comm      = comm;
  c->dom       = &dom;
  c->grids     = &grids;
  c->particles = particles;
  c->fluid     = fluid;
  c->log       = log;
  c->dim       = dom.dim;
  PetscOptionsBegin(comm, "", "Gas-particle coupling (seed eq. 2.11-2.21, two-grid mapping eq. 5.1-5.5)", "Coupling");
  PetscCall(OptionsInt(PetscOptionsObject, "-couple_substeps", "DEM steps per gas step (gas step = DEM step x this)", 1, 100000,
                       &c->substeps, NULL));
  PetscCall(OptionsInt(PetscOptionsObject, "-couple_gas_substeps",
                       "Gas steps per DEM step (gas step = DEM step / this), the particles' void fraction and drag held over them: for a "
                       "DEM step longer than the gas's explicit limit (a soft spring beside a fast jet); only with -couple_substeps 1",
                       1, 1000, &c->gas_substeps, NULL));
  PetscCall(OptionsEnum(PetscOptionsObject, "-couple_grid",
                        "Where void fraction and drag are summed: two (particle grid, eq. 5.1-5.5) or single (fluid grid)",
                        CouplingGridTypes, (PetscEnum *)&c->mode, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-couple_eps_min", "Floor of the void fraction (a cell overfilled by particle centres)", "",
                        Closed(0.01, 0.9), &c->eps_min, NULL));
  PetscCall(OptionsBool(
    PetscOptionsObject, "-couple_drag_model_b",
    "Model B particle drag = eq. 2.18 / eps, so that a packed bed's pressure drop is Ergun's and U_mf is eq. 3.1's (false: eq. 2.18 as "
    "printed, the Model A force)",
    &c->divide_eps, NULL));
  {
    PetscFunctionList laws;
    PetscCall(DragLawList(&laws));
    PetscCall(PetscOptionsFList("-drag_model", "Drag law (ergun_wenyu: the seed's Ergun / Wen-Yu blend, eq. 2.11-2.14)", "DragLawRegister",
                                laws, c->drag_name, c->drag_name, sizeof(c->drag_name), NULL));
  }
  PetscOptionsEnd();
  PetscCheck(c->substeps == 1 || c->gas_substeps == 1, comm, PETSC_ERR_USER_INPUT,
             "-couple_substeps %d and -couple_gas_substeps %d: one of them must be 1 (several DEM steps per gas step, or several gas "
             "steps per DEM step)",
             (int)c->substeps, (int)c->gas_substeps);
  PetscCall(DragLawGet(c->drag_name, &c->drag));
  PetscCheck(FluidIsModelB(fluid), comm, PETSC_ERR_USER_INPUT, "the coupling implements the seed's Model B: use -fluid_model B");
  PetscCall(FluidGetGasProperties(fluid, &c->rho_g, &c->mu_g));

  // Buoyancy (Model B, eq. 2.1): the particles' gravity is (rho_p - rho_g) V_p g.
  ParticlesSetBodyForceFactor(particles, 1.0 - c->rho_g / ParticlesGetProps(particles).density);

  // The coupling grid: the particle cells, or the fluid cells.
  const ParticleGrid   &pg = grids.particle;
  const FluidGrid      &fg = grids.fluid;
  std::vector<PetscInt> own[3];
  for (int a = 0; a < 3; ++a) {
    const bool two = c->mode == COUPLING_GRID_TWO;
    c->n[a]        = two ? pg.n[a] : fg.n[a];
    c->h[a]        = two ? pg.h[a] : fg.h[a];
    c->ratio[a]    = two ? pg.ratio[a] : 1;
    if (a < c->dim)
      for (PetscInt r = 0; r < pg.procs[a]; ++r) own[a].push_back(two ? pg.start[a][r + 1] - pg.start[a][r] : fg.own[a][(std::size_t)r]);
  }
  c->cell_volume     = c->h[0] * c->h[1] * c->h[2];
  c->stats.cells     = (PetscInt64)c->n[0] * c->n[1] * (c->dim == 3 ? c->n[2] : 1);
  const PetscInt dof = 2 + c->dim;
  {
    const DMBoundaryType  bnone[3] = {DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE};
    const PetscInt *const owned[3] = {own[0].data(), own[1].data(), own[2].data()};
    PetscCall(DMDACreateLayout(comm, c->dim, bnone, DMDA_STENCIL_BOX, c->n, pg.procs, owned, dof, 1, &c->da));
  }
  PetscCall(PetscObjectSetName((PetscObject)c->da, "coupling_grid"));
  PetscCall(DMCreateGlobalVector(c->da, &c->deposit));
  PetscCall(DMCreateLocalVector(c->da, &c->deposit_loc));
  PetscCall(VecDuplicate(c->deposit, &c->gas));
  PetscCall(VecDuplicate(c->deposit_loc, &c->gas_loc));
  PetscCall(VecZeroEntries(c->gas));
  PetscCall(VecStrideSet(c->gas, 0, 1.0)); // eps 1 and no gas motion until set

  ParticlesSetExternalForce(particles, ParticleDrag, c);
  *out = c;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingSetUp(Coupling *c)
{
  PetscFunctionBeginUser;
  PetscCall(CouplingAfterFluidStep(c, 0, 1)); // the initial gas velocity per coupling cell
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingBeforeFluidStep(Coupling *c)
{
  DM        da_s, da_v;
  Vec       eps_f, src_f, beta_f;
  DMDAField g, d, e, s, be;

  PetscFunctionBeginUser;
  PetscCall(PhaseBegin(c->log, PHASE_COUPLING));
  PetscCall(FluidGetCellDMs(c->fluid, &da_s, &da_v));
  PetscCall(FluidGetVoidFraction(c->fluid, &eps_f));
  PetscCall(FluidGetMomentumSource(c->fluid, &src_f));
  PetscCall(FluidGetDragCoefficient(c->fluid, &beta_f));
  const PetscReal inv_volume = 1.0 / c->cell_volume;
  PetscCall(DMDAFieldGet(c->da, c->gas, PETSC_FALSE, &g));
  PetscCall(DMDAFieldGet(c->da, c->deposit, PETSC_FALSE, &d));
  PetscCall(DMDAFieldGet(da_s, eps_f, PETSC_FALSE, &e));
  PetscCall(DMDAFieldGet(da_s, beta_f, PETSC_FALSE, &be));
  PetscCall(DMDAFieldGet(da_v, src_f, PETSC_FALSE, &s));
  ForOwnedCells(g, [&](PetscInt i, PetscInt j, PetscInt k) {
    // eq. 5.4-5.5: every fluid cell of the particle cell gets its void fraction; eq. 5.1: the drag reaction is
    // spread by volume, the same per unit volume in each fluid cell (here as beta = B / V and M / V)
    for (PetscInt kk = k * c->ratio[2]; kk < (k + 1) * c->ratio[2]; ++kk)
      for (PetscInt jj = j * c->ratio[1]; jj < (j + 1) * c->ratio[1]; ++jj)
        for (PetscInt ii = i * c->ratio[0]; ii < (i + 1) * c->ratio[0]; ++ii) {
          e(ii, jj, kk, 0)  = g(i, j, k, 0);
          be(ii, jj, kk, 0) = d(i, j, k, 1) * inv_volume;
          for (PetscInt a = 0; a < c->dim; ++a) s(ii, jj, kk, a) = d(i, j, k, 2 + a) * inv_volume;
        }
  });
  PetscCall(DMDAFieldRestore(src_f, &s));
  PetscCall(DMDAFieldRestore(beta_f, &be));
  PetscCall(DMDAFieldRestore(eps_f, &e));
  PetscCall(DMDAFieldRestore(c->deposit, &d));
  PetscCall(DMDAFieldRestore(c->gas, &g));
  c->until_gas = c->substeps;
  PetscCall(PhaseEnd(c->log, PHASE_COUPLING));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingAfterFluidStep(Coupling *c, PetscInt k, PetscInt n)
{
  DM        da_v;
  Vec       u_f;
  DMDAField g, u, d;

  PetscFunctionBeginUser;
  PetscCall(PhaseBegin(c->log, PHASE_COUPLING));
  if (k == 0) c->drag_gas_local[0] = c->drag_gas_local[1] = c->drag_gas_local[2] = 0;
  PetscCall(FluidGetCellDMs(c->fluid, NULL, &da_v));
  PetscCall(FluidGetCellVelocity(c->fluid, &u_f));
  PetscCall(DMDAFieldGet(c->da, c->gas, PETSC_FALSE, &g));
  PetscCall(DMDAFieldGet(c->da, c->deposit, PETSC_FALSE, &d));
  PetscCall(DMDAFieldGet(da_v, u_f, PETSC_FALSE, &u));
  const PetscReal inv  = 1.0 / (PetscReal)(c->ratio[0] * c->ratio[1] * c->ratio[2]);
  const bool      last = k == n - 1;
  ForOwnedCells(g, [&](PetscInt i, PetscInt j, PetscInt kc) {
    // seed step 2: the gas velocity of a particle cell is the average over its fluid cells; with n gas steps in one
    // DEM step (-couple_gas_substeps), also over those steps: the gas received M - B u_s in step s, the mean of which,
    // M - B u_mean, is exactly minus what the particles then feel (a u_mean - b summed over the cell)
    PetscReal sum[3] = {0, 0, 0};
    for (PetscInt kk = kc * c->ratio[2]; kk < (kc + 1) * c->ratio[2]; ++kk)
      for (PetscInt jj = j * c->ratio[1]; jj < (j + 1) * c->ratio[1]; ++jj)
        for (PetscInt ii = i * c->ratio[0]; ii < (i + 1) * c->ratio[0]; ++ii)
          for (PetscInt a = 0; a < c->dim; ++a) sum[a] += u(ii, jj, kk, a);
    for (PetscInt a = 0; a < c->dim; ++a) {
      const PetscReal us = sum[a] * inv;
      g(i, j, kc, 2 + a) = k == 0 ? us / (PetscReal)n : g(i, j, kc, 2 + a) + us / (PetscReal)n; // us / 1 is us, bit for bit
      c->drag_gas_local[a] += (d(i, j, kc, 2 + a) - d(i, j, kc, 1) * us) / (PetscReal)n;        // the gas's drag M - B u (eq. 2.21)
    }
  });
  PetscCall(DMDAFieldRestore(u_f, &u));
  PetscCall(DMDAFieldRestore(c->deposit, &d));
  PetscCall(DMDAFieldRestore(c->gas, &g));
  if (last) {
    PetscCallMPI(MPI_Allreduce(c->drag_gas_local, c->stats.drag_gas, 3, MPIU_REAL, MPI_SUM, c->comm));
    PetscCall(DMGlobalToLocal(c->da, c->gas, INSERT_VALUES, c->gas_loc));
  }
  PetscCall(PhaseEnd(c->log, PHASE_COUPLING));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingWriteHDF5(Coupling *c, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/coupling"));
  PetscCall(PetscObjectSetName((PetscObject)c->deposit, "cell_sums"));
  PetscCall(VecView(c->deposit, viewer));
  PetscCall(PetscObjectSetName((PetscObject)c->gas, "cell_gas"));
  PetscCall(VecView(c->gas, viewer));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/coupling", "until_gas", PETSC_INT, &c->until_gas));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingReadHDF5(Coupling *c, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5PushGroup(viewer, "/coupling"));
  PetscCall(PetscObjectSetName((PetscObject)c->deposit, "cell_sums"));
  PetscCall(VecLoad(c->deposit, viewer));
  PetscCall(PetscObjectSetName((PetscObject)c->gas, "cell_gas"));
  PetscCall(VecLoad(c->gas, viewer));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/coupling", "until_gas", PETSC_INT, NULL, &c->until_gas));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  // the particles are those of the checkpoint: the next refresh keeps nothing of the earlier ones (DepositOrder)
  c->stored_ids.clear();
  PetscCall(DMGlobalToLocal(c->da, c->gas, INSERT_VALUES, c->gas_loc));
  {
    // a rescue may change -couple_substeps on a restart: the DEM steps already taken of the current gas step are kept
    PetscInt  substeps = c->substeps;
    PetscBool has;
    PetscCall(PetscViewerHDF5HasAttribute(viewer, "/", "couple_substeps", &has));
    if (has) PetscCall(PetscViewerHDF5ReadAttribute(viewer, "/", "couple_substeps", PETSC_INT, NULL, &substeps));
    if (substeps != c->substeps) {
      c->until_gas = PetscMin(c->until_gas, c->substeps);
      PetscCall(PetscPrintf(c->comm, "Restart with -couple_substeps %d (the checkpoint's run had %d)\n", (int)c->substeps, (int)substeps));
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingFloorCells(Coupling *c, std::vector<PetscInt64> *fluid_cells, PetscInt first[3])
{
  DMDAField        g;
  const PetscInt64 none = INT64_MAX;
  PetscInt64       lo   = none, glo;
  const PetscInt  *fn   = c->grids->fluid.n;

  PetscFunctionBeginUser;
  fluid_cells->clear();
  PetscCall(DMDAFieldGet(c->da, c->gas, PETSC_FALSE, &g));
  ForOwnedCells(g, [&](PetscInt i, PetscInt j, PetscInt k) {
    if (g(i, j, k, 0) > c->eps_min) return;
    lo = PetscMin(lo, (PetscInt64)i + (PetscInt64)c->n[0] * ((PetscInt64)j + (PetscInt64)c->n[1] * (PetscInt64)k));
    for (PetscInt kk = k * c->ratio[2]; kk < (k + 1) * c->ratio[2]; ++kk)
      for (PetscInt jj = j * c->ratio[1]; jj < (j + 1) * c->ratio[1]; ++jj)
        for (PetscInt ii = i * c->ratio[0]; ii < (i + 1) * c->ratio[0]; ++ii)
          fluid_cells->push_back((PetscInt64)ii + (PetscInt64)fn[0] * ((PetscInt64)jj + (PetscInt64)fn[1] * (PetscInt64)kk));
  });
  PetscCall(DMDAFieldRestore(c->gas, &g));
  PetscCallMPI(MPI_Allreduce(&lo, &glo, 1, MPIU_INT64, MPI_MIN, c->comm));
  if (glo == none) first[0] = first[1] = first[2] = -1;
  else {
    first[0] = (PetscInt)(glo % c->n[0]);
    first[1] = (PetscInt)((glo / c->n[0]) % c->n[1]);
    first[2] = (PetscInt)(glo / ((PetscInt64)c->n[0] * c->n[1]));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCellSize(const Coupling *c, PetscReal h[3], PetscInt ratio[3])
{
  PetscFunctionBeginUser;
  for (int a = 0; a < 3; ++a) {
    h[a]     = c->h[a];
    ratio[a] = c->ratio[a];
  }
  PetscFunctionReturn(0);
}

const char *CouplingDragName(const Coupling *c)
{
  return c->drag_name;
}

PetscBool CouplingOnParticleGrid(const Coupling *c)
{
  return c->mode == COUPLING_GRID_TWO ? PETSC_TRUE : PETSC_FALSE;
}

PetscBool CouplingGasStepDue(const Coupling *c)
{
  return c->until_gas <= 0 ? PETSC_TRUE : PETSC_FALSE;
}

PetscInt CouplingSubsteps(const Coupling *c)
{
  return c->substeps;
}

PetscInt CouplingGasSubsteps(const Coupling *c)
{
  return c->gas_substeps;
}

PetscErrorCode CouplingGasStep(Coupling *c, PetscReal *dt_gas, PetscReal *dt_max)
{
  PetscFunctionBeginUser;
  PetscCheck(FluidFixedTimeStep(c->fluid) == 0, c->comm, PETSC_ERR_USER_INPUT,
             "-fluid_dt: with particles the gas step is the DEM step times -couple_substeps (or over -couple_gas_substeps)");
  *dt_gas = ParticlesTimeStep(c->particles) * c->substeps / c->gas_substeps;
  PetscCall(FluidMaxTimeStep(c->fluid, dt_max));
  PetscFunctionReturn(0);
}

const CouplingStats &CouplingGetStats(const Coupling *c)
{
  return c->stats;
}

PetscErrorCode CouplingView(const Coupling *c, PetscViewer viewer)
{
  char step[64];

  PetscFunctionBeginUser;
  if (c->gas_substeps > 1) PetscCall(PetscSNPrintf(step, sizeof(step), "1 / %d DEM step", (int)c->gas_substeps));
  else PetscCall(PetscSNPrintf(step, sizeof(step), "%d DEM steps", (int)c->substeps));
  if (c->mode == COUPLING_GRID_TWO)
    PetscCall(PetscViewerASCIIPrintf(
      viewer, "Coupling: two grids, particle cells of %d x %d x %d fluid cells; drag %s; buoyancy (Model B); gas step = %s\n",
      (int)c->ratio[0], (int)c->ratio[1], (int)c->ratio[2], c->drag_name, step));
  else
    PetscCall(PetscViewerASCIIPrintf(
      viewer, "Coupling: single grid (void fraction and drag on the fluid cells); drag %s; buoyancy (Model B); gas step = %s\n",
      c->drag_name, step));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingDestroy(Coupling **c)
{
  PetscFunctionBeginUser;
  if (!*c) PetscFunctionReturn(0);
  PetscCall(VecDestroy(&(*c)->deposit));
  PetscCall(VecDestroy(&(*c)->deposit_loc));
  PetscCall(VecDestroy(&(*c)->gas));
  PetscCall(VecDestroy(&(*c)->gas_loc));
  PetscCall(DMDestroy(&(*c)->da));
  delete *c;
  *c = nullptr;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
