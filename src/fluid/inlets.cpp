// Gas inlet types by name (include/fluidbed/inlets.hpp).
#include "fluidbed/inlets.hpp"
#include "fluidbed/registry.hpp"

namespace fluidbed {

namespace {
PetscErrorCode RegisterBuiltins()
{
  PetscFunctionBeginUser;
  PetscCall(InletRegister("slits", InletCreateSlits));
  PetscFunctionReturn(0);
}
NamedRegistry inlet_types("-inlet_type", RegisterBuiltins);
} // namespace

PetscErrorCode InletRegister(const char *name, InletCreate create)
{
  PetscFunctionBeginUser;
  PetscCall(inlet_types.Add(name, (void (*)(void))create));
  PetscFunctionReturn(0);
}

PetscErrorCode InletList(PetscFunctionList *list)
{
  PetscFunctionBeginUser;
  PetscCall(inlet_types.List(list));
  PetscFunctionReturn(0);
}

PetscErrorCode InletSetUp(const char *name, const InletFace &face, Inlet *inlet)
{
  void (*fn)(void);

  PetscFunctionBeginUser;
  PetscCall(inlet_types.Find(name, &fn));
  *inlet = Inlet{};
  PetscCall(((InletCreate)fn)(face, inlet));
  PetscCheck(inlet->velocity.size() == (std::size_t)(face.n[0] * face.n[2]), PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "inlet type %s gave %d face velocities for %d bottom cells", name, (int)inlet->velocity.size(), (int)(face.n[0] * face.n[2]));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
