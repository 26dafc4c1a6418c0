// The drag laws selectable with -drag_model, registered in a PetscFunctionList (include/fluidbed/drag_laws.hpp).
#include "fluidbed/drag_laws.hpp"
#include "fluidbed/kernels/drag_di_felice.hpp"
#include "fluidbed/kernels/drag_ergun.hpp"
#include "fluidbed/kernels/drag_huilin_gidaspow.hpp"
#include "fluidbed/kernels/drag_wen_yu.hpp"

#include <string>

namespace fluidbed {

namespace {

PetscFunctionList drag_laws = NULL;
std::string       drag_names; // the registered names, comma-separated, for the error of an unknown one
bool              builtins = false;

// Each law registered as a function that returns its pair (PetscFunctionList holds plain function pointers).
#define FLUIDBED_DRAG_LAW(law)                                                                                                             \
  []() -> DragLaw {                                                                                                                        \
    return {kernels::law##_cell, static_cast<double (*)(const kernels::DragCellTerms &, const kernels::DragInput &)>(kernels::law##_k)};   \
  }

PetscErrorCode RegisterBuiltins()
{
  PetscFunctionBeginUser;
  if (builtins) PetscFunctionReturn(0);
  builtins = true;
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
  if (!drag_laws)
    PetscCall(PetscRegisterFinalize([]() -> PetscErrorCode {
      drag_names.clear();
      builtins = false;
      return PetscFunctionListDestroy(&drag_laws);
    }));
  PetscCall(PetscFunctionListAdd(&drag_laws, name, (void (*)(void))maker));
  drag_names += (drag_names.empty() ? "" : ", ") + std::string(name);
  PetscFunctionReturn(0);
}

PetscErrorCode DragLawList(PetscFunctionList *list)
{
  PetscFunctionBeginUser;
  PetscCall(RegisterBuiltins());
  *list = drag_laws;
  PetscFunctionReturn(0);
}

PetscErrorCode DragLawGet(const char *name, DragLaw *law)
{
  void (*fn)(void) = NULL;

  PetscFunctionBeginUser;
  PetscCall(RegisterBuiltins());
  PetscCall(PetscFunctionListFind(drag_laws, name, &fn));
  PetscCheck(fn, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-drag_model %s is unknown: choose one of %s", name, drag_names.c_str());
  *law = ((DragLawMaker)fn)();
  PetscFunctionReturn(0);
}

} // namespace fluidbed
