// The drag laws selectable with -drag_model, registered in a PetscFunctionList.
#include "fluidbed/coupling.hpp"
#include "fluidbed/kernels/drag_di_felice.hpp"
#include "fluidbed/kernels/drag_huilin_gidaspow.hpp"

namespace fluidbed {

const char *const DragLawNames = "ergun_wenyu, gidaspow, wen_yu, ergun, di_felice";

namespace {
PetscFunctionList drag_laws = NULL;

PetscErrorCode RegisterDragLaws()
{
  PetscFunctionBeginUser;
  if (drag_laws) PetscFunctionReturn(0);
  // the seed's law: Ergun and Wen-Yu blended around eps = 0.8 (eq. 2.11-2.14)
  PetscCall(PetscFunctionListAdd(&drag_laws, "ergun_wenyu", kernels::huilin_gidaspow_k));
  PetscCall(PetscFunctionListAdd(&drag_laws, "gidaspow", kernels::gidaspow_k));
  PetscCall(PetscFunctionListAdd(&drag_laws, "wen_yu", kernels::wen_yu_k));
  PetscCall(PetscFunctionListAdd(&drag_laws, "ergun", kernels::ergun_k));
  PetscCall(PetscFunctionListAdd(&drag_laws, "di_felice", kernels::di_felice_k));
  PetscCall(PetscRegisterFinalize([]() -> PetscErrorCode { return PetscFunctionListDestroy(&drag_laws); }));
  PetscFunctionReturn(0);
}
} // namespace

PetscErrorCode DragLawGet(const char *name, DragLaw *law)
{
  void (*fn)(void) = NULL;

  PetscFunctionBeginUser;
  PetscCall(RegisterDragLaws());
  PetscCall(PetscFunctionListFind(drag_laws, name, &fn));
  PetscCheck(fn, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-drag_model %s is unknown: choose one of %s", name, DragLawNames);
  *law = (DragLaw)fn;
  PetscFunctionReturn(0);
}

} // namespace fluidbed
