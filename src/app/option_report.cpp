#include "fluidbed/option_report.hpp"
#include "fluidbed/simulation.hpp"

#include <cstdio>
#include <set>

namespace fluidbed {

namespace {

// Options PETSc reads only in PetscFinalize, after the list is made (found by running with each of PETSc's
// start-up and finalize options: -log_view, -malloc_dump, -memory_view, -objects_dump, ... are read at start-up),
// named without the dash: never reported.
const std::set<std::string> &ReadByPetscLate()
{
  static const std::set<std::string> names = {"options_left", "options_view", "citations"};
  return names;
}

std::string Value(const char *v)
{
  return v ? v : "";
}

// The option's value as given, when it was given (whether or not it has been read).
PetscErrorCode Given(const char name[], PetscBool *given, std::string *value)
{
  const char *v = NULL;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsFindPair(NULL, NULL, name, &v, given));
  *value = Value(v);
  PetscFunctionReturn(0);
}

} // namespace

PetscErrorCode UnusedOptionsCollect(Simulation *sim, UnusedOptions *list)
{
  PetscInt  n     = 0;
  char    **names = NULL, **values = NULL;
  PetscBool given;

  PetscFunctionBeginUser;
  list->clear();
  // Never read by any component: misspelled, or read only in scenes that use it (-fluid_* without -fluid, the
  // insertion options in a restart, a solver option of a PC that is not used, ...).
  PetscCall(PetscOptionsLeftGet(NULL, &n, &names, &values));
  for (PetscInt i = 0; i < n; ++i) {
    const std::string name = names[i] ? names[i] : "";
    if (name.empty() || ReadByPetscLate().count(name)) continue;
    // A continued run keeps its first command's insertion options; the particles come from the checkpoint.
    const bool insertion = name.compare(0, 7, "insert_") == 0;
    list->push_back({"-" + name, Value(values[i]),
                     sim->output.restart[0] && insertion ? "has no effect in a restart (the particles come from -restart)"
                                                         : "was not used (misspelled, or no effect in this scene)"});
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));

  // Read, but without effect in 2D: the grids have one layer in z and nothing is periodic in z.
  if (sim->domain.dim == 2) {
    for (const char *name : {"-grid_nz", "-domain_periodic_z"}) {
      std::string v;
      PetscCall(Given(name, &given, &v));
      if (given) list->push_back({name, v, "has no effect in a 2D run (-domain_dim 2)"});
    }
    // z components of vectors that 2D motion drops
    for (const char *name : {"-gravity", "-insert_velocity"}) {
      PetscReal   vec[3] = {0, 0, 0};
      PetscInt    nv     = 3;
      std::string v;
      PetscCall(Given(name, &given, &v));
      if (!given) continue;
      PetscCall(PetscOptionsGetRealArray(NULL, NULL, name, vec, &nv, NULL));
      if (nv == 3 && vec[2] != 0) list->push_back({name, v, "has a z component that has no effect in a 2D run (-domain_dim 2)"});
    }
  }

  // Read, but without effect in this scene as its model found at start-up (averaging that never starts, or is off).
  list->insert(list->end(), sim->model.without_effect.begin(), sim->model.without_effect.end());
  PetscFunctionReturn(0);
}

PetscErrorCode UnusedOptionsPrint(MPI_Comm comm, const UnusedOptions &list)
{
  PetscFunctionBeginUser;
  for (const UnusedOption &u : list)
    if (!u.printed)
      PetscCall(
        PetscPrintf(comm, "WARNING: option %s%s%s %s\n", u.name.c_str(), u.value.empty() ? "" : " ", u.value.c_str(), u.reason.c_str()));
  PetscFunctionReturn(0);
}

} // namespace fluidbed
