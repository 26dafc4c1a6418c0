// One DMDA creation and one array view for the grids, the gas and the coupling (include/fluidbed/dmda_field.hpp).
#include "fluidbed/dmda_field.hpp"

namespace fluidbed {

PetscErrorCode DMDAFieldGet(DM dm, Vec v, PetscBool ghosted, DMDAField *view)
{
  PetscInt dim, dof;

  PetscFunctionBeginUser;
  PetscCall(DMDAGetInfo(dm, &dim, NULL, NULL, NULL, NULL, NULL, NULL, &dof, NULL, NULL, NULL, NULL, NULL));
  if (ghosted) PetscCall(DMDAGetGhostCorners(dm, &view->s[0], &view->s[1], &view->s[2], &view->m[0], &view->m[1], &view->m[2]));
  else PetscCall(DMDAGetCorners(dm, &view->s[0], &view->s[1], &view->s[2], &view->m[0], &view->m[1], &view->m[2]));
  if (dim == 2) {
    view->s[2] = 0;
    view->m[2] = 1;
  }
  view->dof = dof;
  PetscCall(VecGetArray(v, &view->a));
  PetscFunctionReturn(0);
}

PetscErrorCode DMDAFieldRestore(Vec v, DMDAField *view)
{
  PetscFunctionBeginUser;
  PetscCall(VecRestoreArray(v, &view->a));
  view->a = nullptr;
  PetscFunctionReturn(0);
}

PetscErrorCode DMDACreateLayout(MPI_Comm comm, PetscInt dim, const DMBoundaryType bt[3], DMDAStencilType st, const PetscInt N[3],
                                const PetscInt procs[3], const PetscInt *const own[3], PetscInt dof, PetscInt sw, DM *da)
{
  PetscFunctionBeginUser;
  if (dim == 2) PetscCall(DMDACreate2d(comm, bt[0], bt[1], st, N[0], N[1], procs[0], procs[1], dof, sw, own[0], own[1], da));
  else
    PetscCall(
      DMDACreate3d(comm, bt[0], bt[1], bt[2], st, N[0], N[1], N[2], procs[0], procs[1], procs[2], dof, sw, own[0], own[1], own[2], da));
  PetscCall(DMSetUp(*da));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
