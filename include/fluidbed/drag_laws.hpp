// Drag laws by name (-drag_model): K = beta / (1 - eps), N s / m^4, each a pair of kernels (kernels/drag_*.hpp,
// kernels/drag_common.hpp): the terms of a cell's void fraction, computed once per coupling cell, then K of a
// particle in it. A new law is one kernel header with its pair and one DragLawRegister line in
// src/coupling/drag_laws.cpp (or a call from a user's own code before the run is set up).
#pragma once

#include <petscsys.h>

#include "fluidbed/kernels/drag_common.hpp"

namespace fluidbed {

struct DragLaw {
  kernels::DragCellTerms (*cell)(double eps)                                     = nullptr;
  double (*k)(const kernels::DragCellTerms &terms, const kernels::DragInput &in) = nullptr;
};
typedef DragLaw (*DragLawMaker)();

// Adds a law to the registry under name (the value of -drag_model).
PetscErrorCode DragLawRegister(const char *name, DragLawMaker maker);
// The registry with the built-in laws (registered on first use), for PetscOptionsFList.
PetscErrorCode DragLawList(PetscFunctionList *list);
// The law of that name; an unknown name is an input error that lists the registered ones.
PetscErrorCode DragLawGet(const char *name, DragLaw *law);

} // namespace fluidbed
