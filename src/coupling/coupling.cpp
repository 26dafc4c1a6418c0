// Two-grid (and single-grid) gas-particle coupling: see include/fluidbed/coupling.hpp. Gets the fields, loops,
// calls the drag kernel, restores; the drag laws live in kernels/drag_*.hpp.
#include "fluidbed/coupling.hpp"
#include "fluidbed/options.hpp"

#include <cmath>

namespace fluidbed {

using kernels::Vec3;

enum CouplingGrid { COUPLING_GRID_TWO, COUPLING_GRID_SINGLE };
static const char *const CouplingGridTypes[] = {"two", "single", "CouplingGrid", "COUPLING_GRID_", NULL};

// Fields on the coupling grid (dof 1 + dim each):
//   deposit: solid volume (m^3) | drag reaction summed over the cell's particles (N)
//   gas:     void fraction      | gas velocity averaged over the cell's fluid cells (m/s)
struct Coupling {
  MPI_Comm      comm = MPI_COMM_NULL;
  const Domain *dom  = nullptr;
  const Grids  *grids = nullptr;
  Dem          *dem   = nullptr;
  Fluid        *fluid = nullptr;
  PhaseLog     *log   = nullptr;
  PetscInt      dim = 3, substeps = 1;
  CouplingGrid  mode = COUPLING_GRID_TWO;
  PetscInt      n[3]{1, 1, 1}, ratio[3]{1, 1, 1};
  PetscReal     h[3]{1, 1, 1}, cell_volume = 1;
  PetscReal     eps_min = 0.05;
  PetscBool     divide_eps = PETSC_TRUE; // Model B drag = Model A drag / eps
  char          drag_name[64] = "ergun_wenyu";
  DragLaw       drag = nullptr;
  PetscReal     rho_g = 1.205, mu_g = 1.8e-5;

  DM            da = nullptr;
  Vec           deposit = nullptr, deposit_loc = nullptr, gas = nullptr, gas_loc = nullptr;
  Vec           reaction_acc = nullptr; // dof 1 + dim, reaction components summed over the DEM steps since the last gas step
  PetscInt      acc_count = 0;
  PetscReal     drag_acc[3]{0, 0, 0}; // total drag on the particles summed over the same steps
  CouplingStats stats;
};

namespace {

// A DMDA array (global or ghosted local) addressed by global cell index and component.
struct CellView {
  PetscScalar *a = nullptr;
  PetscInt     s[3]{0, 0, 0}, m[3]{1, 1, 1}, dof = 1;
  PetscScalar &operator()(PetscInt i, PetscInt j, PetscInt k, PetscInt c) const { return a[(((k - s[2]) * m[1] + (j - s[1])) * m[0] + (i - s[0])) * dof + c]; }
  bool         Contains(const PetscInt c[3]) const
  {
    for (int d = 0; d < 3; ++d)
      if (c[d] < s[d] || c[d] >= s[d] + m[d]) return false;
    return true;
  }
};

PetscErrorCode ViewGet(DM da, Vec v, PetscBool ghosted, CellView *view)
{
  PetscInt dim;
  PetscFunctionBeginUser;
  PetscCall(DMDAGetInfo(da, &dim, NULL, NULL, NULL, NULL, NULL, NULL, &view->dof, NULL, NULL, NULL, NULL, NULL));
  if (ghosted) PetscCall(DMDAGetGhostCorners(da, &view->s[0], &view->s[1], &view->s[2], &view->m[0], &view->m[1], &view->m[2]));
  else PetscCall(DMDAGetCorners(da, &view->s[0], &view->s[1], &view->s[2], &view->m[0], &view->m[1], &view->m[2]));
  if (dim == 2) {
    view->s[2] = 0;
    view->m[2] = 1;
  }
  PetscCall(VecGetArray(v, &view->a));
  PetscFunctionReturn(0);
}

PetscErrorCode ViewRestore(Vec v, CellView *view)
{
  PetscFunctionBeginUser;
  PetscCall(VecRestoreArray(v, &view->a));
  PetscFunctionReturn(0);
}

// The coupling cell of a particle centre (clamped to the domain).
inline void CellOf(const Coupling *c, const Vec3 &x, PetscInt cell[3])
{
  const PetscReal xx[3] = {x.x, x.y, x.z};
  for (int a = 0; a < 3; ++a) {
    if (a >= c->dim) {
      cell[a] = 0;
      continue;
    }
    const PetscInt q = (PetscInt)std::floor((xx[a] - c->dom->lo[a]) / c->h[a]);
    cell[a]          = PetscMin(PetscMax(q, 0), c->n[a] - 1);
  }
}

template <class Fn>
void ForOwnedCells(const CellView &v, Fn &&fn)
{
  for (PetscInt k = v.s[2]; k < v.s[2] + v.m[2]; ++k)
    for (PetscInt j = v.s[1]; j < v.s[1] + v.m[1]; ++j)
      for (PetscInt i = v.s[0]; i < v.s[0] + v.m[0]; ++i) fn(i, j, k);
}

// Drag on every local particle (eq. 2.11-2.18) with the void fraction of its coupling cell at the particles'
// current positions; the reaction goes to the cell (eq. 2.21). Called by the DEM after the contact forces.
PetscErrorCode ParticleDrag(void *ctx, DM swarm, const ContactBody *bodies)
{
  Coupling *c = (Coupling *)ctx;
  PetscInt  n;
  PetscReal     *f;
  CellView       dep, gas;
  PetscReal      sum_local[3] = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCall(PhaseBegin(c->log, PHASE_COUPLING));
  PetscCall(DMSwarmGetLocalSize(swarm, &n));

  // 1. solid volume per coupling cell (eq. 5.2), halos added to their owners
  PetscCall(VecZeroEntries(c->deposit_loc));
  PetscCall(ViewGet(c->da, c->deposit_loc, PETSC_TRUE, &dep));
  for (PetscInt p = 0; p < n; ++p) {
    PetscInt cell[3];
    CellOf(c, bodies[p].x, cell);
    PetscCheck(dep.Contains(cell), PETSC_COMM_SELF, PETSC_ERR_PLIB, "particle outside its rank's coupling halo");
    dep(cell[0], cell[1], cell[2], 0) += (4.0 / 3.0) * PETSC_PI * bodies[p].r * bodies[p].r * bodies[p].r;
  }
  PetscCall(ViewRestore(c->deposit_loc, &dep));
  PetscCall(VecZeroEntries(c->deposit));
  PetscCall(DMLocalToGlobal(c->da, c->deposit_loc, ADD_VALUES, c->deposit));

  // 2. void fraction of the owned cells (eq. 5.3), then halos
  {
    CellView  d, g;
    PetscReal lo = 1.0, hi = 0.0;
    PetscInt64 clamped = 0;
    PetscCall(ViewGet(c->da, c->deposit, PETSC_FALSE, &d));
    PetscCall(ViewGet(c->da, c->gas, PETSC_FALSE, &g));
    ForOwnedCells(g, [&](PetscInt i, PetscInt j, PetscInt k) {
      PetscReal eps = 1.0 - d(i, j, k, 0) / c->cell_volume;
      if (eps < c->eps_min) {
        eps = c->eps_min;
        ++clamped;
      }
      g(i, j, k, 0) = eps;
      lo            = PetscMin(lo, eps);
      hi            = PetscMax(hi, eps);
    });
    PetscCall(ViewRestore(c->gas, &g));
    PetscCall(ViewRestore(c->deposit, &d));
    PetscCallMPI(MPI_Allreduce(&lo, &c->stats.eps_min, 1, MPIU_REAL, MPI_MIN, c->comm));
    PetscCallMPI(MPI_Allreduce(&hi, &c->stats.eps_max, 1, MPIU_REAL, MPI_MAX, c->comm));
    PetscCallMPI(MPI_Allreduce(&clamped, &c->stats.clamped, 1, MPIU_INT64, MPI_SUM, c->comm));
  }
  PetscCall(DMGlobalToLocal(c->da, c->gas, INSERT_VALUES, c->gas_loc));

  // 3. drag with the predicted velocity (eq. 2.18), reaction into the cells (eq. 2.21)
  PetscCall(VecZeroEntries(c->deposit_loc));
  PetscCall(ViewGet(c->da, c->deposit_loc, PETSC_TRUE, &dep));
  PetscCall(ViewGet(c->da, c->gas_loc, PETSC_TRUE, &gas));
  PetscCall(DMSwarmGetField(swarm, field::force, NULL, NULL, (void **)&f));
  for (PetscInt p = 0; p < n; ++p) {
    const ContactBody &b = bodies[p];
    PetscInt           cell[3];
    CellOf(c, b.x, cell);
    const PetscReal eps = gas(cell[0], cell[1], cell[2], 0);
    Vec3            u;
    for (PetscInt a = 0; a < c->dim; ++a) (&u.x)[a] = gas(cell[0], cell[1], cell[2], 1 + a);
    const Vec3      slip = u - b.v;
    const PetscReal K    = c->drag(kernels::DragInput{eps, 2.0 * b.r, c->rho_g, c->mu_g, kernels::norm(slip)}) / (c->divide_eps ? eps : 1.0);
    const PetscReal Vp   = (4.0 / 3.0) * PETSC_PI * b.r * b.r * b.r;
    const Vec3      F    = (Vp * K) * slip;
    for (PetscInt a = 0; a < c->dim; ++a) {
      f[3 * p + a] += (&F.x)[a];
      dep(cell[0], cell[1], cell[2], 1 + a) -= (&F.x)[a];
      sum_local[a] += (&F.x)[a];
    }
  }
  PetscCall(DMSwarmRestoreField(swarm, field::force, NULL, NULL, (void **)&f));
  PetscCall(ViewRestore(c->gas_loc, &gas));
  PetscCall(ViewRestore(c->deposit_loc, &dep));
  PetscCall(VecZeroEntries(c->deposit));
  PetscCall(DMLocalToGlobal(c->da, c->deposit_loc, ADD_VALUES, c->deposit));
  PetscCall(VecAXPY(c->reaction_acc, 1.0, c->deposit)); // component 0 (volume) is zero here
  c->acc_count++;
  {
    PetscReal sum[3];
    PetscCallMPI(MPI_Allreduce(sum_local, sum, 3, MPIU_REAL, MPI_SUM, c->comm));
    for (int a = 0; a < 3; ++a) c->drag_acc[a] += sum[a];
  }
  PetscCall(PhaseEnd(c->log, PHASE_COUPLING));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode CouplingCreate(MPI_Comm comm, const Domain &dom, const Grids &grids, Dem *dem, Fluid *fluid, PetscInt substeps, PhaseLog *log, Coupling **out)
{
  Coupling *c = new Coupling;

  PetscFunctionBeginUser;
  c->comm     = comm;
  c->dom      = &dom;
  c->grids    = &grids;
  c->dem      = dem;
  c->fluid    = fluid;
  c->log      = log;
  c->dim      = dom.dim;
  c->substeps = substeps;
  PetscOptionsBegin(comm, "", "Gas-particle coupling (seed eq. 2.11-2.21, two-grid mapping eq. 5.1-5.5)", "Coupling");
  PetscCall(OptionsEnum(PetscOptionsObject, "-couple_grid", "Where void fraction and drag are summed: two (particle grid, eq. 5.1-5.5) or single (fluid grid)",
                        CouplingGridTypes, (PetscEnum *)&c->mode, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-couple_eps_min", "Floor of the void fraction (a cell overfilled by particle centres)", "", Closed(0.01, 0.9),
                        &c->eps_min, NULL));
  PetscCall(PetscOptionsBool("-couple_drag_model_b",
                             "Model B particle drag = eq. 2.18 / eps, so that a packed bed's pressure drop is Ergun's and U_mf is eq. 3.1's (false: eq. 2.18 as "
                             "printed, the Model A force)",
                             "", c->divide_eps, &c->divide_eps, NULL));
  PetscCall(PetscOptionsString("-drag_model", "Drag law: ergun_wenyu (the seed's blend, eq. 2.11-2.14), gidaspow, wen_yu, ergun, di_felice", "", c->drag_name,
                               c->drag_name, sizeof(c->drag_name), NULL));
  PetscOptionsEnd();
  PetscCall(DragLawGet(c->drag_name, &c->drag));
  PetscCheck(FluidIsModelB(fluid), comm, PETSC_ERR_USER_INPUT, "the coupling implements the seed's Model B: use -fluid_model B");
  PetscCall(FluidGetGasProperties(fluid, &c->rho_g, &c->mu_g));

  // Buoyancy (Model B, eq. 2.1): the particles' gravity is (rho_p - rho_g) V_p g.
  dem->body_force_factor = 1.0 - c->rho_g / dem->props->density;

  // The coupling grid: the particle cells, or the fluid cells.
  const ParticleGrid &pg = grids.particle;
  const FluidGrid    &fg = grids.fluid;
  std::vector<PetscInt> own[3];
  for (int a = 0; a < 3; ++a) {
    const bool two = c->mode == COUPLING_GRID_TWO;
    c->n[a]        = two ? pg.n[a] : fg.n[a];
    c->h[a]        = two ? pg.h[a] : fg.h[a];
    c->ratio[a]    = two ? pg.ratio[a] : 1;
    if (a < c->dim)
      for (PetscInt r = 0; r < pg.procs[a]; ++r) own[a].push_back(two ? pg.start[a][r + 1] - pg.start[a][r] : fg.own[a][(std::size_t)r]);
  }
  c->cell_volume = c->h[0] * c->h[1] * c->h[2];
  const PetscInt dof = 1 + c->dim;
  if (c->dim == 2)
    PetscCall(DMDACreate2d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, c->n[0], c->n[1], pg.procs[0], pg.procs[1], dof, 1, own[0].data(),
                           own[1].data(), &c->da));
  else
    PetscCall(DMDACreate3d(comm, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DMDA_STENCIL_BOX, c->n[0], c->n[1], c->n[2], pg.procs[0], pg.procs[1],
                           pg.procs[2], dof, 1, own[0].data(), own[1].data(), own[2].data(), &c->da));
  PetscCall(DMSetUp(c->da));
  PetscCall(PetscObjectSetName((PetscObject)c->da, "coupling_grid"));
  PetscCall(DMCreateGlobalVector(c->da, &c->deposit));
  PetscCall(DMCreateLocalVector(c->da, &c->deposit_loc));
  PetscCall(VecDuplicate(c->deposit, &c->gas));
  PetscCall(VecDuplicate(c->deposit_loc, &c->gas_loc));
  PetscCall(VecDuplicate(c->deposit, &c->reaction_acc));
  PetscCall(VecSet(c->gas, 1.0)); // eps 1 and no gas motion until set
  PetscCall(VecZeroEntries(c->reaction_acc));

  dem->external     = ParticleDrag;
  dem->external_ctx = c;
  *out              = c;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingSetUp(Coupling *c)
{
  PetscFunctionBeginUser;
  PetscCall(CouplingAfterFluidStep(c)); // the initial gas velocity per coupling cell
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingBeforeFluidStep(Coupling *c)
{
  DM        da_s, da_v;
  Vec       eps_f, src_f;
  CellView  g, r, e, s;
  PetscReal sum_local[3] = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCall(PhaseBegin(c->log, PHASE_COUPLING));
  PetscCall(FluidGetCellDMs(c->fluid, &da_s, &da_v));
  PetscCall(FluidGetVoidFraction(c->fluid, &eps_f));
  PetscCall(FluidGetMomentumSource(c->fluid, &src_f));
  const PetscReal scale = c->acc_count ? 1.0 / (c->acc_count * c->cell_volume) : 0.0; // mean reaction per unit volume
  PetscCall(ViewGet(c->da, c->gas, PETSC_FALSE, &g));
  PetscCall(ViewGet(c->da, c->reaction_acc, PETSC_FALSE, &r));
  PetscCall(ViewGet(da_s, eps_f, PETSC_FALSE, &e));
  PetscCall(ViewGet(da_v, src_f, PETSC_FALSE, &s));
  const PetscReal fine_volume = c->grids->fluid.h[0] * c->grids->fluid.h[1] * c->grids->fluid.h[2];
  ForOwnedCells(g, [&](PetscInt i, PetscInt j, PetscInt k) {
    // eq. 5.4-5.5: every fluid cell of the particle cell gets its void fraction; eq. 5.1: the reaction is spread
    // by volume, i.e. the same force per unit volume in each fluid cell
    for (PetscInt kk = k * c->ratio[2]; kk < (k + 1) * c->ratio[2]; ++kk)
      for (PetscInt jj = j * c->ratio[1]; jj < (j + 1) * c->ratio[1]; ++jj)
        for (PetscInt ii = i * c->ratio[0]; ii < (i + 1) * c->ratio[0]; ++ii) {
          e(ii, jj, kk, 0) = g(i, j, k, 0);
          for (PetscInt a = 0; a < c->dim; ++a) {
            s(ii, jj, kk, a) = scale * r(i, j, k, 1 + a);
            sum_local[a] += s(ii, jj, kk, a) * fine_volume;
          }
        }
  });
  PetscCall(ViewRestore(src_f, &s));
  PetscCall(ViewRestore(eps_f, &e));
  PetscCall(ViewRestore(c->reaction_acc, &r));
  PetscCall(ViewRestore(c->gas, &g));
  PetscCallMPI(MPI_Allreduce(sum_local, c->stats.drag_gas, 3, MPIU_REAL, MPI_SUM, c->comm));
  for (int a = 0; a < 3; ++a) {
    c->stats.drag_particles[a] = c->acc_count ? c->drag_acc[a] / c->acc_count : 0.0;
    c->drag_acc[a]             = 0.0;
  }
  PetscCall(VecZeroEntries(c->reaction_acc));
  c->acc_count = 0;
  PetscCall(PhaseEnd(c->log, PHASE_COUPLING));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingAfterFluidStep(Coupling *c)
{
  DM       da_v;
  Vec      u_f;
  CellView g, u;

  PetscFunctionBeginUser;
  PetscCall(PhaseBegin(c->log, PHASE_COUPLING));
  PetscCall(FluidGetCellDMs(c->fluid, NULL, &da_v));
  PetscCall(FluidGetCellVelocity(c->fluid, &u_f));
  PetscCall(ViewGet(c->da, c->gas, PETSC_FALSE, &g));
  PetscCall(ViewGet(da_v, u_f, PETSC_FALSE, &u));
  const PetscReal inv = 1.0 / (PetscReal)(c->ratio[0] * c->ratio[1] * c->ratio[2]);
  ForOwnedCells(g, [&](PetscInt i, PetscInt j, PetscInt k) {
    // seed step 2: the gas velocity of a particle cell is the average over its fluid cells
    PetscReal sum[3] = {0, 0, 0};
    for (PetscInt kk = k * c->ratio[2]; kk < (k + 1) * c->ratio[2]; ++kk)
      for (PetscInt jj = j * c->ratio[1]; jj < (j + 1) * c->ratio[1]; ++jj)
        for (PetscInt ii = i * c->ratio[0]; ii < (i + 1) * c->ratio[0]; ++ii)
          for (PetscInt a = 0; a < c->dim; ++a) sum[a] += u(ii, jj, kk, a);
    for (PetscInt a = 0; a < c->dim; ++a) g(i, j, k, 1 + a) = sum[a] * inv;
  });
  PetscCall(ViewRestore(u_f, &u));
  PetscCall(ViewRestore(c->gas, &g));
  PetscCall(PhaseEnd(c->log, PHASE_COUPLING));
  PetscFunctionReturn(0);
}

const CouplingStats &CouplingGetStats(const Coupling *c) { return c->stats; }

PetscErrorCode CouplingView(const Coupling *c, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  if (c->mode == COUPLING_GRID_TWO)
    PetscCall(PetscViewerASCIIPrintf(viewer, "Coupling: two grids, particle cells of %d x %d x %d fluid cells; drag %s; buoyancy (Model B); gas step = %d DEM steps\n",
                                     (int)c->ratio[0], (int)c->ratio[1], (int)c->ratio[2], c->drag_name, (int)c->substeps));
  else
    PetscCall(PetscViewerASCIIPrintf(viewer, "Coupling: single grid (void fraction and drag on the fluid cells); drag %s; buoyancy (Model B); gas step = %d DEM steps\n",
                                     c->drag_name, (int)c->substeps));
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
  PetscCall(VecDestroy(&(*c)->reaction_acc));
  PetscCall(DMDestroy(&(*c)->da));
  delete *c;
  *c = nullptr;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
