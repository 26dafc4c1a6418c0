// The drag laws selectable with -drag_model, registered in a PetscFunctionList (include/fluidbed/drag_laws.hpp).
#include "fluidbed/drag_laws.hpp"
#include "fluidbed/kernels/drag_di_felice.hpp"
#include "fluidbed/kernels/drag_ergun.hpp"
#include "fluidbed/kernels/drag_huilin_gidaspow.hpp"
#include "fluidbed/kernels/drag_wen_yu.hpp"
#include "fluidbed/registry.hpp"

namespace fluidbed {

namespace {

PetscErrorCode RegisterBuiltins();
NamedRegistry  drag_laws("-drag_model", RegisterBuiltins);

// Each law registered as a function that returns its pair (PetscFunctionList holds plain function pointers).
#define FLUIDBED_DRAG_LAW(law)                                                                                                             \
  []() -> DragLaw {                                                                                                                        \
    return {kernels::law##_cell, static_cast<double (*)(const kernels::DragCellTerms &, const kernels::DragInput &)>(kernels::law##_k)};   \
  }

PetscErrorCode RegisterBuiltins()
{
  PetscFunctionBeginUser;
  // the seed's law: Ergun and Wen-Yu blended around eps = 0.8 (eq. 2.11-2.14)
  PetscCall(DragLawRegister("ergun_wenyu", FLUIDBED_DRAG_LAW(huilin_gidaspow)));
  PetscCall(DragLawRegister("gidaspow", FLUIDBED_DRAG_LAW(gidaspow)));
  PetscCall(DragLawRegister("wen_yu", FLUIDBED_DRAG_LAW(wen_yu)));
  PetscCall(DragLawRegister("ergun", FLUIDBED_DRAG_LAW(ergun)));
  PetscCall(DragLawRegister("di_felice", FLUIDBED_DRAG_LAW(di_felice)));
  PetscFunctionReturn(0);
}

#undef FLUIDBED_DRAG_LAW

} // namespace

PetscErrorCode DragLawRegister(const char *name, DragLawMaker maker)
{
  PetscFunctionBeginUser;
  PetscCall(drag_laws.Add(name, (void (*)(void))maker));
  PetscFunctionReturn(0);
}

PetscErrorCode DragLawList(PetscFunctionList *list)
{
  PetscFunctionBeginUser;
  PetscCall(drag_laws.List(list));
  PetscFunctionReturn(0);
}

PetscErrorCode DragLawGet(const char *name, DragLaw *law)
{
  void (*fn)(void);

  PetscFunctionBeginUser;
  PetscCall(drag_laws.Find(name, &fn));
  *law = ((DragLawMaker)fn)();
  PetscFunctionReturn(0);
}

} // namespace fluidbed
