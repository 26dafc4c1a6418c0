// Component test of the coupling's cell sums (src/coupling/coupling.cpp; seed eq. 5.1-5.5) on any number of ranks:
// the void fraction, B = sum V_p K and M = sum V_p K v_p that the particles of each coupling cell deposit and that
// CouplingBeforeFluidStep maps to the fluid cells (eps copied, B / V and M / V spread by volume), against a
// brute-force serial sum over all particles of all ranks, in the order the code documents: by coupling cell, then by
// particle id (include/fluidbed/coupling.hpp, docs/coupling.md).
//
// What the code promises, and what is checked:
//   - each particle's cell (drag_cell) is floor((x - lo) / h) clamped to the grid, and its a = V_p K (drag_coef) is
//     the drag law at its cell's void fraction, the gas velocity averaged over the cell's fluid cells and its
//     predicted velocity, b = a v_p (drag_ref): bit for bit;
//   - a cell whose particles all belong to the rank that owns it (always so right after a migration) gets, bit for
//     bit, the serial sum in id order: eps = 1 - (sum V_p) / V_cell, beta = (sum a) (1 / V_cell), source
//     = (sum b) (1 / V_cell), on every one of its fluid cells. So these cells do not depend on the decomposition;
//   - a cell that also holds particles of other ranks (they drift up to half a skin out of their rank's cells
//     between neighbour-list rebuilds) gets each rank's id-ordered partial sum added to the owner's: bit for bit
//     that model when at most two ranks contribute (two terms add alike in either order), and within
//     2 n DBL_EPSILON sum |terms| of the serial sum in any case (docs/dem.md: such cells differ in the last bits
//     with the decomposition);
//   - with the particles' storage order shuffled (ParticlesPermute, then ghosts and lists rebuilt without the bin
//     sort), the same state deposits the same fields, bit for bit, on any decomposition.
// The checks run after the set-up, after -steps DEM steps without a list rebuild (so that particles have left their
// rank's cells), and for the shuffled storage. Prints one line per check and exits nonzero on the first failure.
#include "component_common.hpp"
#include "dem_scene.hpp"

#include "fluidbed/coupling.hpp"
#include "../../src/contact/dem_impl.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/drag_laws.hpp"
#include "fluidbed/fluid.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/particles.hpp"
#include "fluidbed/phases.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <map>
#include <numeric>
#include <vector>

using namespace fluidbed;
using component::AllGather;
using component::Check;
using component::GatherNatural;
using kernels::Vec3;

static const char help[] = "Coupling cell sums against a brute-force serial sum (-steps N DEM steps before the second check)\n";

namespace {

struct Setup : component::DemScene {
  Fluid    *fluid    = nullptr;
  Coupling *coupling = nullptr;
  PetscReal h[3]{1, 1, 1};     // coupling cell size
  PetscInt  ratio[3]{1, 1, 1}; // fluid cells per coupling cell
  PetscInt  n[3]{1, 1, 1};     // coupling cells
  PetscBool divide_eps = PETSC_TRUE;
  DragLaw   law;
};

// One particle as the last deposit saw it.
struct Deposited {
  PetscInt64  id, cell;
  PetscMPIInt rank;
  Vec3        x, v; // position, predicted velocity
  PetscReal   r, a, b[3];
};

PetscErrorCode GatherDeposited(Setup &s, std::vector<Deposited> *all)
{
  PetscMPIInt            rank;
  ParticleArrays         p;
  std::vector<PetscReal> mine, flat;
  const std::size_t      stride = 14;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(s.comm, &rank));
  PetscCall(ParticleArraysGet(s.swarm, &p));
  for (PetscInt i = 0; i < p.n; ++i) {
    const ParticleBody &b = s.dem->bodies[(std::size_t)i];
    mine.insert(mine.end(), {(PetscReal)p.id[i], (PetscReal)p.dcell[i], (PetscReal)rank, b.x.x, b.x.y, b.x.z, b.v.x, b.v.y, b.v.z, b.r,
                             p.dcoef[i], p.dref[3 * i], p.dref[3 * i + 1], p.dref[3 * i + 2]});
  }
  PetscCall(ParticleArraysRestore(s.swarm, &p));
  PetscCall(AllGather(s.comm, MPIU_REAL, mine, &flat));
  all->clear();
  for (std::size_t k = 0; k < flat.size(); k += stride) {
    const PetscReal *f = &flat[k];
    all->push_back(
      {(PetscInt64)f[0], (PetscInt64)f[1], (PetscMPIInt)f[2], {f[3], f[4], f[5]}, {f[6], f[7], f[8]}, f[9], f[10], {f[11], f[12], f[13]}});
  }
  std::sort(all->begin(), all->end(), [](const Deposited &x, const Deposited &y) { return x.id < y.id; });
  PetscFunctionReturn(0);
}

// The fluid fields the coupling wrote, in natural ordering: eps, beta (dof 1) and source (dof dim).
struct FluidFields {
  std::vector<PetscReal> eps, beta, source, u;
};

PetscErrorCode GetFluidFields(Setup &s, FluidFields *ff)
{
  DM  da_s, da_v;
  Vec eps, beta, src, u;

  PetscFunctionBeginUser;
  PetscCall(FluidGetCellDMs(s.fluid, &da_s, &da_v));
  PetscCall(FluidGetVoidFraction(s.fluid, &eps));
  PetscCall(FluidGetDragCoefficient(s.fluid, &beta));
  PetscCall(FluidGetMomentumSource(s.fluid, &src));
  PetscCall(FluidGetCellVelocity(s.fluid, &u));
  PetscCall(GatherNatural(da_s, eps, &ff->eps));
  PetscCall(GatherNatural(da_s, beta, &ff->beta));
  PetscCall(GatherNatural(da_v, src, &ff->source));
  PetscCall(GatherNatural(da_v, u, &ff->u));
  PetscFunctionReturn(0);
}

// The coupling cells each rank owns, [lo, hi) per axis (the fluid grid's ownership divided by the ratio).
PetscErrorCode GatherOwnership(Setup &s, std::vector<PetscInt> *boxes)
{
  PetscInt              xs[3], xm[3];
  std::vector<PetscInt> mine;

  PetscFunctionBeginUser;
  PetscCall(DMDAGetCorners(s.grids.fluid.da, &xs[0], &xs[1], &xs[2], &xm[0], &xm[1], &xm[2]));
  for (int a = 0; a < 3; ++a) {
    if (a >= s.dom.dim) xs[a] = 0, xm[a] = 1;
    mine.push_back(xs[a] / s.ratio[a]);
    mine.push_back((xs[a] + xm[a]) / s.ratio[a]);
  }
  PetscCall(AllGather(s.comm, MPIU_INT, mine, boxes));
  PetscFunctionReturn(0);
}

struct Sums {
  PetscReal vol = 0, a = 0, b[3]{0, 0, 0};
  PetscReal abs_vol = 0, abs_a = 0, abs_b[3]{0, 0, 0};
  PetscInt  count = 0;
  void      Add(PetscReal v, PetscReal aa, const PetscReal bb[3], int dim)
  {
    vol += v;
    a += aa;
    abs_vol += std::fabs(v);
    abs_a += std::fabs(aa);
    for (int d = 0; d < dim; ++d) {
      b[d] += bb[d];
      abs_b[d] += std::fabs(bb[d]);
    }
    ++count;
  }
};

// Compares the fields with the brute force and prints the checks; label names the state.
PetscErrorCode CheckSums(Setup &s, const char *label, bool expect_strays, FluidFields *fields_out)
{
  const int              dim = (int)s.dom.dim;
  PetscMPIInt            rank, size;
  std::vector<Deposited> all;
  std::vector<PetscInt>  boxes;
  FluidFields            ff;
  const PetscReal        V = s.h[0] * s.h[1] * s.h[2], inv_volume = 1.0 / V;
  const PetscInt         nf[3] = {s.grids.fluid.n[0], s.grids.fluid.n[1], dim == 3 ? s.grids.fluid.n[2] : 1};
  const PetscInt         ncell = s.n[0] * s.n[1] * (dim == 3 ? s.n[2] : 1);
  PetscReal              rho_g, mu_g;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(s.comm, &rank));
  PetscCallMPI(MPI_Comm_size(s.comm, &size));
  PetscCall(GatherDeposited(s, &all));
  PetscCall(GatherOwnership(s, &boxes));
  PetscCall(GetFluidFields(s, &ff));
  PetscCall(FluidGetGasProperties(s.fluid, &rho_g, &mu_g));
  PetscCall(PetscPrintf(s.comm, "%s: %zu particles in %d coupling cells of %d x %d x %d fluid cells\n", label, all.size(), (int)ncell,
                        (int)s.ratio[0], (int)s.ratio[1], (int)s.ratio[2]));
  const bool root = rank == 0; // the comparisons are made on rank 0 (every rank holds the same gathered data)

  // brute force: each particle's cell, the serial sums in id order, and each rank's partial sums
  long long                                  wrong_cell = 0, strays = 0;
  std::vector<Sums>                          serial((std::size_t)ncell);
  std::map<std::pair<PetscInt64, int>, Sums> partial; // (cell, rank)
  for (const Deposited &p : all) {
    PetscInt        c[3] = {0, 0, 0};
    const PetscReal x[3] = {p.x.x, p.x.y, p.x.z};
    for (int a = 0; a < dim; ++a) c[a] = PetscMin(PetscMax((PetscInt)std::floor((x[a] - s.dom.lo[a]) / s.h[a]), 0), s.n[a] - 1);
    const PetscInt64 flat = c[0] + s.n[0] * (c[1] + s.n[1] * (PetscInt64)c[2]);
    if (flat != p.cell) ++wrong_cell;
    const PetscInt *box   = &boxes[6 * (std::size_t)p.rank];
    bool            owned = true;
    for (int a = 0; a < 3; ++a) owned = owned && c[a] >= box[2 * a] && c[a] < box[2 * a + 1];
    if (!owned) ++strays;
    const PetscReal vol = (4.0 / 3.0) * PETSC_PI * p.r * p.r * p.r;
    serial[(std::size_t)flat].Add(vol, p.a, p.b, dim);
    partial[{flat, p.rank}].Add(vol, p.a, p.b, dim);
  }

  // each particle's linearised drag from the law, at its cell's void fraction and mean gas velocity
  long long wrong_drag = 0, clamped = 0;
  auto      cell_u = [&](PetscInt64 flat) {
    const PetscInt c[3]   = {(PetscInt)(flat % s.n[0]), (PetscInt)((flat / s.n[0]) % s.n[1]), (PetscInt)(flat / (s.n[0] * s.n[1]))};
    PetscReal      sum[3] = {0, 0, 0};
    for (PetscInt kk = c[2] * s.ratio[2]; kk < (c[2] + 1) * s.ratio[2]; ++kk)
      for (PetscInt jj = c[1] * s.ratio[1]; jj < (c[1] + 1) * s.ratio[1]; ++jj)
        for (PetscInt ii = c[0] * s.ratio[0]; ii < (c[0] + 1) * s.ratio[0]; ++ii)
          for (int a = 0; a < dim; ++a) sum[a] += ff.u[(std::size_t)(((kk * nf[1] + jj) * nf[0] + ii) * dim + a)];
    const PetscReal inv = 1.0 / (PetscReal)(s.ratio[0] * s.ratio[1] * s.ratio[2]);
    Vec3            u;
    for (int a = 0; a < dim; ++a) (&u.x)[a] = sum[a] * inv;
    return u;
  };
  for (const Sums &q : serial)
    if (1.0 - q.vol / V < 0.05) ++clamped; // -couple_eps_min's default; the scenes stay above it
  for (const Deposited &p : all) {
    // the void fraction the code holds for the cell (checked against the sums below)
    const PetscInt  c[3] = {(PetscInt)(p.cell % s.n[0]), (PetscInt)((p.cell / s.n[0]) % s.n[1]), (PetscInt)(p.cell / (s.n[0] * s.n[1]))};
    const PetscReal eps  = ff.eps[(std::size_t)((c[2] * s.ratio[2] * nf[1] + c[1] * s.ratio[1]) * nf[0] + c[0] * s.ratio[0])];
    const Vec3      u    = cell_u(p.cell);
    const PetscReal K =
      s.law.k(s.law.cell(eps), kernels::DragInput{eps, 2.0 * p.r, rho_g, mu_g, kernels::norm(u - p.v)}) / (s.divide_eps ? eps : 1.0);
    const PetscReal a  = (4.0 / 3.0) * PETSC_PI * p.r * p.r * p.r * K;
    bool            ok = p.a == a;
    for (int d = 0; d < 3; ++d) ok = ok && p.b[d] == (d < dim ? a * (&p.v.x)[d] : 0.0);
    if (!ok) ++wrong_drag;
  }

  // the fluid fields against the sums
  long long single_cells = 0, multi_cells = 0, exact_bad = 0, model_bad = 0, tol_bad = 0;
  double    worst_rel = 0;
  for (PetscInt64 flat = 0; flat < ncell; ++flat) {
    const Sums &q = serial[(std::size_t)flat];
    // the code's model: partial sums per rank (id order), added in rank order
    Sums model;
    int  ranks = 0;
    for (int r = 0; r < size; ++r) {
      const auto it = partial.find({flat, r});
      if (it == partial.end()) continue;
      ++ranks;
      PetscReal bb[3] = {it->second.b[0], it->second.b[1], it->second.b[2]};
      model.Add(it->second.vol, it->second.a, bb, dim);
    }
    if (ranks <= 1) model = q;
    if (ranks <= 1) ++single_cells;
    else ++multi_cells;
    const PetscInt c[3] = {(PetscInt)(flat % s.n[0]), (PetscInt)((flat / s.n[0]) % s.n[1]), (PetscInt)(flat / (s.n[0] * s.n[1]))};
    for (PetscInt kk = c[2] * s.ratio[2]; kk < (c[2] + 1) * s.ratio[2]; ++kk)
      for (PetscInt jj = c[1] * s.ratio[1]; jj < (c[1] + 1) * s.ratio[1]; ++jj)
        for (PetscInt ii = c[0] * s.ratio[0]; ii < (c[0] + 1) * s.ratio[0]; ++ii) {
          const std::size_t f = (std::size_t)((kk * nf[1] + jj) * nf[0] + ii);
          // expected values from the serial sums and from the per-rank model, and the code's
          std::vector<PetscReal> got = {ff.eps[f], ff.beta[f]}, serial_v = {1.0 - q.vol / V, q.a * inv_volume},
                                 model_v = {1.0 - model.vol / V, model.a * inv_volume}, tol = {q.abs_vol / V, q.abs_a * inv_volume};
          for (int d = 0; d < dim; ++d) {
            got.push_back(ff.source[f * (std::size_t)dim + (std::size_t)d]);
            serial_v.push_back(q.b[d] * inv_volume);
            model_v.push_back(model.b[d] * inv_volume);
            tol.push_back(q.abs_b[d] * inv_volume);
          }
          for (std::size_t e = 0; e < got.size(); ++e) {
            const PetscReal bound =
              2.0 * (PetscReal)PetscMax(q.count, 1) * DBL_EPSILON * tol[e] + 2.0 * DBL_EPSILON * std::fabs(serial_v[e]);
            if (ranks <= 1 && got[e] != serial_v[e]) ++exact_bad;
            if (ranks == 2 && got[e] != model_v[e]) ++model_bad;
            if (std::fabs(got[e] - serial_v[e]) > bound) ++tol_bad;
            if (serial_v[e] != 0) worst_rel = std::max(worst_rel, (double)(std::fabs(got[e] - serial_v[e]) / std::fabs(serial_v[e])));
          }
        }
  }
  if (!root) wrong_cell = strays = wrong_drag = clamped = single_cells = multi_cells = exact_bad = model_bad = tol_bad = 0;
  PetscCall(PetscPrintf(s.comm,
                        "  %lld particles outside their rank's cells; %lld cells with one contributing rank, %lld with more; largest "
                        "relative difference from the serial sums %.3g\n",
                        strays, single_cells, multi_cells, worst_rel));
  PetscCall(Check(s.comm, clamped == 0, "  no cell reaches the void-fraction floor (cells)", clamped));
  PetscCall(Check(s.comm, wrong_cell == 0, "  each particle's cell is floor((x - lo) / h) (wrong)", wrong_cell));
  PetscCall(Check(s.comm, wrong_drag == 0, "  each particle's a = V_p K and b = a v_p from the law, bit for bit (wrong)", wrong_drag));
  PetscCall(Check(s.comm, exact_bad == 0,
                  "  cells of one rank: eps, beta, source are the serial id-ordered sums, bit for bit (wrong values)", exact_bad));
  PetscCall(
    Check(s.comm, model_bad == 0, "  cells of two ranks: the owner's partial sum plus the other's, bit for bit (wrong values)", model_bad));
  PetscCall(Check(s.comm, tol_bad == 0, "  every cell within 2 n DBL_EPSILON sum|terms| of the serial sums (wrong values)", tol_bad));
  if (expect_strays) {
    PetscCall(Check(s.comm, !root || strays > 0 || size == 1,
                    "  the scene has particles outside their rank's cells where there are ranks (count)", strays));
  } else {
    PetscCall(Check(s.comm, strays == 0, "  right after a migration every particle lies in its rank's cells (outside)", strays));
  }
  if (fields_out) *fields_out = ff;
  PetscFunctionReturn(0);
}

// Deposits again at the current state (the contact forces' external hook), with the force and torque of the state
// kept so that the predicted velocities, and hence the deposit, depend on the state alone.
PetscErrorCode DepositAgain(Setup &s, const std::vector<PetscReal> &f, const std::vector<PetscReal> &t)
{
  ParticleArrays p;

  PetscFunctionBeginUser;
  PetscCall(ParticleArraysGet(s.swarm, &p));
  std::copy(f.begin(), f.end(), p.f);
  std::copy(t.begin(), t.end(), p.t);
  PetscCall(ParticleArraysRestore(s.swarm, &p));
  PetscCall(ParticlesPackBodies(s.dem));
  PetscCall(ParticlesGhostsUpdate(s.dem));
  PetscCall(DemContactForces(s.dem));
  PetscCall(CouplingBeforeFluidStep(s.coupling));
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv)
{
  Setup           s;
  InsertionReport inserted;
  PetscInt        steps = 40, seed = 3;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  s.comm = PETSC_COMM_WORLD;
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-steps", &steps, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-shuffle_seed", &seed, NULL));
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-couple_drag_model_b", &s.divide_eps, NULL));
  PetscCall(component::DemSceneCreate(PETSC_COMM_WORLD, &s));
  PetscCall(FluidCreate(s.comm, s.dom, s.grids.fluid, &s.log, &s.fluid));
  PetscCall(FluidSetUp(s.fluid));
  PetscCall(CouplingCreate(s.comm, s.dom, s.grids, DemGetParticles(s.dem), s.fluid, &s.log, &s.coupling));
  PetscCall(CouplingCellSize(s.coupling, s.h, s.ratio));
  for (int a = 0; a < 3; ++a) s.n[a] = s.grids.fluid.n[a] / s.ratio[a];
  PetscCall(DragLawGet(CouplingDragName(s.coupling), &s.law));
  PetscCall(ParticlesInsert(s.comm, s.dom, s.grids.particle, s.props, s.swarm, &inserted));
  PetscCall(CouplingSetUp(s.coupling));
  PetscCall(DemSetUp(s.dem, s.swarm, PETSC_FALSE)); // migration, lists, forces and the first deposit
  PetscCall(CouplingBeforeFluidStep(s.coupling));
  PetscCall(CheckSums(s, "after the set-up", false, NULL));

  // DEM steps without a gas step: each deposits again (the drag is linearised every step with -couple_substeps 1)
  const PetscInt64 rebuilds = s.dem->stats.rebuilds;
  for (PetscInt k = 0; k < steps; ++k) PetscCall(DemStep(s.dem));
  PetscCall(CouplingBeforeFluidStep(s.coupling));
  PetscCall(PetscPrintf(s.comm, "%d DEM steps, %lld list rebuilds:\n", (int)steps, (long long)(s.dem->stats.rebuilds - rebuilds)));
  PetscCall(Check(s.comm, s.dem->stats.rebuilds == rebuilds, "no list rebuild in these steps (rebuilds)", 0));
  PetscCall(CheckSums(s, "after the steps", true, NULL));

  // the same state deposited again, in storage order and then with the storage shuffled
  FluidFields            before, after;
  std::vector<PetscReal> f, t;
  {
    ParticleArrays p;
    PetscCall(ParticleArraysGet(s.swarm, &p));
    f.assign(p.f, p.f + 3 * p.n);
    t.assign(p.t, p.t + 3 * p.n);
    PetscCall(ParticleArraysRestore(s.swarm, &p));
  }
  PetscCall(DepositAgain(s, f, t));
  PetscCall(CheckSums(s, "deposited again in storage order", true, &before));
  {
    PetscMPIInt           rank;
    PetscInt              n;
    std::vector<PetscInt> order;
    PetscCallMPI(MPI_Comm_rank(s.comm, &rank));
    PetscCall(DMSwarmGetLocalSize(s.swarm, &n));
    order.resize((std::size_t)n);
    std::iota(order.begin(), order.end(), 0);
    component::Random rng((std::uint64_t)(seed + 1000 * rank));
    for (PetscInt i = n - 1; i > 0; --i) std::swap(order[(std::size_t)i], order[(std::size_t)(rng.Next() % (std::uint64_t)(i + 1))]);
    std::vector<PetscReal> fs(f.size()), ts(t.size());
    for (PetscInt k = 0; k < n; ++k)
      for (int d = 0; d < 3; ++d) {
        fs[3 * (std::size_t)k + (std::size_t)d] = f[3 * (std::size_t)order[(std::size_t)k] + (std::size_t)d];
        ts[3 * (std::size_t)k + (std::size_t)d] = t[3 * (std::size_t)order[(std::size_t)k] + (std::size_t)d];
      }
    PetscCall(DemSyncPairHistory(s.dem));
    PetscCall(ParticlesPermute(s.swarm, order));
    PetscCall(ParticlesPackBodies(s.dem));
    PetscCall(ParticlesGhostsBuild(s.dem));
    PetscCall(DemNeighbourBuild(s.dem));
    PetscCall(DepositAgain(s, fs, ts));
  }
  PetscCall(CheckSums(s, "deposited again with the storage shuffled", true, &after));
  {
    long long differ = 0;
    for (auto pr : {std::make_pair(&before.eps, &after.eps), std::make_pair(&before.beta, &after.beta),
                    std::make_pair(&before.source, &after.source)})
      for (std::size_t e = 0; e < pr.first->size(); ++e) differ += (*pr.first)[e] != (*pr.second)[e];
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(s.comm, &rank));
    PetscCall(
      Check(s.comm, differ == 0, "the shuffled storage deposits the same eps, beta and source, bit for bit (differ)", rank ? 0 : differ));
  }

  PetscCall(CouplingDestroy(&s.coupling));
  PetscCall(FluidDestroy(&s.fluid));
  PetscCall(component::DemSceneDestroy(&s));
  PetscCall(PetscFinalize());
  return 0;
}
