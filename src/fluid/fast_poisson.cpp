// The PC type "fastpoisson" (-fluid_p_pc_type fastpoisson): the exact inverse of the projection's operator with one
// constant face coefficient, by transforms and a tridiagonal solve (kernels/separable_poisson.hpp). On the seed's
// uniform grids the projection's face coefficients c_f differ from a constant only through the implicit drag (model B:
// c_f = eps_f / (eps_f + dt beta_f / rho), within 1.1-1.3 of each other on the running beds, docs/ksp.md) or the void
// fraction (model A), so CG with this preconditioner converges at a rate set by that contrast alone, whatever the grid.
//
// The walled and periodic horizontal axes (x, z) are transformed with FFTW (DCT-II between walls, real Fourier when
// periodic); along y, which may end at the pressure outlet, a Thomas solve per mode finishes the inverse (or, when y
// is periodic, a transform as well). In parallel the data move between two pencil layouts: T, split along y only,
// holds whole x and z lines for the transforms; S, split along x only, holds whole y lines for the solve. PETSc
// VecScatters make the moves (fluid layout -> T -> S and back). Where the grid is split along x only (fluidbed's
// default layout for beds, src/grids/grids.cpp) nothing moves: y and z are transformed on each rank's own block and
// the lines along x, cut by the ranks, are solved by the partition method (kernels::separator_factor), which costs one
// MPI_Allgather of three numbers per line instead of four transposes of the grid.
#include "fluid_impl.hpp"
#include "fluidbed/kernels/separable_poisson.hpp"

#include <petsc/private/pcimpl.h>

#include <fftw3.h>

#include <cmath>
#include <vector>

namespace fluidbed {

namespace {

using kernels::LineBC;

// -log_view events of the PC's parts: the transforms, the line solves, the moves between the layouts
PetscLogEvent ev_transform = 0, ev_solve = 0, ev_move = 0;

struct FastPoisson {
  DM        da  = nullptr; // the pressure grid (a reference is held)
  PetscInt  dim = 3, n[3]{1, 1, 1};
  LineBC    bc[3]{LineBC::WallWall, LineBC::WallWall, LineBC::WallWall};
  PetscReal w[3]{1, 1, 1}; // A_a / h_a
  PetscBool grid_set = PETSC_FALSE;

  PetscMPIInt size = 1;
  // pencil T: cells with y in [ty0, ty1), all x and z, x fastest then y then z; pencil S: x in [sx0, sx1), all y and z;
  // mt and ms their local blocks' cell counts per axis
  PetscInt            ty0 = 0, ty1 = 1, sx0 = 0, sx1 = 1, mt[3]{1, 1, 1}, ms[3]{1, 1, 1};
  double             *buf_t = nullptr, *buf_s = nullptr; // fftw_malloc'ed (buf_s == buf_t on one rank)
  Vec                 vt = nullptr, vs = nullptr;
  VecScatter          to_t = nullptr, to_s = nullptr; // fluid -> T, T -> S
  fftw_plan           fwd[3]{}, bwd[3]{};             // per transformed axis (x, z on T; y on S when periodic)
  bool                transformed[3]{false, false, false};
  std::vector<double> modes[3];            // short axes (at most kDenseCells): the orthonormal modes, V[j n + k], instead of FFTW
  std::vector<double> inv;                 // S layout: Thomas factors per mode line (y solved) or 1 / eigenvalue (y transformed)
  PetscReal           scale = 1, coef = 1; // 1 / (transforms' normalisation), the mean face coefficient
  PetscInt            applies = 0;
  bool                built   = false;
  // The partitioned solve (the grid split along x only, more than one rank): the parts' first x cells (cut[P] = n[0]);
  // this rank's piece's cells; per line (y, z mode) the separators' factors (P - 1 values each, sep_cpl's last unused);
  // the scaled right-hand side and one plane's pieces solved alone, lines interleaved (x[i ny + j]) as inv is; the three
  // numbers per line this rank sends, all ranks' numbers; the separators' values.
  PetscBool           partitioned_opt = PETSC_TRUE; // -pc_fastpoisson_partitioned
  bool                partitioned     = false;
  std::vector<int>    cut;
  PetscInt            piece = 0;
  std::vector<double> sep_inv, sep_cpl, rhs, lines_alone, send, recv, sep;
  // Jacobi steps before and after the inverse (symmetric multiplicative), for operators whose face coefficients jump:
  // -fluid_p_pc_fastpoisson_jacobi forces them on or off; unset, each set-up turns them on where the contrast (the mean
  // coefficient over the smallest cell's, diag A / diag L) exceeds jacobi_contrast. dinv = w / diag A, t and u work
  // vectors of the operator's layout.
  PetscInt         jacobi_mode     = -1; // -1 by the contrast, 0 off, 1 on
  PetscBool        jacobi          = PETSC_FALSE;
  PetscReal        jacobi_weight   = 2.0 / 3.0;
  PetscReal        jacobi_contrast = 10;
  PetscReal        contrast = 0, contrast_max = 0;
  PetscInt         setups = 0, jacobi_setups = 0;
  Vec              dinv = nullptr, t = nullptr, u = nullptr, r0 = nullptr; // r0: r less its null-space part
  PetscObjectState dinv_state = -1;                                        // the operator's state dinv was taken from
};

fftw_r2r_kind ForwardKind(LineBC bc)
{
  return bc == LineBC::Periodic ? FFTW_R2HC : bc == LineBC::WallWall ? FFTW_REDFT10 : FFTW_REDFT11;
}
fftw_r2r_kind BackwardKind(LineBC bc)
{
  return bc == LineBC::Periodic ? FFTW_HC2R : bc == LineBC::WallWall ? FFTW_REDFT01 : FFTW_REDFT11;
}

const char *LineBCName(LineBC bc)
{
  return bc == LineBC::Periodic ? "periodic" : bc == LineBC::WallWall ? "walls" : "wall/outlet";
}

// The first index of part r of n split in P (PETSc's split: the first n % P parts one longer).
PetscInt SplitStart(PetscInt n, PetscMPIInt P, PetscMPIInt r)
{
  return r * (n / P) + PetscMin(r, n % P);
}

// Axes of at most this many cells are transformed by a dense matrix across the planes (the seed's 3-5 cells deep beds:
// half the time of FFTW's strided transforms of length 5, a tenth at length 3).
constexpr PetscInt kDenseCells = 8; // at most 16 (kernels::dense_line_transform)

// A plan of the transforms along axis a of a block of m[0] x m[1] x m[2] values (x fastest), in place on buf.
fftw_plan PlanAxis(int a, const PetscInt m[3], double *buf, fftw_r2r_kind kind)
{
  const int  s[3] = {1, (int)m[0], (int)(m[0] * m[1])};
  fftw_iodim dim  = {(int)m[a], s[a], s[a]};
  fftw_iodim loops[2];
  int        nl = 0;
  for (int b = 0; b < 3; ++b)
    if (b != a && m[b] > 1) loops[nl++] = {(int)m[b], s[b], s[b]};
  return fftw_plan_guru_r2r(1, &dim, nl, loops, buf, buf, &kind, FFTW_ESTIMATE);
}

// Sets up the transform along axis a of a block of m[0] x m[1] x m[2] values in buf: the dense modes of a short axis
// (orthonormal) or FFTW's plans, whose normalisation multiplies *norm.
PetscErrorCode SetUpAxisTransform(PC pc, FastPoisson *fp, int a, const PetscInt m[3], double *buf, double *norm)
{
  PetscFunctionBeginUser;
  fp->transformed[a] = true;
  const int na       = (int)fp->n[a];
  if (na <= kDenseCells) {
    fp->modes[a].resize((size_t)(na * na));
    for (int j = 0; j < na; ++j)
      for (int k = 0; k < na; ++k) fp->modes[a][(size_t)(j * na + k)] = kernels::line_mode(fp->bc[a], na, k, j);
    PetscFunctionReturn(0);
  }
  fp->fwd[a] = PlanAxis(a, m, buf, ForwardKind(fp->bc[a]));
  fp->bwd[a] = PlanAxis(a, m, buf, BackwardKind(fp->bc[a]));
  PetscCheck(fp->fwd[a] && fp->bwd[a], PetscObjectComm((PetscObject)pc), PETSC_ERR_LIB, "FFTW could not plan the transforms along axis %d",
             a);
  *norm *= kernels::line_transform_scale(fp->bc[a], na);
  PetscFunctionReturn(0);
}

// The partitioned layout: each rank's own block of the grid (x in [cut[rank], cut[rank + 1]), all y and z, x fastest),
// y and z transformed in place, the lines along x solved by the partition method; per line the piece's Thomas factors
// and the separators' system, factored once.
PetscErrorCode FastPoissonBuildPartitioned(PC pc, FastPoisson *fp, const PetscInt *lx, PetscMPIInt rank)
{
  const PetscMPIInt P = fp->size;

  PetscFunctionBeginUser;
  fp->partitioned = true;
  fp->cut.assign((size_t)P + 1, 0);
  for (PetscMPIInt r = 0; r < P; ++r) fp->cut[(size_t)r + 1] = fp->cut[(size_t)r] + (int)lx[r];
  PetscInt *ms = fp->ms;
  ms[0] = lx[rank], ms[1] = fp->n[1], ms[2] = fp->n[2];
  const PetscInt nloc = ms[0] * ms[1] * ms[2], lines = ms[1] * ms[2];
  fp->buf_t = fp->buf_s = fftw_alloc_real((size_t)nloc);

  double norm = 1;
  for (int a = 1; a < fp->dim; ++a) PetscCall(SetUpAxisTransform(pc, fp, a, ms, fp->buf_t, &norm));
  fp->scale = 1.0 / norm;

  const int *cut = fp->cut.data(), n0 = (int)fp->n[0];
  const int  j0 = kernels::piece_begin(cut, rank), j1 = kernels::piece_end(cut, P, rank);
  fp->piece = j1 - j0;
  fp->inv.assign((size_t)(lines * fp->piece), 0.0);
  fp->sep_inv.assign((size_t)(lines * (P - 1)), 0.0);
  fp->sep_cpl.assign((size_t)(lines * (P - 1)), 0.0);
  std::vector<double> scratch(2 * (size_t)n0), col((size_t)fp->piece);
  for (PetscInt k = 0; k < ms[2]; ++k)
    for (PetscInt j = 0; j < ms[1]; ++j) {
      const PetscInt q   = k * ms[1] + j;
      double         lam = fp->w[1] * kernels::line_eigenvalue(fp->bc[1], (int)fp->n[1], (int)j);
      if (fp->dim == 3) lam += fp->w[2] * kernels::line_eigenvalue(fp->bc[2], (int)fp->n[2], (int)k);
      kernels::tridiagonal_piece_factor(fp->bc[0], n0, j0, j1, fp->w[0], lam, col.data()); // interleaved by line, per z plane
      for (PetscInt i = 0; i < fp->piece; ++i) fp->inv[(size_t)((k * fp->piece + i) * ms[1] + j)] = col[(size_t)i];
      kernels::separator_factor(fp->bc[0], n0, P, cut, fp->w[0], lam, fp->sep_inv.data() + q * (P - 1), fp->sep_cpl.data() + q * (P - 1),
                                scratch.data());
    }
  fp->rhs.assign((size_t)nloc, 0.0);
  fp->lines_alone.assign((size_t)(fp->piece * ms[1]), 0.0);
  fp->send.assign((size_t)(3 * lines), 0.0);
  fp->recv.assign((size_t)(3 * lines * P), 0.0);
  fp->sep.assign((size_t)P, 0.0);
  PetscFunctionReturn(0);
}

PetscErrorCode FastPoissonBuild(PC pc, FastPoisson *fp)
{
  MPI_Comm    comm;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)pc, &comm));
  PetscCallMPI(MPI_Comm_size(comm, &fp->size));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  const PetscMPIInt P = fp->size;
  if (P > 1 && fp->partitioned_opt) {
    PetscInt        pm, pn, pp;
    const PetscInt *lx;
    PetscCall(DMDAGetInfo(fp->da, NULL, NULL, NULL, NULL, &pm, &pn, &pp, NULL, NULL, NULL, NULL, NULL, NULL));
    PetscCall(DMDAGetOwnershipRanges(fp->da, &lx, NULL, NULL));
    bool fits = pm == P && pn == 1 && pp == 1 && fp->bc[0] != LineBC::Periodic;
    for (PetscMPIInt r = 0; fits && r < P - 1; ++r) fits = lx[r] >= 2; // each part a separator and a piece of at least one cell
    if (fits) {
      PetscCall(FastPoissonBuildPartitioned(pc, fp, lx, rank));
      PetscFunctionReturn(0);
    }
  }
  PetscCheck(FastPoissonPencilsFit(fp->n, P), comm, PETSC_ERR_SUP,
             "-fluid_p_pc_type fastpoisson: the pencils need at least as many cells as ranks along x and y (%d x %d cells, %d ranks)",
             (int)fp->n[0], (int)fp->n[1], (int)P);
  fp->ty0      = SplitStart(fp->n[1], P, rank);
  fp->ty1      = SplitStart(fp->n[1], P, rank + 1);
  fp->sx0      = SplitStart(fp->n[0], P, rank);
  fp->sx1      = SplitStart(fp->n[0], P, rank + 1);
  PetscInt *mt = fp->mt, *ms = fp->ms;
  mt[0] = fp->n[0], mt[1] = fp->ty1 - fp->ty0, mt[2] = fp->n[2];
  ms[0] = fp->sx1 - fp->sx0, ms[1] = fp->n[1], ms[2] = fp->n[2];
  const PetscInt nt = mt[0] * mt[1] * mt[2], ns = ms[0] * ms[1] * ms[2];
  fp->buf_t = fftw_alloc_real((size_t)PetscMax(nt, 1));
  fp->buf_s = P == 1 ? fp->buf_t : fftw_alloc_real((size_t)PetscMax(ns, 1));
  PetscCall(VecCreateMPIWithArray(comm, 1, nt, PETSC_DECIDE, fp->buf_t, &fp->vt));
  if (P > 1) PetscCall(VecCreateMPIWithArray(comm, 1, ns, PETSC_DECIDE, fp->buf_s, &fp->vs));

  // the transforms: x and z on T, y on S when periodic (the solve axis otherwise)
  double norm = 1;
  for (int a = 0; a < fp->dim; ++a)
    if (a != 1 || fp->bc[1] == LineBC::Periodic)
      PetscCall(SetUpAxisTransform(pc, fp, a, a == 1 ? ms : mt, a == 1 ? fp->buf_s : fp->buf_t, &norm));
  fp->scale = 1.0 / norm;

  // per mode line of S: the sum of the transformed axes' eigenvalues, then the Thomas factors along y (or 1 / eigenvalue)
  fp->inv.assign((size_t)ns, 0.0);
  std::vector<double> line((size_t)fp->n[1]);
  for (PetscInt k = 0; k < ms[2]; ++k)
    for (PetscInt i = 0; i < ms[0]; ++i) {
      double lam = fp->w[0] * kernels::line_eigenvalue(fp->bc[0], (int)fp->n[0], (int)(fp->sx0 + i));
      if (fp->dim == 3) lam += fp->w[2] * kernels::line_eigenvalue(fp->bc[2], (int)fp->n[2], (int)k);
      if (fp->transformed[1]) {
        for (PetscInt j = 0; j < ms[1]; ++j) {
          const double total = lam + fp->w[1] * kernels::line_eigenvalue(fp->bc[1], (int)fp->n[1], (int)j);
          line[(size_t)j]    = total == 0.0 ? 0.0 : 1.0 / total; // the constant mode: left out (the null space)
        }
      } else {
        kernels::tridiagonal_factor(fp->bc[1], (int)fp->n[1], fp->w[1], lam, line.data());
      }
      for (PetscInt j = 0; j < ms[1]; ++j) fp->inv[(size_t)((k * ms[1] + j) * ms[0] + i)] = line[(size_t)j];
    }

  if (P == 1) PetscFunctionReturn(0);
  // fluid -> T: each T cell's place in the fluid's global vector (natural index through the DMDA's AO)
  {
    AO                    ao;
    std::vector<PetscInt> idx((size_t)nt);
    PetscInt              start;
    PetscCall(VecGetOwnershipRange(fp->vt, &start, NULL));
    for (PetscInt k = 0, q = 0; k < mt[2]; ++k)
      for (PetscInt j = fp->ty0; j < fp->ty1; ++j)
        for (PetscInt i = 0; i < mt[0]; ++i, ++q) idx[(size_t)q] = i + fp->n[0] * (j + fp->n[1] * k);
    PetscCall(DMDAGetAO(fp->da, &ao));
    PetscCall(AOApplicationToPetsc(ao, nt, idx.data()));
    IS  from, to;
    Vec xf;
    PetscCall(ISCreateGeneral(comm, nt, idx.data(), PETSC_COPY_VALUES, &from));
    PetscCall(ISCreateStride(comm, nt, start, 1, &to));
    PetscCall(DMGetGlobalVector(fp->da, &xf));
    PetscCall(VecScatterCreate(xf, from, fp->vt, to, &fp->to_t));
    PetscCall(DMRestoreGlobalVector(fp->da, &xf));
    PetscCall(ISDestroy(&from));
    PetscCall(ISDestroy(&to));
  }
  // T -> S: each S cell's place in T (rank r of T owns y in [SplitStart(r), SplitStart(r + 1)), blocks in rank order)
  {
    std::vector<PetscInt> idx((size_t)ns), tstart((size_t)P + 1, 0);
    for (PetscMPIInt r = 0; r < P; ++r)
      tstart[(size_t)r + 1] = tstart[(size_t)r] + fp->n[0] * (SplitStart(fp->n[1], P, r + 1) - SplitStart(fp->n[1], P, r)) * fp->n[2];
    PetscMPIInt r = 0;
    for (PetscInt k = 0, q = 0; k < ms[2]; ++k)
      for (PetscInt j = 0; j < ms[1]; ++j) {
        while (j >= SplitStart(fp->n[1], P, r + 1)) ++r;
        while (j < SplitStart(fp->n[1], P, r)) --r;
        const PetscInt y0 = SplitStart(fp->n[1], P, r), ny = SplitStart(fp->n[1], P, r + 1) - y0;
        for (PetscInt i = fp->sx0; i < fp->sx1; ++i, ++q) idx[(size_t)q] = tstart[(size_t)r] + i + fp->n[0] * ((j - y0) + ny * k);
      }
    PetscInt start;
    IS       from, to;
    PetscCall(VecGetOwnershipRange(fp->vs, &start, NULL));
    PetscCall(ISCreateGeneral(comm, ns, idx.data(), PETSC_COPY_VALUES, &from));
    PetscCall(ISCreateStride(comm, ns, start, 1, &to));
    PetscCall(VecScatterCreate(fp->vt, from, fp->vs, to, &fp->to_s));
    PetscCall(ISDestroy(&from));
    PetscCall(ISDestroy(&to));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FastPoissonInverse(PC pc, Vec r, Vec y);

// The forward or backward transform along axis a of the block buf of m[0] x m[1] x m[2] values (x fastest).
void TransformAxis(FastPoisson *fp, int a, bool forward, const PetscInt m[3], double *buf)
{
  if (fp->modes[a].empty()) {
    fftw_execute(forward ? fp->fwd[a] : fp->bwd[a]);
    return;
  }
  const long inner = a == 0 ? 1 : a == 1 ? (long)m[0] : (long)(m[0] * m[1]);
  const long total = (long)(m[0] * m[1] * m[2]), outer = total / (inner * m[a]);
  kernels::dense_line_transform((int)m[a], inner, outer, fp->modes[a].data(), !forward, buf);
}

// The mean face coefficient c of the operator A against the unit-coefficient one L: the ratio of their traces where A
// gives its diagonal, else the Rayleigh estimate (A z, L^-1 A z) / (z, A z) (= c when A = c L) with a fixed z set by
// natural index. It scales the inverse (CG does not depend on it; Richardson and the residual's scale do).
PetscErrorCode MeanCoefficient(PC pc, FastPoisson *fp)
{
  PetscBool has_diag;
  Vec       d, e;
  PetscReal num, den;

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(pc->pmat, &d, &e));
  PetscCall(MatHasOperation(pc->pmat, MATOP_GET_DIAGONAL, &has_diag));
  if (has_diag) {
    PetscCall(MatGetDiagonal(pc->pmat, d));
    PetscCall(VecSum(d, &num));
    den = 0;
    for (int a = 0; a < fp->dim; ++a) {
      double trace = 0; // of T_a, times the number of lines along a
      for (PetscInt j = 0; j < fp->n[a]; ++j) trace += kernels::line_matrix_entry(fp->bc[a], (int)fp->n[a], (int)j, (int)j);
      den += fp->w[a] * trace * (double)(fp->n[0] * fp->n[1] * fp->n[2] / fp->n[a]);
    }
  } else {
    DMDAField z;
    PetscCall(DMDAFieldGet(fp->da, d, PETSC_FALSE, &z));
    for (PetscInt k = z.s[2]; k < z.s[2] + z.m[2]; ++k)
      for (PetscInt j = z.s[1]; j < z.s[1] + z.m[1]; ++j)
        for (PetscInt i = z.s[0]; i < z.s[0] + z.m[0]; ++i) z(i, j, k) = std::sin(0.7 * (double)(i + fp->n[0] * (j + fp->n[1] * k)) + 0.3);
    PetscCall(DMDAFieldRestore(d, &z));
    PetscCall(MatMult(pc->pmat, d, e)); // e = A z
    PetscCall(VecDot(d, e, &den));
    fp->coef = 1;
    PetscCall(FastPoissonInverse(pc, e, d)); // d = L^-1 A z
    PetscCall(VecDot(e, d, &num));
  }
  PetscCall(VecDestroy(&d));
  PetscCall(VecDestroy(&e));
  fp->coef = num > 0 && den > 0 ? num / den : 1.0;
  PetscFunctionReturn(0);
}

// The contrast of the face coefficients the mean leaves out: the mean coefficient over the smallest of the cells' own,
// diag A / diag L (1 for a constant coefficient). Single-grid cells packed to the void-fraction floor reach 200 on the
// 150 N/m 550 um bed, where the inverse alone needs 61 CG iterations and with the Jacobi steps 10. The seed's other beds
// stay at 1.2-2.2 (Muller 1.15, the 2D jetted bed 1.5, the 750 um jet on its fine and coarse grids 1.8 and 2.1), where
// the steps cost 25-45% more per solve than the half iteration they save (docs/ksp.md).
PetscErrorCode Contrast(PC pc, FastPoisson *fp)
{
  PetscBool has_diag;
  Vec       d;
  DMDAField a;
  PetscReal low = PETSC_MAX_REAL, glow;

  PetscFunctionBeginUser;
  fp->contrast = 0;
  PetscCall(MatHasOperation(pc->pmat, MATOP_GET_DIAGONAL, &has_diag));
  if (!has_diag) PetscFunctionReturn(0);
  PetscCall(MatCreateVecs(pc->pmat, &d, NULL));
  PetscCall(MatGetDiagonal(pc->pmat, d));
  PetscCall(DMDAFieldGet(fp->da, d, PETSC_FALSE, &a));
  for (PetscInt k = a.s[2]; k < a.s[2] + a.m[2]; ++k)
    for (PetscInt j = a.s[1]; j < a.s[1] + a.m[1]; ++j)
      for (PetscInt i = a.s[0]; i < a.s[0] + a.m[0]; ++i) {
        const PetscInt c[3] = {i, j, k};
        double         dl   = 0; // diag L at the cell
        for (int ax = 0; ax < fp->dim; ++ax)
          dl += fp->w[ax] * kernels::line_matrix_entry(fp->bc[ax], (int)fp->n[ax], (int)c[ax], (int)c[ax]);
        if (dl > 0) low = PetscMin(low, PetscRealPart(a(i, j, k)) / dl);
      }
  PetscCall(DMDAFieldRestore(d, &a));
  PetscCall(VecDestroy(&d));
  PetscCall(MPIU_Allreduce(&low, &glow, 1, MPIU_REAL, MPIU_MIN, PetscObjectComm((PetscObject)pc)));
  fp->contrast     = glow > 0 && glow < PETSC_MAX_REAL ? fp->coef / glow : PETSC_INFINITY;
  fp->contrast_max = PetscMax(fp->contrast_max, fp->contrast);
  PetscFunctionReturn(0);
}

// dinv = w / diag A of the operator as it is now. The gas reuses a set-up for -fluid_pc_reuse solves while the
// operator changes under it; the inverse's mean coefficient may lag, the Jacobi steps' diagonal may not: a cell that
// leaves the void-fraction floor has its diagonal grow a hundredfold, and w D_old^-1 A then has eigenvalues far above
// 2, which makes the preconditioner indefinite (590 of 121,756 solves of the 550 um bed stopped on
// DIVERGED_INDEFINITE_PC before this was refreshed at every change of the operator).
PetscErrorCode JacobiDiagonal(PC pc, FastPoisson *fp)
{
  PetscObjectState state;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectStateGet((PetscObject)pc->pmat, &state));
  if (state == fp->dinv_state) PetscFunctionReturn(0);
  PetscCall(MatGetDiagonal(pc->pmat, fp->dinv)); // positive: a sum of positive face coefficients
  PetscCall(VecReciprocal(fp->dinv));
  PetscCall(VecScale(fp->dinv, fp->jacobi_weight));
  fp->dinv_state = state;
  PetscFunctionReturn(0);
}

PetscErrorCode PCSetUp_FastPoisson(PC pc)
{
  FastPoisson *fp = (FastPoisson *)pc->data;

  PetscFunctionBeginUser;
  PetscCheck(fp->grid_set, PetscObjectComm((PetscObject)pc), PETSC_ERR_ORDER,
             "-fluid_p_pc_type fastpoisson: the pressure grid was not given (PCFastPoissonSetGrid)");
  if (!fp->built) {
    PetscCall(FastPoissonBuild(pc, fp));
    fp->built = true;
  }
  PetscCall(MeanCoefficient(pc, fp));
  PetscCall(Contrast(pc, fp));
  fp->jacobi = (PetscBool)(fp->jacobi_mode == 1 || (fp->jacobi_mode == -1 && fp->contrast > fp->jacobi_contrast));
  fp->setups++;
  fp->jacobi_setups += fp->jacobi ? 1 : 0;
  if (fp->jacobi) {
    if (!fp->dinv) {
      PetscCall(MatCreateVecs(pc->pmat, &fp->dinv, &fp->t));
      PetscCall(VecDuplicate(fp->t, &fp->u));
      PetscCall(VecDuplicate(fp->t, &fp->r0));
    }
    PetscCall(JacobiDiagonal(pc, fp));
  }
  PetscFunctionReturn(0);
}

// FastPoissonInverse on the partitioned layout: y and z transformed on the rank's block; then per z plane the block is
// turned so that the lines along x interleave (x[i ny + j], j the y mode), as the Thomas sweeps want them (one line's
// sweep is a chain of dependent operations; many lines side by side fill the vector lanes); the pieces solved alone,
// the three numbers of every rank's piece per line gathered, the separators solved, the pieces solved again with them.
PetscErrorCode FastPoissonInversePartitioned(PC pc, FastPoisson *fp, Vec r, Vec y)
{
  const PetscInt    *ms = fp->ms, xm = ms[0], ny = ms[1], nz = ms[2], lines = ny * nz, piece = fp->piece, plane = xm * ny;
  const PetscMPIInt  P = fp->size;
  PetscMPIInt        rank;
  const PetscScalar *a;
  PetscScalar       *b;
  const double       s = fp->scale / fp->coef, w = fp->w[0];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PetscObjectComm((PetscObject)pc), &rank));
  const bool last = rank == P - 1;
  PetscCall(VecGetArrayRead(r, &a));
  PetscCall(PetscArraycpy(fp->buf_t, a, xm * lines));
  PetscCall(VecRestoreArrayRead(r, &a));
  PetscCall(PetscLogEventBegin(ev_transform, pc, 0, 0, 0));
  TransformAxis(fp, 1, true, ms, fp->buf_t);
  if (fp->dim == 3) TransformAxis(fp, 2, true, ms, fp->buf_t);
  PetscCall(PetscLogEventEnd(ev_transform, pc, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_solve, pc, 0, 0, 0));
  for (PetscInt k = 0; k < nz; ++k) {
    const double *x = fp->buf_t + k * plane;
    double       *f = fp->rhs.data() + k * plane, *g = fp->lines_alone.data();
    for (PetscInt j = 0; j < ny; ++j)
      for (PetscInt i = 0; i < xm; ++i) f[i * ny + j] = s * x[j * xm + i];
    PetscCall(PetscArraycpy(g, f, piece * ny));
    kernels::tridiagonal_solve_lines((int)piece, (int)ny, w, 1.0, fp->inv.data() + k * piece * ny, g);
    for (PetscInt j = 0; j < ny; ++j) {
      double *out = fp->send.data() + 3 * (k * ny + j);
      out[0]      = g[j];
      out[1]      = g[(piece - 1) * ny + j];
      out[2]      = last ? 0.0 : f[piece * ny + j]; // the separator's right-hand side
    }
  }
  PetscCall(PetscLogEventEnd(ev_solve, pc, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_move, pc, 0, 0, 0));
  PetscCallMPI(MPI_Allgather(fp->send.data(), (PetscMPIInt)(3 * lines), MPI_DOUBLE, fp->recv.data(), (PetscMPIInt)(3 * lines), MPI_DOUBLE,
                             PetscObjectComm((PetscObject)pc)));
  PetscCall(PetscLogEventEnd(ev_move, pc, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_solve, pc, 0, 0, 0));
  for (PetscInt k = 0; k < nz; ++k) {
    double *f = fp->rhs.data() + k * plane, *x = fp->buf_t + k * plane;
    for (PetscInt j = 0; j < ny; ++j) {
      const PetscInt q = k * ny + j;
      for (PetscMPIInt p = 0; p < P - 1; ++p) {
        const double *mine = fp->recv.data() + (size_t)(p * 3 * lines + 3 * q), *next = mine + 3 * lines;
        fp->sep[(size_t)p] = mine[2] + w * (mine[1] + next[0]);
      }
      kernels::separator_solve(P, fp->sep_inv.data() + q * (P - 1), fp->sep_cpl.data() + q * (P - 1), fp->sep.data());
      if (rank > 0) f[j] += w * fp->sep[(size_t)rank - 1];
      if (!last) {
        f[(piece - 1) * ny + j] += w * fp->sep[(size_t)rank];
        f[piece * ny + j] = fp->sep[(size_t)rank];
      }
    }
    kernels::tridiagonal_solve_lines((int)piece, (int)ny, w, 1.0, fp->inv.data() + k * piece * ny, f);
    for (PetscInt j = 0; j < ny; ++j)
      for (PetscInt i = 0; i < xm; ++i) x[j * xm + i] = f[i * ny + j];
  }
  PetscCall(PetscLogEventEnd(ev_solve, pc, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_transform, pc, 0, 0, 0));
  if (fp->dim == 3) TransformAxis(fp, 2, false, ms, fp->buf_t);
  TransformAxis(fp, 1, false, ms, fp->buf_t);
  PetscCall(PetscLogEventEnd(ev_transform, pc, 0, 0, 0));
  PetscCall(VecGetArrayWrite(y, &b));
  PetscCall(PetscArraycpy(b, fp->buf_t, xm * lines));
  PetscCall(VecRestoreArrayWrite(y, &b));
  PetscFunctionReturn(0);
}

// y = L^-1 r / c: the separable inverse with the mean face coefficient c.
PetscErrorCode FastPoissonInverse(PC pc, Vec r, Vec y)
{
  FastPoisson *fp = (FastPoisson *)pc->data;

  PetscFunctionBeginUser;
  if (fp->partitioned) {
    PetscCall(FastPoissonInversePartitioned(pc, fp, r, y));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscLogEventBegin(ev_move, pc, 0, 0, 0));
  if (fp->size > 1) {
    PetscCall(VecScatterBegin(fp->to_t, r, fp->vt, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(fp->to_t, r, fp->vt, INSERT_VALUES, SCATTER_FORWARD));
  } else {
    const PetscScalar *a;
    PetscInt           nloc;
    PetscCall(VecGetLocalSize(r, &nloc));
    PetscCall(VecGetArrayRead(r, &a));
    PetscCall(PetscArraycpy(fp->buf_t, a, nloc));
    PetscCall(VecRestoreArrayRead(r, &a));
  }
  PetscCall(PetscLogEventEnd(ev_move, pc, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_transform, pc, 0, 0, 0));
  const PetscInt *mt = fp->mt, *ms = fp->ms;
  if (fp->transformed[0]) TransformAxis(fp, 0, true, mt, fp->buf_t);
  if (fp->dim == 3 && fp->transformed[2]) TransformAxis(fp, 2, true, mt, fp->buf_t);
  PetscCall(PetscLogEventEnd(ev_transform, pc, 0, 0, 0));
  if (fp->size > 1) {
    PetscCall(PetscLogEventBegin(ev_move, pc, 0, 0, 0));
    PetscCall(VecScatterBegin(fp->to_s, fp->vt, fp->vs, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(fp->to_s, fp->vt, fp->vs, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(PetscLogEventEnd(ev_move, pc, 0, 0, 0));
  }
  PetscCall(PetscLogEventBegin(ev_solve, pc, 0, 0, 0));
  const PetscInt mx = ms[0], plane = mx * fp->n[1];
  const double   s = fp->scale / fp->coef;
  if (fp->transformed[1]) {
    TransformAxis(fp, 1, true, ms, fp->buf_s);
    for (PetscInt q = 0; q < plane * fp->n[2]; ++q) fp->buf_s[q] *= s * fp->inv[(size_t)q];
    TransformAxis(fp, 1, false, ms, fp->buf_s);
  } else {
    for (PetscInt k = 0; k < fp->n[2]; ++k)
      kernels::tridiagonal_solve_lines((int)fp->n[1], (int)mx, fp->w[1], s, fp->inv.data() + k * plane, fp->buf_s + k * plane);
  }
  PetscCall(PetscLogEventEnd(ev_solve, pc, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_move, pc, 0, 0, 0));
  if (fp->size > 1) {
    PetscCall(VecScatterBegin(fp->to_s, fp->vs, fp->vt, INSERT_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(fp->to_s, fp->vs, fp->vt, INSERT_VALUES, SCATTER_REVERSE));
  }
  PetscCall(PetscLogEventEnd(ev_move, pc, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_transform, pc, 0, 0, 0));
  if (fp->dim == 3 && fp->transformed[2]) TransformAxis(fp, 2, false, mt, fp->buf_t);
  if (fp->transformed[0]) TransformAxis(fp, 0, false, mt, fp->buf_t);
  PetscCall(PetscLogEventEnd(ev_transform, pc, 0, 0, 0));
  PetscCall(PetscLogEventBegin(ev_move, pc, 0, 0, 0));
  if (fp->size > 1) {
    PetscCall(VecScatterBegin(fp->to_t, fp->vt, y, INSERT_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(fp->to_t, fp->vt, y, INSERT_VALUES, SCATTER_REVERSE));
  } else {
    PetscScalar *a;
    PetscInt     nloc;
    PetscCall(VecGetLocalSize(y, &nloc));
    PetscCall(VecGetArrayWrite(y, &a));
    PetscCall(PetscArraycpy(a, fp->buf_t, nloc));
    PetscCall(VecRestoreArrayWrite(y, &a));
  }
  PetscCall(PetscLogEventEnd(ev_move, pc, 0, 0, 0));
  PetscFunctionReturn(0);
}

// The PC: the inverse alone, or with -fluid_p_pc_fastpoisson_jacobi between two Jacobi steps, each on the residual
// left by the step before (PETSc's symmetric multiplicative composite of jacobi and this inverse, without its copies):
//   y1 = D^-1 r,  y2 = y1 + L^-1 (r - A y1) / c,  y = y2 + D^-1 (r - A y2).
// Symmetric, as CG needs. The separable inverse sees one mean coefficient; where the coefficients jump by orders of
// magnitude (single-grid cells packed to the void-fraction floor, whose drag is thousands of times their neighbours')
// the error concentrates in those cells, and the Jacobi steps, which weigh each cell by its own diagonal, remove it:
// on the 550 um bed with two cells at the floor, 10 CG iterations per solve instead of 61 (docs/ksp.md).
PetscErrorCode PCApply_FastPoisson(PC pc, Vec r, Vec y)
{
  FastPoisson *fp = (FastPoisson *)pc->data;

  PetscFunctionBeginUser;
  if (!fp->jacobi) {
    PetscCall(FastPoissonInverse(pc, r, y));
  } else {
    // On an operator with a null space (the constant, walls all round) the steps are taken on r less its part in it,
    // and the result is left with none: Pi B Pi (the inverse alone ignores a constant, the Jacobi steps do not).
    MatNullSpace ns;
    PetscCall(JacobiDiagonal(pc, fp));
    PetscCall(MatGetNullSpace(pc->pmat, &ns));
    if (ns) {
      PetscCall(VecCopy(r, fp->r0));
      PetscCall(MatNullSpaceRemove(ns, fp->r0));
      r = fp->r0;
    }
    PetscCall(VecPointwiseMult(y, fp->dinv, r)); // y1
    PetscCall(MatMult(pc->pmat, y, fp->t));
    PetscCall(VecAYPX(fp->t, -1.0, r)); // r - A y1
    PetscCall(FastPoissonInverse(pc, fp->t, fp->u));
    PetscCall(VecAXPY(y, 1.0, fp->u)); // y2
    PetscCall(MatMult(pc->pmat, y, fp->t));
    PetscCall(VecAYPX(fp->t, -1.0, r));                  // r - A y2
    PetscCall(VecPointwiseMult(fp->u, fp->dinv, fp->t)); // D^-1 (r - A y2)
    PetscCall(VecAXPY(y, 1.0, fp->u));
    if (ns) PetscCall(MatNullSpaceRemove(ns, y));
  }
  fp->applies++;
  PetscFunctionReturn(0);
}

PetscErrorCode PCReset_FastPoisson(PC pc)
{
  FastPoisson *fp = (FastPoisson *)pc->data;

  PetscFunctionBeginUser;
  for (int a = 0; a < 3; ++a) {
    if (fp->fwd[a]) fftw_destroy_plan(fp->fwd[a]);
    if (fp->bwd[a]) fftw_destroy_plan(fp->bwd[a]);
    fp->fwd[a] = fp->bwd[a] = nullptr;
    fp->modes[a].clear();
  }
  PetscCall(VecScatterDestroy(&fp->to_t));
  PetscCall(VecScatterDestroy(&fp->to_s));
  PetscCall(VecDestroy(&fp->vt));
  PetscCall(VecDestroy(&fp->vs));
  PetscCall(VecDestroy(&fp->dinv));
  PetscCall(VecDestroy(&fp->t));
  PetscCall(VecDestroy(&fp->u));
  PetscCall(VecDestroy(&fp->r0));
  if (fp->buf_s != fp->buf_t) fftw_free(fp->buf_s);
  fftw_free(fp->buf_t);
  fp->buf_t = fp->buf_s = nullptr;
  for (bool &t : fp->transformed) t = false;
  fp->built = fp->partitioned = false;
  PetscFunctionReturn(0);
}

PetscErrorCode PCDestroy_FastPoisson(PC pc)
{
  FastPoisson *fp = (FastPoisson *)pc->data;

  PetscFunctionBeginUser;
  PetscCall(PCReset_FastPoisson(pc));
  PetscCall(DMDestroy(&fp->da));
  delete fp;
  pc->data = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode PCView_FastPoisson(PC pc, PetscViewer viewer)
{
  FastPoisson *fp = (FastPoisson *)pc->data;
  PetscBool    ascii;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)viewer, PETSCVIEWERASCII, &ascii));
  if (!ascii || !fp->grid_set) PetscFunctionReturn(0);
  const char *axes = "xyz";
  PetscCall(PetscViewerASCIIPrintf(viewer, "  separable inverse with one face coefficient (mean %g)%s, %d applications\n", (double)fp->coef,
                                   fp->jacobi ? " between two Jacobi steps" : "", (int)fp->applies));
  PetscCall(PetscViewerASCIIPrintf(viewer, "  coefficient contrast %g (largest %g); Jacobi steps %s, in %d of %d set-ups\n",
                                   (double)fp->contrast, (double)fp->contrast_max,
                                   fp->jacobi_mode == 1   ? "forced on"
                                   : fp->jacobi_mode == 0 ? "off"
                                                          : "where the contrast exceeds -fluid_p_pc_fastpoisson_jacobi_contrast",
                                   (int)fp->jacobi_setups, (int)fp->setups));
  if (fp->size > 1)
    PetscCall(PetscViewerASCIIPrintf(viewer,
                                     fp->partitioned ? "  grid split along x over %d ranks: lines along x by the partition method\n"
                                                     : "  %d ranks: transposes between two pencil layouts\n",
                                     (int)fp->size));
  for (int a = 0; a < fp->dim; ++a)
    PetscCall(PetscViewerASCIIPrintf(viewer, "  %c: %d cells, %s, %s\n", axes[a], (int)fp->n[a], LineBCName(fp->bc[a]),
                                     !fp->transformed[a]    ? "tridiagonal solve"
                                     : fp->modes[a].empty() ? "transformed (FFTW)"
                                                            : "transformed (dense modes)"));
  PetscFunctionReturn(0);
}

PetscErrorCode PCSetFromOptions_FastPoisson(PC pc, PetscOptionItems *PetscOptionsObject)
{
  FastPoisson *fp = (FastPoisson *)pc->data;

  PetscFunctionBeginUser;
  PetscOptionsHeadBegin(PetscOptionsObject, "Fast Poisson preconditioner (fluidbed)");
  PetscBool on = (PetscBool)(fp->jacobi_mode == 1), set;
  PetscCall(PetscOptionsBool("-pc_fastpoisson_jacobi",
                             "A Jacobi step before and after the separable inverse (symmetric multiplicative), two more operator products "
                             "per application: on or off at every set-up; unset, on where the coefficients' contrast exceeds "
                             "-fluid_p_pc_fastpoisson_jacobi_contrast",
                             "PCFastPoisson", on, &on, &set));
  if (set) fp->jacobi_mode = on ? 1 : 0;
  PetscCall(PetscOptionsReal("-pc_fastpoisson_jacobi_contrast",
                             "Unless -fluid_p_pc_fastpoisson_jacobi is given: the Jacobi steps are on at a set-up where the mean face "
                             "coefficient exceeds this many times the smallest cell's (cells at the void-fraction floor), in [1, inf]",
                             "PCFastPoisson", fp->jacobi_contrast, &fp->jacobi_contrast, NULL));
  PetscCheck(fp->jacobi_contrast >= 1, PetscObjectComm((PetscObject)pc), PETSC_ERR_ARG_OUTOFRANGE,
             "-fluid_p_pc_fastpoisson_jacobi_contrast = %g is out of range: allowed [1, inf]", (double)fp->jacobi_contrast);
  PetscCall(PetscOptionsReal("-pc_fastpoisson_jacobi_weight",
                             "Weight w of the Jacobi steps, w D^-1, in (0, 1): below 1 keeps the preconditioner positive definite (an "
                             "undamped step sends the checkerboard mode of a walled grid to minus itself)",
                             "PCFastPoisson", fp->jacobi_weight, &fp->jacobi_weight, NULL));
  PetscCheck(fp->jacobi_weight > 0 && fp->jacobi_weight < 1, PetscObjectComm((PetscObject)pc), PETSC_ERR_ARG_OUTOFRANGE,
             "-fluid_p_pc_fastpoisson_jacobi_weight = %g is out of range: allowed (0, 1)", (double)fp->jacobi_weight);
  PetscCall(PetscOptionsBool("-pc_fastpoisson_partitioned",
                             "Where the grid is split among the ranks along x only (the default layout of beds): transform y and z on "
                             "each rank's block and solve the lines along x by the partition method, instead of moving the grid between "
                             "two pencil layouts (the same inverse to round-off)",
                             "PCFastPoisson", fp->partitioned_opt, &fp->partitioned_opt, NULL));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

PetscErrorCode PCCreate_FastPoisson(PC pc)
{
  PetscFunctionBeginUser;
  pc->data                = (void *)new FastPoisson();
  pc->ops->setup          = PCSetUp_FastPoisson;
  pc->ops->apply          = PCApply_FastPoisson;
  pc->ops->reset          = PCReset_FastPoisson;
  pc->ops->destroy        = PCDestroy_FastPoisson;
  pc->ops->view           = PCView_FastPoisson;
  pc->ops->setfromoptions = PCSetFromOptions_FastPoisson;
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FastPoissonRegister()
{
  PetscFunctionBeginUser;
  PetscCall(PCRegister(PCFASTPOISSON, PCCreate_FastPoisson));
  if (!ev_transform) {
    PetscClassId id;
    PetscCall(PetscClassIdRegister("FastPoisson", &id));
    PetscCall(PetscLogEventRegister("FastPoissonFFT", id, &ev_transform));
    PetscCall(PetscLogEventRegister("FastPoissonLines", id, &ev_solve));
    PetscCall(PetscLogEventRegister("FastPoissonMove", id, &ev_move));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode PCFastPoissonGetStats(PC pc, PetscBool *is_fp, PetscInt *setups, PetscInt *jacobi_setups, PetscReal *contrast_max)
{
  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFASTPOISSON, is_fp));
  if (!*is_fp) PetscFunctionReturn(0);
  const FastPoisson *fp = (const FastPoisson *)pc->data;
  *setups               = fp->setups;
  *jacobi_setups        = fp->jacobi_setups;
  *contrast_max         = fp->contrast_max;
  PetscFunctionReturn(0);
}

PetscErrorCode PCFastPoissonSetGrid(PC pc, DM da, const PetscReal weight[3], PetscBool outlet_top)
{
  PetscBool      is_fp;
  DMBoundaryType bt[3];
  PetscInt       dim, M, N, Pz;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFASTPOISSON, &is_fp));
  if (!is_fp) PetscFunctionReturn(0);
  FastPoisson *fp = (FastPoisson *)pc->data;
  PetscCall(PCReset_FastPoisson(pc));
  PetscCall(DMDAGetInfo(da, &dim, &M, &N, &Pz, NULL, NULL, NULL, NULL, NULL, &bt[0], &bt[1], &bt[2], NULL));
  PetscCall(PetscObjectReference((PetscObject)da));
  PetscCall(DMDestroy(&fp->da));
  fp->da   = da;
  fp->dim  = dim;
  fp->n[0] = M;
  fp->n[1] = N;
  fp->n[2] = dim == 3 ? Pz : 1;
  for (int a = 0; a < 3; ++a) {
    fp->w[a]  = a < dim ? weight[a] : 0.0;
    fp->bc[a] = bt[a] == DM_BOUNDARY_PERIODIC ? LineBC::Periodic : LineBC::WallWall;
  }
  if (outlet_top) {
    PetscCheck(fp->bc[1] != LineBC::Periodic, PetscObjectComm((PetscObject)pc), PETSC_ERR_ARG_INCOMP,
               "a pressure outlet on a periodic axis");
    fp->bc[1] = LineBC::WallPressure;
  }
  fp->grid_set = PETSC_TRUE;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
