// What the run-time guards (src/guards) ask of the gas: whether its fields are numbers, and where the gas is fastest.
#include "fluid_impl.hpp"

#include <cmath>
#include <cstdint>

namespace fluidbed {

namespace {

constexpr PetscInt64 kNoCell = INT64_MAX;

PetscInt64 NaturalIndex(const Fluid *f, PetscInt i, PetscInt j, PetscInt k)
{
  return (PetscInt64)i + (PetscInt64)f->n[0] * ((PetscInt64)j + (PetscInt64)f->n[1] * (PetscInt64)k);
}

// The first owned cell (natural ordering) with a non-finite entry of a global vector on the fluid layout.
PetscErrorCode FirstNonFinite(Fluid *f, DM dm, Vec v, PetscInt64 *cell)
{
  DMDAField       V;
  PetscInt64      first = kNoCell;
  const PetscReal big   = PETSC_MAX_REAL;

  PetscFunctionBeginUser;
  PetscCall(DMDAFieldGet(dm, v, PETSC_FALSE, &V));
  ForEachOwnedCell(f, [&](PetscInt i, PetscInt j, PetscInt k) {
    for (PetscInt c = 0; c < V.dof; ++c) {
      const PetscReal x = V(i, j, k, c);
      if (!(x > -big && x < big)) first = PetscMin(first, NaturalIndex(f, i, j, k));
    }
  });
  PetscCall(DMDAFieldRestore(v, &V));
  PetscCallMPI(MPI_Allreduce(&first, cell, 1, MPIU_INT64, MPI_MIN, f->comm));
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode FluidCheckFinite(Fluid *f, PetscBool *finite, PetscInt64 *cell, const char **field)
{
  struct {
    const char *name;
    DM          dm;
    Vec         v;
  } fields[] = {{"velocity", f->da_u, f->u}, {"pressure", f->da_p, f->p}, {"void_fraction", f->da_s, f->eps}};

  PetscFunctionBeginUser;
  *finite = PETSC_TRUE;
  *cell   = -1;
  *field  = "";
  {
    // the common case in one pass over the owned arrays and one reduction; the cells are searched only on a fault
    PetscBool ok = PETSC_TRUE, all;
    for (auto &x : fields) {
      const PetscScalar *a;
      PetscInt           n;
      PetscCall(VecGetLocalSize(x.v, &n));
      PetscCall(VecGetArrayRead(x.v, &a));
      PetscReal sum = 0;
      for (PetscInt i = 0; i < n; ++i) sum += a[i] - a[i]; // 0 for a number, NaN for NaN or inf
      PetscCall(VecRestoreArrayRead(x.v, &a));
      if (sum != 0) ok = PETSC_FALSE;
    }
    PetscCallMPI(MPI_Allreduce(&ok, &all, 1, MPIU_BOOL, MPI_LAND, f->comm));
    if (all) PetscFunctionReturn(0);
  }
  for (auto &x : fields) {
    PetscInt64 first;
    PetscCall(FirstNonFinite(f, x.dm, x.v, &first));
    if (first != kNoCell) {
      *finite = PETSC_FALSE;
      *cell   = first;
      *field  = x.name;
      break;
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidLocateMaxSpeed(Fluid *f, PetscInt64 *cell, PetscReal *speed)
{
  DMDAField U;
  struct {
    double v;
    int    rank;
  } loc{-1.0, 0}, glob; // MPI_DOUBLE_INT
  PetscInt64  at = -1;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(f->comm, &rank));
  PetscCall(DMDAFieldGet(f->da_u, f->u, PETSC_FALSE, &U));
  ForEachOwnedCell(f, [&](PetscInt i, PetscInt j, PetscInt k) {
    for (PetscInt a = 0; a < U.dof; ++a) {
      const PetscReal s = PetscAbsReal(U(i, j, k, a));
      if (s > loc.v) {
        loc.v = s;
        at    = NaturalIndex(f, i, j, k);
      }
    }
  });
  PetscCall(DMDAFieldRestore(f->u, &U));
  loc.rank = rank;
  PetscCallMPI(MPI_Allreduce(&loc, &glob, 1, MPI_DOUBLE_INT, MPI_MAXLOC, f->comm));
  PetscCallMPI(MPI_Bcast(&at, 1, MPIU_INT64, (PetscMPIInt)glob.rank, f->comm));
  *cell  = at;
  *speed = glob.v;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidPressureSolverInfo(Fluid *f, const char **ksp, const char **pc, PetscInt *max_it)
{
  PetscFunctionBeginUser;
  PetscCall(FluidSolverNames(f, ksp, pc));
  PetscCall(KSPGetTolerances(f->ksp, NULL, NULL, NULL, max_it));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
