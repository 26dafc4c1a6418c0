// Models by name on a PetscFunctionList (include/fluidbed/registry.hpp).
#include "fluidbed/registry.hpp"

#include <vector>

namespace fluidbed {

namespace {
std::vector<NamedRegistry *> &Registries()
{
  static std::vector<NamedRegistry *> all; // those holding a list, emptied at PetscFinalize
  return all;
}
} // namespace

PetscErrorCode NamedRegistry::Finalize()
{
  PetscFunctionBeginUser;
  for (NamedRegistry *r : Registries()) {
    PetscCall(PetscFunctionListDestroy(&r->list_));
    r->names_.clear();
    r->have_builtins_ = r->finalize_registered_ = false;
  }
  Registries().clear();
  PetscFunctionReturn(0);
}

PetscErrorCode NamedRegistry::Add(const char *name, void (*fn)(void))
{
  PetscFunctionBeginUser;
  if (!finalize_registered_) {
    if (Registries().empty()) PetscCall(PetscRegisterFinalize(Finalize));
    Registries().push_back(this);
    finalize_registered_ = true;
  }
  PetscCall(PetscFunctionListAdd(&list_, name, fn));
  names_ += (names_.empty() ? "" : ", ") + std::string(name);
  PetscFunctionReturn(0);
}

PetscErrorCode NamedRegistry::Builtins()
{
  PetscFunctionBeginUser;
  if (!have_builtins_) {
    have_builtins_ = true;
    PetscCall(builtins_());
  }
  PetscFunctionReturn(0);
}

PetscErrorCode NamedRegistry::List(PetscFunctionList *list)
{
  PetscFunctionBeginUser;
  PetscCall(Builtins());
  *list = list_;
  PetscFunctionReturn(0);
}

PetscErrorCode NamedRegistry::Find(const char *name, void (**fn)(void))
{
  PetscFunctionBeginUser;
  PetscCall(Builtins());
  *fn = NULL;
  PetscCall(PetscFunctionListFind(list_, name, fn));
  PetscCheck(*fn, PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s %s is unknown: choose one of %s", option_, name, names_.c_str());
  PetscFunctionReturn(0);
}

} // namespace fluidbed
