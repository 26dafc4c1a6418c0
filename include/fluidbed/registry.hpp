// Models chosen by name: a PetscFunctionList (what PetscOptionsFList offers in -help) with the names kept for
// the error of an unknown one. The drag laws (-drag_model) and the contact models (-dem_contact_model) are each one
// registry; a new model is one Add call, from fluidbed's list of built-ins or from a user's code before set-up.
#pragma once

#include <petscsys.h>

#include <string>

namespace fluidbed {

class NamedRegistry {
public:
  // option: the option that picks a name (for the error message); builtins: registers the built-in models, called
  // once before the first lookup.
  NamedRegistry(const char *option, PetscErrorCode (*builtins)()) : option_(option), builtins_(builtins) {}

  // Adds fn under name.
  PetscErrorCode Add(const char *name, void (*fn)(void));
  // The list with the built-ins registered, for PetscOptionsFList.
  PetscErrorCode List(PetscFunctionList *list);
  // The function registered under name; an unknown name is an input error naming the option and the choices.
  PetscErrorCode Find(const char *name, void (**fn)(void));

private:
  PetscErrorCode        Builtins();
  static PetscErrorCode Finalize();

  const char *option_;
  PetscErrorCode (*builtins_)();
  PetscFunctionList list_ = NULL;
  std::string       names_; // the registered names, comma-separated
  bool              have_builtins_ = false, finalize_registered_ = false;
};

} // namespace fluidbed
