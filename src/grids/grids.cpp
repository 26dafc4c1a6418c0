#include "fluidbed/grids.hpp"
#include "fluidbed/dmda_field.hpp"
#include "fluidbed/options.hpp"
#include "fluidbed/kernels/grid_ratio.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace fluidbed {

namespace {

const char *const AxisName[3] = {"x", "y", "z"};
// -pgrid_layout: how the process grid is chosen when -pgrid_processors is not given (PETSc's enum list format)
const char *const LayoutNames[] = {"horizontal", "petsc", "particles", "GridLayout", "GRID_LAYOUT_", NULL};

// Creates a DMDA of dimension dim with given global sizes, process grid and ownership ranges (NULL: decide).
// Default process grid: split x and z only (particles settle at the bottom of a bed, so a vertical split
// leaves the upper ranks idle), choosing the factorisation with the squarest subdomains; fall back to PETSc's
// choice when x and z have too few cells.
void HorizontalProcessGrid(PetscInt dim, const PetscInt n[3], PetscMPIInt size, PetscInt procs[3])
{
  double best = -1;
  for (PetscInt px = 1; px <= size; ++px) {
    if (size % px) continue;
    const PetscInt pz = dim == 3 ? size / px : 1;
    if (dim == 2 && px != size) continue;
    if (px > n[0] || pz > n[2]) continue;
    const double ax = (double)n[0] / px, az = dim == 3 ? (double)n[2] / pz : ax;
    const double score = std::min(ax, az) / std::max(ax, az);
    if (score > best) {
      best     = score;
      procs[0] = px;
      procs[1] = 1;
      procs[2] = pz;
    }
  }
  if (best < 0) procs[0] = procs[1] = procs[2] = PETSC_DECIDE;
}

// -pgrid_layout particles: the initial particles in each particle cell, in natural order (x fastest).
std::vector<double> CellParticles(const Domain &dom, const ParticleGrid &pg, const std::vector<PetscReal> &points)
{
  const kernels::CellGrid g = GridsCellGrid(dom, pg.n);
  std::vector<double>     w((std::size_t)kernels::cell_count(g), 0.0);
  for (std::size_t p = 0; p + 2 < points.size(); p += 3) w[(std::size_t)kernels::cell_of_point(g, &points[p])] += 1.0;
  return w;
}

// Ownership of the cells of one axis by parts processes: cuts where the running sum of the axis's weights m reaches
// k / parts of the total, each process keeping at least one cell.
std::vector<PetscInt> SplitAxis(const std::vector<double> &m, PetscInt parts)
{
  const PetscInt        n     = (PetscInt)m.size();
  double                total = 0;
  std::vector<PetscInt> start((std::size_t)parts + 1, 0);
  for (double x : m) total += x;
  double   run = 0;
  PetscInt i   = 0;
  for (PetscInt k = 1; k < parts; ++k) {
    const double   target = total * (double)k / (double)parts;
    const PetscInt cut    = PetscMax(i, start[(std::size_t)k - 1] + 1);
    for (; i < cut; ++i) run += m[(std::size_t)i];
    // take the next cell while that brings the running sum closer to the target
    while (i < n - (parts - k) && std::fabs(run + m[(std::size_t)i] - target) < std::fabs(run - target)) run += m[(std::size_t)i++];
    start[(std::size_t)k] = i;
  }
  start[(std::size_t)parts] = n;
  return start;
}

// The process grid and ownership ranges that take the least time per step, over every factorisation of the ranks
// (2D: z not split). The particles' stages and the gas's are separated by collective steps, so a step takes about
// the busiest rank's particles plus cell_weight times the busiest rank's fluid cells. Each axis is cut at the
// quantiles of its particles, of its cells (even), or of the two's sum, whichever combination is best.
void BalancedProcessGrid(const ParticleGrid &pg, PetscInt dim, PetscMPIInt size, const std::vector<double> &particles,
                         PetscReal cell_weight, PetscInt procs[3], std::vector<PetscInt> start[3], double *cost, double *even_cost)
{
  const PetscInt *n     = pg.n;
  const double    cells = (double)(pg.ratio[0] * pg.ratio[1] * pg.ratio[2]); // fluid cells per particle cell
  double          best = -1, total = 0;
  for (double x : particles) total += x;
  std::vector<double> marg[3], flat[3], both[3];
  for (int a = 0; a < 3; ++a) {
    marg[a].assign((std::size_t)n[a], 0.0);
    flat[a].assign((std::size_t)n[a], 1.0);
  }
  for (PetscInt k = 0; k < n[2]; ++k)
    for (PetscInt j = 0; j < n[1]; ++j)
      for (PetscInt i = 0; i < n[0]; ++i) {
        const double x = particles[(std::size_t)((k * n[1] + j) * n[0] + i)];
        marg[0][(std::size_t)i] += x;
        marg[1][(std::size_t)j] += x;
        marg[2][(std::size_t)k] += x;
      }
  for (int a = 0; a < 3; ++a) {
    both[a].resize((std::size_t)n[a]);
    const double per = cell_weight * cells * (double)(n[0] * n[1] * n[2] / n[a]); // the gas work of one slab
    for (PetscInt i = 0; i < n[a]; ++i) both[a][(std::size_t)i] = marg[a][(std::size_t)i] + per;
  }
  const double ncell_total = (double)(n[0] * n[1] * n[2]) * cells;
  *even_cost               = total / size + cell_weight * ncell_total / size;
  for (PetscInt px = 1; px <= size; ++px) {
    if (size % px) continue;
    for (PetscInt py = 1; py <= size / px; ++py) {
      if ((size / px) % py) continue;
      const PetscInt pz = size / px / py;
      if (dim == 2 && pz != 1) continue;
      const PetscInt p[3] = {px, py, pz};
      if (px > n[0] || py > n[1] || pz > n[2]) continue;
      std::vector<PetscInt> cand[3][3];
      for (int a = 0; a < 3; ++a) {
        cand[a][0] = SplitAxis(marg[a], p[a]);
        cand[a][1] = SplitAxis(flat[a], p[a]);
        cand[a][2] = SplitAxis(both[a], p[a]);
      }
      for (int cx = 0; cx < 3; ++cx)
        for (int cy = 0; cy < 3; ++cy)
          for (int cz = 0; cz < 3; ++cz) {
            const std::vector<PetscInt> *s[3] = {&cand[0][cx], &cand[1][cy], &cand[2][cz]};
            std::vector<double>          rank_particles((std::size_t)(px * py * pz), 0.0);
            double                       max_cells = 0;
            for (PetscInt rz = 0; rz < pz; ++rz)
              for (PetscInt ry = 0; ry < py; ++ry)
                for (PetscInt rx = 0; rx < px; ++rx) {
                  const PetscInt lo[3] = {(*s[0])[(std::size_t)rx], (*s[1])[(std::size_t)ry], (*s[2])[(std::size_t)rz]};
                  const PetscInt hi[3] = {(*s[0])[(std::size_t)rx + 1], (*s[1])[(std::size_t)ry + 1], (*s[2])[(std::size_t)rz + 1]};
                  double         sum   = 0;
                  for (PetscInt k = lo[2]; k < hi[2]; ++k)
                    for (PetscInt j = lo[1]; j < hi[1]; ++j)
                      for (PetscInt i = lo[0]; i < hi[0]; ++i) sum += particles[(std::size_t)((k * n[1] + j) * n[0] + i)];
                  rank_particles[(std::size_t)((rz * py + ry) * px + rx)] = sum;
                  max_cells = std::max(max_cells, cells * (double)((hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2])));
                }
            const double c = *std::max_element(rank_particles.begin(), rank_particles.end()) + cell_weight * max_cells;
            if (best < 0 || c < best * (1.0 - 1e-12)) {
              best = c;
              for (int a = 0; a < 3; ++a) {
                procs[a] = p[a];
                start[a] = *s[a];
              }
            }
          }
    }
  }
  *cost = best;
}

} // namespace

kernels::CellGrid GridsCellGrid(const Domain &dom, const PetscInt n[3])
{
  return kernels::cell_grid((int)dom.dim, {dom.lo[0], dom.lo[1], dom.lo[2]}, {dom.hi[0], dom.hi[1], dom.hi[2]}, (int)n[0], (int)n[1],
                            (int)n[2]);
}

const char *GridsLayoutName(GridLayout layout)
{
  return LayoutNames[layout];
}

PetscErrorCode GridsCreate(MPI_Comm comm, const Domain &dom, PetscReal d_max, Grids *g, const InitialPoints &points, PetscBool gas)
{
  FluidGrid    &fg    = g->fluid;
  ParticleGrid &pg    = g->particle;
  const int     dim   = (int)dom.dim;
  PetscInt      nf[3] = {0, 0, 0}, ratio[3] = {0, 0, 0}, nratio = 3, procs[3] = {PETSC_DECIDE, PETSC_DECIDE, PETSC_DECIDE}, nprocs = 3;
  PetscReal     cell_diameters = 3.0;
  PetscBool     set_n[3] = {PETSC_FALSE, PETSC_FALSE, PETSC_FALSE}, set_ratio = PETSC_FALSE, set_procs = PETSC_FALSE;
  PetscEnum     layout      = (PetscEnum)GRID_LAYOUT_HORIZONTAL;
  PetscReal     cell_weight = gas ? 3.0 : 0.0;

  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, "grid_", "Fluid grid (fine, cell-centred)", "Grids");
  PetscCall(
    OptionsInt(PetscOptionsObject, "-nx", "Fluid cells along x (default: the particle grid, ratio 1)", 0, 1 << 20, &nf[0], &set_n[0]));
  PetscCall(OptionsInt(PetscOptionsObject, "-ny", "Fluid cells along y (vertical)", 0, 1 << 20, &nf[1], &set_n[1]));
  PetscCall(OptionsInt(PetscOptionsObject, "-nz", "Fluid cells along z (3D only)", 0, 1 << 20, &nf[2], &set_n[2]));
  PetscOptionsEnd();

  PetscOptionsBegin(comm, "pgrid_", "Particle grid (coarse, aligned with the fluid grid)", "Grids");
  PetscCall(OptionsIntArray(PetscOptionsObject, "-ratio",
                            "Fluid cells per particle cell along x,y,z (one value: all directions); must divide -grid_n*; 1 = single grid",
                            PETSC_MIN_INT, PETSC_MAX_INT, ratio, &nratio, &set_ratio));
  PetscCall(OptionsReal(PetscOptionsObject, "-cell_diameters",
                        "Target particle cell size in largest particle diameters, used when -pgrid_ratio is not given", "d",
                        Closed(1.0, 1000.0), &cell_diameters, NULL));
  PetscCall(OptionsIntArray(PetscOptionsObject, "-processors", "Process grid m,n[,p] (default: split x and z only, squarest subdomains)",
                            PETSC_MIN_INT, PETSC_MAX_INT, procs, &nprocs, &set_procs));
  PetscCall(OptionsEnum(PetscOptionsObject, "-layout",
                        "Process grid when -pgrid_processors is not given: horizontal (split x and z only, so that a bed settled at "
                        "the bottom is shared by every rank), petsc (PETSc's balanced choice, which splits the longest direction, "
                        "y in a tall box) or particles (the process grid and ownership ranges that share the work of the initial "
                        "particles and the gas cells evenly; known before insertion for -insert_type file, else horizontal)",
                        LayoutNames, &layout, NULL));
  PetscCall(OptionsReal(PetscOptionsObject, "-cell_weight",
                        "-pgrid_layout particles: the work of one fluid cell in particles (default 3 with the gas, from the coupled beds' "
                        "instruction counts of 3-6, docs/performance.md; 0 without it)",
                        "particles", Closed(0.0, 1e6), &cell_weight, NULL));
  PetscOptionsEnd();
  pg.layout = (GridLayout)layout;

  if (set_ratio) {
    PetscCheck(nratio == 1 || nratio == dim, comm, PETSC_ERR_USER_INPUT, "-pgrid_ratio takes 1 or %d values, got %d", dim, (int)nratio);
    if (nratio == 1) ratio[1] = ratio[2] = ratio[0];
    for (int a = 0; a < dim; ++a)
      PetscCheck(ratio[a] >= 1, comm, PETSC_ERR_ARG_OUTOFRANGE, "-pgrid_ratio along %s = %d is out of range: allowed whole numbers >= 1",
                 AxisName[a], (int)ratio[a]);
  }
  if (set_procs) PetscCheck(nprocs == dim, comm, PETSC_ERR_USER_INPUT, "-pgrid_processors takes %d values, got %d", dim, (int)nprocs);

  const PetscReal target = cell_diameters * d_max;
  for (int a = 0; a < 3; ++a) {
    if (a >= dim) {
      nf[a]    = 1;
      ratio[a] = 1;
      continue;
    }
    PetscCheck(d_max > 0 || (set_n[a] && nf[a] > 0), comm, PETSC_ERR_USER_INPUT, "-grid_n%s is required without particles (-particles 0)",
               AxisName[a]);
    if (!set_n[a] || nf[a] == 0) {
      // no fluid grid given: particle cells of about the target size, fluid cells from the ratio (default 1)
      const PetscInt nc = PetscMax(1, (PetscInt)std::floor(dom.len[a] / target));
      if (!set_ratio) ratio[a] = 1;
      nf[a] = nc * ratio[a];
    } else if (!set_ratio) {
      ratio[a] = (PetscInt)kernels::nearest_divisor(nf[a], target / (dom.len[a] / nf[a]));
    }
    PetscCheck(nf[a] % ratio[a] == 0, comm, PETSC_ERR_USER_INPUT,
               "non-integer grid ratio: -grid_n%s %d is not a multiple of -pgrid_ratio %d along %s; whole divisors of %d are %s",
               AxisName[a], (int)nf[a], (int)ratio[a], AxisName[a], (int)nf[a], kernels::divisor_list(nf[a]).c_str());
    fg.n[a]     = nf[a];
    fg.h[a]     = dom.len[a] / nf[a];
    pg.ratio[a] = ratio[a];
    pg.n[a]     = nf[a] / ratio[a];
    pg.h[a]     = dom.len[a] / pg.n[a];
    PetscCheck(pg.h[a] >= d_max * (1.0 - 1e-12), comm, PETSC_ERR_USER_INPUT,
               "particle cell of %.6g m along %s is smaller than the largest particle diameter %.6g m: use a larger -pgrid_ratio (divisors "
               "of %d: %s) or fewer "
               "-grid_n%s cells",
               (double)pg.h[a], AxisName[a], (double)d_max, (int)nf[a], kernels::divisor_list(nf[a]).c_str(), AxisName[a]);
  }
  if (dim == 2) { fg.h[2] = pg.h[2] = dom.len[2]; }

  // Coarse cell-centred DMDA: PETSc picks a balanced process grid; the other two follow its ownership.
  DMBoundaryType bt[3], bnone[3] = {DM_BOUNDARY_NONE, DM_BOUNDARY_NONE, DM_BOUNDARY_NONE};
  for (int a = 0; a < 3; ++a) bt[a] = dom.periodic[a] ? DM_BOUNDARY_PERIODIC : DM_BOUNDARY_NONE;
  {
    const PetscInt       *owned[3] = {NULL, NULL, NULL};
    std::vector<PetscInt> balanced[3], balanced_own[3];
    PetscInt              size[3];
    PetscMPIInt           nranks;
    PetscCallMPI(MPI_Comm_size(comm, &nranks));
    if (set_procs) {
      PetscCheck(procs[0] * procs[1] * (dim == 3 ? procs[2] : 1) == nranks, comm, PETSC_ERR_USER_INPUT,
                 "-pgrid_processors product must equal the %d ranks", (int)nranks);
    } else if (pg.layout == GRID_LAYOUT_PARTICLES) {
      std::vector<PetscReal> xyz;
      PetscBool              known = PETSC_FALSE;
      double                 worst = -1, even = 0;
      if (points) PetscCall(points(&xyz, &known));
      if (known) BalancedProcessGrid(pg, dim, nranks, CellParticles(dom, pg, xyz), cell_weight, procs, balanced, &worst, &even);
      if (worst >= 0) {
        PetscCall(PetscInfo(NULL, "-pgrid_layout particles: %d x %d x %d, work per step %.4g against %.4g if evenly shared\n",
                            (int)procs[0], (int)procs[1], (int)procs[2], worst, even));
        for (int a = 0; a < dim; ++a) {
          balanced_own[a].resize((std::size_t)procs[a]);
          for (PetscInt r = 0; r < procs[a]; ++r)
            balanced_own[a][(std::size_t)r] = balanced[a][(std::size_t)r + 1] - balanced[a][(std::size_t)r];
          owned[a] = balanced_own[a].data();
        }
      } else {
        PetscCall(PetscPrintf(comm, "-pgrid_layout particles: the particles' positions are known before insertion only with -insert_type "
                                    "file (and not on a restart); the horizontal layout is used\n"));
        pg.layout = GRID_LAYOUT_HORIZONTAL;
      }
    }
    if (!set_procs && pg.layout == GRID_LAYOUT_HORIZONTAL) HorizontalProcessGrid(dim, pg.n, nranks, procs);
    for (int a = 0; a < dim; ++a) {
      // a rank must own at least one particle cell in every direction
      PetscCheck(!set_procs || procs[a] <= pg.n[a], comm, PETSC_ERR_USER_INPUT, "%d ranks along %s but only %d particle cells",
                 (int)procs[a], AxisName[a], (int)pg.n[a]);
    }
    PetscCheck(pg.n[0] * pg.n[1] * (dim == 3 ? pg.n[2] : 1) >= nranks, comm, PETSC_ERR_USER_INPUT,
               "the particle grid has %d x %d x %d cells, fewer than the %d ranks: use fewer ranks or smaller particle cells", (int)pg.n[0],
               (int)pg.n[1], (int)(dim == 3 ? pg.n[2] : 1), (int)nranks);
    PetscCall(DMDACreateLayout(comm, dim, bnone, DMDA_STENCIL_BOX, pg.n, procs, owned, 1, 1, &pg.da_cell));
    PetscCall(PetscObjectSetName((PetscObject)pg.da_cell, "particle_grid"));
    PetscCall(DMDAGetInfo(pg.da_cell, NULL, NULL, NULL, NULL, &size[0], &size[1], &size[2], NULL, NULL, NULL, NULL, NULL, NULL));
    const PetscInt *own[3] = {NULL, NULL, NULL};
    PetscCall(DMDAGetOwnershipRanges(pg.da_cell, &own[0], &own[1], &own[2]));
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(comm, &rank));
    PetscInt r = rank;
    for (int a = 0; a < 3; ++a) {
      pg.procs[a] = a < dim ? size[a] : 1;
      pg.start[a].assign(pg.procs[a] + 1, 0);
      for (PetscInt i = 0; i < pg.procs[a]; ++i) pg.start[a][i + 1] = pg.start[a][i] + (a < dim ? own[a][i] : 1);
    }
    pg.proc[0] = r % pg.procs[0];
    pg.proc[1] = (r / pg.procs[0]) % pg.procs[1];
    pg.proc[2] = r / (pg.procs[0] * pg.procs[1]);
    for (int a = 0; a < 3; ++a) {
      pg.cell_lo[a] = pg.start[a][pg.proc[a]];
      pg.cell_hi[a] = pg.start[a][pg.proc[a] + 1];
      pg.sub_lo[a]  = dom.lo[a] + pg.cell_lo[a] * pg.h[a];
      pg.sub_hi[a]  = dom.lo[a] + pg.cell_hi[a] * pg.h[a];
      if (a >= dim) {
        pg.sub_lo[a] = dom.lo[a];
        pg.sub_hi[a] = dom.hi[a];
      }
    }

    // Vertex DMDA for the swarm: rank 0 along a direction owns lc[0] + 1 nodes, the others lc[i].
    std::vector<PetscInt> lv[3], lf[3];
    PetscInt              nv[3];
    for (int a = 0; a < dim; ++a) {
      lv[a].resize(pg.procs[a]);
      lf[a].resize(pg.procs[a]);
      fg.own[a].resize(pg.procs[a]);
      for (PetscInt i = 0; i < pg.procs[a]; ++i) {
        const PetscInt cells = pg.start[a][i + 1] - pg.start[a][i];
        lv[a][i]             = cells + (i == 0 ? 1 : 0);
        lf[a][i]             = cells * pg.ratio[a];
        fg.own[a][i]         = lf[a][i];
      }
      nv[a] = pg.n[a] + 1;
    }
    const PetscInt *lvp[3] = {lv[0].data(), lv[1].data(), dim == 3 ? lv[2].data() : NULL};
    const PetscInt *lfp[3] = {lf[0].data(), lf[1].data(), dim == 3 ? lf[2].data() : NULL};
    PetscCall(DMDACreateLayout(comm, dim, bnone, DMDA_STENCIL_BOX, nv, pg.procs, lvp, 1, 1, &pg.da_vertex));
    PetscCall(DMDASetUniformCoordinates(pg.da_vertex, dom.lo[0], dom.hi[0], dom.lo[1], dom.hi[1], dom.lo[2], dom.hi[2]));
    PetscCall(PetscObjectSetName((PetscObject)pg.da_vertex, "particle_grid_vertices"));
    PetscCall(DMDACreateLayout(comm, dim, bt, DMDA_STENCIL_STAR, fg.n, pg.procs, lfp, 1, 1, &fg.da));
    PetscCall(PetscObjectSetName((PetscObject)fg.da, "fluid_grid"));

    // Check the alignment promised above: every coarse cell's fine block is local.
    PetscInt xs[3], xm[3];
    PetscCall(DMDAGetCorners(fg.da, &xs[0], &xs[1], &xs[2], &xm[0], &xm[1], &xm[2]));
    for (int a = 0; a < dim; ++a)
      PetscCheck(xs[a] == pg.cell_lo[a] * pg.ratio[a] && xm[a] == (pg.cell_hi[a] - pg.cell_lo[a]) * pg.ratio[a], PETSC_COMM_SELF,
                 PETSC_ERR_PLIB, "fluid and particle grids are not aligned along %s", AxisName[a]);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode GridsLocalCells(const Grids &g, PetscInt64 *owned, PetscInt64 *halo)
{
  PetscInt dim, sw, xs[3], xm[3], gs[3], gm[3];

  PetscFunctionBeginUser;
  PetscCall(DMDAGetInfo(g.fluid.da, &dim, NULL, NULL, NULL, NULL, NULL, NULL, NULL, &sw, NULL, NULL, NULL, NULL));
  PetscCall(DMDAGetCorners(g.fluid.da, &xs[0], &xs[1], &xs[2], &xm[0], &xm[1], &xm[2]));
  PetscCall(DMDAGetGhostCorners(g.fluid.da, &gs[0], &gs[1], &gs[2], &gm[0], &gm[1], &gm[2]));
  *owned = (PetscInt64)xm[0] * xm[1] * xm[2];
  *halo  = 0;
  // star stencil: the layers of width sw on each face that has a neighbour (the ghost box's corners are not exchanged)
  for (PetscInt a = 0; a < dim; ++a) {
    const PetscInt64 face  = *owned / xm[a];
    const PetscInt   sides = (gs[a] < xs[a] ? 1 : 0) + (gs[a] + gm[a] > xs[a] + xm[a] ? 1 : 0);
    *halo += face * sides * sw;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode GridsDestroy(Grids *g)
{
  PetscFunctionBeginUser;
  PetscCall(DMDestroy(&g->fluid.da));
  PetscCall(DMDestroy(&g->particle.da_cell));
  PetscCall(DMDestroy(&g->particle.da_vertex));
  PetscFunctionReturn(0);
}

PetscErrorCode GridsView(const Grids &g, const Domain &dom, PetscViewer viewer)
{
  const FluidGrid    &fg = g.fluid;
  const ParticleGrid &pg = g.particle;

  PetscFunctionBeginUser;
  if (dom.dim == 2) {
    PetscCall(PetscViewerASCIIPrintf(viewer, "Fluid grid:    %d x %d cells of %.4g x %.4g mm\n", (int)fg.n[0], (int)fg.n[1], 1e3 * fg.h[0],
                                     1e3 * fg.h[1]));
    PetscCall(PetscViewerASCIIPrintf(viewer, "Particle grid: %d x %d cells of %.4g x %.4g mm, ratio %d x %d%s, process grid %d x %d\n",
                                     (int)pg.n[0], (int)pg.n[1], 1e3 * pg.h[0], 1e3 * pg.h[1], (int)pg.ratio[0], (int)pg.ratio[1],
                                     (pg.ratio[0] * pg.ratio[1] == 1) ? " (single grid)" : " (two-grid)", (int)pg.procs[0],
                                     (int)pg.procs[1]));
  } else {
    PetscCall(PetscViewerASCIIPrintf(viewer, "Fluid grid:    %d x %d x %d cells of %.4g x %.4g x %.4g mm\n", (int)fg.n[0], (int)fg.n[1],
                                     (int)fg.n[2], 1e3 * fg.h[0], 1e3 * fg.h[1], 1e3 * fg.h[2]));
    PetscCall(PetscViewerASCIIPrintf(
      viewer, "Particle grid: %d x %d x %d cells of %.4g x %.4g x %.4g mm, ratio %d x %d x %d%s, process grid %d x %d x %d\n", (int)pg.n[0],
      (int)pg.n[1], (int)pg.n[2], 1e3 * pg.h[0], 1e3 * pg.h[1], 1e3 * pg.h[2], (int)pg.ratio[0], (int)pg.ratio[1], (int)pg.ratio[2],
      (pg.ratio[0] * pg.ratio[1] * pg.ratio[2] == 1) ? " (single grid)" : " (two-grid)", (int)pg.procs[0], (int)pg.procs[1],
      (int)pg.procs[2]));
  }
  PetscFunctionReturn(0);
}

} // namespace fluidbed
