// Gas inlets by name (-inlet_type): what enters through the bottom face (y = 0), as the superficial velocity of each
// of its cells. An inlet type reads its own -inlet_* options and fills the face's profile; the gas solver only sees
// the profile (and the openings, for the run's report and the jet measures). A new inlet (orifices, a shaped
// distributor) is one file in src/fluid/ with its Create function and one InletRegister line in
// src/fluid/inlets.cpp, or a call from a user's code before set-up.
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

#include "fluidbed/domain.hpp"
#include "fluidbed/kernels/fluid_flux.hpp"

namespace fluidbed {

// The bottom face of the fluid grid: n[0] x n[2] cells of h[0] x h[2] (n[2] = 1 in 2D).
struct InletFace {
  MPI_Comm      comm = MPI_COMM_NULL;
  const Domain *dom  = nullptr;
  PetscInt      n[3]{1, 1, 1};
  PetscReal     h[3]{0, 0, 0};
};

struct Inlet {
  // superficial velocity through each bottom cell (m/s), cell (i, k) at i + n[0] k
  std::vector<PetscReal> velocity;
  // the openings as ranges of cells along x through the depth (slits), in the order given, for the report and the
  // jet measures; empty for an inlet without openings
  std::vector<kernels::JetCells> openings;
  std::string                    summary; // one phrase for the run's report ("distributor 0.5 m/s, 1 slit(s)")
};
typedef PetscErrorCode (*InletCreate)(const InletFace &face, Inlet *inlet);

// Adds an inlet type to the registry under name.
PetscErrorCode InletRegister(const char *name, InletCreate create);
// The registry with the built-in types, for PetscOptionsFList.
PetscErrorCode InletList(PetscFunctionList *list);
// Fills inlet by the type of that name; an unknown name is an input error that lists the registered ones.
PetscErrorCode InletSetUp(const char *name, const InletFace &face, Inlet *inlet);

// The built-in types (src/fluid/inlet_*.cpp).
// slits: a porous distributor (-inlet_velocity) and slits through the depth (-inlet_jets), the seed's beds.
PetscErrorCode InletCreateSlits(const InletFace &face, Inlet *inlet);

} // namespace fluidbed
