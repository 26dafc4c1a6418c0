// The projection: the pressure matrix, its KSP (prefix -fluid_p_), the correction and the divergence check.
//
// With phi = dt p / rho and the face coefficient c_f (1 for model B, eps_f for model A), the correction
// eps_f u = eps_f u* - c_f grad phi and the continuity equation div(eps u) = -d(eps)/dt (0 by default) give
// div(c grad phi) = div(eps u*) + d(eps)/dt. The matrix is the volume integral of -div(c grad .): symmetric,
// positive semi-definite, singular (constants) unless the top is a pressure outlet (phi = 0 on that face).
#include "fluid_impl.hpp"
#include "fluidbed/options.hpp"

#include <petscdmda.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace fluidbed {

namespace {

// c_f of the projection at the lower a-face of the cell at offset p of the arrays of E (void fraction) and B (the
// drag coefficient, read only when the coupling set one), which share one ghosted layout; sa: the offset between
// neighbours along a, dt the step.
inline PetscReal FaceCoefficient(const Fluid *f, const PetscReal *E, const PetscReal *B, PetscReal dt, PetscInt p, PetscInt sa)
{
  const PetscReal e = 0.5 * (E[p - sa] + E[p]);
  return ProjectionCoefficient(f->model == FLUID_MODEL_B ? 1.0 : e, e, f->has_drag ? 0.5 * (B[p - sa] + B[p]) : 0.0, dt, f->rho);
}

// Volume flux eps_f u A out of the cell at offset p through its faces (m^3/s); U (dof dim) and E share one ghosted
// layout, st: the offsets between neighbours.
inline PetscReal NetOutflow(const Fluid *f, const PetscReal *U, const PetscReal *E, PetscInt dof, const PetscInt st[3], PetscInt p)
{
  PetscReal out = 0;
  for (int a = 0; a < f->dim; ++a) {
    const PetscInt up = p + st[a];
    out += f->area[a] * (0.5 * (E[p] + E[up]) * U[up * dof + a] - 0.5 * (E[p - st[a]] + E[p]) * U[p * dof + a]);
  }
  return out;
}

// The operator's rows (eq. 2.21's projection: the face coefficients c_f A_f / h_f of docs/fluid.md): calls
// row(stencil of the row, n, stencils of its columns, values), each owned row once and whole, the diagonal last.
// keep: the face coefficients and the diagonals also go to f->op, the stencil form's (pressure_stencil.cpp).
template <class Row>
PetscErrorCode ForEachOperatorRow(Fluid *f, PetscReal dt, bool keep, Row &&row)
{
  DMDAField E, B;

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &E));
  PetscCall(DMDAFieldGet(f->da_s, f->drag_loc, PETSC_TRUE, &B));
  PetscCheck(SameLayout(E, B), f->comm, PETSC_ERR_PLIB, "the scalar ghosted layouts differ");
  // c_f A / h of every face between two cells of the rows this rank owns, computed once for the two rows that share
  // it: W[a * N + p] for the lower a-face of the cell at offset p
  const PetscInt N = E.m[0] * E.m[1] * E.m[2];
  PetscReal     *W, *D = nullptr;
  if (keep) {
    f->op.face.resize((std::size_t)(f->dim * N));
    f->op.diag.resize((std::size_t)(f->xm[0] * f->xm[1] * f->xm[2]));
    f->op.layout   = E;
    f->op.layout.a = nullptr;
    W              = f->op.face.data();
    D              = f->op.diag.data();
  } else {
    W = FluidWork(f, (std::size_t)(f->dim * N));
  }
  for (int a = 0; a < f->dim; ++a) {
    const PetscInt sa = E.stride(a);
    PetscReal     *Wa = W + a * N;
    PetscInt       lo[3], hi[3];
    OwnedBox(f, lo, hi);
    hi[a] += 1; // the upper face of the last cell
    ForEachCellInBox(E, lo, hi, [&](PetscInt p) { Wa[p] = FaceCoefficient(f, E.a, B.a, dt, p, sa) * f->area[a] / f->h[a]; });
  }
  for (PetscInt k = f->xs[2]; k < f->xs[2] + f->xm[2]; ++k)
    for (PetscInt j = f->xs[1]; j < f->xs[1] + f->xm[1]; ++j) {
      PetscInt p = E.cell(f->xs[0], j, k);
      for (PetscInt i = f->xs[0]; i < f->xs[0] + f->xm[0]; ++i, ++p) {
        const PetscInt c[3] = {i, j, k};
        MatStencil     rs   = {k, j, i, 0}, col[7];
        PetscScalar    val[7], diag = 0;
        PetscInt       n = 0;
        for (int a = 0; a < f->dim; ++a) {
          const PetscInt sa = E.stride(a);
          for (int side = 0; side < 2; ++side) {
            const PetscInt d = side ? 1 : -1;
            if (!f->periodic[a] && (c[a] + d < 0 || c[a] + d >= f->n[a])) {
              if (f->bc[2 * a + side] == FLUID_BC_PRESSURE)
                diag += ProjectionCoefficient(f->model == FLUID_MODEL_B ? 1.0 : E.a[p], E.a[p], f->has_drag ? B.a[p] : 0.0, dt, f->rho) *
                        f->area[a] / (0.5 * f->h[a]);
              continue; // otherwise the normal velocity is given: no pressure flux
            }
            const PetscReal coef = W[a * N + (side ? p + sa : p)]; // the shared face, as the lower face of its upper cell
            if (side && f->periodic[a] && f->n[a] == 2) {
              // two periodic cells along a: both faces join the same pair, one entry (MatSetValues would keep only the last)
              val[n - 1] -= coef;
              diag += coef;
              continue;
            }
            col[n]   = {k + d * (a == 2), j + d * (a == 1), i + d * (a == 0), 0};
            val[n++] = -coef;
            diag += coef;
          }
        }
        col[n]   = rs;
        val[n++] = diag;
        if (D) *D++ = diag;
        PetscCall(row(rs, n, col, val));
      }
    }
  PetscCall(DMDAFieldRestore(f->drag_loc, &B));
  PetscCall(DMDAFieldRestore(f->eps_loc, &E));
  PetscFunctionReturn(0);
}

// The value arrays of an AIJ matrix: the diagonal block's and (MPIAIJ) the off-diagonal block's, with their lengths.
struct AIJValues {
  Mat          d = nullptr, o = nullptr;
  PetscScalar *ad = nullptr, *ao = nullptr;
  PetscInt     nd = 0, no = 0;
};
PetscErrorCode AIJValuesGet(Mat M, AIJValues *v)
{
  PetscBool mpi;
  MatInfo   info;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)M, MATMPIAIJ, &mpi));
  if (mpi) PetscCall(MatMPIAIJGetSeqAIJ(M, &v->d, &v->o, NULL));
  else v->d = M;
  PetscCall(MatSeqAIJGetArray(v->d, &v->ad));
  PetscCall(MatGetInfo(v->d, MAT_LOCAL, &info));
  v->nd = (PetscInt)info.nz_used;
  if (v->o) {
    PetscCall(MatSeqAIJGetArray(v->o, &v->ao));
    PetscCall(MatGetInfo(v->o, MAT_LOCAL, &info));
    v->no = (PetscInt)info.nz_used;
  }
  PetscFunctionReturn(0);
}
PetscErrorCode AIJValuesRestore(Mat M, AIJValues *v)
{
  PetscFunctionBeginUser;
  PetscCall(MatSeqAIJRestoreArray(v->d, &v->ad));
  if (v->o) PetscCall(MatSeqAIJRestoreArray(v->o, &v->ao));
  PetscCall(MatAssemblyBegin(M, MAT_FINAL_ASSEMBLY)); // nothing to communicate: the operator's state advances, so
  PetscCall(MatAssemblyEnd(M, MAT_FINAL_ASSEMBLY));   // the solver sees the new values
  PetscFunctionReturn(0);
}

PetscErrorCode AssembleThroughStencils(Fluid *f, Mat M, PetscReal dt)
{
  PetscBool structured;

  PetscFunctionBeginUser;
  // PETSc 3.18's MatZeroEntries of a MATHYPRESTRUCT writes outside hypre's arrays on ranks with small boxes (valgrind:
  // hypre_StructMatrixClearBoxValues; a crash on 4 x 4 x 4 cells over 4 ranks). It is not needed there: hypre's matrix
  // starts from zeros and every assembly inserts the same entries of every row.
  PetscCall(PetscObjectTypeCompare((PetscObject)M, MATHYPRESTRUCT, &structured));
  if (!structured) PetscCall(MatZeroEntries(M));
  PetscCall(
    ForEachOperatorRow(f, dt, M == f->A && f->op.A, [&](const MatStencil &r, PetscInt n, const MatStencil *col, const PetscScalar *val) {
      return MatSetValuesStencil(M, 1, &r, n, col, val, INSERT_VALUES); // each row once, whole
    }));
  PetscCall(MatAssemblyBegin(M, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(M, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

// For f->A in AIJ: finds where each entry lands (an assembly whose values are the entries' numbers), and keeps the
// direct path only when every place of the pattern is an entry's, once.
PetscErrorCode FindOperatorPositions(Fluid *f, PetscReal dt)
{
  PetscInt  count = 0;
  AIJValues v;
  PetscBool aij;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompareAny((PetscObject)f->A, &aij, MATSEQAIJ, MATMPIAIJ, ""));
  if (!aij) PetscFunctionReturn(0);
  PetscCall(MatZeroEntries(f->A));
  PetscCall(ForEachOperatorRow(f, dt, false, [&](const MatStencil &r, PetscInt n, const MatStencil *col, const PetscScalar *) {
    PetscScalar tag[7];
    for (PetscInt e = 0; e < n; ++e) tag[e] = (PetscScalar)(++count);
    return MatSetValuesStencil(f->A, 1, &r, n, col, tag, INSERT_VALUES);
  }));
  PetscCall(MatAssemblyBegin(f->A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(f->A, MAT_FINAL_ASSEMBLY));
  f->a_pos.assign((std::size_t)count, PETSC_MIN_INT);
  PetscCall(AIJValuesGet(f->A, &v));
  bool ok = v.nd + v.no == count;
  for (int blk = 0; blk < 2 && ok; ++blk) {
    const PetscScalar *a = blk ? v.ao : v.ad;
    for (PetscInt q = 0; q < (blk ? v.no : v.nd) && ok; ++q) {
      const PetscInt e = (PetscInt)PetscRealPart(a[q]) - 1;
      ok               = e >= 0 && e < count && f->a_pos[(std::size_t)e] == PETSC_MIN_INT;
      if (ok) f->a_pos[(std::size_t)e] = blk ? -1 - q : q;
    }
  }
  PetscCall(AIJValuesRestore(f->A, &v));
  f->a_direct = ok ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FluidAssembleOperator(Fluid *f, Mat M, PetscReal dt)
{
  PetscFunctionBeginUser;
  if (M != f->A) PetscFunctionReturn(AssembleThroughStencils(f, M, dt)); // a copy (the pressure dumps)
  if (!f->a_direct && f->a_pos.empty()) PetscCall(FindOperatorPositions(f, dt));
  if (!f->a_direct) PetscFunctionReturn(AssembleThroughStencils(f, M, dt));
  // the values straight into the arrays, each place the same entry as MatSetValuesStencil would give it
  AIJValues v;
  PetscInt  e = 0;
  PetscCall(AIJValuesGet(M, &v));
  PetscCall(ForEachOperatorRow(f, dt, f->op.A != nullptr, [&](const MatStencil &, PetscInt n, const MatStencil *, const PetscScalar *val) {
    for (PetscInt k = 0; k < n; ++k, ++e) {
      const PetscInt q                  = f->a_pos[(std::size_t)e];
      (q >= 0 ? v.ad[q] : v.ao[-1 - q]) = val[k];
    }
    return (PetscErrorCode)0;
  }));
  PetscCall(AIJValuesRestore(M, &v));
  PetscFunctionReturn(0);
}

namespace {

PetscErrorCode AssembleMatrix(Fluid *f, PetscReal dt)
{
  PetscFunctionBeginUser;
  f->dt_last = dt;
  PetscCall(FluidAssembleOperator(f, f->A, dt));
  if (f->op.A) { // its coefficients changed with A's values: its state advances with A's
    PetscCall(MatAssemblyBegin(f->op.A, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(f->op.A, MAT_FINAL_ASSEMBLY));
  }
  f->assemblies++;
  PetscFunctionReturn(0);
}

// Geometric multigrid on the cell-centred grid: each level coarsens direction a by a fixed whole factor, and
// every rank's cells must coarsen exactly (the Q0 interpolation keeps each coarse cell's children on its rank).
// Factors for L levels: per direction the smallest q in 2..8 with q^(L-1) dividing every rank's cells and
// leaving at least two coarse cells, else 1. Returns false when no direction coarsens.
bool CoarseningFactors(const Fluid *f, PetscInt L, PetscInt fac[3], double *coarse)
{
  *coarse = 1;
  for (int a = 0; a < 3; ++a) fac[a] = 1;
  for (int a = 0; a < f->dim; ++a) {
    PetscInt pw = 1;
    for (PetscInt q = 2; q <= 8 && fac[a] == 1; ++q) {
      pw = 1;
      for (PetscInt l = 1; l < L; ++l) pw *= q;
      bool ok = f->n[a] % pw == 0 && f->n[a] / pw >= 2;
      for (PetscInt own : f->grid->own[a]) ok = ok && own % pw == 0;
      if (ok) fac[a] = q;
    }
    pw = 1;
    for (PetscInt l = 1; l < L; ++l) pw *= fac[a];
    *coarse *= (double)(f->n[a] / pw);
  }
  return fac[0] * fac[1] * fac[2] > 1;
}

// Without -fluid_p_pc_mg_levels: the number of levels (2..8) that gives the smallest coarse grid.
PetscInt ChooseLevels(const Fluid *f)
{
  PetscInt levels = 1, fac[3];
  double   best   = 0, coarse;
  for (PetscInt L = 2; L <= 8; ++L) {
    if (!CoarseningFactors(f, L, fac, &coarse)) break;
    if (best == 0 || coarse < best) {
      best   = coarse;
      levels = L;
    }
  }
  return levels;
}

// Piecewise-constant (Q0) interpolation from a grid coarser by fac per direction, for one rank's block of
// m[3] fine cells: each fine cell takes the value of the coarse cell that contains it, which the same rank owns.
// Rows and columns in PETSc's DMDA ordering (each rank's block contiguous, x fastest).
PetscErrorCode Q0Interpolation(MPI_Comm comm, const PetscInt m[3], const PetscInt fac[3], Mat *P)
{
  const PetscInt mc[3] = {m[0] / fac[0], m[1] / fac[1], m[2] / fac[2]};
  PetscInt       rstart, cstart;

  PetscFunctionBeginUser;
  PetscCall(MatCreateAIJ(comm, m[0] * m[1] * m[2], mc[0] * mc[1] * mc[2], PETSC_DETERMINE, PETSC_DETERMINE, 1, NULL, 0, NULL, P));
  PetscCall(MatGetOwnershipRange(*P, &rstart, NULL));
  PetscCall(MatGetOwnershipRangeColumn(*P, &cstart, NULL));
  for (PetscInt k = 0; k < m[2]; ++k)
    for (PetscInt j = 0; j < m[1]; ++j)
      for (PetscInt i = 0; i < m[0]; ++i) {
        const PetscInt row = rstart + (k * m[1] + j) * m[0] + i;
        const PetscInt col = cstart + ((k / fac[2]) * mc[1] + j / fac[1]) * mc[0] + i / fac[0];
        PetscCall(MatSetValue(*P, row, col, 1.0, INSERT_VALUES));
      }
  PetscCall(MatAssemblyBegin(*P, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*P, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

// PCMG with Galerkin coarse operators and Q0 interpolation built here: PETSc's DMDA coarsening halves each
// direction (a grid of 175 cells does not halve) and its Q0 interpolation takes factors of 2 only.
PetscErrorCode SetUpMultigrid(Fluid *f, PC pc, const char *prefix)
{
  PetscInt  levels, fac[3];
  PetscBool set;
  double    coarse;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(NULL, prefix, "-pc_mg_levels", &set));
  PetscCall(PCMGGetLevels(pc, &levels));
  if (!set) levels = ChooseLevels(f);
  if (levels > 1)
    PetscCheck(CoarseningFactors(f, levels, fac, &coarse), f->comm, PETSC_ERR_USER_INPUT,
               "-%spc_mg_levels %d: the fluid grid (per rank) cannot be coarsened %d times by whole factors; leave the option out to "
               "choose automatically",
               prefix, (int)levels, (int)levels - 1);
  PetscCall(PCMGSetLevels(pc, levels, NULL));
  if (levels == 1) PetscFunctionReturn(0);
  PetscCall(PCMGSetGalerkin(pc, PC_MG_GALERKIN_BOTH));
  PetscInt m[3] = {f->xm[0], f->xm[1], f->xm[2]};
  for (PetscInt l = levels - 1; l >= 1; --l) {
    Mat P;
    PetscCall(Q0Interpolation(f->comm, m, fac, &P));
    PetscCall(PCMGSetInterpolation(pc, l, P));
    PetscCall(MatDestroy(&P));
    for (int a = 0; a < 3; ++a) m[a] /= fac[a];
  }
  PetscCall(PetscInfo(pc, "PCMG: %d levels, coarsening factors %d x %d x %d\n", (int)levels, (int)fac[0], (int)fac[1], (int)fac[2]));
  PetscFunctionReturn(0);
}

// Makes the PCs named in the issue work on this operator without extra options: ICC/ILU in parallel run as
// block Jacobi with that sub-PC, and PCMG gets its hierarchy from SetUpMultigrid.
PetscErrorCode AdaptPreconditioner(Fluid *f)
{
  PC          pc;
  PetscBool   is_icc, is_ilu, is_mg;
  PetscMPIInt size;
  const char *prefix;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(f->comm, &size));
  PetscCall(KSPGetPC(f->ksp, &pc));
  PetscCall(KSPGetOptionsPrefix(f->ksp, &prefix));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCICC, &is_icc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCILU, &is_ilu));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCMG, &is_mg));
  if ((is_icc || is_ilu) && size > 1) {
    KSP     *sub;
    PetscInt nsub;
    PC       subpc;
    PetscCall(PCSetType(pc, PCBJACOBI));
    PetscCall(KSPSetUp(f->ksp));
    PetscCall(PCBJacobiGetSubKSP(pc, &nsub, NULL, &sub));
    PetscCall(KSPGetPC(sub[0], &subpc));
    PetscCall(PCSetType(subpc, is_icc ? PCICC : PCILU));
    PetscCall(PetscInfo(pc, "%s in parallel: block Jacobi with %s on each rank\n", is_icc ? "ICC" : "ILU", is_icc ? "ICC" : "ILU"));
  }
  if (is_mg) {
    PetscCall(SetUpMultigrid(f, pc, prefix));
    PetscCall(KSPSetFromOptions(f->ksp)); // the level smoothers read their options
  }
  PetscFunctionReturn(0);
}

// The matrix type and the default PC. The default is fastpoisson (src/fluid/fast_poisson.cpp: the separable inverse with
// one face coefficient, exact for model B without drag and a few CG iterations with it; 1.4-8 times cheaper per solve
// than PFMG and BoomerAMG on the seed's beds, docs/ksp.md) on an AIJ matrix wherever its pencils fit. Otherwise
// hypre's structured multigrid (PFMG, on a MATHYPRESTRUCT matrix), which PETSc 3.18 offers for 3D, non-periodic DMDAs
// only, and BoomerAMG on AIJ elsewhere. -fluid_p_pc_type other than pfmg selects AIJ; -fluid_p_mat_type overrides the
// choice.
PetscErrorCode ChooseMatrixType(Fluid *f, PetscBool fast_fits, PetscBool *structured, PetscBool *fast)
{
  char      pc_type[64] = "", mat_type[64] = "";
  PetscBool pc_set, mat_set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, "fluid_p_", "-pc_type", pc_type, sizeof(pc_type), &pc_set));
  PetscOptionsBegin(f->comm, "fluid_p_", "Pressure matrix", "Fluid");
  PetscCall(OptionsString(PetscOptionsObject, "-mat_type", "Pressure matrix type (default: aij; hyprestruct with -fluid_p_pc_type pfmg)",
                          "a Mat type", mat_type, sizeof(mat_type), &mat_set));
  PetscOptionsEnd();
  const PetscBool struct_ok = (PetscBool)(f->dim == 3 && !f->periodic[0] && !f->periodic[1] && !f->periodic[2]);
  *fast                     = (PetscBool)(!pc_set && fast_fits);
  PetscBool want_pfmg       = pc_set ? (PetscBool)!strcmp(pc_type, PCPFMG) : (PetscBool)(struct_ok && !*fast);
  if (mat_set) {
    PetscCall(DMSetMatType(f->da_p, mat_type));
    *structured = (PetscBool)!strcmp(mat_type, MATHYPRESTRUCT);
  } else {
    PetscCheck(!want_pfmg || struct_ok, f->comm, PETSC_ERR_USER_INPUT,
               "-fluid_p_pc_type pfmg needs a 3D grid without periodic directions (PETSc's MATHYPRESTRUCT); use hypre (BoomerAMG)");
    PetscCall(DMSetMatType(f->da_p, want_pfmg ? MATHYPRESTRUCT : MATAIJ));
    *structured = want_pfmg;
  }
  PetscFunctionReturn(0);
}

// BoomerAMG's default smoother is one symmetric hybrid Gauss-Seidel sweep down and one up (relax type 6): four passes
// over each level per V-cycle. A forward sweep down and a backward sweep up (types 3 and 4) keep the V-cycle
// symmetric, as CG needs, with half the passes: on the 2D 750 um pseudo-bed (15,750 cells, docs/ksp.md) the same
// 5.3-5.4 iterations per solve and a quarter less time in KSPSolve. Used unless the run sets either relax type.
PetscErrorCode SplitBoomerAMGSmoother(Fluid *f)
{
  PC          pc;
  PetscBool   is_hypre, down_set, up_set, all_set;
  const char *hypre_type = NULL;

  PetscFunctionBeginUser;
  PetscCall(KSPGetPC(f->ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCHYPRE, &is_hypre));
  if (!is_hypre) PetscFunctionReturn(0);
  PetscCall(PCHYPREGetType(pc, &hypre_type));
  if (!hypre_type || strcmp(hypre_type, "boomeramg")) PetscFunctionReturn(0);
  PetscCall(PetscOptionsHasName(NULL, "fluid_p_", "-pc_hypre_boomeramg_relax_type_down", &down_set));
  PetscCall(PetscOptionsHasName(NULL, "fluid_p_", "-pc_hypre_boomeramg_relax_type_up", &up_set));
  PetscCall(PetscOptionsHasName(NULL, "fluid_p_", "-pc_hypre_boomeramg_relax_type_all", &all_set));
  if (down_set || up_set || all_set) PetscFunctionReturn(0);
  PetscCall(PetscOptionsSetValue(NULL, "-fluid_p_pc_hypre_boomeramg_relax_type_down", "SOR/Jacobi"));
  PetscCall(PetscOptionsSetValue(NULL, "-fluid_p_pc_hypre_boomeramg_relax_type_up", "backward-SOR/Jacobi"));
  PetscCall(PCSetFromOptions(pc));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FluidPressureCreate(Fluid *f)
{
  PC          pc;
  PetscBool   structured = PETSC_FALSE, fast = PETSC_FALSE;
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(f->comm, &size));
  const PetscBool fast_fits = (PetscBool)FastPoissonPencilsFit(f->n, size);
  PetscCall(DMDASetInterpolationType(f->da_p, DMDA_Q0));
  PetscCall(FastPoissonRegister());                        // -fluid_p_pc_type fastpoisson
  PetscCall(OptionsCheckSolverTypes(f->comm, "fluid_p_")); // a misspelled -fluid_p_ksp_type names the choices
  PetscCall(ChooseMatrixType(f, fast_fits, &structured, &fast));
  PetscCall(DMCreateMatrix(f->da_p, &f->A));
  PetscCall(PetscObjectSetName((PetscObject)f->A, "pressure_matrix"));
  PetscCall(MatSetOption(f->A, MAT_SYMMETRIC, PETSC_TRUE));
  PetscCall(MatSetOption(f->A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  PetscCall(FluidStencilOperatorCreate(f)); // before the first assembly, which fills its coefficients
  PetscCall(AssembleMatrix(f, 0.0));
  if (!f->has_dirichlet) {
    PetscCall(MatNullSpaceCreate(f->comm, PETSC_TRUE, 0, NULL, &f->nullspace));
    for (Mat M : {f->A, f->op.A}) {
      if (!M) continue;
      PetscCall(MatSetNullSpace(M, f->nullspace));
      PetscCall(MatSetTransposeNullSpace(M, f->nullspace));
    }
  }
  PetscCall(KSPCreate(f->comm, &f->ksp));
  PetscCall(KSPSetOptionsPrefix(f->ksp, "fluid_p_"));
  PetscCall(KSPSetType(f->ksp, KSPCG));
  PetscCall(KSPGetPC(f->ksp, &pc));
  if (fast) {
    PetscCall(PCSetType(pc, PCFASTPOISSON));
  } else if (structured) {
    PetscCall(PCSetType(pc, PCPFMG));
  } else {
    PetscCall(PCSetType(pc, PCHYPRE));
    PetscCall(PCHYPRESetType(pc, "boomeramg"));
  }
  PetscCall(KSPSetTolerances(f->ksp, 1e-8, PETSC_DEFAULT, PETSC_DEFAULT, 10000));
  PetscCall(KSPSetOperators(f->ksp, f->op.A ? f->op.A : f->A, f->A));
  PetscCall(KSPSetFromOptions(f->ksp));
  PetscCall(SplitBoomerAMGSmoother(f));
  PetscCall(AdaptPreconditioner(f));
  {
    // The stencil form serves the preconditioners that only multiply by the solver's operator (theirs is the
    // assembled one). Others take more of it: PCMG's Galerkin coarse operators are products with it (MatPtAP),
    // field split takes its blocks, a composite hands it to its parts. They, and any other not named here, get the
    // assembled matrix.
    PetscBool multiplies_only;
    PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &multiplies_only, PCFASTPOISSON, PCHYPRE, PCGAMG, PCJACOBI, PCPBJACOBI, PCBJACOBI,
                                        PCSOR, PCICC, PCILU, PCNONE, PCASM, ""));
    if (!multiplies_only && f->op.A) {
      PetscCall(FluidStencilOperatorDestroy(f));
      PetscCall(KSPSetOperators(f->ksp, f->A, f->A));
    }
  }
  {
    PetscBool is_fp;
    PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFASTPOISSON, &is_fp));
    PetscCheck(!is_fp || fast_fits, f->comm, PETSC_ERR_USER_INPUT,
               "-fluid_p_pc_type fastpoisson needs at least as many fluid cells as ranks along x and along y (here %d x %d cells on %d "
               "ranks): use fewer ranks, more -grid_nx / -grid_ny cells, or another -fluid_p_pc_type (pfmg, hypre)",
               (int)f->n[0], (int)f->n[1], (int)size);
    const PetscReal weight[3] = {f->area[0] / f->h[0], f->area[1] / f->h[1], f->area[2] / f->h[2]};
    PetscCall(PCFastPoissonSetGrid(pc, f->da_p, weight, f->has_dirichlet));
    PetscBool is_composite;
    PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCCOMPOSITE, &is_composite));
    if (is_composite) { // e.g. -fluid_p_pc_composite_pcs sor,fastpoisson: each fastpoisson part gets the grid
      PetscInt parts;
      PetscCall(PCCompositeGetNumberPC(pc, &parts));
      for (PetscInt q = 0; q < parts; ++q) {
        PC sub;
        PetscCall(PCCompositeGetPC(pc, q, &sub));
        PetscCall(PCFastPoissonSetGrid(sub, f->da_p, weight, f->has_dirichlet));
      }
    }
  }
  PetscCall(FluidDumpSetFromOptions(f));
  {
    // The residual in the true (unpreconditioned) norm, so that -fluid_p_ksp_rtol bounds div(eps u) itself: CG
    // tracks it with the preconditioner on the left; the GMRES and BiCGStab families need it on the right. Other
    // Krylov methods keep their defaults, as do runs that set -fluid_p_ksp_norm_type or -fluid_p_ksp_pc_side.
    PetscBool is_cg, is_right, norm_set, side_set;
    PetscCall(PetscObjectTypeCompare((PetscObject)f->ksp, KSPCG, &is_cg));
    PetscCall(PetscObjectTypeCompareAny((PetscObject)f->ksp, &is_right, KSPGMRES, KSPFGMRES, KSPLGMRES, KSPBCGS, KSPBCGSL, ""));
    PetscCall(PetscOptionsHasName(NULL, "fluid_p_", "-ksp_norm_type", &norm_set));
    PetscCall(PetscOptionsHasName(NULL, "fluid_p_", "-ksp_pc_side", &side_set));
    if (!norm_set && !side_set && (is_cg || is_right)) {
      if (is_right) PetscCall(KSPSetPCSide(f->ksp, PC_RIGHT));
      PetscCall(KSPSetNormType(f->ksp, KSP_NORM_UNPRECONDITIONED));
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSolverNames(Fluid *f, const char **ksp, const char **pc)
{
  PC p;

  PetscFunctionBeginUser;
  PetscCall(KSPGetType(f->ksp, ksp));
  PetscCall(KSPGetPC(f->ksp, &p));
  PetscCall(PCGetType(p, pc));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidPressureDestroy(Fluid *f)
{
  PetscFunctionBeginUser;
  PetscCall(FluidDumpDestroy(f));
  PetscCall(KSPDestroy(&f->ksp));
  PetscCall(MatNullSpaceDestroy(&f->nullspace));
  PetscCall(FluidStencilOperatorDestroy(f));
  PetscCall(MatDestroy(&f->A));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidPressureSolve(Fluid *f, PetscReal dt)
{
  DMDAField          U, E, E0, b;
  KSPConvergedReason reason;
  PetscBool          rebuild = PETSC_FALSE, same = PETSC_TRUE;

  PetscFunctionBeginUser;
  // model A: the operator follows eps (assembled last with eps_old); with an implicit drag it follows the drag
  // coefficient and dt (and eps) at every step. The preconditioner is rebuilt every -fluid_pc_reuse solves at most.
  if (f->model == FLUID_MODEL_A) PetscCall(VecEqual(f->eps, f->eps_old, &same));
  if (f->has_drag || f->dt_last != 0) same = PETSC_FALSE; // dt_last != 0: the last assembly had a drag to undo
  if (!same) {
    PetscCall(AssembleMatrix(f, f->has_drag ? dt : 0.0));
    rebuild = (PetscBool)(f->since_pc + 1 >= f->pc_reuse);
    PetscCall(KSPSetReusePreconditioner(f->ksp, rebuild ? PETSC_FALSE : PETSC_TRUE));
  }

  PetscCall(DMDAFieldGet(f->da_u, f->u_loc, PETSC_TRUE, &U));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &E));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_old_loc, PETSC_TRUE, &E0));
  PetscCall(DMDAFieldGet(f->da_p, f->rhs, PETSC_FALSE, &b));
  PetscCheck(SameLayout(U, E) && SameLayout(U, E0), f->comm, PETSC_ERR_PLIB, "the velocity and scalar ghosted layouts differ");
  {
    const PetscInt st[3] = {U.stride(0), U.stride(1), U.stride(2)};
    ForEachOwnedOffset(f, U, b, [&](PetscInt p, PetscInt q) {
      const PetscReal deps = f->deps_dt ? (E.a[p] - E0.a[p]) / dt : 0.0;
      b.a[q]               = -(NetOutflow(f, U.a, E.a, U.dof, st, p) + f->vol * deps);
    });
  }
  PetscCall(DMDAFieldRestore(f->rhs, &b));
  PetscCall(DMDAFieldRestore(f->eps_old_loc, &E0));
  PetscCall(DMDAFieldRestore(f->eps_loc, &E));
  PetscCall(DMDAFieldRestore(f->u_loc, &U));
  if (f->nullspace) PetscCall(MatNullSpaceRemove(f->nullspace, f->rhs));
  PetscCall(VecNorm(f->rhs, NORM_2, &f->stats.rhs_scale));
  f->stats.rhs_scale /= f->vol;

  // initial guess: the last step's pressure (phi = dt p / rho); the pressure changes little from step to step
  PetscCall(VecAXPBY(f->phi, dt / f->rho, 0.0, f->p));
  PetscCall(KSPSetInitialGuessNonzero(f->ksp, PETSC_TRUE));
  PetscCall(FluidDumpBeforeSolve(f, dt));
  const double t0 = MPI_Wtime();
  PetscCall(KSPSetUp(f->ksp));
  PetscCall(KSPSolve(f->ksp, f->rhs, f->phi));
  const double t1 = MPI_Wtime();
  PetscCall(KSPGetConvergedReason(f->ksp, &reason));
  // A failed solve is recorded, not raised: the pressure guard (src/guards) stops the run with the solver's figures
  // and a diagnostic snapshot, or warns and lets it continue under -guard_action warn.
  f->stats.ksp_reason = (PetscInt)reason;
  if (reason < 0) f->stats.ksp_failures++;
  if (f->nullspace) PetscCall(MatNullSpaceRemove(f->nullspace, f->phi));
  PetscCall(KSPGetIterationNumber(f->ksp, &f->stats.ksp_its));
  PetscCall(KSPGetResidualNorm(f->ksp, &f->stats.ksp_rnorm));
  f->stats.ksp_time = t1 - t0;
  f->stats.ksp_time_total += t1 - t0;
  f->stats.ksp_its_total += f->stats.ksp_its;
  f->stats.solves++;
  if (f->stats.solves == 1 || rebuild) {
    f->stats.pc_setups++;
    f->since_pc = 0;
  } else {
    f->since_pc++;
  }
  PetscCall(FluidDumpAfterSolve(f, dt, (PetscBool)(f->since_pc == 0)));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidCorrect(Fluid *f, PetscReal dt)
{
  DMDAField U, E, B, Ph, Un;

  PetscFunctionBeginUser;
  PetscCall(DMGlobalToLocal(f->da_p, f->phi, INSERT_VALUES, f->phi_loc));
  PetscCall(DMDAFieldGet(f->da_s, f->drag_loc, PETSC_TRUE, &B));
  PetscCall(DMDAFieldGet(f->da_u, f->u_loc, PETSC_TRUE, &U));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &E));
  PetscCall(DMDAFieldGet(f->da_p, f->phi_loc, PETSC_TRUE, &Ph));
  PetscCall(DMDAFieldGet(f->da_u, f->u, PETSC_FALSE, &Un));
  PetscCheck(SameLayout(U, E) && SameLayout(U, B), f->comm, PETSC_ERR_PLIB, "the velocity and scalar ghosted layouts differ");
  for (int a = 0; a < f->dim; ++a) {
    // the faces this rank owns, boundary faces excepted (their velocity is given)
    const PetscInt dof = U.dof, sa = U.stride(a), sp = Ph.stride(a);
    PetscInt       lo[3], hi[3];
    OwnedBox(f, lo, hi);
    if (!f->periodic[a]) lo[a] = PetscMax(lo[a], 1);
    for (PetscInt k = lo[2]; k < hi[2]; ++k)
      for (PetscInt j = lo[1]; j < hi[1]; ++j) {
        PetscInt p = U.cell(lo[0], j, k), pp = Ph.cell(lo[0], j, k), q = Un.cell(lo[0], j, k);
        for (PetscInt i = lo[0]; i < hi[0]; ++i, ++p, ++pp, ++q) {
          const PetscReal e = 0.5 * (E.a[p - sa] + E.a[p]);
          Un.a[q * dof + a] = U.a[p * dof + a] - FaceCoefficient(f, E.a, B.a, dt, p, sa) / e * (Ph.a[pp] - Ph.a[pp - sp]) / f->h[a];
        }
      }
  }
  if (f->has_dirichlet && f->xs[1] + f->xm[1] == f->n[1]) {
    DMDAField      top;
    const PetscInt j = f->n[1] - 1;
    PetscCall(DMDAFieldGet(f->da_p, f->u_top, PETSC_FALSE, &top));
    for (PetscInt k = f->xs[2]; k < f->xs[2] + f->xm[2]; ++k)
      for (PetscInt i = f->xs[0]; i < f->xs[0] + f->xm[0]; ++i) {
        const PetscInt  c[3] = {i, j, k};
        const PetscReal coef =
          ProjectionCoefficient(f->model == FLUID_MODEL_B ? 1.0 : E.at(c), E.at(c), f->has_drag ? B.at(c) : 0.0, dt, f->rho) / E.at(c);
        top(i, j, k) = U(i, j + 1, k, 1) - coef * (0.0 - Ph.at(c)) / (0.5 * f->h[1]);
      }
    PetscCall(DMDAFieldRestore(f->u_top, &top));
  }
  PetscCall(DMDAFieldRestore(f->u, &Un));
  PetscCall(DMDAFieldRestore(f->phi_loc, &Ph));
  PetscCall(DMDAFieldRestore(f->drag_loc, &B));
  PetscCall(DMDAFieldRestore(f->eps_loc, &E));
  PetscCall(DMDAFieldRestore(f->u_loc, &U));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDivergence(Fluid *f, PetscReal dt, PetscReal *max_div)
{
  DMDAField U, E, E0;
  PetscReal loc = 0;

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(f->da_u, f->u_loc, PETSC_TRUE, &U));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_loc, PETSC_TRUE, &E));
  PetscCall(DMDAFieldGet(f->da_s, f->eps_old_loc, PETSC_TRUE, &E0));
  PetscCheck(SameLayout(U, E) && SameLayout(U, E0), f->comm, PETSC_ERR_PLIB, "the velocity and scalar ghosted layouts differ");
  {
    const PetscInt st[3] = {U.stride(0), U.stride(1), U.stride(2)};
    ForEachOwnedOffset(f, U, U, [&](PetscInt p, PetscInt) {
      const PetscReal deps = f->deps_dt ? (E.a[p] - E0.a[p]) / dt : 0.0;
      loc                  = PetscMax(loc, PetscAbsReal(NetOutflow(f, U.a, E.a, U.dof, st, p) / f->vol + deps));
    });
  }
  PetscCall(DMDAFieldRestore(f->eps_old_loc, &E0));
  PetscCall(DMDAFieldRestore(f->eps_loc, &E));
  PetscCall(DMDAFieldRestore(f->u_loc, &U));
  PetscCallMPI(MPI_Allreduce(&loc, max_div, 1, MPIU_REAL, MPI_MAX, f->comm));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
