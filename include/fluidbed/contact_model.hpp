// Contact models by name (-dem_contact_model): the law a contact obeys and the history it keeps between steps.
//
// The particle code knows a contact's history only as history_size reals: each particle's swarm slots hold that
// many per contact (field contact_hist, moved with the particle, written to checkpoints), and the neighbour lists
// keep the evaluating side's copy between rebuilds (NeighbourList::pair_hist, wall_hist). A model reads and
// writes its own layout inside those reals. A new model is one file in src/contact/ with its Create function and
// one ContactModelRegister line in src/contact/contact_model.cpp (or a call from a user's code before set-up);
// its kernels, header-only and without PETSc, go in include/fluidbed/kernels/.
#pragma once

#include <petscsys.h>

namespace fluidbed {

struct Dem;

struct ContactModel {
  const char *name         = nullptr; // as given to -dem_contact_model
  PetscInt    history_size = 0;       // reals of history per contact
  // Forces, torques and dashpot impulse corrections of the local particles' contacts, plus gravity, into the
  // swarm's force and torque fields and Dem::impulse; the pairs' and walls' histories advance (dem.hpp).
  PetscErrorCode (*forces)(Dem *dem) = nullptr;
  // The history of a pair as its partner sees it (the same contact from the other side), from h into out.
  void (*mirror)(const PetscReal *h, PetscReal *out) = nullptr;
  // The elastic energy stored in one contact in touch with history h, J (wall: a contact with a wall).
  PetscReal (*elastic_energy)(const Dem &dem, const PetscReal *h, bool wall) = nullptr;
};
typedef PetscErrorCode (*ContactModelCreate)(ContactModel *model);

// Adds a model to the registry under name.
PetscErrorCode ContactModelRegister(const char *name, ContactModelCreate create);
// The registry with the built-in models, for PetscOptionsFList.
PetscErrorCode ContactModelList(PetscFunctionList *list);
// The model of that name; an unknown name is an input error that lists the registered ones.
PetscErrorCode ContactModelGet(const char *name, ContactModel *model);

// The built-in models (src/contact/contact_*.cpp).
PetscErrorCode ContactModelCreateLsd(ContactModel *model); // linear spring-dashpot, seed eq. 2.3-2.10

} // namespace fluidbed
