// The drag laws selectable with -drag_model, registered in a PetscFunctionList.
#include "fluidbed/coupling.hpp"
#include "fluidbed/kernels/drag_di_felice.hpp"
#include "fluidbed/kernels/drag_huilin_gidaspow.hpp"

namespace fluidbed {

const char *const DragLawNames = "ergun_wenyu, gidaspow, wen_yu, ergun, di_felice";

namespace {

PetscFunctionList drag_laws = NULL;

// Each law registered as a function that returns its pair (PetscFunctionList holds plain function pointers).
#define FLUIDBED_DRAG_LAW(law)                                                                                                             \
  []() -> DragLaw {                                                                                                                        \
    return {kernels::law##_cell, static_cast<double (*)(const kernels::DragCellTerms &, const kernels::DragInput &)>(kernels::law##_k)};   \
  }

PetscErrorCode RegisterDragLaws()
{
  using Maker = DragLaw (*)();

  PetscFunctionBeginUser;
  if (drag_laws) PetscFunctionReturn(0);
  // the seed's law: Ergun and Wen-Yu blended around eps = 0.8 (eq. 2.11-2.14)
  PetscCall(PetscFunctionListAdd(&drag_laws, "ergun_wenyu", (Maker)FLUIDBED_DRAG_LAW(huilin_gidaspow)));
  PetscCall(PetscFunctionListAdd(&drag_laws, "gidaspow", (Maker)FLUIDBED_DRAG_LAW(gidaspow)));
  PetscCall(PetscFunctionListAdd(&drag_laws, "wen_yu", (Maker)FLUIDBED_DRAG_LAW(wen_yu)));
  PetscCall(PetscFunctionListAdd(&drag_laws, "ergun", (Maker)FLUIDBED_DRAG_LAW(ergun)));
  PetscCall(PetscFunctionListAdd(&drag_laws, "di_felice", (Maker)FLUIDBED_DRAG_LAW(di_felice)));
  PetscCall(PetscRegisterFinalize([]() -> PetscErrorCode { return PetscFunctionListDestroy(&drag_laws); }));
  PetscFunctionReturn(0);
}

#undef FLUIDBED_DRAG_LAW

} // namespace

PetscErrorCode DragLawGet(const char *name, DragLaw *law)
{
  void (*fn)(void) = NULL;

  PetscFunctionBeginUser;
  PetscCall(RegisterDragLaws());
  PetscCall(PetscFunctionListFind(drag_laws, name, &fn));
  PetscCheck(fn, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-drag_model %s is unknown: choose one of %s", name, DragLawNames);
  *law = ((DragLaw(*)())fn)();
  PetscFunctionReturn(0);
}

} // namespace fluidbed
