// Component test of the pressure matrix (src/fluid/pressure.cpp) on any number of ranks: the operator the solver
// uses is extracted column by column (MatMult with unit vectors, which serves AIJ and hypre's struct matrix alike;
// natural ordering, gathered on every rank) and compared entry by entry with an operator built here from the
// discretisation of docs/fluid.md ("Step", 3):
//   - per face between cells P and N (periodic faces included): c_f A_f / h_a on the diagonals of P and N and
//     -c_f A_f / h_a at (P, N) and (N, P), where A_f is the face area, h_a the spacing along the face normal and
//     c_f = c0 eps_f / (eps_f + dt beta_f / rho_g), eps_f and beta_f the means of the two cells' void fraction and
//     drag coefficient, c0 = 1 (model B) or eps_f (model A); dt = 0 at the set-up assembly;
//   - faces with a given normal velocity (walls, inlet, uniform outlet) add nothing; a pressure outlet (top face)
//     adds c_P A / (h / 2) to the diagonal, c_P from the cell's own eps and beta.
// The operator is checked as the set-up assembled it (the void fraction of the options), then after a gas step with
// a pseudo-random void fraction in [0.35, 1) and, with -drag, a drag coefficient in [0, 2000) N s/m^4 (some cells 0)
// set in every cell by its natural index, so that the fields do not depend on the decomposition. Tolerance:
// |entry - hand-built| <= 1e-12 |diagonal of the row|. Prints one line per check and exits nonzero on the first
// failure.
#include "component_common.hpp"
#include "gas_scene.hpp"

#include "fluidbed/dmda_field.hpp"
#include "fluidbed/domain.hpp"
#include "fluidbed/fluid.hpp"
#include "fluidbed/grids.hpp"
#include "fluidbed/phases.hpp"

#include <petscao.h>

#include <cmath>
#include <cstring>
#include <vector>

using namespace fluidbed;
using component::Check;
using component::GatherNatural;
using component::SetByNaturalIndex;

static const char help[] = "Pressure operator against a hand-built one (-drag: with an implicit drag; -dt step; -field_seed S)\n";

namespace {

// The operator as a dense N x N array in natural ordering (row-major), on every rank: column j is A e_j.
PetscErrorCode ExtractDense(Mat A, DM da, PetscInt N, std::vector<PetscReal> *D)
{
  Vec                    x, y;
  AO                     ao;
  std::vector<PetscReal> col;

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(A, &x, &y));
  PetscCall(DMDAGetAO(da, &ao));
  D->assign((std::size_t)(N * N), 0.0);
  for (PetscInt j = 0; j < N; ++j) {
    PetscInt pj = j, lo, hi;
    PetscCall(AOApplicationToPetsc(ao, 1, &pj));
    PetscCall(VecZeroEntries(x));
    PetscCall(VecGetOwnershipRange(x, &lo, &hi));
    if (pj >= lo && pj < hi) PetscCall(VecSetValue(x, pj, 1.0, INSERT_VALUES));
    PetscCall(VecAssemblyBegin(x));
    PetscCall(VecAssemblyEnd(x));
    PetscCall(MatMult(A, x, y));
    PetscCall(GatherNatural(da, y, &col));
    for (PetscInt i = 0; i < N; ++i) (*D)[(std::size_t)(i * N + j)] = col[(std::size_t)i];
  }
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&y));
  PetscFunctionReturn(0);
}

struct Scene {
  const Domain *dom;
  PetscInt      n[3];
  PetscReal     h[3], area[3], rho;
  bool          model_b, pressure_top;
};

// The operator of docs/fluid.md for void fraction eps and drag beta (natural ordering) and step dt.
std::vector<PetscReal> HandBuilt(const Scene &s, const std::vector<PetscReal> &eps, const std::vector<PetscReal> &beta, PetscReal dt)
{
  const int              dim = (int)s.dom->dim;
  const PetscInt         N   = s.n[0] * s.n[1] * s.n[2];
  std::vector<PetscReal> H((std::size_t)(N * N), 0.0);
  auto                   index = [&](PetscInt i, PetscInt j, PetscInt k) { return i + s.n[0] * (j + s.n[1] * k); };
  auto                   coef  = [&](PetscReal e, PetscReal b) { return (s.model_b ? 1.0 : e) * e / (e + dt * b / s.rho); };
  for (PetscInt k = 0; k < s.n[2]; ++k)
    for (PetscInt j = 0; j < s.n[1]; ++j)
      for (PetscInt i = 0; i < s.n[0]; ++i) {
        const PetscInt P = index(i, j, k);
        for (int a = 0; a < dim; ++a) {
          // the upper a-face of P: to its neighbour, periodic images wrapped, or the boundary
          PetscInt q[3] = {i, j, k};
          q[a] += 1;
          if (q[a] == s.n[a]) {
            if (!s.dom->periodic[a]) {
              if (a == 1 && s.pressure_top)
                H[(std::size_t)(P * N + P)] += coef(eps[(std::size_t)P], beta[(std::size_t)P]) * s.area[a] / (0.5 * s.h[a]);
              continue;
            }
            q[a] = 0;
          }
          const PetscInt  Q = index(q[0], q[1], q[2]);
          const PetscReal w = coef(0.5 * (eps[(std::size_t)P] + eps[(std::size_t)Q]), 0.5 * (beta[(std::size_t)P] + beta[(std::size_t)Q])) *
                              s.area[a] / s.h[a];
          H[(std::size_t)(P * N + P)] += w;
          H[(std::size_t)(Q * N + Q)] += w;
          H[(std::size_t)(P * N + Q)] -= w;
          H[(std::size_t)(Q * N + P)] -= w;
        }
      }
  return H;
}

PetscErrorCode Compare(MPI_Comm comm, const char *label, const std::vector<PetscReal> &D, const std::vector<PetscReal> &H, PetscInt N)
{
  PetscMPIInt rank;
  long long   bad = 0, nonzero = 0, first = -1;
  double      worst = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  for (PetscInt i = 0; i < N; ++i) {
    const PetscReal scale = std::fabs(H[(std::size_t)(i * N + i)]);
    for (PetscInt j = 0; j < N; ++j) {
      const std::size_t e = (std::size_t)(i * N + j);
      if (H[e] != 0) ++nonzero;
      const double rel = std::fabs(D[e] - H[e]) / (scale > 0 ? scale : 1.0);
      worst            = std::max(worst, rel);
      if (rel > 1e-12) {
        if (first < 0 && rank == 0)
          PetscCall(PetscPrintf(PETSC_COMM_SELF, "  first wrong entry (%d, %d): assembled %.17g, hand-built %.17g\n", (int)i, (int)j,
                                (double)D[e], (double)H[e]));
        if (first < 0) first = i * N + j;
        ++bad;
      }
    }
  }
  PetscCall(PetscPrintf(comm, "%s: %d x %d operator, %lld nonzero entries by hand, largest difference %.3g of the row's diagonal\n", label,
                        (int)N, (int)N, nonzero, worst));
  PetscCall(
    Check(comm, bad == 0, "  every entry within 1e-12 of the row's diagonal of the hand-built operator (wrong entries)", rank ? 0 : bad));
  PetscFunctionReturn(0);
}

// The stencil form the solver multiplies by (-fluid_p_stencil_mult, src/fluid/pressure_stencil.cpp) against the
// assembled matrix: the products of three pseudo-random vectors (set by natural index) must agree bit for bit, since
// the stencil form sums each row's terms in the order of PETSc's AIJ product. Absent (periodic grids, hypre's struct
// matrix, -fluid_p_stencil_mult 0): one line saying so.
PetscErrorCode CompareStencilProduct(MPI_Comm comm, const char *label, Fluid *fluid, DM da, const PetscInt n[3], PetscInt seed)
{
  Mat       A, S;
  Vec       x, ya, ys;
  long long differ = 0, rows = 0;

  PetscFunctionBeginUser;
  PetscCall(FluidGetPressureMatrix(fluid, &A));
  PetscCall(FluidGetPressureStencilMatrix(fluid, &S));
  if (!S) {
    PetscCall(PetscPrintf(comm, "%s: no stencil form (periodic grid, a structured matrix or -fluid_p_stencil_mult 0)\n", label));
    PetscFunctionReturn(0);
  }
  PetscCall(DMCreateGlobalVector(da, &x));
  PetscCall(VecDuplicate(x, &ya));
  PetscCall(VecDuplicate(x, &ys));
  for (PetscInt t = 0; t < 3; ++t) {
    PetscCall(SetByNaturalIndex(da, x, n, [&](PetscInt q) {
      return component::Random((std::uint64_t)(seed * 31 + t * 1000003 + q + 5)).Uniform(-1.0, 1.0) * (t == 2 ? 1e6 : 1.0);
    }));
    PetscCall(MatMult(A, x, ya));
    PetscCall(MatMult(S, x, ys));
    const PetscScalar *a, *b;
    PetscInt           m;
    PetscCall(VecGetLocalSize(ya, &m));
    PetscCall(VecGetArrayRead(ya, &a));
    PetscCall(VecGetArrayRead(ys, &b));
    for (PetscInt i = 0; i < m; ++i) differ += std::memcmp(&a[i], &b[i], sizeof(PetscScalar)) != 0;
    rows += m;
    PetscCall(VecRestoreArrayRead(ys, &b));
    PetscCall(VecRestoreArrayRead(ya, &a));
  }
  PetscCall(VecDestroy(&ys));
  PetscCall(VecDestroy(&ya));
  PetscCall(VecDestroy(&x));
  long long sums[2] = {differ, rows}, all[2];
  PetscCallMPI(MPI_Allreduce(sums, all, 2, MPI_LONG_LONG, MPI_SUM, comm));
  PetscCall(
    PetscPrintf(comm, "%s: stencil form against the matrix, 3 products of %lld rows: %lld entries differ\n", label, all[1] / 3, all[0]));
  PetscCall(Check(comm, all[0] == 0, "  the stencil form's product equals the matrix's bit for bit (entries that differ)", all[0]));
  PetscFunctionReturn(0);
}

} // namespace

int main(int argc, char **argv)
{
  component::GasScene    sc;
  PetscBool              drag = PETSC_FALSE;
  PetscReal              dt   = 1e-3, mu;
  PetscInt               seed = 7;
  DM                     da_s, da_v;
  Mat                    A;
  Vec                    eps_v, beta_v;
  std::vector<PetscReal> eps, beta, D;
  Scene                  s;
  MatType                type;

  PetscCall(PetscInitialize(&argc, &argv, NULL, help));
  PetscCall(PetscOptionsGetBool(NULL, NULL, "-drag", &drag, NULL));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-dt", &dt, NULL));
  PetscCall(PetscOptionsGetInt(NULL, NULL, "-field_seed", &seed, NULL));
  PetscCall(component::GasSceneCreate(PETSC_COMM_WORLD, &sc));
  const MPI_Comm comm  = sc.comm;
  const Domain  &dom   = sc.dom;
  const Grids   &grids = sc.grids;
  Fluid         *fluid = sc.fluid;

  s.dom = &dom;
  for (int a = 0; a < 3; ++a) {
    s.n[a] = a < dom.dim ? grids.fluid.n[a] : 1;
    s.h[a] = a < dom.dim ? grids.fluid.h[a] : dom.len[2];
  }
  for (int a = 0; a < 3; ++a) s.area[a] = s.h[(a + 1) % 3] * s.h[(a + 2) % 3];
  PetscCall(FluidGetGasProperties(fluid, &s.rho, &mu));
  s.model_b        = FluidIsModelB(fluid) == PETSC_TRUE;
  s.pressure_top   = !std::strcmp(FluidBoundaryType(fluid, FACE_YHI), "pressure");
  const PetscInt N = s.n[0] * s.n[1] * s.n[2];

  PetscCall(FluidGetCellDMs(fluid, &da_s, &da_v));
  PetscCall(FluidGetVoidFraction(fluid, &eps_v));
  PetscCall(FluidGetDragCoefficient(fluid, &beta_v));
  PetscCall(FluidGetPressureMatrix(fluid, &A));
  PetscCall(MatGetType(A, &type));
  PetscCall(PetscPrintf(comm, "%dD grid %d x %d x %d, model %s, top %s, periodic %s%s%s, matrix %s%s\n", (int)dom.dim, (int)s.n[0],
                        (int)s.n[1], (int)s.n[2], s.model_b ? "B" : "A", FluidBoundaryType(fluid, FACE_YHI), dom.periodic[0] ? "x" : "",
                        dom.periodic[1] ? "y" : "", dom.periodic[2] ? "z" : "", type, drag ? ", with drag" : ""));

  // the set-up's operator: the void fraction of the options, no drag
  PetscCall(GatherNatural(da_s, eps_v, &eps));
  beta.assign((std::size_t)N, 0.0);
  PetscCall(ExtractDense(A, da_s, N, &D));
  PetscCall(Compare(comm, "set-up", D, HandBuilt(s, eps, beta, 0.0), N));
  PetscCall(CompareStencilProduct(comm, "set-up", fluid, da_s, s.n, seed));

  // a gas step with a non-uniform void fraction (and drag)
  PetscCall(SetByNaturalIndex(da_s, eps_v, s.n,
                              [&](PetscInt q) { return component::Random((std::uint64_t)(seed * 1000003 + q)).Uniform(0.35, 1.0); }));
  PetscCall(SetByNaturalIndex(da_s, beta_v, s.n, [&](PetscInt q) {
    component::Random r((std::uint64_t)(seed * 7919 + q + 1));
    const PetscReal   b = r.Uniform(0.0, 2000.0);
    return drag && r.Uniform() < 0.8 ? b : 0.0;
  }));
  PetscCall(GatherNatural(da_s, eps_v, &eps));
  PetscCall(GatherNatural(da_s, beta_v, &beta));
  PetscCall(FluidStep(fluid, dt));
  PetscCall(FluidGetPressureMatrix(fluid, &A));
  PetscCall(ExtractDense(A, da_s, N, &D));
  // model B without drag keeps the set-up's operator (constant coefficients); otherwise it follows eps, beta and dt
  PetscCall(Compare(comm, "after a gas step", D, HandBuilt(s, eps, beta, drag ? dt : 0.0), N));
  PetscCall(CompareStencilProduct(comm, "after a gas step", fluid, da_s, s.n, seed));

  PetscCall(component::GasSceneDestroy(&sc));
  PetscCall(PetscFinalize());
  return 0;
}
