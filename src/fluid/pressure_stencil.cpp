// The pressure operator's stencil form (-fluid_p_stencil_mult): the Krylov method's products A x from the face
// coefficients and diagonals of A's last assembly (Fluid::StencilOperator, kept by pressure.cpp's assembly) instead of
// from the AIJ matrix. Each row reads three face coefficients and a diagonal (32 bytes) where AIJ reads seven values,
// seven column indices and a row offset (88 bytes): the product streams memory, and on the fine 175 x 200 x 5 grid it
// is a third of the pressure solve (docs/performance.md). The preconditioner keeps the assembled matrix.
#include "fluid_impl.hpp"
#include "fluidbed/options.hpp"

namespace fluidbed {

namespace {

// y = A x, bit for bit the AIJ matrix's product: each row's terms are summed as MatMult_SeqAIJ sums a row, in column
// order from 0 (within the rank the natural order: the lower neighbours, the diagonal, the upper neighbours), and the
// neighbours on other ranks after all of them, as MatMult_MPIAIJ adds its off-diagonal block after the diagonal block.
// Without periodic directions the off-rank neighbours' global order is the natural one too (a lower neighbour lies on
// a lower rank). The off-diagonal values are -c_f, as the assembly stores them. X: x on the layout XL (the owned cells
// on one rank, the ghosted ones on several); Y: the owned rows.
template <int DIM>
void StencilProduct(const Fluid *f, const PetscScalar *X, const DMDAField &XL, PetscScalar *Y)
{
  const Fluid::StencilOperator &op = f->op;
  const DMDAField              &L  = op.layout;
  const PetscInt                N  = L.m[0] * L.m[1] * L.m[2];
  const PetscReal              *Wx = op.face.data(), *Wy = Wx + N, *Wz = DIM == 3 ? Wy + N : nullptr;
  const PetscReal              *D   = op.diag.data();
  const PetscInt                sw1 = L.stride(1), sw2 = L.stride(2), sx1 = XL.stride(1), sx2 = XL.stride(2);
  const PetscInt                i0 = f->xs[0], i1 = f->xs[0] + f->xm[0];
  for (PetscInt k = f->xs[2]; k < f->xs[2] + f->xm[2]; ++k)
    for (PetscInt j = f->xs[1]; j < f->xs[1] + f->xm[1]; ++j) {
      // the y and z neighbours: whether they exist (not past a wall or the outlet) and whether this rank owns them
      const bool has_ylo = j > 0, has_yhi = j < f->n[1] - 1;
      const bool in_ylo = has_ylo && j - 1 >= f->xs[1], in_yhi = has_yhi && j + 1 < f->xs[1] + f->xm[1];
      const bool has_zlo = DIM == 3 && k > 0, has_zhi = DIM == 3 && k < f->n[2] - 1;
      const bool in_zlo = has_zlo && k - 1 >= f->xs[2], in_zhi = has_zhi && k + 1 < f->xs[2] + f->xm[2];
      const bool off_line = (has_ylo && !in_ylo) || (has_yhi && !in_yhi) || (has_zlo && !in_zlo) || (has_zhi && !in_zhi);
      PetscInt   p = L.cell(i0, j, k), px = XL.cell(i0, j, k);
      for (PetscInt i = i0; i < i1; ++i, ++p, ++px, ++Y, ++D) {
        const bool  has_xlo = i > 0, has_xhi = i < f->n[0] - 1;
        const bool  in_xlo = has_xlo && i - 1 >= i0, in_xhi = has_xhi && i + 1 < i1;
        PetscScalar s = 0;
        if (DIM == 3 && in_zlo) s += -Wz[p] * X[px - sx2];
        if (in_ylo) s += -Wy[p] * X[px - sx1];
        if (in_xlo) s += -Wx[p] * X[px - 1];
        s += *D * X[px];
        if (in_xhi) s += -Wx[p + 1] * X[px + 1];
        if (in_yhi) s += -Wy[p + sw1] * X[px + sx1];
        if (DIM == 3 && in_zhi) s += -Wz[p + sw2] * X[px + sx2];
        if (off_line || (has_xlo && !in_xlo) || (has_xhi && !in_xhi)) {
          if (DIM == 3 && has_zlo && !in_zlo) s += -Wz[p] * X[px - sx2];
          if (has_ylo && !in_ylo) s += -Wy[p] * X[px - sx1];
          if (has_xlo && !in_xlo) s += -Wx[p] * X[px - 1];
          if (has_xhi && !in_xhi) s += -Wx[p + 1] * X[px + 1];
          if (has_yhi && !in_yhi) s += -Wy[p + sw1] * X[px + sx1];
          if (DIM == 3 && has_zhi && !in_zhi) s += -Wz[p + sw2] * X[px + sx2];
        }
        *Y = s;
      }
    }
}

PetscErrorCode StencilMult(Mat A, Vec x, Vec y)
{
  Fluid             *f;
  const PetscScalar *xa;
  PetscScalar       *ya;
  DMDAField          XL;
  Vec                xv = x;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &f));
  if (f->op.x_loc) { // several ranks: the neighbours on other ranks
    PetscCall(DMGlobalToLocalBegin(f->da_p, x, INSERT_VALUES, f->op.x_loc));
    PetscCall(DMGlobalToLocalEnd(f->da_p, x, INSERT_VALUES, f->op.x_loc));
    xv = f->op.x_loc;
    PetscCall(DMDAGetGhostCorners(f->da_p, &XL.s[0], &XL.s[1], &XL.s[2], &XL.m[0], &XL.m[1], &XL.m[2]));
  } else {
    PetscCall(DMDAGetCorners(f->da_p, &XL.s[0], &XL.s[1], &XL.s[2], &XL.m[0], &XL.m[1], &XL.m[2]));
  }
  PetscCall(VecGetArrayRead(xv, &xa));
  PetscCall(VecGetArrayWrite(y, &ya));
  if (f->dim == 3) StencilProduct<3>(f, xa, XL, ya);
  else StencilProduct<2>(f, xa, XL, ya);
  PetscCall(VecRestoreArrayWrite(y, &ya));
  PetscCall(VecRestoreArrayRead(xv, &xa));
  PetscCall(PetscLogFlops(f->op.flops));
  PetscFunctionReturn(0);
}

PetscErrorCode StencilGetDiagonal(Mat A, Vec d)
{
  Fluid       *f;
  PetscScalar *da;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &f));
  PetscCall(VecGetArrayWrite(d, &da));
  std::copy(f->op.diag.begin(), f->op.diag.end(), da);
  PetscCall(VecRestoreArrayWrite(d, &da));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FluidStencilOperatorCreate(Fluid *f)
{
  PetscBool on = PETSC_TRUE, aij;

  PetscFunctionBeginUser;
  PetscOptionsBegin(f->comm, "fluid_p_", "Pressure operator", "Fluid");
  PetscCall(OptionsBool(PetscOptionsObject, "-stencil_mult",
                        "The Krylov method multiplies by the operator's stencil (its face coefficients and diagonal) instead of the "
                        "assembled AIJ matrix: the same products bit for bit, at about half the memory traffic; for an AIJ matrix on "
                        "a grid without periodic directions (the preconditioner keeps the assembled matrix)",
                        &on, NULL));
  PetscOptionsEnd();
  PetscCall(PetscObjectTypeCompareAny((PetscObject)f->A, &aij, MATSEQAIJ, MATMPIAIJ, ""));
  const bool periodic = f->periodic[0] || f->periodic[1] || (f->dim == 3 && f->periodic[2]);
  if (!on || !aij || periodic) PetscFunctionReturn(0);
  PetscInt nlocal, nglobal;
  PetscCall(MatGetLocalSize(f->A, &nlocal, NULL));
  PetscCall(MatGetSize(f->A, &nglobal, NULL));
  PetscCall(MatCreateShell(f->comm, nlocal, nlocal, nglobal, nglobal, f, &f->op.A));
  PetscCall(MatShellSetOperation(f->op.A, MATOP_MULT, (void (*)(void))StencilMult));
  PetscCall(MatShellSetOperation(f->op.A, MATOP_MULT_TRANSPOSE, (void (*)(void))StencilMult)); // symmetric
  PetscCall(MatShellSetOperation(f->op.A, MATOP_GET_DIAGONAL, (void (*)(void))StencilGetDiagonal));
  PetscCall(PetscObjectSetName((PetscObject)f->op.A, "pressure_stencil"));
  PetscCall(MatSetOption(f->op.A, MAT_SYMMETRIC, PETSC_TRUE));
  PetscCall(MatSetOption(f->op.A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  // The flops MatMult_*AIJ logs for the same product, 2 nz - rows: each owned row has its diagonal and a neighbour on
  // each side that is not past the grid's end.
  PetscLogDouble nz = 1;
  for (int a = 0; a < f->dim; ++a) nz *= f->xm[a];
  const PetscLogDouble rows = nz;
  for (int a = 0; a < f->dim; ++a) {
    PetscLogDouble across = 1;
    for (int b = 0; b < f->dim; ++b)
      if (b != a) across *= f->xm[b];
    const PetscInt with_lower = f->xm[a] - (f->xs[a] == 0 ? 1 : 0), with_upper = f->xm[a] - (f->xs[a] + f->xm[a] == f->n[a] ? 1 : 0);
    nz += across * (with_lower + with_upper);
  }
  f->op.flops = 2 * nz - rows;
  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(f->comm, &size));
  if (size > 1) PetscCall(DMCreateLocalVector(f->da_p, &f->op.x_loc));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidStencilOperatorDestroy(Fluid *f)
{
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&f->op.x_loc));
  PetscCall(MatDestroy(&f->op.A));
  f->op.face.clear();
  f->op.diag.clear();
  PetscFunctionReturn(0);
}

} // namespace fluidbed
